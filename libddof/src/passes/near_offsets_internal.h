/* SPDX-License-Identifier: MIT */
/* near_offsets_internal.h - what the offset fill's two files share (near_offsets_fill.c: the search
 * level, the scores and the copies; near_offsets_search.c: which offsets). */
#ifndef DDOF_NEAR_OFFSETS_INTERNAL_H
#define DDOF_NEAR_OFFSETS_INTERNAL_H

#include "near_offsets.h"

#include "ddof_near_rules.h"

#include <stdint.h>

/* The rules' lengths (ddof_near_rules.h, shared with the device) under this file's names. */
#define CANDIDATES DDOF_NEAR_CANDIDATES
#define MIN_OFFSET DDOF_NEAR_MIN_OFFSET
#define OFFSET_STEP DDOF_NEAR_OFFSET_STEP
#define SAMPLE_STRIDE DDOF_NEAR_SAMPLE_STRIDE
#define MAX_BOX_MAPS DDOF_NEAR_MAX_BOX_MAPS
#define REFINE_SAMPLES DDOF_NEAR_REFINE_SAMPLES
#define COARSE_KEPT DDOF_NEAR_COARSE_KEPT

typedef ddof_near_offset offset;
typedef ddof_near_ranked ranked;

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
    float *refine_error; /* a candidate's band errors around it, (2 S + 1)^2 */
    uint32_t *todo; /* the fine pass's grid offsets */
    /* the candidates */
    offset level[CANDIDATES], full[CANDIDATES];
    uint32_t candidates, current;
} offsets_job;

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

static inline uint32_t ddof_offsets_grid_side(const offsets_job *j)
{
    return ddof_near_grid_side(j->reach);
}

#endif
