/* SPDX-License-Identifier: MIT */
/* near_offsets_fill.c - the near layer's holes filled from where the frame repeats itself
 * (near_offsets.h).
 *
 * The work is done on a search level: the frame in blocks of S x S pixels (S a power of two,
 * the level at most SEARCH_SIZE on a side), each block the mean of its sources, so that a 1080p
 * frame is searched as the study's 480x270 ones are. Four steps (the first two in
 * near_offsets_search.c):
 *  1. search: the offsets d (at least MIN_OFFSET blocks long) for which the sources, on a sparse
 *     grid of samples, best match themselves moved by d; the CANDIDATES best, SEPARATION apart;
 *  2. refine: each to the pixel, on the sources beside the holes, in the frame itself;
 *  3. score: per block of a hole, how well each candidate moves the sources within BAND of the
 *     hole and within SCORE_RADIUS of the block (mean squared difference); the KEPT best are
 *     kept, with the variance of those sources;
 *  4. copy: each hole pixel p takes its kept candidates' sources p + d, weighted by their scores
 *     (exp(-(c - c_min) / (SOFTNESS c_min))), and mixes them into the smooth fill by
 *     (v / (v + c_min))^2, v the variance: where a copy matches far better than the
 *     surroundings vary, the copy; where nothing repeats, the smooth fill.
 * The constants were measured on the study's near scenes (docs/accuracy.md, the near layer). */
#include "near_offsets_internal.h"

#include "runtime/parallel_rows.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SEARCH_SIZE DDOF_NEAR_SEARCH_SIZE
#define BAND DDOF_NEAR_BAND
#define SCORE_RADIUS DDOF_NEAR_SCORE_RADIUS
#define MIN_BAND_SAMPLES DDOF_NEAR_MIN_BAND_SAMPLES
#define KEPT DDOF_NEAR_KEPT
#define SOFTNESS DDOF_NEAR_SOFTNESS
#define SOFT_FLOOR DDOF_NEAR_SOFT_FLOOR
#define MEAN_LIMIT DDOF_NEAR_MEAN_LIMIT

/* ---- the search level --------------------------------------------------------------------- */

static void reduce_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const offsets_job *j = user;
    const adi_request *r = j->f->frame;
    for (uint32_t by = y0; by < y1; by++)
        for (uint32_t bx = 0; bx < j->wl; bx++) {
            double sum[3] = {0.0, 0.0, 0.0};
            uint32_t pixels = 0, sources = 0, holes = 0;
            for (uint32_t y = by * j->S; y < (by + 1) * j->S && y < r->height; y++)
                for (uint32_t x = bx * j->S; x < (bx + 1) * j->S && x < r->width; x++) {
                    const size_t i = (size_t)y * r->width + x;
                    pixels++;
                    holes += j->f->matte[i] >= 1.0f;
                    if (j->f->source[i] < 1.0f)
                        continue;
                    sources++;
                    const float *c = offsets_color_at(r, x, y);
                    for (uint32_t k = 0; k < 3; k++)
                        sum[k] += c[k];
                }
            const size_t b = (size_t)by * j->wl + bx;
            /* Clamped so that squared differences stay finite (any colour is DDOF_MAX_COLOR
             * at most, 1e20): the scores only rank candidates. */
            for (uint32_t k = 0; k < 3; k++) {
                const double m = sources ? sum[k] / sources : 0.0;
                j->mean[b * 3 + k] = (float)(m < -MEAN_LIMIT ? -MEAN_LIMIT
                                             : m > MEAN_LIMIT ? MEAN_LIMIT
                                                              : m);
            }
            j->known[b] = sources == pixels;
            j->hole[b] = holes > 0;
        }
}

/* Box sums of radius r along one line of n values `stride` floats apart (clipped at the
 * line's ends), into out at the same stride: a running sum, in double so that it does not
 * drift. */
static void box_line(const float *in, float *out, uint32_t n, size_t stride, uint32_t r)
{
    double s = 0.0;
    for (uint32_t i = 0; i <= r && i < n; i++)
        s += in[i * stride];
    for (uint32_t i = 0; i < n; i++) {
        out[i * stride] = (float)s;
        if (i + r + 1 < n)
            s += in[(i + r + 1) * stride];
        if (i >= r)
            s -= in[(i - r) * stride];
    }
}

/* Map m of j->box: the level's size apart, MAX_BOX_MAPS of them and as many after for the box
 * sums' first pass. */
static float *box_map(const offsets_job *j, uint32_t m)
{
    return j->box + (size_t)m * j->wl * j->hl;
}

/* Box sums of radius j->radius over the level (clipped at its edges), of the first
 * j->box_maps maps of j->box, in place: along the rows into the maps after them, then along
 * the columns back. */
static void box_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const offsets_job *j = user;
    for (uint32_t m = 0; m < j->box_maps; m++)
        for (uint32_t y = y0; y < y1; y++)
            box_line(box_map(j, m) + (size_t)y * j->wl,
                     box_map(j, MAX_BOX_MAPS + m) + (size_t)y * j->wl, j->wl, 1, j->radius);
}

static void box_columns(void *user, uint32_t x0, uint32_t x1, uint32_t chunk)
{
    (void)chunk;
    const offsets_job *j = user;
    for (uint32_t m = 0; m < j->box_maps; m++)
        for (uint32_t x = x0; x < x1; x++)
            box_line(box_map(j, MAX_BOX_MAPS + m) + x, box_map(j, m) + x, j->hl, j->wl, j->radius);
}

static void box_sums(ddof_context *context, offsets_job *j, uint32_t maps, uint32_t radius)
{
    j->box_maps = maps;
    j->radius = radius;
    ddof_parallel_rows(context, j->hl, box_rows, j);
    ddof_parallel_rows(context, j->wl, box_columns, j);
}

/* ---- 3. scores ---------------------------------------------------------------------------- */

/* Whether block b moved by the current candidate's offset lands on a known block of the level,
 * which is then *t. */
static int lands_on_known(const offsets_job *j, size_t b, size_t *t)
{
    const offset d = j->level[j->current];
    const int64_t tx = (int64_t)(b % j->wl) + d.dx, ty = (int64_t)(b / j->wl) + d.dy;
    if (tx < 0 || ty < 0 || tx >= j->wl || ty >= j->hl)
        return 0;
    *t = (size_t)ty * j->wl + (size_t)tx;
    return j->known[*t] > 0.0f;
}

static void candidate_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const offsets_job *j = user;
    for (size_t b = (size_t)y0 * j->wl; b < (size_t)y1 * j->wl; b++) {
        size_t t = 0;
        const int used = j->band[b] > 0.0f && lands_on_known(j, b, &t);
        j->box[b] = used ? offsets_sq_distance3(j->mean + b * 3, j->mean + t * 3) : 0.0f;
        box_map(j, 1)[b] = (float)used;
    }
}

/* Keeps the candidate among each hole block's KEPT best (its copy must land on sources). */
static void keep_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const offsets_job *j = user;
    for (size_t b = (size_t)y0 * j->wl; b < (size_t)y1 * j->wl; b++) {
        size_t t;
        const float samples = box_map(j, 1)[b];
        if (j->hole[b] <= 0.0f || !(samples > MIN_BAND_SAMPLES) || !lands_on_known(j, b, &t))
            continue;
        const float cost = j->box[b] / samples;
        float *tc = j->top_cost + b * KEPT, *ti = j->top_index + b * KEPT;
        if (!(cost < tc[KEPT - 1]))
            continue; /* NaN (an overflow) included */
        uint32_t k = KEPT - 1;
        for (; k > 0 && cost < tc[k - 1]; k--) {
            tc[k] = tc[k - 1];
            ti[k] = ti[k - 1];
        }
        tc[k] = cost;
        ti[k] = (float)j->current;
    }
}

/* The maps of the band's colour variance: band, band x mean, band x mean^2. */
static void variance_maps_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const offsets_job *j = user;
    for (size_t b = (size_t)y0 * j->wl; b < (size_t)y1 * j->wl; b++) {
        const float w = j->band[b];
        j->box[b] = w;
        for (uint32_t k = 0; k < 3; k++) {
            const float m = j->mean[b * 3 + k];
            box_map(j, 1 + k)[b] = w * m;
            box_map(j, 4 + k)[b] = w * m * m;
        }
    }
}

static void variance_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const offsets_job *j = user;
    for (size_t b = (size_t)y0 * j->wl; b < (size_t)y1 * j->wl; b++) {
        const double count = j->box[b];
        double v = 0.0;
        if (count > MIN_BAND_SAMPLES)
            for (uint32_t k = 0; k < 3; k++) {
                const double m = box_map(j, 1 + k)[b] / count;
                v += box_map(j, 4 + k)[b] / count - m * m;
            }
        j->variance[b] = (float)(v > 0.0 ? v : 0.0);
        for (uint32_t k = 0; k < KEPT; k++) {
            j->top_cost[b * KEPT + k] = INFINITY;
            j->top_index[b * KEPT + k] = 0.0f;
        }
    }
}

/* ---- 4. the copies ------------------------------------------------------------------------ */

static void copy_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const offsets_job *j = user;
    const offset_fill *f = j->f;
    const adi_request *r = f->frame;
    const uint32_t C = r->channels;
    for (uint32_t y = y0; y < y1; y++)
        for (uint32_t x = 0; x < r->width; x++) {
            const size_t p = (size_t)y * r->width + x;
            if (f->matte[p] < 1.0f)
                continue;
            const size_t b = (size_t)(y / j->S) * j->wl + x / j->S;
            const float *tc = j->top_cost + b * KEPT, *ti = j->top_index + b * KEPT;
            const float c_min = tc[0], v = j->variance[b];
            float share = v / (v + c_min);
            share *= share;
            if (!(share > 0.0f && share <= 1.0f))
                continue; /* no candidate (c_min infinite), nothing varies, or an overflow */
            float sum[5] = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f};
            float total = 0.0f;
            for (uint32_t k = 0; k < KEPT && tc[k] < INFINITY; k++) {
                const offset d = j->full[(uint32_t)ti[k]];
                const int64_t sx = (int64_t)x + d.dx, sy = (int64_t)y + d.dy;
                if (!offsets_is_source(f, sx, sy))
                    continue;
                const float w =
                    expf(-ddof_minf(50.0f, (tc[k] - c_min) / (SOFTNESS * c_min + SOFT_FLOOR)));
                const float *c = offsets_color_at(r, sx, sy);
                for (uint32_t i = 0; i < C; i++)
                    sum[i] += w * c[i];
                sum[C] += w * adi_request_coc(r, (size_t)sx, (size_t)sy);
                total += w;
            }
            if (!(total > 0.0f))
                continue;
            float *rest = f->rest + p * C;
            for (uint32_t i = 0; i < C; i++)
                rest[i] += share * (sum[i] / total - rest[i]);
            f->rest_coc[p] += share * (sum[C] / total - f->rest_coc[p]);
        }
}

/* ---- the whole ---------------------------------------------------------------------------- */

ddof_status ddof_fill_from_offsets(ddof_context *context, const offset_fill *f)
{
    const adi_request *r = f->frame;
    offsets_job j = {.f = f};
    ddof_near_level level;
    if (!ddof_near_search_level(r->width, r->height, &level))
        return DDOF_OK; /* too small a frame to repeat itself */
    j.S = level.s;
    j.wl = level.wl;
    j.hl = level.hl;
    j.reach = level.reach;
    const uint32_t side = ddof_offsets_grid_side(&j);
    const size_t n = (size_t)j.wl * j.hl, grid = (size_t)side * side;
    j.gw = (j.wl + SAMPLE_STRIDE - 1) / SAMPLE_STRIDE;
    j.gh = (j.hl + SAMPLE_STRIDE - 1) / SAMPLE_STRIDE;
    const size_t gn = (size_t)j.gw * j.gh;
    const size_t phases = (size_t)SAMPLE_STRIDE * 4 * j.gw * j.hl;
    const size_t refine = (size_t)(2 * j.S + 1) * (2 * j.S + 1); /* ddof_near_refine_reach */
    const size_t floats =
        n * (3 + 4 + 2 * KEPT + 2 * MAX_BOX_MAPS) + grid + 4 * gn + phases + refine;
    const size_t bytes =
        floats * sizeof(float) + REFINE_SAMPLES * sizeof(uint32_t) + grid * sizeof(ranked) +
        9 * COARSE_KEPT * sizeof(uint32_t);
    float *memory = ddof_scratch_get(context, DDOF_SCRATCH_NEAR_OFFSETS, bytes);
    if (!memory)
        return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                         "could not allocate the near layer's offset search for %ux%u",
                         r->width, r->height);
    j.mean = memory;
    j.known = j.mean + 3 * n;
    j.band = j.known + n;
    j.hole = j.band + n;
    j.variance = j.hole + n;
    j.top_cost = j.variance + n;
    j.top_index = j.top_cost + KEPT * n;
    j.box = j.top_index + KEPT * n;
    j.search_error = j.box + 2 * MAX_BOX_MAPS * n;
    j.grid = j.search_error + grid;
    j.phases = j.grid + 4 * gn;
    j.refine_error = j.phases + phases;
    j.band_samples = (uint32_t *)(void *)(j.refine_error + refine);
    ranked *rank = (ranked *)(void *)(j.band_samples + REFINE_SAMPLES);
    j.todo = (uint32_t *)(void *)(rank + grid);

    ddof_parallel_rows(context, j.hl, reduce_rows, &j);

    /* The band: known blocks within BAND of a hole block. */
    memcpy(j.box, j.hole, n * sizeof(float));
    box_sums(context, &j, 1, BAND);
    for (size_t b = 0; b < n; b++)
        j.band[b] = j.known[b] > 0.0f && j.box[b] > 0.0f;

    if (!ddof_offsets_find(context, &j, rank) || j.candidates == 0)
        return DDOF_OK;

    ddof_parallel_rows(context, j.hl, variance_maps_rows, &j);
    box_sums(context, &j, 7, SCORE_RADIUS);
    ddof_parallel_rows(context, j.hl, variance_rows, &j);
    for (j.current = 0; j.current < j.candidates; j.current++) {
        ddof_parallel_rows(context, j.hl, candidate_rows, &j);
        box_sums(context, &j, 2, SCORE_RADIUS);
        ddof_parallel_rows(context, j.hl, keep_rows, &j);
    }
    ddof_parallel_rows(context, r->height, copy_rows, &j);
    return DDOF_OK;
}
