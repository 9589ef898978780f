/* SPDX-License-Identifier: MIT */
/* highlights.c - the highlight pass (highlights.h): find, take out, scatter as discs. */
#include "highlights.h"

#include "parallel_rows.h"

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Brightness classes, a quarter octave each: a highlight of brightness L is in class
 * floor(4 log2(L / threshold)), so raising the threshold by 2^(k/4) drops the classes below k. */
#define CLASSES_PER_OCTAVE 4
#define CLASSES 128

typedef struct class_count {
    uint32_t count[CLASSES];
    double cost[CLASSES];
} class_count;

typedef struct find_job {
    const adi_request *r;
    float threshold; /* the user's                                  */
    uint32_t first_class;  /* the classes kept (after the budget)   */
    int coc_signed;
    int area_cost;         /* an aperture image: a highlight costs its area */
    class_count *counts;   /* per chunk                               */
    uint32_t *offsets;     /* per chunk: where its highlights go      */
    highlight *items;
    float *base;
} find_job;

static float coc_at(const adi_request *r, uint32_t x, uint32_t y)
{
    return r->coc[(size_t)y * r->coc_stride + (size_t)x * r->coc_channels];
}

static float brightness(const float *px)
{
    return ddof_highlight_brightness(px);
}

/* The CoC a highlight's light is drawn with: that of the brightest pixel of its 3 x 3
 * neighbourhood (itself on a tie). A pinhole render's depth is not anti-aliased: the rim pixels
 * of a small bright object carry much of its light (coverage times its brightness) but the
 * depth of what lies behind it, and drawn with that CoC they ring the object's disc with a
 * halo of the background's size (the highlights scene's near lights; an in-focus light gets a
 * blurred ring). Their light is the object's, so it goes with the object's CoC. */
static float highlight_coc(const adi_request *r, uint32_t x, uint32_t y)
{
    const uint32_t x0 = x > 0 ? x - 1 : 0, x1 = x + 1 < r->width ? x + 1 : x;
    const uint32_t y0 = y > 0 ? y - 1 : 0, y1 = y + 1 < r->height ? y + 1 : y;
    uint32_t bx = x, by = y;
    float best = brightness(r->color + (size_t)y * r->color_stride + (size_t)x * r->channels);
    for (uint32_t v = y0; v <= y1; v++)
        for (uint32_t u = x0; u <= x1; u++) {
            const float l = brightness(r->color + (size_t)v * r->color_stride +
                                       (size_t)u * r->channels);
            if (l > best) {
                best = l;
                bx = u;
                by = v;
            }
        }
    return coc_at(r, bx, by);
}

/* What drawing a disc of this CoC costs, in pixel operations: its rows, and its rim pixels
 * (about twice its circumference) for the weights and the scatter; an aperture image's every
 * pixel (`area`). */
static double disc_cost(float coc, float aspect, int area)
{
    const double r = 0.5 * fabs((double)coc) + 0.5;
    if (area)
        return 2.0 * (2.0 * r + 1.0) * (2.0 * r * (double)aspect + 1.0);
    return 2.0 * r * (double)aspect + 1.0 + 4.0 * 3.14159265358979 * r;
}

/* The class of pixel (x, y) of colour px, or -1 when it is no highlight; *coc gets the CoC its
 * light is drawn with. */
static int highlight_class(const find_job *job, const float *px, uint32_t x, uint32_t y,
                           float *coc)
{
    const float l = brightness(px);
    /* Its own CoC too: a pixel the diffusion leaves in focus is never taken from. */
    if (!ddof_is_highlight(l, coc_at(job->r, x, y), job->threshold))
        return -1;
    *coc = highlight_coc(job->r, x, y);
    if (!(fabsf(*coc) >= DDOF_HIGHLIGHT_MIN_COC_PX))
        return -1;
    /* Over a tiny threshold l / threshold overflows to +inf: the top class, decided before
     * any conversion to int (undefined for inf; libFuzzer found it under UBSan). */
    const float octaves = CLASSES_PER_OCTAVE * log2f(l / job->threshold);
    if (!(octaves < (float)CLASSES))
        return CLASSES - 1;
    const int k = (int)floorf(octaves);
    return k < 0 ? 0 : k;
}

static void count_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    const find_job *job = user;
    const adi_request *r = job->r;
    class_count *c = &job->counts[chunk];
    memset(c, 0, sizeof *c);
    for (uint32_t y = y0; y < y1; y++) {
        const float *row = r->color + (size_t)y * r->color_stride;
        for (uint32_t x = 0; x < r->width; x++) {
            float coc;
            const int k = highlight_class(job, row + (size_t)x * r->channels, x, y, &coc);
            if (k >= 0) {
                c->count[k]++;
                c->cost[k] += disc_cost(coc, r->pixel_aspect, job->area_cost);
            }
        }
    }
}

/* Writes the chunk's highlights (in row order) and its rows of base. */
static void fill_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    const find_job *job = user;
    const adi_request *r = job->r;
    const float kept = job->threshold * exp2f((float)job->first_class / CLASSES_PER_OCTAVE);
    highlight *item = job->items + job->offsets[chunk];
    for (uint32_t y = y0; y < y1; y++) {
        const float *row = r->color + (size_t)y * r->color_stride;
        float *out = job->base + (size_t)y * r->width * r->channels;
        memcpy(out, row, (size_t)r->width * r->channels * sizeof *out);
        for (uint32_t x = 0; x < r->width; x++) {
            float *px = out + (size_t)x * r->channels;
            float coc;
            const int k = highlight_class(job, px, x, y, &coc);
            if (k < (int)job->first_class)
                continue;
            /* The part above the kept threshold, hue kept: px * (1 - t / L). */
            const float keep = kept / brightness(px);
            *item = (highlight){.x = x, .y = y, .coc = coc};
            for (int c = 0; c < 3; c++) {
                item->excess[c] = px[c] * (1.0f - keep);
                px[c] -= item->excess[c];
            }
            item++;
        }
    }
}

/* ---- the scatter --------------------------------------------------------------------------
 *
 * A disc costs its rows, not its area: each row of it is an interior span of weight 1, added to
 * a difference image as +v at its start and -v past its end, plus its anti-aliased rim pixels
 * one by one; a running sum along each row then turns the differences into values. Where the
 * light may land is a property of the pixel and of the highlight's size, so the highlights are
 * drawn in classes of one octave of |CoC| (and one class for the near field), each with one
 * rule for the whole class: a far highlight's class lands on pixels whose signed CoC is at
 * least half its smallest |CoC| (never on in-focus or nearer pixels); the near class lands
 * everywhere. Each disc's weights are renormalised over the pixels it lands on, counted from
 * per-row prefix counts of the class's rule, so its light is kept. */

#define SIZE_CLASSES 20 /* octaves of |CoC| from the minimum; the last one is open */
#define NEAR_CLASS SIZE_CLASSES

static int size_class(float coc, int coc_signed)
{
    if (coc_signed && coc < 0.0f)
        return NEAR_CLASS;
    const int k = (int)floorf(log2f(fabsf(coc) / DDOF_HIGHLIGHT_MIN_COC_PX));
    return k < 0 ? 0 : k >= SIZE_CLASSES ? SIZE_CLASSES - 1 : k;
}

/* The signed CoC a pixel needs to receive a class's light (NEAR_CLASS: any). */
static float landing_threshold(int size)
{
    return size == NEAR_CLASS ? -INFINITY
                              : 0.5f * DDOF_HIGHLIGHT_MIN_COC_PX * exp2f((float)size);
}

static int lands(const adi_request *r, int coc_signed, float threshold, uint32_t x, uint32_t y)
{
    const float c = coc_at(r, x, y);
    return (coc_signed ? c : fabsf(c)) >= threshold;
}

static float radius_of(const highlight *h)
{
    return 0.5f * fabsf(h->coc);
}

/* The rim's reach beyond the shape's edge in the shape's axes (rows scaled by 1 / aspect): half
 * a pixel, which is more than half a unit vertically when rows are squeezed (aspect < 1). */
static float rim_margin(float aspect)
{
    return aspect >= 1.0f ? 0.5f : 0.5f / aspect;
}

/* Rows of a disc above and below its centre (the pixel aspect stretches it vertically). */
static int half_height(const highlight *h, float aspect)
{
    return (int)ceilf((radius_of(h) + rim_margin(aspect)) * aspect);
}

/* One row of a highlight's shape, in columns dx from its centre: [inner_l, inner_r] has weight
 * 1 (empty when inner_l > inner_r), the rim pixels around it up to [outer_l, outer_r] are
 * anti-aliased, clamp(0.5 - signed distance to the shape's edge, 0, 1). The rim is walked
 * outward from the interior, left before right (rim_column), so a disc's pixels are visited
 * and summed in one order whatever the shape code. */
typedef struct disc_row {
    int inner_l, inner_r, outer_l, outer_r;
    float v;  /* the row's vertical offset in horizontal pixels (down the image) */
    float v2; /* v squared                                                         */
    int clipped;    /* the cat's eye: the shape clipped by a circle of its radius at */
    float clip_x, clip_y; /* (clip_x, clip_y) from its centre (shape units)         */
} disc_row;

/* The aperture as the scatter draws it: a disc, or a regular polygon inscribed in the disc,
 * whose edge normals point at rotation + 2 pi k / blades (Cycles' polygon: at rotation 0 an
 * edge's middle lies on the +x axis, y up). A far highlight (CoC >= 0) is the aperture as the
 * lens' rays cross the focus plane, upright; a near one is turned by 180 degrees. */
typedef struct shape {
    float aspect;                       /* rows per unit of the shape's y (>= 1: rows stretched) */
    uint32_t sides;                     /* 0: a disc                              */
    float normal[DDOF_MAX_APERTURE_BLADES][2];
    float apothem;                      /* the inscribed polygon's, per unit radius */
    double catseye;                     /* highlight_aperture's; 0: no clip       */
    double centre_x, centre_y, inv_half_width, inv_half_height;
    const double *sums;                 /* an aperture image's table (NULL: none) */
    uint32_t image_width, image_height;
} shape;

static shape shape_of(const highlight_aperture *aperture, const double *sums, float aspect)
{
    shape s = {.aspect = aspect};
    if (!aperture)
        return s;
    if (aperture->image && sums) {
        s.sums = sums;
        s.image_width = aperture->image_width;
        s.image_height = aperture->image_height;
    }
    if (aperture->catseye > 0.0 && aperture->half_width > 0.0 && aperture->half_height > 0.0) {
        s.catseye = aperture->catseye;
        s.centre_x = aperture->centre_x;
        s.centre_y = aperture->centre_y;
        s.inv_half_width = 1.0 / aperture->half_width;
        s.inv_half_height = 1.0 / aperture->half_height;
    }
    if (aperture->blades < 3 || s.sums)
        return s;
    s.sides = aperture->blades;
    const double step = 2.0 * 3.14159265358979323846 / s.sides;
    for (uint32_t k = 0; k < s.sides; k++) {
        s.normal[k][0] = (float)cos(aperture->rotation_rad + step * k);
        s.normal[k][1] = (float)sin(aperture->rotation_rad + step * k);
    }
    s.apothem = (float)cos(0.5 * step);
    return s;
}

/* The signed distance of a highlight's point (dx, v) (image axes: v down, in the shape's units)
 * from the polygon's edge, the aperture's axes having y up, turned by 180 degrees for a near
 * highlight; in pixels when `pixels` (rows stretched by the aspect), else in the shape's units. */
static float polygon_distance(const shape *s, const highlight *h, float dx, float v, int pixels)
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
static void polygon_span(const shape *s, const highlight *h, float v, float t, float *lo,
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
static int clip_offset(const shape *s, const highlight *h, float *x, float *y)
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
static int clip_row(const highlight *h, float margin, disc_row *row)
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
static int shape_row_at(const shape *s, const highlight *h, float aspect, int dy, disc_row *row)
{
    const float margin = rim_margin(aspect);
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

/* clamp(0.5 - the pixel's signed distance from the shape's edge, 0, 1). With rows stretched by
 * the aspect the distance in the shape's units is divided by its gradient's length in pixels. */
/* A row of the highlight's shape, clipped by the cat's eye when there is one. */
static int disc_row_at(const shape *s, const highlight *h, float aspect, int dy, disc_row *row)
{
    if (!shape_row_at(s, h, aspect, dy, row))
        return 0;
    row->clipped = clip_offset(s, h, &row->clip_x, &row->clip_y);
    return !row->clipped || clip_row(h, rim_margin(aspect), row);
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
static double image_integral(const shape *s, double x, double y)
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
static float image_weight(const shape *s, const highlight *h, const disc_row *row, int dx)
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

static float rim_weight(const shape *s, const highlight *h, const disc_row *row, int dx)
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

/* The k-th rim column (k >= 1) on `side` (-1 left, 1 right), or INT_MIN when there is none
 * there: left columns inner_l - k down to outer_l, right ones inner_r + k up to outer_r, a
 * row without interior starting with its middle column once. */
static int rim_column(const disc_row *row, int k, int side)
{
    const int x = side < 0 ? row->inner_l - k : row->inner_r + k;
    if (side > 0 && x == row->inner_l - k)
        return INT_MIN; /* the middle column of a row without interior, once */
    return (side < 0 ? x >= row->outer_l : x <= row->outer_r) ? x : INT_MIN;
}

/* Rim columns to walk on either side. */
static int rim_steps(const disc_row *row)
{
    const int left = row->inner_l - row->outer_l, right = row->outer_r - row->inner_r;
    return left > right ? left : right;
}

typedef struct scatter_job {
    const adi_request *r;
    shape shape;
    int coc_signed;
    const highlight *items; /* of one size class, in row order                           */
    uint32_t count;
    float threshold;        /* the class's landing threshold                             */
    int reach_rows;         /* the class's largest half height                           */
    int bx0, bx1, by0, by1; /* the box its discs cover (end exclusive): the passes' area    */
    uint32_t *landing;      /* per box row: prefix counts of the pixels the class lands on  */
    float *weights;         /* per item: 1 / its weights' sum over the pixels it lands on */
    float *diff;            /* W x H x 3: the difference image                           */
} scatter_job;

/* The landing counts of a box row: count[i] = pixels the class lands on in [bx0, bx0 + i). */
static const uint32_t *landing_row(const scatter_job *job, int y)
{
    return job->landing + (size_t)(y - job->by0) * (size_t)(job->bx1 - job->bx0 + 1);
}

static void landing_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const scatter_job *job = user;
    const adi_request *r = job->r;
    for (uint32_t yy = y0; yy < y1; yy++) {
        const int y = job->by0 + (int)yy;
        uint32_t *count = (uint32_t *)landing_row(job, y);
        count[0] = 0;
        for (int x = job->bx0; x < job->bx1; x++)
            count[x - job->bx0 + 1] =
                count[x - job->bx0] +
                (uint32_t)lands(r, job->coc_signed, job->threshold, (uint32_t)x, (uint32_t)y);
    }
}

/* The interior span of a disc row, clipped to the image: [*a, *b], empty when *a > *b. */
static void interior_span(const adi_request *r, const highlight *h, const disc_row *row, int *a,
                          int *b)
{
    *a = (int)h->x + row->inner_l < 0 ? 0 : (int)h->x + row->inner_l;
    *b = (int)h->x + row->inner_r >= (int)r->width ? (int)r->width - 1
                                                    : (int)h->x + row->inner_r;
}

/* Rim column dx of a row: *x its image column, 0 when it is outside the image or has no
 * weight. */
static int rim_pixel(const scatter_job *job, const highlight *h, const disc_row *row, int dx,
                     int *x, float *w)
{
    *w = rim_weight(&job->shape, h, row, dx);
    *x = (int)h->x + dx;
    return *w > 0.0f && *x >= 0 && *x < (int)job->r->width;
}

static void weigh_items(void *user, uint32_t i0, uint32_t i1, uint32_t chunk)
{
    (void)chunk;
    const scatter_job *job = user;
    const adi_request *r = job->r;
    for (uint32_t i = i0; i < i1; i++) {
        const highlight *h = &job->items[i];
        const int reach = half_height(h, r->pixel_aspect);
        double sum = 0.0;
        for (int dy = -reach; dy <= reach; dy++) {
            const int y = (int)h->y + dy;
            disc_row row;
            if (y < 0 || y >= (int)r->height ||
                !disc_row_at(&job->shape, h, r->pixel_aspect, dy, &row))
                continue;
            if (row.inner_l <= row.inner_r) {
                int a, b;
                interior_span(r, h, &row, &a, &b);
                const uint32_t *count = landing_row(job, y);
                if (a <= b)
                    sum += h->hidden ? (double)(b + 1 - a)
                                     : (double)(count[b + 1 - job->bx0] - count[a - job->bx0]);
            }
            const int steps = rim_steps(&row);
            for (int k = 1; k <= steps; k++)
                for (int side = -1; side <= 1; side += 2) {
                    const int dx = rim_column(&row, k, side);
                    int x;
                    float w;
                    if (dx != INT_MIN && rim_pixel(job, h, &row, dx, &x, &w) &&
                        (h->hidden ||
                         lands(r, job->coc_signed, job->threshold, (uint32_t)x, (uint32_t)y)))
                        sum += w;
                }
        }
        /* The centre always lands (its own CoC passes its class's rule), so sum > 0; a hidden
         * part's disc counts every pixel of the frame it covers. */
        job->weights[i] = sum > 0.0 ? (float)(1.0 / sum) : 0.0f;
    }
}

/* +v at x, -v at x + 1 (when that is still in the box, whose running sum ends there). */
static void add_diff(float *row, int end, int x, const float v[3])
{
    for (int c = 0; c < 3; c++)
        row[(size_t)x * 3 + c] += v[c];
    if (x + 1 < end)
        for (int c = 0; c < 3; c++)
            row[(size_t)(x + 1) * 3 + c] -= v[c];
}

/* The output rows [y0, y1): the class's discs that reach them, into the difference image, then
 * summed along each row and added where the class lands. */
static void scatter_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const scatter_job *job = user;
    const adi_request *r = job->r;
    const size_t row_floats = (size_t)r->width * 3;
    /* Box rows [y0, y1) of the call are image rows [by0 + y0, by0 + y1). */
    y0 += (uint32_t)job->by0;
    y1 += (uint32_t)job->by0;
    for (uint32_t y = y0; y < y1; y++)
        memset(job->diff + (size_t)y * row_floats + (size_t)job->bx0 * 3, 0,
               (size_t)(job->bx1 - job->bx0) * 3 * sizeof(float));
    /* The items are in row order: skip to the first whose disc may reach y0. */
    uint32_t lo = 0, hi = job->count;
    while (lo < hi) {
        const uint32_t mid = lo + (hi - lo) / 2;
        if ((int)job->items[mid].y + job->reach_rows < (int)y0)
            lo = mid + 1;
        else
            hi = mid;
    }
    for (uint32_t i = lo; i < job->count && (int)job->items[i].y - job->reach_rows < (int)y1;
         i++) {
        const highlight *h = &job->items[i];
        const float k = job->weights[i];
        const float e[3] = {h->excess[0] * k, h->excess[1] * k, h->excess[2] * k};
        const int reach = half_height(h, r->pixel_aspect);
        for (int dy = -reach; dy <= reach; dy++) {
            const int y = (int)h->y + dy;
            disc_row row;
            if (y < (int)y0 || y >= (int)y1 ||
                !disc_row_at(&job->shape, h, r->pixel_aspect, dy, &row))
                continue;
            float *d = job->diff + (size_t)y * row_floats;
            if (row.inner_l <= row.inner_r) {
                int a, b;
                interior_span(r, h, &row, &a, &b);
                if (a <= b)
                    for (int c = 0; c < 3; c++) {
                        d[(size_t)a * 3 + c] += e[c];
                        if (b + 1 < job->bx1)
                            d[(size_t)(b + 1) * 3 + c] -= e[c];
                    }
            }
            const int steps = rim_steps(&row);
            for (int k = 1; k <= steps; k++)
                for (int side = -1; side <= 1; side += 2) {
                    const int dx = rim_column(&row, k, side);
                    int x;
                    float w;
                    if (dx != INT_MIN && rim_pixel(job, h, &row, dx, &x, &w)) {
                        const float v[3] = {e[0] * w, e[1] * w, e[2] * w};
                        add_diff(d, job->bx1, x, v);
                    }
                }
        }
    }
    for (uint32_t y = y0; y < y1; y++) {
        const float *d = job->diff + (size_t)y * row_floats;
        float *out = r->out + (size_t)y * r->out_stride;
        double sum[3] = {0.0, 0.0, 0.0};
        for (uint32_t x = (uint32_t)job->bx0; x < (uint32_t)job->bx1; x++) {
            for (int c = 0; c < 3; c++)
                sum[c] += d[(size_t)x * 3 + c];
            if (lands(r, job->coc_signed, job->threshold, x, y))
                for (int c = 0; c < 3; c++) {
                    /* In double and kept within float's range: colour near -FLT_MAX (valid
                     * input) diffuses to near -FLT_MAX, and its light's share on top of that
                     * would overflow to -inf. */
                    float *o = &out[(size_t)x * r->channels + c];
                    const double v = (double)*o + sum[c];
                    *o = (float)(v > FLT_MAX ? FLT_MAX : v < -FLT_MAX ? -FLT_MAX : v);
                }
        }
    }
}

/* The aperture image's summed-area table, scaled so that its largest texel is 1: sums[j][i]
 * holds the texels of rows < j and columns < i. */
static const double *aperture_sums(ddof_context *context, const highlight_aperture *a)
{
    const uint32_t w = a->image_width, h = a->image_height;
    double *sums = ddof_scratch_get(context, DDOF_SCRATCH_APERTURE_SUMS,
                                    (size_t)(w + 1) * (h + 1) * sizeof *sums);
    if (!sums)
        return NULL;
    float peak = 0.0f;
    for (uint32_t i = 0; i < w * h; i++)
        peak = ddof_maxf(peak, a->image[i]);
    memset(sums, 0, (size_t)(w + 1) * sizeof *sums);
    for (uint32_t j = 0; j < h; j++) {
        double run = 0.0;
        double *above = sums + (size_t)j * (w + 1), *here = above + (w + 1);
        here[0] = 0.0;
        for (uint32_t i = 0; i < w; i++) {
            run += (double)a->image[(size_t)j * w + i] / peak;
            here[i + 1] = above[i + 1] + run;
        }
    }
    return sums;
}

/* ---- the parts hidden by sharp occluders --------------------------------------------------
 *
 * A thin sharp occluder (a bar, a strand, a wire: |CoC| < DDOF_HIGHLIGHT_SHARP_PX) in front of
 * a far highlight hides part of it from the pinhole, but the lens sees the whole disc around
 * the occluder. The occluder's pixels are the background layer's holes, and the hidden part is
 * filled across them as the layers fill a hole: along the row, the column and both diagonals
 * from each of the highlight's visible pixels that borders the occluder, over a run of occluder
 * pixels no longer than the highlight's radius, to the first pixel past it, which must be a
 * pixel the highlight's disc lands on (else what lies behind is unknown); each run's pixels get
 * the linear mix of the two ends' excess (a far end that is no highlight has none: only rows
 * and columns may end there, a diagonal from a highlight's corner would grow it), weighted
 * by 1 / the run's length squared, so the shorter runs, the ones across the occluder, dominate.
 * Each occluder pixel that got some becomes a highlight of its own (the mixed excess and CoC),
 * drawn after the visible ones within what is left of the budget, in row order: its disc lands
 * like any far disc only on pixels at least half as blurred, around the occluder, never on it.
 * A run between two highlights is walked once, forward (the first four directions). */

#define HIDDEN_DIRECTIONS 8
static const int hidden_step[HIDDEN_DIRECTIONS][2] = {{1, 0}, {0, 1},  {1, 1},  {-1, 1},
                                                      {-1, 0}, {0, -1}, {-1, -1}, {1, -1}};

typedef struct hidden_entry {
    uint32_t x, y, order; /* order: the entries' own, for a sort that is a total order */
    float w, coc;         /* the run's weight, and w times the mixed CoC                */
    float excess[3];      /* w times the mixed excess                                   */
} hidden_entry;

static int is_sharp(const adi_request *r, int x, int y)
{
    return fabsf(coc_at(r, (uint32_t)x, (uint32_t)y)) < DDOF_HIGHLIGHT_SHARP_PX;
}

/* The excess and CoC of pixel (x, y) when it is a kept far highlight; 0 when it is none. */
static int kept_highlight(const find_job *job, uint32_t x, uint32_t y, float excess[3],
                          float *coc)
{
    const adi_request *r = job->r;
    const float *px = r->color + (size_t)y * r->color_stride + (size_t)x * r->channels;
    const int k = highlight_class(job, px, x, y, coc);
    if (k < (int)job->first_class || (job->coc_signed && *coc < 0.0f))
        return 0;
    /* fill_rows' split, on the same values */
    const float keep =
        job->threshold * exp2f((float)job->first_class / CLASSES_PER_OCTAVE) / brightness(px);
    for (int c = 0; c < 3; c++)
        excess[c] = px[c] * (1.0f - keep);
    return 1;
}

/* How many kept highlight pixels lie in a line from h (itself included) in direction d, up to
 * `limit`. */
static int visible_width(const find_job *job, const highlight *h, int d, int limit)
{
    const adi_request *r = job->r;
    int x = (int)h->x, y = (int)h->y, m = 1;
    for (; m < limit; m++) {
        x += hidden_step[d][0];
        y += hidden_step[d][1];
        float e[3], coc;
        if (x < 0 || y < 0 || x >= (int)r->width || y >= (int)r->height ||
            !kept_highlight(job, (uint32_t)x, (uint32_t)y, e, &coc))
            break;
    }
    return m;
}

/* The run of sharp pixels from highlight h in direction d: their number (0: no run to fill),
 * the far end's excess and CoC, and *ramp: the run's pixels k < *ramp are filled, with the mix
 * at k / *ramp. Between two highlights the ramp is the run's length + 1; where the far end is
 * none, the highlight reaches behind the occluder at most as far as it shows on its side (its
 * visible width along the line), so the ramp to 0 is no longer than that + 1. */
static int hidden_run(const find_job *job, const highlight *h, int d, float end_excess[3],
                      float *end_coc, int *ramp)
{
    const adi_request *r = job->r;
    if (job->coc_signed && h->coc < 0.0f)
        return 0;
    const float radius = radius_of(h);
    const int limit =
        radius < (float)DDOF_MAX_DIMENSION ? (int)radius : (int)DDOF_MAX_DIMENSION;
    const float landing = landing_threshold(size_class(h->coc, job->coc_signed));
    int x = (int)h->x, y = (int)h->y, n = 0;
    for (;;) {
        x += hidden_step[d][0];
        y += hidden_step[d][1];
        if (x < 0 || y < 0 || x >= (int)r->width || y >= (int)r->height)
            return 0;
        if (!is_sharp(r, x, y))
            break;
        if (++n > limit)
            return 0;
    }
    if (n == 0 || !lands(r, job->coc_signed, landing, (uint32_t)x, (uint32_t)y))
        return 0;
    if (kept_highlight(job, (uint32_t)x, (uint32_t)y, end_excess, end_coc)) {
        if (d >= HIDDEN_DIRECTIONS / 2)
            return 0; /* walked from the other end */
    } else {
        if (hidden_step[d][0] && hidden_step[d][1])
            return 0; /* a diagonal from a highlight's corner would grow it past its rows */
        end_excess[0] = end_excess[1] = end_excess[2] = 0.0f;
        *end_coc = h->coc;
        *ramp = visible_width(job, h, (d + HIDDEN_DIRECTIONS / 2) % HIDDEN_DIRECTIONS, n) + 1;
        return n;
    }
    *ramp = n + 1;
    return n;
}

/* Walks every run of the items; writes its entries when `out` (else only counts them). */
static size_t hidden_entries(const find_job *job, const highlight *items, uint32_t count,
                             hidden_entry *out)
{
    size_t at = 0;
    for (uint32_t i = 0; i < count; i++)
        for (int d = 0; d < HIDDEN_DIRECTIONS; d++) {
            const highlight *h = &items[i];
            float e[3], coc;
            int ramp = 0;
            const int run = hidden_run(job, h, d, e, &coc, &ramp);
            const int n = run < ramp - 1 ? run : ramp - 1;
            if (!out) {
                at += (size_t)(n > 0 ? n : 0);
                continue;
            }
            const float length = (float)(run + 1) * (hidden_step[d][0] && hidden_step[d][1]
                                                        ? 1.41421356f : 1.0f);
            const float w = 1.0f / (length * length);
            for (int k = 1; k <= n; k++, at++) {
                const float t = (float)k / (float)ramp;
                hidden_entry *o = &out[at];
                o->x = (uint32_t)((int)h->x + k * hidden_step[d][0]);
                o->y = (uint32_t)((int)h->y + k * hidden_step[d][1]);
                o->order = (uint32_t)at;
                o->w = w;
                o->coc = w * (h->coc + (coc - h->coc) * t);
                for (int c = 0; c < 3; c++)
                    o->excess[c] = w * (h->excess[c] + (e[c] - h->excess[c]) * t);
            }
        }
    return at;
}

static int entry_order(const void *a, const void *b)
{
    const hidden_entry *p = a, *q = b;
    if (p->y != q->y)
        return p->y < q->y ? -1 : 1;
    if (p->x != q->x)
        return p->x < q->x ? -1 : 1;
    return p->order < q->order ? -1 : p->order > q->order;
}

/* The entries of each pixel merged into one highlight, in row order, as many as the budget
 * left allows (*cost grows by theirs); returns how many. */
static uint32_t merge_entries(const hidden_entry *e, size_t count, float aspect, int area,
                              double budget, double *cost, highlight *out)
{
    uint32_t n = 0;
    for (size_t i = 0; i < count;) {
        double w = 0.0, coc = 0.0, excess[3] = {0.0, 0.0, 0.0};
        size_t j = i;
        for (; j < count && e[j].x == e[i].x && e[j].y == e[i].y; j++) {
            w += e[j].w;
            coc += e[j].coc;
            for (int c = 0; c < 3; c++)
                excess[c] += e[j].excess[c];
        }
        const highlight h = {.x = e[i].x, .y = e[i].y, .coc = (float)(coc / w),
                             .excess = {(float)(excess[0] / w), (float)(excess[1] / w),
                                        (float)(excess[2] / w)},
                             .hidden = 1};
        const double c = disc_cost(h.coc, aspect, area);
        if (*cost + c <= budget) {
            *cost += c;
            out[n++] = h;
        }
        i = j;
    }
    return n;
}

/* Adds the hidden parts of the set's `*kept` items (items: their allocation, which may move)
 * in row order; *kept and *cost grow by them, *hidden says how many. */
static ddof_status add_hidden_parts(ddof_context *context, find_job *job, size_t landing_bytes,
                                    double budget, highlight **items, uint64_t *kept,
                                    double *cost, uint32_t *hidden)
{
    *hidden = 0;
    const uint32_t visible = (uint32_t)*kept;
    const size_t entries = hidden_entries(job, *items, visible, NULL);
    /* A frame with more than that (thin occluders over a quarter of a highlight-covered frame)
     * keeps its memory bounded and draws the visible parts alone. */
    if (!entries || entries > (size_t)job->r->width * job->r->height / 4)
        return DDOF_OK;
    /* The entries, their merged highlights and a copy of the visible ones. */
    hidden_entry *e = ddof_scratch_get(context, DDOF_SCRATCH_HIGHLIGHT_HIDDEN,
                                       entries * sizeof *e +
                                           (entries + visible) * sizeof(highlight));
    if (!e)
        return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                         "could not allocate the highlight pass's %llu hidden parts",
                         (unsigned long long)entries);
    highlight *merged = (highlight *)(e + entries), *copy = merged + entries;
    hidden_entries(job, *items, visible, e);
    qsort(e, entries, sizeof *e, entry_order);
    const uint32_t n = merge_entries(e, entries, job->r->pixel_aspect, job->area_cost, budget,
                                     cost, merged);
    if (!n)
        return DDOF_OK;
    memcpy(copy, *items, visible * sizeof *copy);
    const uint64_t total = (uint64_t)visible + n;
    highlight *all = ddof_scratch_get(context, DDOF_SCRATCH_HIGHLIGHTS,
                                      2 * (size_t)total * sizeof *all +
                                          (size_t)total * sizeof(float) + landing_bytes);
    if (!all)
        return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                         "could not allocate the highlight pass's %llu highlights",
                         (unsigned long long)total);
    /* Both lists are in row order and never share a pixel (a sharp pixel is no highlight). */
    for (uint32_t a = 0, b = 0, o = 0; o < total; o++) {
        const int take_copy =
            b >= n || (a < visible && (copy[a].y < merged[b].y ||
                                       (copy[a].y == merged[b].y && copy[a].x < merged[b].x)));
        all[o] = take_copy ? copy[a++] : merged[b++];
    }
    *items = all;
    *kept = total;
    *hidden = n;
    return DDOF_OK;
}

ddof_status ddof_find_highlights(ddof_context *context, const adi_request *r, float threshold,
                                 int coc_signed, const highlight_aperture *aperture,
                                 int hidden_parts, float *base, highlight_set *set)
{
    memset(set, 0, sizeof *set);
    set->threshold = threshold;
    const int image = aperture && aperture->image;
    const double *sums = image ? aperture_sums(context, aperture) : NULL;
    if (image && !sums)
        return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                         "could not allocate the aperture image's table");
    const uint32_t chunks = ddof_row_chunks(r->height);
    class_count *counts = ddof_scratch_get(context, DDOF_SCRATCH_HIGHLIGHT_COUNTS,
                                           chunks * (sizeof *counts + sizeof(uint32_t)));
    if (!counts)
        return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                         "could not allocate the highlight pass's counts");
    find_job job = {.r = r, .threshold = threshold, .coc_signed = coc_signed,
                    .area_cost = image, .counts = counts,
                    .offsets = (uint32_t *)(counts + chunks), .base = base};
    ddof_parallel_rows(context, r->height, count_rows, &job);

    /* The brightest classes that fit the budget. */
    double cost[CLASSES] = {0};
    uint64_t count[CLASSES] = {0};
    for (uint32_t c = 0; c < chunks; c++)
        for (int k = 0; k < CLASSES; k++) {
            cost[k] += counts[c].cost[k];
            count[k] += counts[c].count[k];
        }
    const double budget = DDOF_HIGHLIGHT_BUDGET * (double)r->width * r->height;
    double kept_cost = 0.0;
    uint64_t kept = 0;
    int first = CLASSES;
    while (first > 0 && kept_cost + cost[first - 1] <= budget) {
        first--;
        kept_cost += cost[first];
        kept += count[first];
    }
    if (kept == 0) {
        /* None fits: say so when there were some (the threshold is then that of the
         * brightest class, which alone is over the budget). */
        for (int k = CLASSES - 1; k >= 0 && !set->over_budget; k--)
            if (count[k]) {
                set->over_budget = 1;
                set->threshold = threshold * exp2f((float)k / CLASSES_PER_OCTAVE);
            }
        return DDOF_OK;
    }
    job.first_class = (uint32_t)first;
    for (uint32_t c = 0, at = 0; c < chunks; c++) {
        job.offsets[c] = at;
        for (int k = first; k < CLASSES; k++)
            at += counts[c].count[k];
    }
    /* The highlights twice (found, then sorted into size classes), their weights, and the
     * per-row landing counts of one size class at a time. */
    const size_t landing_bytes = (size_t)(r->width + 1) * r->height * sizeof(uint32_t);
    highlight *items = ddof_scratch_get(context, DDOF_SCRATCH_HIGHLIGHTS,
                                        2 * (size_t)kept * sizeof *items +
                                            (size_t)kept * sizeof(float) + landing_bytes);
    if (!items)
        return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                         "could not allocate the highlight pass's %llu highlights",
                         (unsigned long long)kept);
    job.items = items;
    ddof_parallel_rows(context, r->height, fill_rows, &job);
    uint32_t hidden = 0;
    if (hidden_parts) {
        const ddof_status status = add_hidden_parts(context, &job, landing_bytes, budget,
                                                    &items, &kept, &kept_cost, &hidden);
        if (status != DDOF_OK)
            return status;
    }
    *set = (highlight_set){items, (uint32_t)kept,
                           threshold * exp2f((float)first / CLASSES_PER_OCTAVE),
                           (uint64_t)kept_cost, 0, (float *)(items + 2 * kept),
                           (uint32_t *)((float *)(items + 2 * kept) + kept), sums, hidden};
    return DDOF_OK;
}

void ddof_scatter_highlights(ddof_context *context, const adi_request *r, int coc_signed,
                             const highlight_aperture *aperture, const highlight_set *set,
                             float *scratch)
{
    if (!set->count)
        return;
    /* Counting sort into size classes; the row order within each class is kept. */
    uint32_t start[SIZE_CLASSES + 2] = {0};
    for (uint32_t i = 0; i < set->count; i++)
        start[size_class(set->items[i].coc, coc_signed) + 1]++;
    for (int k = 0; k <= SIZE_CLASSES; k++)
        start[k + 1] += start[k];
    highlight *sorted = set->items + set->count; /* the second half of the allocation */
    uint32_t at[SIZE_CLASSES + 1];
    memcpy(at, start, sizeof at);
    for (uint32_t i = 0; i < set->count; i++)
        sorted[at[size_class(set->items[i].coc, coc_signed)]++] = set->items[i];

    scatter_job job = {.r = r,
                       .shape = shape_of(aperture, set->aperture_sums, r->pixel_aspect),
                       .coc_signed = coc_signed,
                       .landing = set->landing, .weights = set->weights, .diff = scratch};
    for (int k = 0; k <= SIZE_CLASSES; k++) {
        if (start[k + 1] == start[k])
            continue;
        job.items = sorted + start[k];
        job.count = start[k + 1] - start[k];
        job.threshold = landing_threshold(k);
        job.reach_rows = 0;
        job.bx0 = job.by0 = INT32_MAX;
        job.bx1 = job.by1 = INT32_MIN;
        for (uint32_t i = 0; i < job.count; i++) {
            const highlight *h = &job.items[i];
            const int reach = half_height(h, r->pixel_aspect);
            const int reach_x = (int)ceilf(radius_of(h) + 0.5f) + 1;
            job.reach_rows = reach > job.reach_rows ? reach : job.reach_rows;
            job.bx0 = (int)h->x - reach_x < job.bx0 ? (int)h->x - reach_x : job.bx0;
            job.bx1 = (int)h->x + reach_x + 1 > job.bx1 ? (int)h->x + reach_x + 1 : job.bx1;
            job.by0 = (int)h->y - reach < job.by0 ? (int)h->y - reach : job.by0;
            job.by1 = (int)h->y + reach + 1 > job.by1 ? (int)h->y + reach + 1 : job.by1;
        }
        job.bx0 = job.bx0 < 0 ? 0 : job.bx0;
        job.by0 = job.by0 < 0 ? 0 : job.by0;
        job.bx1 = job.bx1 > (int)r->width ? (int)r->width : job.bx1;
        job.by1 = job.by1 > (int)r->height ? (int)r->height : job.by1;
        const uint32_t rows = (uint32_t)(job.by1 - job.by0);
        ddof_parallel_rows(context, rows, landing_rows, &job);
        ddof_parallel_rows(context, job.count, weigh_items, &job);
        ddof_parallel_rows(context, rows, scatter_rows, &job);
    }
}
