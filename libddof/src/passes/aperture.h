/* SPDX-License-Identifier: MIT */
/* aperture.h - the aperture as the highlight pass draws it (aperture.c): a disc, Cycles'
 * polygon, an anamorphic ratio, a custom aperture image and the cat's eye, as a highlight's
 * rows of interior and rim and the weights of its rim pixels. */
#ifndef DDOF_APERTURE_H
#define DDOF_APERTURE_H

#include "highlights.h"

#include <limits.h>

/* One row of a highlight's shape, in columns dx from its centre: [inner_l, inner_r] has weight
 * 1 (empty when inner_l > inner_r), the rim pixels around it up to [outer_l, outer_r] are
 * anti-aliased, clamp(0.5 - signed distance to the shape's edge, 0, 1). The rim is walked
 * outward from the interior, left before right (aperture_rim_column), so a disc's pixels are
 * visited and summed in one order whatever the shape code. */
typedef struct aperture_row {
    int inner_l, inner_r, outer_l, outer_r;
    float v;  /* the row's vertical offset in horizontal pixels (down the image) */
    float v2; /* v squared                                                         */
    int clipped;    /* the cat's eye: the shape clipped by a circle of its radius at */
    float clip_x, clip_y; /* (clip_x, clip_y) from its centre (shape units)         */
} aperture_row;

/* The aperture as the scatter draws it: a disc, or a regular polygon inscribed in the disc,
 * whose edge normals point at rotation + 2 pi k / blades (Cycles' polygon: at rotation 0 an
 * edge's middle lies on the +x axis, y up). A far highlight (CoC >= 0) is the aperture as the
 * lens' rays cross the focus plane, upright; a near one is turned by 180 degrees. */
typedef struct aperture_shape {
    float aspect;                       /* rows per unit of the shape's y (>= 1: rows stretched) */
    uint32_t sides;                     /* 0: a disc                              */
    float normal[DDOF_MAX_APERTURE_BLADES][2];
    float apothem;                      /* the inscribed polygon's, per unit radius */
    double catseye;                     /* highlight_aperture's; 0: no clip       */
    double centre_x, centre_y, inv_half_width, inv_half_height;
    const double *sums;                 /* an aperture image's table (NULL: none) */
    uint32_t image_width, image_height;
} aperture_shape;

/* The shape of the camera's aperture (NULL: a disc) with its image's summed-area table
 * (sums, or NULL) for rows stretched by the pixel aspect. */
aperture_shape aperture_shape_of(const highlight_aperture *aperture, const double *sums,
                                 float aspect);

/* Rows of a highlight's shape above and below its centre. */
int aperture_half_height(const aperture_shape *s, const highlight *h);

/* Row dy (from the centre) of a highlight's shape, clipped by the cat's eye when there is one;
 * 0 when the row is empty. */
int aperture_row_at(const aperture_shape *s, const highlight *h, int dy, aperture_row *row);

/* The weight of rim pixel dx of a row: clamp(0.5 - its signed distance from the shape's edge,
 * 0, 1), or an aperture image's average over the pixel. */
float aperture_rim_weight(const aperture_shape *s, const highlight *h, const aperture_row *row,
                          int dx);

/* The k-th rim column (k >= 1) on `side` (-1 left, 1 right), or INT_MIN when there is none
 * there: left columns inner_l - k down to outer_l, right ones inner_r + k up to outer_r, a
 * row without interior starting with its middle column once. */
static inline int aperture_rim_column(const aperture_row *row, int k, int side)
{
    const int x = side < 0 ? row->inner_l - k : row->inner_r + k;
    if (side > 0 && x == row->inner_l - k)
        return INT_MIN; /* the middle column of a row without interior, once */
    return (side < 0 ? x >= row->outer_l : x <= row->outer_r) ? x : INT_MIN;
}

/* Rim columns to walk on either side. */
static inline int aperture_rim_steps(const aperture_row *row)
{
    const int left = row->inner_l - row->outer_l, right = row->outer_r - row->inner_r;
    return left > right ? left : right;
}

#endif
