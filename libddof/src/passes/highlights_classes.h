/* SPDX-License-Identifier: MIT */
/* highlights_classes.h - what finding the highlights (highlights_find.c) and drawing them
 * (highlights_draw.c) share: a pixel's CoC, the highlights' size classes and where a class's
 * light may land. */
#ifndef DDOF_HIGHLIGHTS_CLASSES_H
#define DDOF_HIGHLIGHTS_CLASSES_H

#include "highlights.h"

#include <math.h>

#define SIZE_CLASSES 20 /* octaves of |CoC| from the minimum; the last one is open */
#define NEAR_CLASS SIZE_CLASSES

static inline int size_class(float coc, int coc_signed)
{
    if (coc_signed && coc < 0.0f)
        return NEAR_CLASS;
    const int k = (int)floorf(log2f(fabsf(coc) / DDOF_HIGHLIGHT_MIN_COC_PX));
    return k < 0 ? 0 : k >= SIZE_CLASSES ? SIZE_CLASSES - 1 : k;
}

/* The signed CoC a pixel needs to receive a class's light (NEAR_CLASS: any). */
static inline float landing_threshold(int size)
{
    return size == NEAR_CLASS ? -INFINITY
                              : 0.5f * DDOF_HIGHLIGHT_MIN_COC_PX * exp2f((float)size);
}

static inline int lands(const adi_request *r, int coc_signed, float threshold, uint32_t x, uint32_t y)
{
    const float c = adi_request_coc(r, x, y);
    return (coc_signed ? c : fabsf(c)) >= threshold;
}

static inline float radius_of(const highlight *h)
{
    return 0.5f * fabsf(h->coc);
}

#endif
