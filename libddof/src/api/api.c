/* SPDX-License-Identifier: MIT */
/* api.c - version, defaults of the parameter structs, names. */
#include "cards/cards.h"
#include "runtime/internal.h"

#include <string.h>

unsigned ddof_version_number(void)
{
    return DDOF_VERSION_NUMBER;
}

#define DDOF_STR2(x) #x
#define DDOF_STR(x) DDOF_STR2(x)

const char *ddof_version_string(void)
{
    return DDOF_STR(DDOF_VERSION_MAJOR) "." DDOF_STR(DDOF_VERSION_MINOR) "." DDOF_STR(
        DDOF_VERSION_PATCH);
}

/* What a preset sets; everything else keeps its base default. */
typedef struct preset_settings {
    ddof_method method;
    ddof_solver solver;
    uint32_t substeps;
    float beta_scale;
    ddof_layer_mode background;
    uint32_t background_levels;
    ddof_layer_mode near_spread;
    ddof_kernel kernel;
    ddof_layer_mode near_layer;
    ddof_layer_mode far_field;
    ddof_layer_mode silhouettes;
    ddof_layer_mode blurred_edges;
} preset_settings;

/* Written by the accuracy study from its measured front (docs/accuracy.md). */
static const preset_settings presets[DDOF_PRESET_COUNT_] = {
#include "presets_measured.inc"
};

const char *ddof_preset_name(ddof_preset preset)
{
    switch (preset) {
    case DDOF_PRESET_PREVIEW: return "preview";
    case DDOF_PRESET_DEFAULT: return "default";
    case DDOF_PRESET_FINAL: return "final";
    case DDOF_PRESET_COUNT_:
    case DDOF_PRESET_FORCE_32BIT_: break;
    }
    return NULL;
}

/* The caller's first `size` bytes of `full` (never more than full_size), with struct_size
 * saying how many were written. Nothing below the size field's own 4 bytes. */
static void write_prefix(void *caller, size_t size, const void *full, size_t full_size)
{
    if (!caller || size < sizeof(uint32_t))
        return;
    const size_t n = size < full_size ? size : full_size;
    memcpy(caller, full, n);
    const uint32_t written = (uint32_t)n;
    memcpy(caller, &written, sizeof written);
}

/* The whole struct of each kind with its defaults; the init functions write a prefix of it. */
static ddof_params preset_params(ddof_preset preset)
{
    const int known = (unsigned)preset < DDOF_PRESET_COUNT_;
    const preset_settings *s = &presets[known ? preset : DDOF_PRESET_DEFAULT];
    return (ddof_params){
        .struct_size = sizeof(ddof_params),
        .method = s->method,
        .solver = s->solver,
        .substeps = s->substeps,
        .beta_scale = s->beta_scale,
        .pixel_aspect = 1.0f,
        .jacobi_iterations = 50,
        .coc_signed = 0,
        .background = s->background,
        .background_threshold_px = 8.0f,
        .background_ramp_start_px = 2.0f,
        .background_levels = s->background_levels,
        .near_spread = s->near_spread,
        .near_spread_threshold_px = 4.0f,
        .precision = DDOF_PRECISION_FLOAT,
        .kernel = s->kernel,
        .in_focus_threshold_px = DDOF_DEFAULT_IN_FOCUS_THRESHOLD_PX,
        .highlights = DDOF_LAYER_AUTO,
        .highlight_threshold = 0.25f, /* measured: docs/disc-kernel.md, the highlight pass */
        .near_layer = s->near_layer,
        .near_layer_threshold_px = 8.0f,
        .far_field = s->far_field,
        .silhouettes = s->silhouettes,
        .blurred_edges = s->blurred_edges,
    };
}

static ddof_camera default_camera(void)
{
    return (ddof_camera){
        .struct_size = sizeof(ddof_camera),
        .lens_model = DDOF_LENS_CYCLES,
        .depth_kind = DDOF_DEPTH_PLANAR,
        .sensor_fit = DDOF_SENSOR_FIT_AUTO,
        .focal_length_mm = 50.0,
        .sensor_width_mm = 36.0,
        .fstop = 2.8,
        .focus_distance_m = 10.0,
        .pixel_aspect = 1.0,
        .depth_unit_m = 1.0,
        .aperture_ratio = 1.0,
    };
}

static ddof_curve default_curve(void)
{
    return (ddof_curve){
        .struct_size = sizeof(ddof_curve),
        .near_blur_px = 0.0,
        .near_start = 0.0,
        .near_end = 0.0,
        .far_start = 10.0,
        .far_end = 100.0,
        .far_blur_px = 16.0,
    };
}

static int preset_known(ddof_preset preset)
{
    return (unsigned)preset < DDOF_PRESET_COUNT_;
}

ddof_status ddof_params_init_preset_sized(ddof_params *caller, size_t size, ddof_preset preset)
{
    if (!caller)
        return DDOF_ERROR_NULL_POINTER;
    const ddof_params full = preset_params(preset);
    write_prefix(caller, size, &full, sizeof full);
    return preset_known(preset) ? DDOF_OK : DDOF_ERROR_BAD_PARAMETER;
}

void ddof_params_init_sized(ddof_params *params, size_t size)
{
    (void)ddof_params_init_preset_sized(params, size, DDOF_PRESET_DEFAULT);
}

void ddof_camera_init_sized(ddof_camera *camera, size_t size)
{
    const ddof_camera full = default_camera();
    write_prefix(camera, size, &full, sizeof full);
}

void ddof_curve_init_sized(ddof_curve *curve, size_t size)
{
    const ddof_curve full = default_curve();
    write_prefix(curve, size, &full, sizeof full);
}

void ddof_foreground_init_sized(ddof_foreground *foreground, size_t size)
{
    const ddof_foreground full = {.struct_size = sizeof full, .premultiplied = 1};
    write_prefix(foreground, size, &full, sizeof full);
}

void ddof_cards_params_init_sized(ddof_cards_params *params, size_t size)
{
    const ddof_cards_params full = {.struct_size = sizeof full,
                                    .expansion = DDOF_CARDS_EXPAND_OFFSET,
                                    .strips = CARDS_DEFAULT_STRIPS};
    write_prefix(params, size, &full, sizeof full);
}

/* The plain names: called by binaries built against 0.5, whose structs have the 0.5 layout. */
ddof_status (ddof_params_init_preset)(ddof_params *params, ddof_preset preset)
{
    return ddof_params_init_preset_sized(params, DDOF_PARAMS_SIZE_0_5, preset);
}

void (ddof_params_init)(ddof_params *params)
{
    ddof_params_init_sized(params, DDOF_PARAMS_SIZE_0_5);
}

void (ddof_camera_init)(ddof_camera *camera)
{
    ddof_camera_init_sized(camera, DDOF_CAMERA_SIZE_0_5);
}

void (ddof_curve_init)(ddof_curve *curve)
{
    ddof_curve_init_sized(curve, DDOF_CURVE_SIZE_0_5);
}

void (ddof_foreground_init)(ddof_foreground *foreground)
{
    ddof_foreground_init_sized(foreground, DDOF_FOREGROUND_SIZE_0_5);
}

void (ddof_cards_params_init)(ddof_cards_params *params)
{
    ddof_cards_params_init_sized(params, DDOF_CARDS_PARAMS_SIZE_0_5);
}

const char *ddof_kernel_name(ddof_kernel kernel)
{
    switch (kernel) {
    case DDOF_KERNEL_HEAT: return "heat";
    case DDOF_KERNEL_DISC_2X2: return "disc-2x2";
    case DDOF_KERNEL_DISC_2X3: return "disc-2x3";
    case DDOF_KERNEL_DISC_3X3: return "disc-3x3";
    case DDOF_KERNEL_COUNT_:
    case DDOF_KERNEL_FORCE_32BIT_: break;
    }
    return NULL;
}

const char *ddof_solver_name(ddof_solver solver)
{
    switch (solver) {
    case DDOF_SOLVER_THOMAS: return "thomas";
    case DDOF_SOLVER_CYCLIC_REDUCTION: return "cr";
    case DDOF_SOLVER_PCR: return "pcr";
    case DDOF_SOLVER_JACOBI: return "jacobi";
    case DDOF_SOLVER_REFERENCE_F64: return "reference";
    case DDOF_SOLVER_GRUEN: return "gruen";
    case DDOF_SOLVER_COUNT_:
    case DDOF_SOLVER_FORCE_32BIT_: break;
    }
    return NULL;
}
