/* SPDX-License-Identifier: MIT */
/* ddof_highlight_rules.h - the highlight pass's rules that the CPU's drawing
 * (libddof/src/passes/highlights_draw.c, aperture.c) and the device's (passes/gl/
 * gl_highlights.c, highlights.comp, which gets the constants as defines) share to the bit:
 * the size classes a highlight is drawn in, where a class's light lands, and how far a
 * highlight's shape reaches. Header-only, so that each side compiles the same expressions. */
#ifndef DDOF_HIGHLIGHT_RULES_H
#define DDOF_HIGHLIGHT_RULES_H

#include <math.h>
#include <stdint.h>

#define DDOF_HIGHLIGHT_MIN_COC_PX 4.0f /* below this a disc and a blob look the same */
#define DDOF_HIGHLIGHT_BUDGET 8.0f     /* disc rows and rim pixels per frame pixel     */
#define DDOF_HIGHLIGHT_SHARP_PX 2.0f   /* |CoC| below this: a sharp occluder            */

/* Brightness classes, a quarter octave each: a highlight of brightness L is in class
 * floor(4 log2(L / threshold)), so raising the threshold by 2^(k/4) drops the classes below k. */
#define DDOF_HIGHLIGHT_CLASSES_PER_OCTAVE 4
#define DDOF_HIGHLIGHT_CLASSES 128

/* The rows of a chunk whose disc costs are summed apart before the chunks' sums are added, in
 * that order (the CPU's row chunks, DDOF_ROWS_PER_CHUNK): a device that sums in the same
 * order arrives at the same budget. */
#define DDOF_HIGHLIGHT_CHUNK_ROWS 16u

/* The brightness class of a highlight of brightness l (> threshold). Over a tiny threshold
 * l / threshold overflows to +inf: the top class, decided before any conversion to int
 * (undefined for inf; libFuzzer found it under UBSan). Non-decreasing in l, so a device finds
 * the same class by comparing l with the class bounds this gives (the device's log2 is not the
 * host's). */
static inline int ddof_highlight_brightness_class(float l, float threshold)
{
    const float octaves = DDOF_HIGHLIGHT_CLASSES_PER_OCTAVE * log2f(l / threshold);
    if (!(octaves < (float)DDOF_HIGHLIGHT_CLASSES))
        return DDOF_HIGHLIGHT_CLASSES - 1;
    const int k = (int)floorf(octaves);
    return k < 0 ? 0 : k;
}

/* The threshold that keeps the classes from `first` up. */
static inline float ddof_highlight_kept_threshold(float threshold, uint32_t first)
{
    return threshold * exp2f((float)first / DDOF_HIGHLIGHT_CLASSES_PER_OCTAVE);
}

/* What drawing a disc of this CoC costs, in pixel operations: its rows, and its rim pixels
 * (about twice its circumference) for the weights and the scatter; an aperture image's every
 * pixel (`area`). */
static inline double ddof_highlight_disc_cost(float coc, float aspect, int area)
{
    const double r = 0.5 * fabs((double)coc) + 0.5;
    if (area)
        return 2.0 * (2.0 * r + 1.0) * (2.0 * r * (double)aspect + 1.0);
    return 2.0 * r * (double)aspect + 1.0 + 4.0 * 3.14159265358979 * r;
}

/* The budget's choice from the classes' counts and costs: the brightest classes whose discs
 * together cost at most `budget`. None: `over_budget` when some were found (the threshold is
 * then that of the brightest class, which alone is over the budget). */
typedef struct ddof_highlight_choice {
    uint32_t first;     /* the first class kept (DDOF_HIGHLIGHT_CLASSES: none)  */
    uint64_t kept;      /* highlights kept                                      */
    double kept_cost;
    int over_budget;
    float threshold;    /* the threshold applied                                */
} ddof_highlight_choice;

static inline ddof_highlight_choice ddof_highlight_choose(const uint64_t *count,
                                                          const double *cost, double budget,
                                                          float threshold)
{
    ddof_highlight_choice c = {DDOF_HIGHLIGHT_CLASSES, 0, 0.0, 0, threshold};
    int first = DDOF_HIGHLIGHT_CLASSES;
    while (first > 0 && c.kept_cost + cost[first - 1] <= budget) {
        first--;
        c.kept_cost += cost[first];
        c.kept += count[first];
    }
    if (c.kept == 0) {
        for (int k = DDOF_HIGHLIGHT_CLASSES - 1; k >= 0 && !c.over_budget; k--)
            if (count[k]) {
                c.over_budget = 1;
                c.threshold = ddof_highlight_kept_threshold(threshold, (uint32_t)k);
            }
        c.kept_cost = 0.0;
        return c;
    }
    c.first = (uint32_t)first;
    c.threshold = ddof_highlight_kept_threshold(threshold, c.first);
    return c;
}
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

/* The aperture a highlight is drawn with (libddof/src/passes/aperture.h), in the layout the
 * device reads (std430, the doubles first): a disc, or a regular polygon inscribed in it whose
 * edge normals (x, y) point at rotation + 2 pi k / sides (Cycles' polygon), or an aperture
 * image's size; the cat's eye's frame; rows stretched by `aspect`. */
typedef struct ddof_highlight_shape {
    double catseye; /* 0: no clip */
    double centre_x, centre_y, inv_half_width, inv_half_height;
    float aspect, apothem;
    uint32_t sides;                     /* 0: a disc, or the image           */
    uint32_t image_width, image_height; /* 0: no aperture image              */
    float normal[2 * 16];
} ddof_highlight_shape;

/* The shape of an aperture of `blades` (0..2: a disc) turned by rotation_rad, with the cat's
 * eye `catseye` (0: off) about a frame of centre and half sizes, or an aperture image of the
 * given size (image: 1), for rows stretched by `aspect`. */
static inline ddof_highlight_shape ddof_highlight_shape_of(uint32_t blades, double rotation_rad,
                                                           double catseye, double centre_x,
                                                           double centre_y, double half_width,
                                                           double half_height, int image,
                                                           uint32_t image_width,
                                                           uint32_t image_height, float aspect)
{
    ddof_highlight_shape s = {.aspect = aspect};
    if (image) {
        s.image_width = image_width;
        s.image_height = image_height;
    }
    if (catseye > 0.0 && half_width > 0.0 && half_height > 0.0) {
        s.catseye = catseye;
        s.centre_x = centre_x;
        s.centre_y = centre_y;
        s.inv_half_width = 1.0 / half_width;
        s.inv_half_height = 1.0 / half_height;
    }
    if (blades < 3 || image)
        return s;
    s.sides = blades;
    const double step = 2.0 * 3.14159265358979323846 / s.sides;
    for (uint32_t k = 0; k < s.sides; k++) {
        s.normal[2 * k] = (float)cos(rotation_rad + step * k);
        s.normal[2 * k + 1] = (float)sin(rotation_rad + step * k);
    }
    s.apothem = (float)cos(0.5 * step);
    return s;
}

#endif
