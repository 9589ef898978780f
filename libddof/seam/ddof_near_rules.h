/* SPDX-License-Identifier: MIT */
/* ddof_near_rules.h - the near layer's rules that the CPU's split (libddof/src/passes/
 * near_layer.c, near_offsets_*.c) and the device's (passes/gl/gl_near_layer.c, near_layer.comp,
 * near_offsets.comp, which get the constants as defines) share to the bit: the matte, the
 * fringe's split, the offset fill's lengths, and the choices the offsets' search makes from its
 * errors (on the host on either side). Header-only, so that each side compiles the same
 * expressions. Measured on the study's near scenes (docs/accuracy.md, the near layer). */
#ifndef DDOF_NEAR_RULES_H
#define DDOF_NEAR_RULES_H

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

/* The fringe's split (near_layer.c, split_fringe): a pixel beside the element is split only
 * where the object is this many times brighter than what lies behind it, and gives it at most
 * this share. */
#define DDOF_NEAR_FRINGE_CONTRAST 4.0f
#define DDOF_NEAR_FRINGE_MAX_SHARE 0.95f

/* The pyramid level whose means are the line fill's end values (2x2 pixels). */
#define DDOF_NEAR_END_LEVEL 1u

/* The offset fill (near_offsets_fill.c); lengths in blocks of the search level. */
#define DDOF_NEAR_SEARCH_SIZE 512u
#define DDOF_NEAR_BAND 4u
#define DDOF_NEAR_SCORE_RADIUS 24u
#define DDOF_NEAR_MIN_BAND_SAMPLES 3.0f
#define DDOF_NEAR_KEPT 4u
#define DDOF_NEAR_SOFTNESS 2.0f
#define DDOF_NEAR_SOFT_FLOOR 1e-4f
#define DDOF_NEAR_MEAN_LIMIT 1e18
#define DDOF_NEAR_CANDIDATES 24u
#define DDOF_NEAR_MIN_OFFSET 8
#define DDOF_NEAR_MAX_OFFSET 96
#define DDOF_NEAR_OFFSET_STEP 2
#define DDOF_NEAR_SAMPLE_STRIDE 4u
#define DDOF_NEAR_MAX_BOX_MAPS 7u
#define DDOF_NEAR_REFINE_SAMPLES 4096u
#define DDOF_NEAR_COARSE_KEPT (3u * DDOF_NEAR_CANDIDATES) /* whose neighbours are tried     */
#define DDOF_NEAR_MIN_OVERLAP 0.2
#define DDOF_NEAR_SEPARATION 3
#define DDOF_NEAR_SEARCH_LANES 8 /* the search's independent sums, in a fixed order          */

/* The near layer's matte of a pixel of signed CoC c: 0 for in-focus, far or mildly blurred
 * near pixels, 1 for near pixels of |CoC| >= threshold, linear from threshold / 2. A soft
 * matte: a near surface that recedes to the focus plane has no seam where it leaves the
 * layer. */
static inline float ddof_near_matte(float c, float threshold)
{
    const float t0 = 0.5f * threshold;
    const float m = (-c - t0) / (threshold - t0);
    return m <= 0.0f ? 0.0f : m >= 1.0f ? 1.0f : m;
}

/* A displacement, in blocks of the search level or in pixels. */
typedef struct ddof_near_offset {
    int32_t dx, dy;
} ddof_near_offset;

/* An offset of the search's grid and its error. */
typedef struct ddof_near_ranked {
    float error;
    uint32_t index;
} ddof_near_ranked;

/* The search level: blocks of s x s pixels (a power of two, the level at most SEARCH_SIZE on
 * a side), wl x hl of them, and the offsets' reach (blocks). 0: a frame too small to repeat
 * itself (no offset of MIN_OFFSET blocks fits). */
typedef struct ddof_near_level {
    uint32_t s, wl, hl;
    int32_t reach;
} ddof_near_level;

static inline int ddof_near_search_level(uint32_t width, uint32_t height, ddof_near_level *l)
{
    l->s = 1;
    while ((width + l->s - 1) / l->s > DDOF_NEAR_SEARCH_SIZE ||
           (height + l->s - 1) / l->s > DDOF_NEAR_SEARCH_SIZE)
        l->s *= 2;
    l->wl = (width + l->s - 1) / l->s;
    l->hl = (height + l->s - 1) / l->s;
    const uint32_t longest = l->wl > l->hl ? l->wl : l->hl;
    l->reach = (int32_t)(longest / 5) / DDOF_NEAR_OFFSET_STEP * DDOF_NEAR_OFFSET_STEP;
    l->reach = l->reach < DDOF_NEAR_MAX_OFFSET ? l->reach : DDOF_NEAR_MAX_OFFSET;
    return l->reach >= DDOF_NEAR_MIN_OFFSET;
}

/* The search's grid: offsets -reach to reach in steps of OFFSET_STEP, side x side of them. */
static inline uint32_t ddof_near_grid_side(int32_t reach)
{
    return (uint32_t)(2 * reach / DDOF_NEAR_OFFSET_STEP + 1);
}

/* Grid offset `index` in blocks. */
static inline ddof_near_offset ddof_near_grid_offset(int32_t reach, uint32_t index)
{
    const uint32_t side = ddof_near_grid_side(reach);
    return (ddof_near_offset){-reach + (int32_t)(index % side) * DDOF_NEAR_OFFSET_STEP,
                              -reach + (int32_t)(index / side) * DDOF_NEAR_OFFSET_STEP};
}

static inline int ddof_near_by_error(const void *a, const void *b)
{
    const ddof_near_ranked *x = a, *y = b;
    if (x->error != y->error)
        return x->error < y->error ? -1 : 1;
    return x->index < y->index ? -1 : x->index > y->index;
}

/* The search's finite errors (side x side), ranked best first; returns their count. */
static inline uint32_t ddof_near_rank(const float *errors, uint32_t side,
                                      ddof_near_ranked *rank)
{
    uint32_t finite = 0;
    for (uint32_t i = 0; i < side * side; i++)
        if (errors[i] < INFINITY)
            rank[finite++] = (ddof_near_ranked){errors[i], i};
    qsort(rank, finite, sizeof *rank, ddof_near_by_error);
    return finite;
}

/* Coarse to fine: after every second grid offset (rows and columns), the grid offsets left
 * beside the COARSE_KEPT best of `ranked` (of `best`), each once; returns their count (at most
 * 8 COARSE_KEPT). */
static inline uint32_t ddof_near_fine_offsets(const ddof_near_ranked *rank, uint32_t best,
                                              uint32_t side, uint32_t *todo)
{
    uint32_t count = 0;
    for (uint32_t i = 0; i < best && i < DDOF_NEAR_COARSE_KEPT; i++) {
        const int64_t row = rank[i].index / side, col = rank[i].index % side;
        for (int64_t r = row - 1; r <= row + 1; r++)
            for (int64_t c = col - 1; c <= col + 1; c++)
                if (r >= 0 && c >= 0 && r < side && c < side && (r % 2 || c % 2)) {
                    const uint32_t g = (uint32_t)(r * side + c);
                    int listed = 0; /* a neighbour of two: once (the list is short) */
                    for (uint32_t k = 0; k < count && !listed; k++)
                        listed = todo[k] == g;
                    if (!listed)
                        todo[count++] = g;
                }
    }
    return count;
}

/* The CANDIDATES best offsets of the ranked search (`finite` of them), SEPARATION apart, into
 * `level` (blocks); returns their count. */
static inline uint32_t ddof_near_choose(const ddof_near_ranked *rank, uint32_t finite,
                                        int32_t reach, ddof_near_offset *level)
{
    uint32_t candidates = 0;
    for (uint32_t i = 0; i < finite && candidates < DDOF_NEAR_CANDIDATES; i++) {
        const ddof_near_offset d = ddof_near_grid_offset(reach, rank[i].index);
        int apart = 1;
        for (uint32_t k = 0; k < candidates && apart; k++)
            apart = abs(d.dx - level[k].dx) >= DDOF_NEAR_SEPARATION ||
                    abs(d.dy - level[k].dy) >= DDOF_NEAR_SEPARATION;
        if (apart)
            level[candidates++] = d;
    }
    return candidates;
}

/* The refinement's reach around a candidate, pixels: the search's grid step. */
static inline int32_t ddof_near_refine_reach(uint32_t s)
{
    return (int32_t)s * DDOF_NEAR_OFFSET_STEP / 2;
}

/* A candidate to the pixel: of the band errors of its offsets start + (ex, ey), ey and ex from
 * -reach to reach (`errors`, row by row), the first smallest, the start's own counting first.
 * Unless another candidate came to the same offset (then dropped), it is kept as full[*kept]
 * (pixels) and level[*kept] (to the nearest block). level may be the array read from. */
static inline void ddof_near_refine_keep(const float *errors, ddof_near_offset start,
                                         uint32_t s, ddof_near_offset *full,
                                         ddof_near_offset *level, uint32_t *kept)
{
    const int32_t reach = ddof_near_refine_reach(s), side = 2 * reach + 1;
    ddof_near_offset best = start;
    float best_error = errors[reach * side + reach];
    for (int32_t ey = -reach; ey <= reach; ey++)
        for (int32_t ex = -reach; ex <= reach; ex++) {
            const float e = (ex || ey) ? errors[(ey + reach) * side + ex + reach] : INFINITY;
            if (e < best_error) {
                best_error = e;
                best = (ddof_near_offset){start.dx + ex, start.dy + ey};
            }
        }
    for (uint32_t k = 0; k < *kept; k++)
        if (full[k].dx == best.dx && full[k].dy == best.dy)
            return;
    full[*kept] = best;
    level[*kept] = (ddof_near_offset){(int32_t)lround((double)best.dx / s),
                                      (int32_t)lround((double)best.dy / s)};
    (*kept)++;
}

#endif
