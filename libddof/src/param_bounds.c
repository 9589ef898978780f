/* SPDX-License-Identifier: MIT */
/* param_bounds.c - the ranges of ddof_params' numeric fields (param_bounds.h) and
 * ddof_param_bounds(). */
#include "param_bounds.h"

#include <float.h>
#include <string.h>

/* At the largest CoC (DDOF_MAX_COC_PX) and one sub-step, beta_scale 1 and pixel aspect 100
 * make the column links' beta 1e14; the reference solver's overflows near 1e16, the others'
 * later (tests/test_bad_input.c runs every CPU solver at the bounds and checks the output is
 * finite). "> 0" is the smallest float above 0. */
static const param_range ranges[PARAM_COUNT] = {
    [PARAM_SUBSTEPS] = {"substeps", 1.0, 4096.0},
    [PARAM_BETA_SCALE] = {"beta_scale", FLT_TRUE_MIN, 1.0},
    [PARAM_PIXEL_ASPECT] = {"pixel_aspect", (float)DDOF_MIN_PIXEL_ASPECT,
                            (float)DDOF_MAX_PIXEL_ASPECT},
    [PARAM_JACOBI_ITERATIONS] = {"jacobi_iterations", 1.0, 1000000.0},
    [PARAM_BACKGROUND_THRESHOLD] = {"background_threshold_px", FLT_TRUE_MIN, DDOF_MAX_COC_PX},
    [PARAM_BACKGROUND_RAMP_START] = {"background_ramp_start_px", 0.0, DDOF_MAX_COC_PX},
    [PARAM_BACKGROUND_LEVELS] = {"background_levels", 1.0, 8.0},
    [PARAM_NEAR_SPREAD_THRESHOLD] = {"near_spread_threshold_px", FLT_TRUE_MIN, DDOF_MAX_COC_PX},
    [PARAM_IN_FOCUS_THRESHOLD] = {"in_focus_threshold_px", 0.0, DDOF_MAX_COC_PX},
    [PARAM_HIGHLIGHT_THRESHOLD] = {"highlight_threshold", FLT_TRUE_MIN, FLT_MAX},
    [PARAM_NEAR_LAYER_THRESHOLD] = {"near_layer_threshold_px", FLT_TRUE_MIN, DDOF_MAX_COC_PX},
};

const param_range *ddof_param_range(param_id id)
{
    return &ranges[id];
}

int ddof_param_ok(param_id id, double v)
{
    return v >= ranges[id].lowest && v <= ranges[id].highest;
}

ddof_status ddof_param_bounds(const char *field, double *lowest, double *highest)
{
    if (!field || !lowest || !highest)
        return DDOF_ERROR_NULL_POINTER;
    for (int i = 0; i < PARAM_COUNT; i++)
        if (strcmp(field, ranges[i].field) == 0) {
            *lowest = ranges[i].lowest;
            *highest = ranges[i].highest;
            return DDOF_OK;
        }
    return DDOF_ERROR_BAD_PARAMETER;
}
