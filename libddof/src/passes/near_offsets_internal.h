/* SPDX-License-Identifier: MIT */
/* near_offsets_internal.h - what the offset fill's two files share (near_offsets_fill.c: the search
 * level, the scores and the copies; near_offsets_search.c: which offsets). */
#ifndef DDOF_NEAR_OFFSETS_INTERNAL_H
#define DDOF_NEAR_OFFSETS_INTERNAL_H

#include "near_offsets.h"

#include <stdint.h>

/* Lengths in blocks of the search level (near_offsets_fill.c). Measured on the study's near scenes
 * (docs/design.md, the near layer). */
#define CANDIDATES 24u
#define MIN_OFFSET 8
#define MAX_OFFSET 96
#define OFFSET_STEP 2
#define SAMPLE_STRIDE 4u
#define MAX_BOX_MAPS 7u
#define REFINE_SAMPLES 4096u
#define COARSE_KEPT (3u * CANDIDATES) /* the coarse search's best, whose neighbours are tried */

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

typedef struct ranked {
    float error;
    uint32_t index;
} ranked;

static inline int offsets_is_source(const offset_fill *f, int64_t x, int64_t y)
{
    const adi_request *r = f->frame;
    return x >= 0 && y >= 0 && x < r->width && y < r->height &&
           f->source[(size_t)y * r->width + (size_t)x] >= 1.0f;
}

static inline const float *offsets_color_at(const adi_request *r, int64_t x, int64_t y)
{
    return r->color + (size_t)y * r->color_stride + (size_t)x * r->channels;
}

static inline float offsets_sq_distance3(const float *a, const float *b)
{
    float s = 0.0f;
    for (uint32_t k = 0; k < 3; k++)
        s += (a[k] - b[k]) * (a[k] - b[k]);
    return s;
}

/* Steps 1 and 2 (near_offsets_search.c): j's level, known and band maps and its search fields
 * set up, rank scratch for every offset of the grid; sets j->candidates and their offsets.
 * Returns 0 when no sample of the search is known (nothing to search). */
int ddof_offsets_find(ddof_context *context, offsets_job *j, ranked *rank);

/* The search's grid: offsets -reach to reach in steps of OFFSET_STEP, side x side of them. */
static inline uint32_t ddof_offsets_grid_side(const offsets_job *j)
{
    return (uint32_t)(2 * j->reach / OFFSET_STEP + 1);
}

#endif
