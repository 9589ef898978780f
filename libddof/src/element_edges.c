/* SPDX-License-Identifier: MIT */
/* element_edges.c - a foreground element's partly covered edge pixels take the CoC of the
 * surface that covers them (element_edges.h). */
#include "element_edges.h"

#include "parallel_rows.h"

#include <math.h>

typedef struct edges_job {
    const float *color, *depth;
    size_t color_stride, depth_stride;
    uint32_t depth_channels, width, height;
    const float *coc_in; /* read: the CoC as computed        */
    float *coc;          /* written: only the fixed pixels    */
    uint64_t *changed;   /* one count per row chunk           */
} edges_job;

static float alpha_at(const edges_job *j, uint32_t x, uint32_t y)
{
    return j->color[(size_t)y * j->color_stride + (size_t)x * 4 + 3];
}

static float depth_at(const edges_job *j, uint32_t x, uint32_t y)
{
    return j->depth[(size_t)y * j->depth_stride + (size_t)x * j->depth_channels];
}

/* The nearest fully covered pixel within the reach of (x, y) (Euclidean, the first in row
 * order on a tie); 0 when there is none. */
static int nearest_covered(const edges_job *j, uint32_t x, uint32_t y, uint32_t *qx,
                           uint32_t *qy)
{
    const int reach = DDOF_ELEMENT_EDGE_REACH;
    int best = INT32_MAX;
    for (int dy = -reach; dy <= reach; dy++)
        for (int dx = -reach; dx <= reach; dx++) {
            const int64_t nx = (int64_t)x + dx, ny = (int64_t)y + dy;
            const int d2 = dx * dx + dy * dy;
            if ((dx | dy) == 0 || nx < 0 || ny < 0 || nx >= j->width || ny >= j->height ||
                d2 >= best)
                continue;
            const float a = alpha_at(j, (uint32_t)nx, (uint32_t)ny);
            if (a >= DDOF_ELEMENT_COVERED && isfinite(depth_at(j, (uint32_t)nx, (uint32_t)ny))) {
                best = d2;
                *qx = (uint32_t)nx;
                *qy = (uint32_t)ny;
            }
        }
    return best != INT32_MAX;
}

static void edges_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    const edges_job *j = user;
    uint64_t changed = 0;
    for (uint32_t y = y0; y < y1; y++)
        for (uint32_t x = 0; x < j->width; x++) {
            const float a = alpha_at(j, x, y);
            const float z = depth_at(j, x, y);
            uint32_t qx, qy;
            /* +inf ("no surface" as the sky) counts as far; NaN is the checks' to report. */
            if (!(a > 0.0f && a < DDOF_ELEMENT_COVERED) || isnan(z) ||
                !nearest_covered(j, x, y, &qx, &qy) || !(depth_at(j, qx, qy) < z))
                continue;
            j->coc[(size_t)y * j->width + x] = j->coc_in[(size_t)qy * j->width + qx];
            changed++;
        }
    j->changed[chunk] = changed;
}

uint64_t ddof_fix_element_edges(ddof_context *context, const float *color, size_t color_stride,
                                const float *depth, size_t depth_stride, uint32_t depth_channels,
                                float *coc, uint32_t width, uint32_t height)
{
    enum { max_chunks = (DDOF_MAX_DIMENSION + DDOF_ROWS_PER_CHUNK - 1) / DDOF_ROWS_PER_CHUNK };
    uint64_t changed[max_chunks];
    /* A covered pixel is never changed, and only covered pixels are read as sources: fixing
     * in place gives the same result in any order. */
    edges_job j = {color, depth, color_stride, depth_stride, depth_channels, width, height,
                   coc, coc, changed};
    ddof_parallel_rows(context, height, edges_rows, &j);
    uint64_t total = 0;
    for (uint32_t c = 0; c < ddof_row_chunks(height); c++)
        total += changed[c];
    return total;
}
