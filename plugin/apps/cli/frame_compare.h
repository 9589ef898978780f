/* SPDX-License-Identifier: MIT */
/* frame_compare.h - --compare: a frame's result and its input measured against the ground
 * truth's RGB (compare.h's errors). */
#ifndef DDOF_CLI_FRAME_COMPARE_H
#define DDOF_CLI_FRAME_COMPARE_H

#include "frame.h"
#include "exrio.h"

/* Reads paths->compare (same data window as `part`) and fills result's errors and compared.
 * color and out: the input's and the result's interleaved colour, `channels` per pixel.
 * Returns 0 or -1 (result->error). */
int frame_compare_with_truth(const frame_paths *paths, const float *color, const float *out,
                             int channels, const exrio_part *part, frame_result *result);

#endif

