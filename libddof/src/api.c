/* api.c - version, defaults of the parameter structs, names. */
#include "internal.h"

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

void ddof_params_init(ddof_params *params)
{
    if (!params)
        return;
    *params = (ddof_params){
        .struct_size = sizeof *params,
        .solver = DDOF_SOLVER_THOMAS,
        .substeps = 1,
        .beta_scale = DDOF_DEFAULT_BETA_SCALE,
        .pixel_aspect = 1.0f,
        .jacobi_iterations = 50,
        .coc_signed = 0,
        .background = DDOF_LAYER_AUTO,
        .background_threshold_px = 8.0f,
        .background_ramp_start_px = 2.0f,
        .background_levels = 1,
        .near_spread = DDOF_LAYER_AUTO,
        .near_spread_threshold_px = 4.0f,
    };
}

void ddof_camera_init(ddof_camera *camera)
{
    if (!camera)
        return;
    *camera = (ddof_camera){
        .struct_size = sizeof *camera,
        .lens_model = DDOF_LENS_CYCLES,
        .depth_kind = DDOF_DEPTH_PLANAR,
        .sensor_fit = DDOF_SENSOR_FIT_AUTO,
        .focal_length_mm = 50.0,
        .sensor_width_mm = 36.0,
        .fstop = 2.8,
        .focus_distance_m = 10.0,
        .pixel_aspect = 1.0,
        .depth_unit_m = 1.0,
    };
}

void ddof_curve_init(ddof_curve *curve)
{
    if (!curve)
        return;
    *curve = (ddof_curve){
        .struct_size = sizeof *curve,
        .near_blur_px = 0.0,
        .near_start = 0.0,
        .near_end = 0.0,
        .far_start = 10.0,
        .far_end = 100.0,
        .far_blur_px = 16.0,
    };
}

void ddof_foreground_init(ddof_foreground *foreground)
{
    if (foreground)
        *foreground = (ddof_foreground){.struct_size = sizeof *foreground, .premultiplied = 1};
}

const char *ddof_solver_name(ddof_solver solver)
{
    switch (solver) {
    case DDOF_SOLVER_THOMAS: return "thomas";
    case DDOF_SOLVER_CYCLIC_REDUCTION: return "cr";
    case DDOF_SOLVER_PCR: return "pcr";
    case DDOF_SOLVER_JACOBI: return "jacobi";
    case DDOF_SOLVER_REFERENCE_F64: return "reference";
    case DDOF_SOLVER_COUNT_: break;
    }
    return NULL;
}
