/* SPDX-License-Identifier: MIT */
/* near_offsets.h - the near layer's holes filled from where the frame repeats itself: a wall's
 * bricks, a hedge, tiles, a fence continue behind a near object, and the frame holds copies of
 * what it hides one period away. */
#ifndef DDOF_NEAR_OFFSETS_H
#define DDOF_NEAR_OFFSETS_H

#include "adi/adi.h"

typedef struct offset_fill {
    const adi_request *frame; /* colour (3 or 4 channels) and signed CoC                   */
    const float *source;      /* per pixel, its weight as a source of the fill: 1 for a
                                 pixel wholly outside the element (those are copied)        */
    const float *matte;       /* per pixel, the element's share: the holes are those of 1   */
    float *rest, *rest_coc;   /* in: the holes' smooth fill; out: mixed with the copies      */
} offset_fill;

/* Finds the frame's dominant self-similar offsets (He and Sun 2012, "Statistics of patch
 * offsets for image completion"): the few displacements d for which the frame's sources best
 * match themselves moved by d. For each hole pixel p the candidates are scored on the sources
 * around the hole near p (how well they match their own copies moved by d), and the copies
 * from p + d are blended by their scores into one value; it replaces the smooth fill by a
 * share that grows with how much better the copy matches than the surroundings vary, so
 * where nothing repeats the smooth fill stays. Every value written is a convex mix of the
 * smooth fill and sources. Frames too small for an offset of 8 px are left as they are. */
ddof_status ddof_fill_from_offsets(ddof_context *context, const offset_fill *f);

#endif
