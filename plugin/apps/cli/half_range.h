/* SPDX-License-Identifier: MIT */
/* half_range.h - the type an output channel is written as, so that no value becomes an
 * infinity it was not: half's largest value is 65504, and a finite value from 65520 up rounds
 * to infinity (a float texture's HDR light, a boosted highlight). Where the command chose half
 * (its default) such a channel is written as float instead; where the user asked for half
 * (--pixel-type half) the write is refused with the value named. */
#ifndef DDOF_CLI_HALF_RANGE_H
#define DDOF_CLI_HALF_RANGE_H

#include "exrio.h"

#include <stddef.h>

/* The type for `count` values `stride` floats apart: `type` unless it is EXRIO_HALF and a
 * finite value would overflow it; then EXRIO_FLOAT when !user_chose, or -1 with the channel,
 * the value and what to do in error. `name` names the channel for the message. */
int half_range_type(exrio_pixel_type type, int user_chose, const float *values, size_t count,
                    size_t stride, const char *name, char *error, size_t error_size);

#endif
