/* SPDX-License-Identifier: MIT */
/* far_field_internal.h - what far_field.c (where the pass runs) hands far_field_gather.c (the
 * gather itself). */
#ifndef DDOF_FAR_FIELD_INTERNAL_H
#define DDOF_FAR_FIELD_INTERNAL_H

#include "ddof_backend_seam.h"
#include "ddof_far_rules.h"
#include "runtime/internal.h"


/* A level of the frame, 2^k pixels a side each, and what continues it beyond the frame: the
 * full-resolution frame's edge pixels reduced the same way (a level's own edge pixel would
 * average 2^k rows of the inside into the continuation). */
typedef struct far_level {
    const float *image; /* the level's colour (level 0: the caller's)                      */
    size_t stride;      /* floats a row of image                                           */
    float *prefix;      /* height + 2 rows of (width + 1) * channels: each row's running sums
                         * from 0; the last two: the frame's top and bottom rows reduced     */
    float *sides;       /* height + 2 rows of 2 * channels: the frame's left and right pixels
                         * reduced to the level's rows, then the top's and bottom's corners  */
    float *samples;     /* k >= 1: the gather at each level pixel's centre (channels each)  */
    uint8_t *needed;    /* k >= 1: 1 where a frame pixel interpolates that sample           */
    uint32_t width, height;
} far_level;

struct far_layer_sink;

typedef struct far_gather {
    const adi_request *r; /* the frame: out holds the layers' result, blended in place;
                           * its channels are the gathered image's                      */
    const float *color;   /* what the layers diffused, color_stride floats a row        */
    size_t color_stride;
    const float *radius;  /* |CoC| / 2 where a pixel blurs, else 0 (width x height)     */
    const float *weight;  /* the gather's share of each pixel, 0..1                     */
    far_level levels[FAR_FIELD_MAX_LEVELS];
    uint32_t level_count;
    uint32_t level; /* the level a parallel pass works on */
    /* NULL: the gather is blended into r->out by `weight`. Else a depth slice's gather
     * (far_layers.c): where weight > 0 the gathered premultiplied colour and coverage go to
     * the sink instead. */
    struct far_layer_sink *sink;
} far_gather;

/* Builds the levels that radii up to `largest` need, gathers and blends into r->out. */
ddof_status ddof_far_field_gather(ddof_context *context, far_gather *g, float largest);

#endif
