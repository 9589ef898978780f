/* SPDX-License-Identifier: MIT */
/* cone_dilate.h - grey-level dilation by a cone: v(p) <- max over q of v(q) - slope * d(p, q).
 *
 * The near spread (layers.c) uses it to let every near-field pixel claim the pixels around it
 * with a CoC that falls linearly with the distance, so that a small near object spreads as far
 * as a large one of the same CoC (a blur of the CoC map dilutes small objects away). */
#ifndef DDOF_CONE_DILATE_H
#define DDOF_CONE_DILATE_H

#include <stddef.h>
#include <stdint.h>

/* In place on a w x h map of floats, rows `stride` floats apart (>= w). d is the chamfer
 * distance of 8-connected steps of length 1 and sqrt 2 (an octagon: within 8% of Euclidean,
 * never above it), computed exactly in one forward and one backward raster pass. slope > 0.
 * O(w h), one thread: a few milliseconds per megapixel. */
void ddof_cone_dilate(float *map, uint32_t w, uint32_t h, size_t stride, float slope);

#endif
