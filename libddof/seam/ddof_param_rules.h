/* SPDX-License-Identifier: MIT */
/* ddof_param_rules.h - the ranges of ddof_params' numeric fields: one table that the core's
 * parameter checks (call_checks.c), ddof_param_bounds() (what hosts read for their sliders) and
 * the GL plugin's texture entry points (host_api.c, which cannot call into libddof) all judge
 * by, so no two can drift apart. */
#ifndef DDOF_PARAM_RULES_H
#define DDOF_PARAM_RULES_H

#include "ddof.h"

#include <float.h>

typedef enum param_id {
    PARAM_SUBSTEPS,
    PARAM_BETA_SCALE,
    PARAM_PIXEL_ASPECT,
    PARAM_JACOBI_ITERATIONS,
    PARAM_BACKGROUND_THRESHOLD,
    PARAM_BACKGROUND_RAMP_START,
    PARAM_BACKGROUND_LEVELS,
    PARAM_NEAR_SPREAD_THRESHOLD,
    PARAM_IN_FOCUS_THRESHOLD,
    PARAM_HIGHLIGHT_THRESHOLD,
    PARAM_NEAR_LAYER_THRESHOLD,
    PARAM_COUNT
} param_id;

typedef struct param_range {
    const char *field;      /* the ddof_params field's name          */
    double lowest, highest; /* accepted values, inclusive             */
} param_range;

/* A camera's pixel aspect (a double) is judged by the same decimal range as the float
 * params.pixel_aspect: 0.01..100 exactly, not their float roundings. */
#define DDOF_MIN_PIXEL_ASPECT 0.01
#define DDOF_MAX_PIXEL_ASPECT 100.0

/* At the largest CoC (DDOF_MAX_COC_PX) and one sub-step, beta_scale 1 and pixel aspect 100
 * make the column links' beta 1e14; the reference solver's overflows near 1e16, the others'
 * later (tests/test_bad_input_params.c runs every CPU solver at the bounds and checks the
 * output is finite). "> 0" is the smallest float above 0. */
static inline const param_range *ddof_param_range(param_id id)
{
    static const param_range ranges[PARAM_COUNT] = {
        [PARAM_SUBSTEPS] = {"substeps", 1.0, 4096.0},
        [PARAM_BETA_SCALE] = {"beta_scale", FLT_TRUE_MIN, 1.0},
        [PARAM_PIXEL_ASPECT] = {"pixel_aspect", (float)DDOF_MIN_PIXEL_ASPECT,
                                (float)DDOF_MAX_PIXEL_ASPECT},
        [PARAM_JACOBI_ITERATIONS] = {"jacobi_iterations", 1.0, 1000000.0},
        [PARAM_BACKGROUND_THRESHOLD] = {"background_threshold_px", FLT_TRUE_MIN,
                                        DDOF_MAX_COC_PX},
        [PARAM_BACKGROUND_RAMP_START] = {"background_ramp_start_px", 0.0, DDOF_MAX_COC_PX},
        [PARAM_BACKGROUND_LEVELS] = {"background_levels", 1.0, 8.0},
        [PARAM_NEAR_SPREAD_THRESHOLD] = {"near_spread_threshold_px", FLT_TRUE_MIN,
                                         DDOF_MAX_COC_PX},
        [PARAM_IN_FOCUS_THRESHOLD] = {"in_focus_threshold_px", 0.0, DDOF_MAX_COC_PX},
        [PARAM_HIGHLIGHT_THRESHOLD] = {"highlight_threshold", FLT_TRUE_MIN, FLT_MAX},
        [PARAM_NEAR_LAYER_THRESHOLD] = {"near_layer_threshold_px", FLT_TRUE_MIN,
                                        DDOF_MAX_COC_PX},
    };
    return &ranges[id];
}

/* lowest <= v <= highest (never for NaN). A float field's value converts to double exactly,
 * so comparing in double is comparing the float. */
static inline int ddof_param_ok(param_id id, double v)
{
    return v >= ddof_param_range(id)->lowest && v <= ddof_param_range(id)->highest;
}

#endif
