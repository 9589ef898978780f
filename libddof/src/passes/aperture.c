/* SPDX-License-Identifier: MIT */
/* aperture.c - the aperture as the highlight pass draws it (aperture.h). */
#include "aperture.h"
#include "highlights_classes.h"

#include "runtime/float_ops.h"

#include <math.h>

static float rim_margin(float aspect)
{
    return ddof_highlight_rim_margin(aspect);
}

int aperture_half_height(const aperture_shape *s, const highlight *h)
{
    return ddof_highlight_half_height(radius_of(h), s->aspect);
}

aperture_shape aperture_shape_of(const highlight_aperture *aperture, const double *sums,
                                 float aspect)
{
    aperture_shape s = {.aspect = aspect};
    if (!aperture)
        return s;
    /* A table exists only with an aperture image. */
    const ddof_highlight_shape d = ddof_highlight_shape_of(
        aperture->blades, aperture->rotation_rad, aperture->catseye, aperture->centre_x,
        aperture->centre_y, aperture->half_width, aperture->half_height, sums != NULL,
        aperture->image_width, aperture->image_height, aspect);
    s.sums = sums;
    s.image_width = d.image_width;
    s.image_height = d.image_height;
    s.catseye = d.catseye;
    s.centre_x = d.centre_x;
    s.centre_y = d.centre_y;
    s.inv_half_width = d.inv_half_width;
    s.inv_half_height = d.inv_half_height;
    s.sides = d.sides;
    for (uint32_t k = 0; k < d.sides; k++) {
        s.normal[k][0] = d.normal[2 * k];
        s.normal[k][1] = d.normal[2 * k + 1];
    }
    s.apothem = d.apothem;
    return s;
}

/* The signed distance of a highlight's point (dx, v) (image axes: v down, in the shape's units)
 * from the polygon's edge, the aperture's axes having y up, turned by 180 degrees for a near
 * highlight; in pixels when `pixels` (rows stretched by the aspect), else in the shape's units. */
static float polygon_distance(const aperture_shape *s, const highlight *h, float dx, float v,
                              int pixels)
{
    const float sign = h->coc < 0.0f ? -1.0f : 1.0f;
    const float px = sign * dx, py = -sign * v;
    float far = -INFINITY;
    uint32_t edge = 0;
    for (uint32_t k = 0; k < s->sides; k++) {
        const float d = px * s->normal[k][0] + py * s->normal[k][1];
        if (d > far) {
            far = d;
            edge = k;
        }
    }
    const float units = far - s->apothem * radius_of(h);
    if (!pixels)
        return units;
    const float ny = s->normal[edge][1] / s->aspect;
    return units / sqrtf(s->normal[edge][0] * s->normal[edge][0] + ny * ny);
}

/* Columns dx of the row where the polygon's signed distance is at most t: [*lo, *hi] (real
 * numbers), empty when *lo > *hi. Each edge bounds dx on one side (or the whole row). */
static void polygon_span(const aperture_shape *s, const highlight *h, float v, float t, float *lo,
                         float *hi)
{
    const float sign = h->coc < 0.0f ? -1.0f : 1.0f;
    const float limit = s->apothem * radius_of(h) + t;
    *lo = -INFINITY;
    *hi = INFINITY;
    for (uint32_t k = 0; k < s->sides; k++) {
        const float c = sign * s->normal[k][0];
        const float e = limit + sign * v * s->normal[k][1];
        if (c > 1e-6f)
            *hi = ddof_minf(*hi, e / c);
        else if (c < -1e-6f)
            *lo = ddof_maxf(*lo, e / c);
        else if (e < 0.0f)
            *lo = INFINITY;
    }
}

/* The cat's eye clip circle's centre for a highlight, in shape units from its centre: toward
 * the frame's centre by catseye x radius x the highlight's distance from it (1 at a corner).
 * 0 when there is no clip (off, or a highlight at the centre). */
static int clip_offset(const aperture_shape *s, const highlight *h, float *x, float *y)
{
    if (s->catseye <= 0.0)
        return 0;
    const double px = h->x + 0.5 - s->centre_x, py = h->y + 0.5 - s->centre_y;
    const double a = px * s->inv_half_width, b = py * s->inv_half_height;
    const double reach = sqrt(0.5 * (a * a + b * b)); /* 1 at the corners */
    const double ux = -px, uy = -py / s->aspect, length = sqrt(ux * ux + uy * uy);
    if (!(length > 0.0))
        return 0;
    const double shift = s->catseye * fmin(reach, 1.0) * radius_of(h) / length;
    *x = (float)(ux * shift);
    *y = (float)(uy * shift);
    return 1;
}

/* The row's spans clipped by the cat's eye circle (radius R + margin for the rim's end,
 * R - margin for the interior); 0 when nothing of the row is left. */
static int clip_row(const highlight *h, float margin, aperture_row *row)
{
    const float dv = row->v - row->clip_y, dv2 = dv * dv;
    const float outer_r = radius_of(h) + margin, inner_r = radius_of(h) - margin;
    if (dv2 >= outer_r * outer_r)
        return 0;
    const float reach = sqrtf(outer_r * outer_r - dv2);
    const int lo = (int)floorf(row->clip_x - reach), hi = (int)ceilf(row->clip_x + reach);
    row->outer_l = row->outer_l > lo ? row->outer_l : lo;
    row->outer_r = row->outer_r < hi ? row->outer_r : hi;
    if (row->outer_l > row->outer_r)
        return 0;
    if (row->inner_l <= row->inner_r && inner_r > 0.0f && dv2 <= inner_r * inner_r) {
        const float in = sqrtf(inner_r * inner_r - dv2);
        const int a = (int)ceilf(row->clip_x - in), b = (int)floorf(row->clip_x + in);
        row->inner_l = row->inner_l > a ? row->inner_l : a;
        row->inner_r = row->inner_r < b ? row->inner_r : b;
    } else {
        row->inner_l = 1;
        row->inner_r = -1;
    }
    if (row->inner_l > row->inner_r) { /* no interior left: walk the rim from the middle */
        const int c = (row->outer_l + row->outer_r) / 2;
        row->inner_l = c + 1;
        row->inner_r = c - 1;
    }
    return 1;
}

/* The row of the shape itself (disc or polygon), before any clip. */
static int shape_row_at(const aperture_shape *s, const highlight *h, int dy, aperture_row *row)
{
    const float aspect = s->aspect, margin = rim_margin(aspect);
    const float outer_r = radius_of(h) + margin, inner_r = outer_r - 2.0f * margin;
    const float v = (float)dy / aspect, v2 = v * v;
    if (v2 >= outer_r * outer_r)
        return 0;
    row->v = v;
    row->v2 = v2;
    /* Columns past the disc's half a pixel hold no weight (the rows' margin may be wider). */
    const int reach = (int)ceilf(radius_of(h) + 0.5f);
    if (s->sums) { /* the image's square: every pixel weighed, from the middle out */
        row->outer_l = -reach;
        row->outer_r = reach;
        row->inner_l = 1;
        row->inner_r = -1;
        return 1;
    }
    if (!s->sides) {
        int outer = (int)ceilf(sqrtf(outer_r * outer_r - v2));
        outer = outer > reach ? reach : outer;
        const int inner = inner_r > 0.0f && v2 <= inner_r * inner_r
                              ? (int)floorf(sqrtf(inner_r * inner_r - v2))
                              : -1;
        row->outer_l = -outer;
        row->outer_r = outer;
        row->inner_l = inner >= 0 ? -inner : 1;
        row->inner_r = inner >= 0 ? inner : -1;
        return 1;
    }
    float lo, hi, in_lo, in_hi;
    polygon_span(s, h, v, margin, &lo, &hi);
    if (!(lo < hi))
        return 0;
    row->outer_l = lo < (float)-reach ? -reach : (int)floorf(lo);
    row->outer_r = hi > (float)reach ? reach : (int)ceilf(hi);
    polygon_span(s, h, v, -margin, &in_lo, &in_hi);
    if (in_lo <= in_hi && ceilf(in_lo) <= floorf(in_hi)) {
        row->inner_l = (int)ceilf(in_lo);
        row->inner_r = (int)floorf(in_hi);
    } else { /* no interior: the rim is walked from the row's middle */
        const int middle = (int)lrintf(0.5f * (lo + hi));
        const int c = middle < row->outer_l ? row->outer_l
                                            : middle > row->outer_r ? row->outer_r : middle;
        row->inner_l = c + 1;
        row->inner_r = c - 1;
    }
    return 1;
}

/* A row of the highlight's shape, clipped by the cat's eye when there is one. */
int aperture_row_at(const aperture_shape *s, const highlight *h, int dy, aperture_row *row)
{
    if (!shape_row_at(s, h, dy, row))
        return 0;
    row->clipped = clip_offset(s, h, &row->clip_x, &row->clip_y);
    return !row->clipped || clip_row(h, rim_margin(s->aspect), row);
}

/* 0.5 - the signed distance in pixels of shape point (u, v) from a circle of radius r about
 * the shape's centre, with rows stretched by the aspect. */
static float circle_weight(float aspect, float r, float u, float v)
{
    const float u2 = u * u, v2 = v * v, d = sqrtf(u2 + v2);
    if (aspect == 1.0f)
        return r + 0.5f - d;
    const float grad = d > 0.0f ? sqrtf(u2 + v2 / (aspect * aspect)) / d : 1.0f;
    return 0.5f - (d - r) / grad;
}

/* The integral of the (scaled) aperture image over [0, x] x [0, y] texels, clamped to it:
 * exact for piecewise-constant texels, as the bilinear blend of the table's corners. */
static double image_integral(const aperture_shape *s, double x, double y)
{
    const uint32_t w = s->image_width, h = s->image_height;
    x = x < 0.0 ? 0.0 : x > w ? w : x;
    y = y < 0.0 ? 0.0 : y > h ? h : y;
    uint32_t i = (uint32_t)x, j = (uint32_t)y;
    i = i >= w ? w - 1 : i;
    j = j >= h ? h - 1 : j;
    const double fx = x - i, fy = y - j;
    const double *s00 = s->sums + (size_t)j * (w + 1) + i, *s01 = s00 + (w + 1);
    return (1 - fy) * ((1 - fx) * s00[0] + fx * s00[1]) + fy * ((1 - fx) * s01[0] + fx * s01[1]);
}

/* The aperture image's average over pixel (dx, row)'s footprint: the image spans the square
 * of the CoC (shape units -R..R both ways, row 0 at the top), turned by 180 degrees for a near
 * highlight. */
static float image_weight(const aperture_shape *s, const highlight *h, const aperture_row *row,
                          int dx)
{
    const double r = radius_of(h), half_v = 0.5 / s->aspect;
    const double sx = s->image_width / (2.0 * r), sy = s->image_height / (2.0 * r);
    double x0 = (dx - 0.5 + r) * sx, x1 = (dx + 0.5 + r) * sx;
    double y0 = (row->v - half_v + r) * sy, y1 = (row->v + half_v + r) * sy;
    if (h->coc < 0.0f) { /* near: the image turned by 180 degrees */
        const double fx0 = s->image_width - x1, fy0 = s->image_height - y1;
        x1 = s->image_width - x0;
        y1 = s->image_height - y0;
        x0 = fx0;
        y0 = fy0;
    }
    const double sum = image_integral(s, x1, y1) - image_integral(s, x0, y1) -
                       image_integral(s, x1, y0) + image_integral(s, x0, y0);
    return (float)(sum / ((x1 - x0) * (y1 - y0)));
}

/* clamp(0.5 - the pixel's signed distance from the shape's edge, 0, 1). With rows stretched by
 * the aspect the distance in the shape's units is divided by its gradient's length in pixels. */
float aperture_rim_weight(const aperture_shape *s, const highlight *h, const aperture_row *row,
                          int dx)
{
    float w;
    if (s->sums)
        w = image_weight(s, h, row, dx);
    else if (s->sides)
        w = 0.5f - polygon_distance(s, h, (float)dx, row->v, s->aspect != 1.0f);
    else
        w = circle_weight(s->aspect, radius_of(h), (float)dx, row->v);
    if (row->clipped)
        w = ddof_minf(w, circle_weight(s->aspect, radius_of(h), (float)dx - row->clip_x,
                                       row->v - row->clip_y));
    return w <= 0.0f ? 0.0f : w >= 1.0f ? 1.0f : w;
}
