/* SPDX-License-Identifier: MIT */
/* near_offsets.c - the near layer's holes filled from where the frame repeats itself
 * (near_offsets.h).
 *
 * The work is done on a search level: the frame in blocks of S x S pixels (S a power of two,
 * the level at most SEARCH_SIZE on a side), each block the mean of its sources, so that a 1080p
 * frame is searched as the study's 480x270 ones are. Four steps:
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
#include "near_offsets.h"

#include "parallel_rows.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SEARCH_SIZE 512u
#define CANDIDATES 24u
#define MIN_OFFSET 8
#define MAX_OFFSET 96
#define OFFSET_STEP 2
#define SAMPLE_STRIDE 4u
#define MIN_OVERLAP 0.2
#define SEPARATION 3
#define BAND 4u
#define SCORE_RADIUS 24u
#define MIN_BAND_SAMPLES 3.0f
#define KEPT 4u
#define SOFTNESS 2.0f
#define SOFT_FLOOR 1e-4f
#define MAX_BOX_MAPS 7u
#define MEAN_LIMIT 1e18
#define REFINE_SAMPLES 4096u

typedef struct offset {
    int32_t dx, dy;
} offset;

typedef struct offsets_job {
    const offset_fill *f;
    uint32_t S, wl, hl; /* block size, the search level's size */
    float *mean;        /* wl x hl x 3: each block's mean colour of sources           */
    float *known;       /* 1 where every pixel of the block is a source                */
    float *band;        /* 1 where known and within BAND blocks of a hole block        */
    float *hole;        /* 1 where the block holds a hole pixel                        */
    float *variance;    /* the band's colour variance within SCORE_RADIUS              */
    float *top_cost;    /* KEPT per block, ascending; INFINITY: none                   */
    float *top_index;   /* the candidates they belong to                               */
    float *box;         /* MAX_BOX_MAPS maps, then as many for the box sums' first pass */
    uint32_t box_maps, radius;
    /* the search: the blocks on a grid SAMPLE_STRIDE apart (gw x gh: planes of the 3 means
     * and of 1 where known), and the level split by x modulo SAMPLE_STRIDE into as many
     * phases (each gw x hl, the same 4 planes), so that the copies of a row of samples moved
     * by any offset are consecutive floats of one phase; the refinement: band blocks */
    float *grid, *phases;
    uint32_t gw, gh, sample_count;
    uint32_t *band_samples;
    uint32_t band_sample_count;
    int32_t reach; /* offsets from -reach to reach in steps of OFFSET_STEP       */
    float *search_error;
    uint32_t *todo; /* the fine pass's grid offsets */
    /* the candidates */
    offset level[CANDIDATES], full[CANDIDATES];
    uint32_t candidates, current;
} offsets_job;

static int is_source(const offset_fill *f, int64_t x, int64_t y)
{
    const adi_request *r = f->frame;
    return x >= 0 && y >= 0 && x < r->width && y < r->height &&
           f->source[(size_t)y * r->width + (size_t)x] >= 1.0f;
}

static const float *color_at(const adi_request *r, int64_t x, int64_t y)
{
    return r->color + (size_t)y * r->color_stride + (size_t)x * r->channels;
}

static float sq_distance3(const float *a, const float *b)
{
    float s = 0.0f;
    for (uint32_t k = 0; k < 3; k++)
        s += (a[k] - b[k]) * (a[k] - b[k]);
    return s;
}

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
                    const float *c = color_at(r, x, y);
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

/* Box sums of radius j->radius over the level (clipped at its edges), of the first
 * j->box_maps maps of j->box, in place; two passes through the maps after them. */
static void box_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const offsets_job *j = user;
    const size_t n = (size_t)j->wl * j->hl;
    const uint32_t w = j->wl, r = j->radius;
    for (uint32_t m = 0; m < j->box_maps; m++)
        for (uint32_t y = y0; y < y1; y++) {
            const float *in = j->box + m * n + (size_t)y * w;
            float *out = j->box + (MAX_BOX_MAPS + m) * n + (size_t)y * w;
            double s = 0.0;
            for (uint32_t x = 0; x <= r && x < w; x++)
                s += in[x];
            for (uint32_t x = 0; x < w; x++) {
                out[x] = (float)s;
                if (x + r + 1 < w)
                    s += in[x + r + 1];
                if (x >= r)
                    s -= in[x - r];
            }
        }
}

static void box_columns(void *user, uint32_t x0, uint32_t x1, uint32_t chunk)
{
    (void)chunk;
    const offsets_job *j = user;
    const size_t n = (size_t)j->wl * j->hl;
    const uint32_t w = j->wl, h = j->hl, r = j->radius;
    for (uint32_t m = 0; m < j->box_maps; m++)
        for (uint32_t x = x0; x < x1; x++) {
            const float *in = j->box + (MAX_BOX_MAPS + m) * n + x;
            float *out = j->box + m * n + x;
            double s = 0.0;
            for (uint32_t y = 0; y <= r && y < h; y++)
                s += in[(size_t)y * w];
            for (uint32_t y = 0; y < h; y++) {
                out[(size_t)y * w] = (float)s;
                if (y + r + 1 < h)
                    s += in[(size_t)(y + r + 1) * w];
                if (y >= r)
                    s -= in[(size_t)(y - r) * w];
            }
        }
}

static void box_sums(ddof_context *context, offsets_job *j, uint32_t maps, uint32_t radius)
{
    j->box_maps = maps;
    j->radius = radius;
    ddof_parallel_rows(context, j->hl, box_rows, j);
    ddof_parallel_rows(context, j->wl, box_columns, j);
}

/* ---- 1. the search ------------------------------------------------------------------------ */

#define SEARCH_LANES 8

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

/* The search's grid: offsets -reach to reach in steps of OFFSET_STEP, side x side of them. */
static uint32_t grid_side(const offsets_job *j)
{
    return (uint32_t)(2 * j->reach / OFFSET_STEP + 1);
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
    const uint32_t side = grid_side(j);
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
    const uint32_t side = grid_side(j);
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

typedef struct ranked {
    float error;
    uint32_t index;
} ranked;

static int by_error(const void *a, const void *b)
{
    const ranked *x = a, *y = b;
    if (x->error != y->error)
        return x->error < y->error ? -1 : 1;
    return x->index < y->index ? -1 : x->index > y->index;
}

/* The search's finite errors, ranked (best first); returns their count. */
static uint32_t rank_offsets(const offsets_job *j, ranked *rank)
{
    const uint32_t side = grid_side(j);
    uint32_t finite = 0;
    for (uint32_t i = 0; i < side * side; i++)
        if (j->search_error[i] < INFINITY)
            rank[finite++] = (ranked){j->search_error[i], i};
    qsort(rank, finite, sizeof *rank, by_error);
    return finite;
}

/* Coarse to fine: every second grid offset, then the neighbours of the COARSE_KEPT best. */
#define COARSE_KEPT (3u * CANDIDATES)

static void search(ddof_context *context, offsets_job *j, ranked *rank)
{
    const uint32_t side = grid_side(j);
    ddof_parallel_rows(context, side, search_coarse_rows, j);
    const uint32_t best = rank_offsets(j, rank);
    uint32_t count = 0;
    for (uint32_t i = 0; i < best && i < COARSE_KEPT; i++) {
        const int64_t row = rank[i].index / side, col = rank[i].index % side;
        for (int64_t r = row - 1; r <= row + 1; r++)
            for (int64_t c = col - 1; c <= col + 1; c++)
                if (r >= 0 && c >= 0 && r < side && c < side && (r % 2 || c % 2)) {
                    const uint32_t g = (uint32_t)(r * side + c);
                    int listed = 0; /* a neighbour of two: once (the list is short) */
                    for (uint32_t k = 0; k < count && !listed; k++)
                        listed = j->todo[k] == g;
                    if (!listed)
                        j->todo[count++] = g;
                }
    }
    ddof_parallel_rows(context, count, search_fine, j);
}

/* The CANDIDATES best offsets of the search, SEPARATION apart. */
static void choose_candidates(offsets_job *j, ranked *rank)
{
    const uint32_t side = grid_side(j);
    const uint32_t finite = rank_offsets(j, rank);
    j->candidates = 0;
    for (uint32_t i = 0; i < finite && j->candidates < CANDIDATES; i++) {
        const offset d = {-j->reach + (int32_t)(rank[i].index % side) * OFFSET_STEP,
                          -j->reach + (int32_t)(rank[i].index / side) * OFFSET_STEP};
        int apart = 1;
        for (uint32_t k = 0; k < j->candidates && apart; k++)
            apart = abs(d.dx - j->level[k].dx) >= SEPARATION ||
                    abs(d.dy - j->level[k].dy) >= SEPARATION;
        if (apart)
            j->level[j->candidates++] = d;
    }
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
        if (!is_source(j->f, x + d.dx, y + d.dy))
            continue;
        sum += sq_distance3(color_at(r, x, y), color_at(r, x + d.dx, y + d.dy));
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
    const int32_t reach = (int32_t)j->S * OFFSET_STEP / 2;
    uint32_t kept = 0;
    for (uint32_t c = 0; c < j->candidates; c++) {
        const offset start = {j->level[c].dx * (int32_t)j->S, j->level[c].dy * (int32_t)j->S};
        offset best = start;
        float best_error = band_error(j, start);
        for (int32_t ey = -reach; ey <= reach; ey++)
            for (int32_t ex = -reach; ex <= reach; ex++) {
                const offset d = {start.dx + ex, start.dy + ey};
                const float e = (ex || ey) ? band_error(j, d) : INFINITY;
                if (e < best_error) {
                    best_error = e;
                    best = d;
                }
            }
        int duplicate = 0;
        for (uint32_t k = 0; k < kept; k++)
            duplicate |= j->full[k].dx == best.dx && j->full[k].dy == best.dy;
        if (duplicate)
            continue;
        j->full[kept] = best;
        /* On the level, the refined offset to the nearest block. */
        j->level[kept] = (offset){(int32_t)lround((double)best.dx / j->S),
                                  (int32_t)lround((double)best.dy / j->S)};
        kept++;
    }
    j->candidates = kept;
}

/* ---- 3. scores ---------------------------------------------------------------------------- */

static void candidate_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const offsets_job *j = user;
    const size_t n = (size_t)j->wl * j->hl;
    const offset d = j->level[j->current];
    for (uint32_t y = y0; y < y1; y++)
        for (uint32_t x = 0; x < j->wl; x++) {
            const size_t b = (size_t)y * j->wl + x;
            const int64_t tx = (int64_t)x + d.dx, ty = (int64_t)y + d.dy;
            const int inside = tx >= 0 && ty >= 0 && tx < j->wl && ty < j->hl;
            const size_t t = inside ? (size_t)ty * j->wl + (size_t)tx : 0;
            const int used = j->band[b] > 0.0f && inside && j->known[t] > 0.0f;
            j->box[b] = used ? sq_distance3(j->mean + b * 3, j->mean + t * 3) : 0.0f;
            j->box[n + b] = (float)used;
        }
}

/* Keeps the candidate among each hole block's KEPT best (its copy must land on sources). */
static void keep_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const offsets_job *j = user;
    const size_t n = (size_t)j->wl * j->hl;
    const offset d = j->level[j->current];
    for (uint32_t y = y0; y < y1; y++)
        for (uint32_t x = 0; x < j->wl; x++) {
            const size_t b = (size_t)y * j->wl + x;
            if (j->hole[b] <= 0.0f || !(j->box[n + b] > MIN_BAND_SAMPLES))
                continue;
            const int64_t tx = (int64_t)x + d.dx, ty = (int64_t)y + d.dy;
            if (tx < 0 || ty < 0 || tx >= j->wl || ty >= j->hl ||
                j->known[(size_t)ty * j->wl + (size_t)tx] <= 0.0f)
                continue;
            const float cost = j->box[b] / j->box[n + b];
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
    const size_t n = (size_t)j->wl * j->hl;
    for (size_t b = (size_t)y0 * j->wl; b < (size_t)y1 * j->wl; b++) {
        const float w = j->band[b];
        j->box[b] = w;
        for (uint32_t k = 0; k < 3; k++) {
            const float m = j->mean[b * 3 + k];
            j->box[(1 + k) * n + b] = w * m;
            j->box[(4 + k) * n + b] = w * m * m;
        }
    }
}

static void variance_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const offsets_job *j = user;
    const size_t n = (size_t)j->wl * j->hl;
    for (size_t b = (size_t)y0 * j->wl; b < (size_t)y1 * j->wl; b++) {
        const double count = j->box[b];
        double v = 0.0;
        if (count > MIN_BAND_SAMPLES)
            for (uint32_t k = 0; k < 3; k++) {
                const double m = j->box[(1 + k) * n + b] / count;
                v += j->box[(4 + k) * n + b] / count - m * m;
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
                if (!is_source(f, sx, sy))
                    continue;
                const float w =
                    expf(-ddof_minf(50.0f, (tc[k] - c_min) / (SOFTNESS * c_min + SOFT_FLOOR)));
                const float *c = color_at(r, sx, sy);
                for (uint32_t i = 0; i < C; i++)
                    sum[i] += w * c[i];
                sum[C] += w * r->coc[(size_t)sy * r->coc_stride + (size_t)sx * r->coc_channels];
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
    offsets_job j = {.f = f, .S = 1};
    while ((r->width + j.S - 1) / j.S > SEARCH_SIZE || (r->height + j.S - 1) / j.S > SEARCH_SIZE)
        j.S *= 2;
    j.wl = (r->width + j.S - 1) / j.S;
    j.hl = (r->height + j.S - 1) / j.S;
    const uint32_t longest = j.wl > j.hl ? j.wl : j.hl;
    j.reach = (int32_t)(longest / 5) / OFFSET_STEP * OFFSET_STEP;
    j.reach = j.reach < MAX_OFFSET ? j.reach : MAX_OFFSET;
    if (j.reach < MIN_OFFSET)
        return DDOF_OK; /* too small a frame to repeat itself */
    const uint32_t side = grid_side(&j);
    const size_t n = (size_t)j.wl * j.hl, grid = (size_t)side * side;
    j.gw = (j.wl + SAMPLE_STRIDE - 1) / SAMPLE_STRIDE;
    j.gh = (j.hl + SAMPLE_STRIDE - 1) / SAMPLE_STRIDE;
    const size_t gn = (size_t)j.gw * j.gh;
    const size_t phases = (size_t)SAMPLE_STRIDE * 4 * j.gw * j.hl;
    const size_t floats = n * (3 + 4 + 2 * KEPT + 2 * MAX_BOX_MAPS) + grid + 4 * gn + phases;
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
    j.band_samples = (uint32_t *)(void *)(j.phases + phases);
    ranked *rank = (ranked *)(void *)(j.band_samples + REFINE_SAMPLES);
    j.todo = (uint32_t *)(void *)(rank + grid);

    ddof_parallel_rows(context, j.hl, reduce_rows, &j);

    /* The band: known blocks within BAND of a hole block. */
    memcpy(j.box, j.hole, n * sizeof(float));
    box_sums(context, &j, 1, BAND);
    for (size_t b = 0; b < n; b++)
        j.band[b] = j.known[b] > 0.0f && j.box[b] > 0.0f;

    search_planes(&j);
    if (j.sample_count == 0)
        return DDOF_OK;
    collect_band_samples(&j);
    search(context, &j, rank);
    choose_candidates(&j, rank);
    refine_candidates(&j);
    if (j.candidates == 0)
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
