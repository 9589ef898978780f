/* SPDX-License-Identifier: MIT */
/* element_edges.c - a foreground element's partly covered edge pixels take the CoC of the
 * surface that covers them (element_edges.h). */
#include "element_edges.h"

#include "runtime/parallel_rows.h"

#include <math.h>
#include <string.h>

typedef struct edges_job {
    const float *color, *depth;
    size_t color_stride, depth_stride;
    uint32_t depth_channels, width, height;
    const float *coc_in; /* read: the CoC as computed        */
    float *coc;          /* written: only the fixed pixels    */
    uint64_t *changed;   /* one count per row chunk           */
    uint64_t *orphans;   /* per chunk: partly covered "no surface" pixels without a covered
                          * pixel near (thin strands, which no pixel covers fully) */
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

/* The partly covered pixel within the reach of (x, y) that is most covered among those whose
 * depth is under half of z (a surface well in front of what the pixel's depth says; the
 * nearest, then the first in row order, on a tie); 0 when there is none. */
static int best_partial(const edges_job *j, uint32_t x, uint32_t y, float z, uint32_t *qx,
                        uint32_t *qy)
{
    const int reach = DDOF_ELEMENT_EDGE_REACH;
    float best_alpha = 0.0f;
    int best_d2 = INT32_MAX;
    for (int dy = -reach; dy <= reach; dy++)
        for (int dx = -reach; dx <= reach; dx++) {
            const int64_t nx = (int64_t)x + dx, ny = (int64_t)y + dy;
            if ((dx | dy) == 0 || nx < 0 || ny < 0 || nx >= j->width || ny >= j->height)
                continue;
            const float a = alpha_at(j, (uint32_t)nx, (uint32_t)ny);
            const float d = depth_at(j, (uint32_t)nx, (uint32_t)ny);
            const int d2 = dx * dx + dy * dy;
            if (!(a > 0.0f) || !(d < 0.5f * z) || a < best_alpha ||
                (a == best_alpha && d2 >= best_d2))
                continue;
            best_alpha = a;
            best_d2 = d2;
            *qx = (uint32_t)nx;
            *qy = (uint32_t)ny;
        }
    return best_d2 != INT32_MAX;
}

/* A pixel the fix considers: partly covered, its depth not NaN (+inf, "no surface" as the sky,
 * counts as far; NaN is the checks' to report). */
static int partly_covered(const edges_job *j, uint32_t x, uint32_t y)
{
    const float a = alpha_at(j, x, y);
    return a > 0.0f && a < DDOF_ELEMENT_COVERED && !isnan(depth_at(j, x, y));
}

static void edges_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    const edges_job *j = user;
    uint64_t changed = 0, orphans = 0;
    for (uint32_t y = y0; y < y1; y++)
        for (uint32_t x = 0; x < j->width; x++) {
            const float z = depth_at(j, x, y);
            uint32_t qx, qy;
            if (!partly_covered(j, x, y))
                continue;
            if (!nearest_covered(j, x, y, &qx, &qy)) {
                orphans++;
                continue;
            }
            if (!(depth_at(j, qx, qy) < z))
                continue;
            j->coc[(size_t)y * j->width + x] = j->coc_in[(size_t)qy * j->width + qx];
            changed++;
        }
    j->changed[chunk] = changed;
    j->orphans[chunk] = orphans;
}

/* The orphans: from the best partly covered source, read from a copy of the CoC the first pass
 * left (coc_in), so that the order of the rows does not matter. */
static void orphan_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    const edges_job *j = user;
    uint64_t changed = 0;
    for (uint32_t y = y0; y < y1; y++)
        for (uint32_t x = 0; x < j->width; x++) {
            uint32_t qx, qy;
            if (!partly_covered(j, x, y) || nearest_covered(j, x, y, &qx, &qy) ||
                !best_partial(j, x, y, depth_at(j, x, y), &qx, &qy))
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
    uint64_t changed[max_chunks], orphans[max_chunks];
    /* A covered pixel is never changed, and only covered pixels are read as sources: fixing
     * in place gives the same result in any order. */
    edges_job j = {color, depth, color_stride, depth_stride, depth_channels, width, height,
                   coc, coc, changed, orphans};
    ddof_parallel_rows(context, height, edges_rows, &j);
    uint64_t total = 0, orphan_count = 0;
    for (uint32_t c = 0; c < ddof_row_chunks(height); c++) {
        total += changed[c];
        orphan_count += orphans[c];
    }
    if (!orphan_count)
        return total;
    /* Partly covered pixels are sources now, and some are changed: a copy keeps the order of
     * the rows from mattering. Without memory for it the orphans keep their CoC. */
    float *copy = ddof_scratch_get(context, DDOF_SCRATCH_ELEMENT_EDGES,
                                   (size_t)width * height * sizeof(float));
    if (!copy)
        return total;
    memcpy(copy, coc, (size_t)width * height * sizeof(float));
    j.coc_in = copy;
    ddof_parallel_rows(context, height, orphan_rows, &j);
    for (uint32_t c = 0; c < ddof_row_chunks(height); c++)
        total += changed[c];
    return total;
}
