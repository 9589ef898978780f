/* SPDX-License-Identifier: MIT */
/* ddof_highlight_rules.h - the highlight pass's rules that the CPU's drawing
 * (libddof/src/passes/highlights_draw.c, aperture.c) and the device's (passes/gl/
 * gl_highlights.c, highlights.comp, which gets the constants as defines) share to the bit:
 * the size classes a highlight is drawn in, where a class's light lands, and how far a
 * highlight's shape reaches. Header-only, so that each side compiles the same expressions. */
#ifndef DDOF_HIGHLIGHT_RULES_H
#define DDOF_HIGHLIGHT_RULES_H

#include <math.h>

#define DDOF_HIGHLIGHT_MIN_COC_PX 4.0f /* below this a disc and a blob look the same */
#define DDOF_HIGHLIGHT_SIZE_CLASSES 20 /* octaves of |CoC| from the minimum; the last one open */
#define DDOF_HIGHLIGHT_NEAR_CLASS DDOF_HIGHLIGHT_SIZE_CLASSES

/* A highlight's class: its octave of |CoC|, or the near class. */
static inline int ddof_highlight_size_class(float coc, int coc_signed)
{
    if (coc_signed && coc < 0.0f)
        return DDOF_HIGHLIGHT_NEAR_CLASS;
    const int k = (int)floorf(log2f(fabsf(coc) / DDOF_HIGHLIGHT_MIN_COC_PX));
    return k < 0 ? 0 : k >= DDOF_HIGHLIGHT_SIZE_CLASSES ? DDOF_HIGHLIGHT_SIZE_CLASSES - 1 : k;
}

/* The signed CoC a pixel needs to receive a class's light (the near class: any). */
static inline float ddof_highlight_landing_threshold(int size)
{
    return size == DDOF_HIGHLIGHT_NEAR_CLASS
               ? -INFINITY
               : 0.5f * DDOF_HIGHLIGHT_MIN_COC_PX * exp2f((float)size);
}

/* The rim's reach beyond the shape's edge in the shape's axes (rows scaled by 1 / aspect): half
 * a pixel, which is more than half a unit vertically when rows are squeezed (aspect < 1). */
static inline float ddof_highlight_rim_margin(float aspect)
{
    return aspect >= 1.0f ? 0.5f : 0.5f / aspect;
}

/* Rows of a highlight's shape of radius r above and below its centre (the pixel aspect
 * stretches it vertically). */
static inline int ddof_highlight_half_height(float radius, float aspect)
{
    return (int)ceilf((radius + ddof_highlight_rim_margin(aspect)) * aspect);
}

/* Columns of it either side of its centre that a class's box must hold. */
static inline int ddof_highlight_reach_x(float radius)
{
    return (int)ceilf(radius + 0.5f) + 1;
}

#endif
