/* SPDX-License-Identifier: MIT */
/* highlights_classes.h - what finding the highlights (highlights_find.c) and drawing them
 * (highlights_draw.c) share: a pixel's CoC, the highlights' size classes and where a class's
 * light may land. */
#ifndef DDOF_HIGHLIGHTS_CLASSES_H
#define DDOF_HIGHLIGHTS_CLASSES_H

#include "highlights.h"
#include "ddof_highlight_rules.h"

#include <math.h>

#define SIZE_CLASSES DDOF_HIGHLIGHT_SIZE_CLASSES
#define NEAR_CLASS DDOF_HIGHLIGHT_NEAR_CLASS

static inline int size_class(float coc, int coc_signed)
{
    return ddof_highlight_size_class(coc, coc_signed);
}

/* The signed CoC a pixel needs to receive a class's light (NEAR_CLASS: any). */
static inline float landing_threshold(int size)
{
    return ddof_highlight_landing_threshold(size);
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
