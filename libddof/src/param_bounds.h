/* SPDX-License-Identifier: MIT */
/* param_bounds.h - the ranges of ddof_params' numeric fields: one table that the parameter
 * checks (call_checks.c) judge by and ddof_param_bounds() hands to hosts, so the two cannot
 * drift apart. */
#ifndef DDOF_PARAM_BOUNDS_H
#define DDOF_PARAM_BOUNDS_H

#include "ddof.h"

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
    const char *field;     /* the ddof_params field's name          */
    double lowest, highest; /* accepted values, inclusive             */
} param_range;

const param_range *ddof_param_range(param_id id);

/* lowest <= v <= highest (never for NaN). A float field's value converts to double exactly,
 * so comparing in double is comparing the float. */
int ddof_param_ok(param_id id, double v);

/* A camera's pixel aspect (a double) is judged by the same decimal range as the float
 * params.pixel_aspect: 0.01..100 exactly, not their float roundings. */
#define DDOF_MIN_PIXEL_ASPECT 0.01
#define DDOF_MAX_PIXEL_ASPECT 100.0

#endif
