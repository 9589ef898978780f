/* SPDX-License-Identifier: MIT */
/* element_edges.h - the CoC of a foreground element's partly covered edge pixels. */
#ifndef DDOF_ELEMENT_EDGES_H
#define DDOF_ELEMENT_EDGES_H

#include "runtime/internal.h"

/* An element rendered over transparent film has anti-aliased edge pixels (0 < alpha < 1)
 * whose depth is the render's first sample: where that sample missed the element, the depth
 * says "no surface" (Blender writes 1e10) or lies far behind it, and the pixel's CoC would be
 * the far field's, blurring the element's fringe with the background's blur. Such a pixel, when
 * a fully covered pixel (alpha >= DDOF_ELEMENT_COVERED) lies within DDOF_ELEMENT_EDGE_REACH px
 * and is nearer, takes the CoC of the nearest such pixel: the element's part of the pixel is
 * that surface. A strand one or two pixels wide has no fully covered pixel: a partly covered
 * pixel with none within reach takes the CoC of the most covered pixel within reach whose
 * depth is under half its own (the strand's surface). `coc` (w x h, tightly packed) was computed from `depth`; alpha is channel 3 of
 * `color`. Non-finite alpha or depth leaves a pixel alone (the checks that follow report it).
 * Returns the pixels changed. */
#define DDOF_ELEMENT_COVERED 0.999f
#define DDOF_ELEMENT_EDGE_REACH 2

uint64_t ddof_fix_element_edges(ddof_context *context, const float *color, size_t color_stride,
                                const float *depth, size_t depth_stride, uint32_t depth_channels,
                                float *coc, uint32_t width, uint32_t height);

#endif
