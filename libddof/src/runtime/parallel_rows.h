/* SPDX-License-Identifier: MIT */
/* parallel_rows.h - split an image's rows into chunks and run them on the context's threads. */
#ifndef DDOF_PARALLEL_ROWS_H
#define DDOF_PARALLEL_ROWS_H

#include "internal.h"

#define DDOF_ROWS_PER_CHUNK 16u

/* fn(user, first_row, end_row, chunk_index) for consecutive chunks covering [0, height). */
typedef void (*row_chunk_fn)(void *user, uint32_t y0, uint32_t y1, uint32_t chunk);

static inline uint32_t ddof_row_chunks(uint32_t height)
{
    return (height + DDOF_ROWS_PER_CHUNK - 1) / DDOF_ROWS_PER_CHUNK;
}

void ddof_parallel_rows(ddof_context *context, uint32_t height, row_chunk_fn fn, void *user);

/* What a value must satisfy. */
typedef enum value_rule {
    VALUE_FINITE,     /* not NaN, not +-inf                                           */
    VALUE_COLOR,      /* colour: |v| <= DDOF_MAX_COLOR (so finite)                   */
    VALUE_DEPTH,      /* > 0, +inf allowed                                            */
    VALUE_DEPTH_ZERO, /* >= 0, +inf allowed (the artist curve accepts depth 0)        */
    VALUE_COC,        /* finite, 0 <= v <= DDOF_MAX_COC_PX                            */
    VALUE_COC_SIGNED  /* finite, |v| <= DDOF_MAX_COC_PX (negative: the near field)      */
} value_rule;

typedef struct bad_value {
    uint32_t x, y, channel;
    float value;
} bad_value;

/* Scans the first `channels_read` of each pixel (1 or all `channels`); returns 1 and the first offending
 * value in row-major order, or 0 when all pass. max_abs (may be NULL): on 0, the largest
 * |value| scanned, found in the same read (the planner's copy test needs no second pass). */
int ddof_find_bad_value(ddof_context *context, const float *pixels, uint32_t width,
                        uint32_t height, uint32_t channels, uint32_t channels_read,
                        size_t stride_floats, value_rule rule, bad_value *bad, float *max_abs);

/* Copies `height` rows of row_floats floats on the context's threads (nothing when src is
 * dst): one core's memcpy does not reach the memory's bandwidth on every machine. */
void ddof_parallel_copy(ddof_context *context, const float *src, size_t src_stride, float *dst,
                        size_t dst_stride, size_t row_floats, uint32_t height);

#endif
