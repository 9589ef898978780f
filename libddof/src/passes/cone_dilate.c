/* SPDX-License-Identifier: MIT */
/* cone_dilate.c - grey-level dilation by a cone (cone_dilate.h), the chamfer way.
 *
 * max over q of v(q) - slope * d(p, q) with d the 8-connected chamfer distance is a shortest
 * path problem whose edge weights are slope and slope * sqrt 2, so two raster passes compute
 * it exactly (Rosenfeld & Pfaltz; Borgefors 1986): the forward pass takes the best of the
 * upper-left, upper, upper-right and left neighbours, the backward pass the mirror image. Any
 * optimal path splits into a part the forward pass follows and a part the backward pass
 * follows, because a chamfer-shortest path can be ordered so that it first runs through
 * neighbours that come earlier in raster order and then through later ones. */
#include "cone_dilate.h"

#include "runtime/float_ops.h"

/* One row from the row before it (dy = -1 forward, +1 backward): the three neighbours above
 * (or below). Vectorises: nothing in the row depends on the row itself. */
static void from_row(float *row, const float *prev, uint32_t w, float axial, float diagonal)
{
    row[0] = ddof_maxf(row[0], prev[0] - axial);
    if (w > 1) {
        row[0] = ddof_maxf(row[0], prev[1] - diagonal);
        row[w - 1] = ddof_maxf(row[w - 1], ddof_maxf(prev[w - 1] - axial, prev[w - 2] - diagonal));
    }
    for (uint32_t x = 1; x + 1 < w; x++) {
        const float side = ddof_maxf(prev[x - 1], prev[x + 1]) - diagonal;
        row[x] = ddof_maxf(row[x], ddof_maxf(prev[x] - axial, side));
    }
}

void ddof_cone_dilate(float *map, uint32_t w, uint32_t h, size_t stride, float slope)
{
    const float axial = slope, diagonal = slope * 1.41421356f;
    for (uint32_t y = 0; y < h; y++) {
        float *row = map + (size_t)y * stride;
        if (y > 0)
            from_row(row, row - stride, w, axial, diagonal);
        for (uint32_t x = 1; x < w; x++)
            row[x] = ddof_maxf(row[x], row[x - 1] - axial);
    }
    for (uint32_t y = h; y-- > 0;) {
        float *row = map + (size_t)y * stride;
        if (y + 1 < h)
            from_row(row, row + stride, w, axial, diagonal);
        for (uint32_t x = w - 1; x-- > 0;)
            row[x] = ddof_maxf(row[x], row[x + 1] - axial);
    }
}
