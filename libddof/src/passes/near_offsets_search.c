/* SPDX-License-Identifier: MIT */
/* near_offsets_search.c - the offsets by which the frame repeats itself, for the near layer's
 * fill (near_offsets_fill.c has the whole method):
 *  1. search: the offsets d (at least MIN_OFFSET blocks long) for which the sources, on a
 *     sparse grid of samples, best match themselves moved by d, every second offset of the
 *     grid first and then the neighbours of the best; the CANDIDATES best, SEPARATION apart;
 *  2. refine: each to the pixel, on the sources beside the holes, in the frame itself. */
#include "near_offsets_internal.h"

#include "runtime/parallel_rows.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MIN_OVERLAP DDOF_NEAR_MIN_OVERLAP

/* ---- 1. the search ------------------------------------------------------------------------ */

#define SEARCH_LANES DDOF_NEAR_SEARCH_LANES

/* Sum over a row of samples of known x known' x |mean - mean'|^2, and of known x known', in
 * SEARCH_LANES independent sums (in a fixed order: the result does not depend on the
 * machine's vector width). a: the 4 sample planes at the row's start, b: the phase's. */
static void search_row(const float *const a[4], const float *const b[4], int64_t count,
                       double *sum, double *used)
{
    float s[SEARCH_LANES] = {0}, u[SEARCH_LANES] = {0};
    int64_t i = 0;
    for (; i + SEARCH_LANES <= count; i += SEARCH_LANES)
        for (int l = 0; l < SEARCH_LANES; l++) {
            const float k = a[3][i + l] * b[3][i + l];
            const float d0 = a[0][i + l] - b[0][i + l], d1 = a[1][i + l] - b[1][i + l],
                        d2 = a[2][i + l] - b[2][i + l];
            s[l] += k * (d0 * d0 + d1 * d1 + d2 * d2);
            u[l] += k;
        }
    for (; i < count; i++) {
        const float k = a[3][i] * b[3][i];
        const float d0 = a[0][i] - b[0][i], d1 = a[1][i] - b[1][i], d2 = a[2][i] - b[2][i];
        s[0] += k * (d0 * d0 + d1 * d1 + d2 * d2);
        u[0] += k;
    }
    for (int l = 0; l < SEARCH_LANES; l++) {
        *sum += s[l];
        *used += u[l];
    }
}

/* The search's error of offset (row, col) of its grid. */
static float search_error(const offsets_job *j, uint32_t row, uint32_t col)
{
    const int32_t dy = -j->reach + (int32_t)row * OFFSET_STEP;
    const int32_t dx = -j->reach + (int32_t)col * OFFSET_STEP;
    if (abs(dx) < MIN_OFFSET && abs(dy) < MIN_OFFSET)
        return INFINITY;
    const int64_t stride = SAMPLE_STRIDE;
    const size_t grid_plane = (size_t)j->gw * j->gh, phase_plane = (size_t)j->gw * j->hl;
    /* The samples whose copy lies in the level, so no test inside the loop; a copy's
     * x = gx * stride + dx is column gx + q of phase `phase`. */
    const int64_t gx0 = dx < 0 ? (-dx + stride - 1) / stride : 0;
    const int64_t gy0 = dy < 0 ? (-dy + stride - 1) / stride : 0;
    int64_t gx1 = ((int64_t)j->wl - dx + stride - 1) / stride;
    int64_t gy1 = ((int64_t)j->hl - dy + stride - 1) / stride;
    gx1 = gx1 < j->gw ? gx1 : j->gw;
    gy1 = gy1 < j->gh ? gy1 : j->gh;
    const int64_t phase = ((dx % stride) + stride) % stride, q = (dx - phase) / stride;
    const float *phase_base = j->phases + (size_t)phase * 4 * phase_plane;
    double sum = 0.0, used = 0.0;
    for (int64_t gy = gy0; gy < gy1; gy++) {
        const size_t at = (size_t)gy * j->gw + (size_t)gx0;
        const size_t to = (size_t)(gy * stride + dy) * j->gw + (size_t)(gx0 + q);
        const float *a[4], *b[4];
        for (int k = 0; k < 4; k++) {
            a[k] = j->grid + k * grid_plane + at;
            b[k] = phase_base + k * phase_plane + to;
        }
        search_row(a, b, gx1 - gx0, &sum, &used);
    }
    return used > 0.0 && used >= MIN_OVERLAP * j->sample_count ? (float)(sum / used) : INFINITY;
}

/* The coarse pass: every second offset of the grid in x and y (the others INFINITY). */
static void search_coarse_rows(void *user, uint32_t r0, uint32_t r1, uint32_t chunk)
{
    (void)chunk;
    const offsets_job *j = user;
    const uint32_t side = ddof_offsets_grid_side(j);
    for (uint32_t row = r0; row < r1; row++)
        for (uint32_t col = 0; col < side; col++)
            j->search_error[(size_t)row * side + col] =
                row % 2 == 0 && col % 2 == 0 ? search_error(j, row, col) : INFINITY;
}

/* The fine pass: the grid offsets listed in j->todo. */
static void search_fine(void *user, uint32_t i0, uint32_t i1, uint32_t chunk)
{
    (void)chunk;
    const offsets_job *j = user;
    const uint32_t side = ddof_offsets_grid_side(j);
    for (uint32_t i = i0; i < i1; i++)
        j->search_error[j->todo[i]] = search_error(j, j->todo[i] / side, j->todo[i] % side);
}

/* The search's planes: the grid of samples and the level's phases. */
static void search_planes(offsets_job *j)
{
    const size_t grid_plane = (size_t)j->gw * j->gh, phase_plane = (size_t)j->gw * j->hl;
    for (uint32_t phase = 0; phase < SAMPLE_STRIDE; phase++)
        for (uint32_t y = 0; y < j->hl; y++)
            for (uint32_t q = 0; q < j->gw; q++) {
                const uint32_t x = q * SAMPLE_STRIDE + phase;
                const size_t b = (size_t)y * j->wl + x;
                float *to = j->phases + (size_t)phase * 4 * phase_plane + (size_t)y * j->gw + q;
                for (int k = 0; k < 4; k++) /* beyond the level's edge: unknown */
                    to[k * phase_plane] = x >= j->wl ? 0.0f : k < 3 ? j->mean[b * 3 + k]
                                                                     : j->known[b];
            }
    j->sample_count = 0;
    for (uint32_t gy = 0; gy < j->gh; gy++)
        for (uint32_t gx = 0; gx < j->gw; gx++) {
            const size_t b = (size_t)gy * SAMPLE_STRIDE * j->wl + (size_t)gx * SAMPLE_STRIDE;
            const size_t g = (size_t)gy * j->gw + gx;
            for (int k = 0; k < 4; k++)
                j->grid[k * grid_plane + g] = k < 3 ? j->mean[b * 3 + k] : j->known[b];
            j->sample_count += j->known[b] > 0.0f;
        }
}

/* Coarse to fine: every second grid offset, then the neighbours of the COARSE_KEPT best. */
static void search(ddof_context *context, offsets_job *j, ranked *rank)
{
    const uint32_t side = ddof_offsets_grid_side(j);
    ddof_parallel_rows(context, side, search_coarse_rows, j);
    const uint32_t best = ddof_near_rank(j->search_error, side, rank);
    const uint32_t count = ddof_near_fine_offsets(rank, best, side, j->todo);
    ddof_parallel_rows(context, count, search_fine, j);
}

/* The CANDIDATES best offsets of the search, SEPARATION apart. */
static void choose_candidates(offsets_job *j, ranked *rank)
{
    const uint32_t finite = ddof_near_rank(j->search_error, ddof_offsets_grid_side(j), rank);
    j->candidates = ddof_near_choose(rank, finite, j->reach, j->level);
}

/* ---- 2. refinement ------------------------------------------------------------------------ */

/* Mean squared difference of the frame's band sources (one pixel per sampled band block) and
 * their copies moved by d; INFINITY without overlap. */
static float band_error(const offsets_job *j, offset d)
{
    const adi_request *r = j->f->frame;
    double sum = 0.0;
    uint32_t used = 0;
    for (uint32_t s = 0; s < j->band_sample_count; s++) {
        const uint32_t b = j->band_samples[s];
        const int64_t x = (int64_t)(b % j->wl) * j->S, y = (int64_t)(b / j->wl) * j->S;
        if (!offsets_is_source(j->f, x + d.dx, y + d.dy))
            continue;
        sum += offsets_sq_distance3(offsets_color_at(r, x, y), offsets_color_at(r, x + d.dx, y + d.dy));
        used++;
    }
    return used ? (float)(sum / used) : INFINITY;
}

/* The band blocks, evenly thinned to at most REFINE_SAMPLES / S (the refinement tries
 * (2 S + 1)^2 offsets per candidate). */
static void collect_band_samples(offsets_job *j)
{
    const size_t n = (size_t)j->wl * j->hl;
    size_t band = 0;
    for (size_t b = 0; b < n; b++)
        band += j->band[b] > 0.0f;
    const size_t every = band / (REFINE_SAMPLES / j->S) + 1;
    size_t seen = 0;
    j->band_sample_count = 0;
    for (size_t b = 0; b < n; b++)
        if (j->band[b] > 0.0f && seen++ % every == 0)
            j->band_samples[j->band_sample_count++] = (uint32_t)b;
}

/* Each candidate to the pixel (the search's grid is OFFSET_STEP blocks); duplicates dropped. */
static void refine_candidates(offsets_job *j)
{
    const int32_t reach = ddof_near_refine_reach(j->S), side = 2 * reach + 1;
    uint32_t kept = 0;
    for (uint32_t c = 0; c < j->candidates; c++) {
        const offset start = {j->level[c].dx * (int32_t)j->S, j->level[c].dy * (int32_t)j->S};
        for (int32_t ey = -reach; ey <= reach; ey++)
            for (int32_t ex = -reach; ex <= reach; ex++)
                j->refine_error[(ey + reach) * side + ex + reach] =
                    band_error(j, (offset){start.dx + ex, start.dy + ey});
        ddof_near_refine_keep(j->refine_error, start, j->S, j->full, j->level, &kept);
    }
    j->candidates = kept;
}

int ddof_offsets_find(ddof_context *context, offsets_job *j, ranked *rank)
{
    search_planes(j);
    if (j->sample_count == 0)
        return 0;
    collect_band_samples(j);
    search(context, j, rank);
    choose_candidates(j, rank);
    refine_candidates(j);
    return 1;
}
