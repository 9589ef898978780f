/* SPDX-License-Identifier: MIT */
/* choices.c - the named values of the options: the library's names, and the few lists the
 * library has no name function for. */
#include "choices.h"

#include "exrio.h"

#include <ddof.h>

#include <stdio.h>
#include <strings.h>

static const char *preset_name(int v) { return ddof_preset_name((ddof_preset)v); }
static const char *solver_name(int v) { return ddof_solver_name((ddof_solver)v); }
static const char *kernel_name(int v) { return ddof_kernel_name((ddof_kernel)v); }

/* The host-GL backend renders into a host application's GL context, which a command has not. */
static const char *backend_name(int v)
{
    return v == DDOF_BACKEND_HOST_GL ? NULL : ddof_backend_name((ddof_backend_kind)v);
}

/* A uint channel holds ids, not colour: the command writes half or float. */
static const char *pixel_type_name(int v)
{
    return v == EXRIO_UINT ? NULL : exrio_pixel_type_name((exrio_pixel_type)v);
}

/* Every compression exrio can write (all of the format's: DWAA/DWAB through the C++ library). */
static const char *compression_name(int v)
{
    const exrio_compression c = (exrio_compression)v;
    return exrio_compression_can_encode(c) ? exrio_compression_name(c) : NULL;
}

/* A list of names in the enum's order; out of range is no name. */
#define NAMES_OF(fn, ...)                                                                    \
    static const char *fn(int v)                                                             \
    {                                                                                        \
        static const char *const names[] = {__VA_ARGS__};                                    \
        return v >= 0 && (size_t)v < sizeof names / sizeof names[0] ? names[v] : NULL;       \
    }

NAMES_OF(method_name, "diffusion", "cod4")
NAMES_OF(precision_name, "float", "packed-half")
NAMES_OF(layer_mode_name, "auto", "off", "on")
NAMES_OF(sensor_fit_name, "auto", "horizontal", "vertical")
NAMES_OF(depth_kind_name, "planar", "radial")
NAMES_OF(lens_name, "cycles", "thin-lens")
NAMES_OF(progress_name, "auto", "always", "never")

/* The lists above follow their enums: a reordered enum must fail the build, not the names. */
_Static_assert(DDOF_METHOD_COD4_PREVIEW == 1 && DDOF_PRECISION_PACKED_HALF == 1 &&
                   DDOF_LAYER_OFF == 1 && DDOF_LAYER_ON == 2 &&
                   DDOF_SENSOR_FIT_VERTICAL == 2 && DDOF_DEPTH_RADIAL == 1 &&
                   DDOF_LENS_THIN_LENS == 1,
               "choices.c names these enums by position");

const cli_choices cli_choices_preset = {preset_name, DDOF_PRESET_COUNT_};
const cli_choices cli_choices_solver = {solver_name, DDOF_SOLVER_COUNT_};
const cli_choices cli_choices_kernel = {kernel_name, DDOF_KERNEL_COUNT_};
const cli_choices cli_choices_backend = {backend_name, DDOF_BACKEND_COUNT_};
const cli_choices cli_choices_method = {method_name, 2};
const cli_choices cli_choices_precision = {precision_name, 2};
const cli_choices cli_choices_layer_mode = {layer_mode_name, 3};
const cli_choices cli_choices_sensor_fit = {sensor_fit_name, 3};
const cli_choices cli_choices_depth_kind = {depth_kind_name, 2};
const cli_choices cli_choices_lens = {lens_name, 2};
const cli_choices cli_choices_pixel_type = {pixel_type_name, EXRIO_FLOAT + 1};
const cli_choices cli_choices_compression = {compression_name, EXRIO_COMPRESSION_COUNT_};
const cli_choices cli_choices_progress = {progress_name, 3};

const char *cli_choice_name(const cli_choices *choices, int value)
{
    const char *name = value >= 0 && value < choices->count ? choices->name_of(value) : NULL;
    return name ? name : "?";
}

int cli_choice_find(const cli_choices *choices, const char *text)
{
    int v;
    for (v = 0; v < choices->count; v++) {
        const char *name = choices->name_of(v);
        if (name && strcasecmp(name, text) == 0)
            return v;
    }
    return -1;
}

void cli_choice_list(const cli_choices *choices, const char *separator, char *out,
                     size_t out_size)
{
    size_t used = 0;
    int v;
    if (out_size == 0)
        return;
    out[0] = '\0';
    for (v = 0; v < choices->count && used < out_size; v++) {
        const char *name = choices->name_of(v);
        int n;
        if (!name)
            continue;
        n = snprintf(out + used, out_size - used, "%s%s", used ? separator : "", name);
        if (n < 0)
            break;
        used += (size_t)n;
    }
}
