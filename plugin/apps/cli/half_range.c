/* SPDX-License-Identifier: MIT */
/* half_range.c - float where half would overflow (half_range.h). */
#include "half_range.h"

#include <math.h>
#include <stdio.h>

/* The smallest magnitude that rounds to infinity as a half (round to nearest even). */
#define HALF_OVERFLOW 65520.0f

int half_range_type(exrio_pixel_type type, int user_chose, const float *values, size_t count,
                    size_t stride, const char *name, char *error, size_t error_size)
{
    if (type != EXRIO_HALF)
        return (int)type;
    for (size_t i = 0; i < count; i++) {
        const float v = values[i * stride];
        if (isfinite(v) && fabsf(v) >= HALF_OVERFLOW) {
            if (!user_chose)
                return EXRIO_FLOAT;
            snprintf(error, error_size, "--pixel-type half: channel %s holds %g, beyond half's "
                     "range (65504), which would be written as infinity; use --pixel-type "
                     "float", name, (double)v);
            return -1;
        }
    }
    return EXRIO_HALF;
}
