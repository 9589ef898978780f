/* SPDX-License-Identifier: MIT */
/* ddof_far_rules.h - the far field's constants and the few decisions taken from its counts,
 * shared to the bit by the CPU's pass (libddof/src/passes/far_field*.c, far_layers.c) and the
 * device's (libddof/src/passes/gl/gl_far_field.c, far_field.comp, which gets the constants as
 * defines): where an edge is, the ramp, the image levels a radius needs, and how the depth
 * slices' cuts are chosen from the counts of the pairs each bin edge separates. Header-only,
 * so that each side compiles the same expressions. */
#ifndef DDOF_FAR_RULES_H
#define DDOF_FAR_RULES_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

/* A depth edge: 4-neighbours whose signed CoC differs by this much; one between two blurred
 * surfaces: both |CoC| at least FAR_BLURRED_PX. */
#define FAR_EDGE_STEP_PX 2.0f
#define FAR_BLURRED_PX 2.0f
/* The ramp (px) over which the gather's share falls to 0 toward an edge. */
#define FAR_RAMP_PX 4.0f
/* A seed of the distance maps where there is no edge. */
#define FAR_NO_EDGE (-1e30f)
/* Colour (up to 4) and, in a slice's gather, its coverage. */
#define FAR_FIELD_MAX_CHANNELS 5
/* Image levels: a pixel whose disc is wider than FAR_LEVEL_RADIUS px interpolates a coarser
 * level's samples (far_field_gather.c). */
#define FAR_FIELD_MAX_LEVELS 16
#define FAR_LEVEL_RADIUS 8.0f
/* The depth slices: at most this many, cut at bin edges FAR_BIN_PX apart (at most
 * FAR_MAX_BINS), each cut separating at least FAR_MIN_SEPARATED pairs. */
#define FAR_LAYERS_MAX_SLICES 4
#define FAR_BIN_PX 0.25f
#define FAR_MAX_BINS 4096u
#define FAR_MIN_SEPARATED 16u

/* The image levels a gather of radii up to `largest` reads, of a width x height frame: level k
 * is ceil(size / 2^k) a side, and the last is the first whose pixels are at least an eighth of
 * the largest disc's extent apart (or 1 x 1, or the FAR_FIELD_MAX_LEVELS-th). */
static inline uint32_t ddof_far_level_count(float largest, float pixel_aspect, uint32_t width,
                                            uint32_t height)
{
    const float extent = largest * (pixel_aspect > 1.0f ? pixel_aspect : 1.0f);
    uint32_t count = 0, w = width, h = height;
    for (;;) {
        count++;
        if (count == FAR_FIELD_MAX_LEVELS ||
            extent <= FAR_LEVEL_RADIUS * (float)(1u << (count - 1)) || (w == 1 && h == 1))
            return count;
        w = (w + 1) / 2;
        h = (h + 1) / 2;
    }
}

/* The bins between the pairs' smallest signed CoC lo and largest hi, and their width. */
static inline uint32_t ddof_far_bins(float lo, float hi, float *width)
{
    const float span = (hi - lo) / FAR_BIN_PX;
    const uint32_t bins = span < (float)FAR_MAX_BINS ? (uint32_t)ceilf(span) + 1u : FAR_MAX_BINS;
    *width = (hi - lo) / (float)bins;
    return bins;
}

/* The bin edges [b0, b1] that separate a pair (plo, phi) (edge b is the value lo + b width,
 * and separates it when plo < it <= phi); none when b0 > b1. */
static inline void ddof_far_pair_bins(float plo, float phi, float lo, float width, uint32_t bins,
                                      uint32_t *b0, uint32_t *b1)
{
    *b0 = (uint32_t)floorf((plo - lo) / width) + 1u;
    const float last = floorf((phi - lo) / width);
    *b1 = (uint32_t)(last < (float)bins ? last : (float)bins);
}

/* Whether a pair (plo, phi) is separated by one of the cuts so far. */
static inline int ddof_far_separated(float plo, float phi, const float *cuts, uint32_t count)
{
    for (uint32_t i = 0; i < count; i++)
        if (plo < cuts[i] && cuts[i] <= phi)
            return 1;
    return 0;
}

/* From the difference array `runs` (bins + 2 counters: +1 at a pair's first separating edge,
 * -1 after its last), the edge that separates the most pairs: inserted into the ascending
 * `cuts` (count so far) when it separates at least FAR_MIN_SEPARATED. Returns the new count,
 * the same count when no edge does (the cuts are done). */
static inline uint32_t ddof_far_take_cut(const int64_t *runs, uint32_t bins, float lo,
                                         float width, float *cuts, uint32_t count)
{
    int64_t run = 0, best = 0;
    uint32_t best_bin = 0;
    for (uint32_t b = 1; b <= bins; b++) {
        run += runs[b];
        if (run > best) {
            best = run;
            best_bin = b;
        }
    }
    if (best < (int64_t)FAR_MIN_SEPARATED)
        return count;
    const float cut = lo + (float)best_bin * width;
    uint32_t at = count;
    while (at > 0 && cuts[at - 1] > cut) {
        cuts[at] = cuts[at - 1];
        at--;
    }
    cuts[at] = cut;
    return count + 1;
}

#endif
