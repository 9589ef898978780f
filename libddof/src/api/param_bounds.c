/* SPDX-License-Identifier: MIT */
/* param_bounds.c - ddof_param_bounds(): the ranges of ddof_params' numeric fields
 * (ddof_param_rules.h) by name. */
#include "ddof_param_rules.h"

#include <string.h>

ddof_status ddof_param_bounds(const char *field, double *lowest, double *highest)
{
    if (!field || !lowest || !highest)
        return DDOF_ERROR_NULL_POINTER;
    for (int i = 0; i < PARAM_COUNT; i++)
        if (strcmp(field, ddof_param_range((param_id)i)->field) == 0) {
            *lowest = ddof_param_range((param_id)i)->lowest;
            *highest = ddof_param_range((param_id)i)->highest;
            return DDOF_OK;
        }
    return DDOF_ERROR_BAD_PARAMETER;
}
