/* SPDX-License-Identifier: MIT */
/* highlights_draw.c - the highlight pass's drawing (highlights.h): each highlight's excess
 * scattered as its disc or the aperture's shape, anti-aliased, over the pixels its light may
 * land on. */
#include "highlights.h"
#include "highlights_classes.h"

#include "runtime/parallel_rows.h"

#include <float.h>
#include <limits.h>
#include <math.h>
#include <string.h>

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
 * per-row prefix counts of the class's rule, so its light is kept; the part of a disc past the
 * frame's edges counts as landing, so the light that falls there leaves the frame. */

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

/* What the k-th rim column on `side` of a row (rim_column) is to the image. */
typedef enum rim_place {
    RIM_NONE,   /* the row has no such column                                 */
    RIM_OFF,    /* weight *w, but 0 or past the frame's left or right edge     */
    RIM_ON      /* image column *x, weight *w > 0                              */
} rim_place;

static rim_place rim_pixel(const scatter_job *job, const highlight *h, const disc_row *row,
                           int k, int side, int *x, float *w)
{
    const int dx = rim_column(row, k, side);
    if (dx == INT_MIN)
        return RIM_NONE;
    *w = rim_weight(&job->shape, h, row, dx);
    *x = (int)h->x + dx;
    return *w > 0.0f && *x >= 0 && *x < (int)job->r->width ? RIM_ON : RIM_OFF;
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
            if (!disc_row_at(&job->shape, h, r->pixel_aspect, dy, &row))
                continue;
            const int row_inside = y >= 0 && y < (int)r->height;
            if (row.inner_l <= row.inner_r) {
                const int whole = row.inner_r + 1 - row.inner_l;
                int a = 0, b = -1;
                if (row_inside)
                    interior_span(r, h, &row, &a, &b);
                /* What lies past the frame's edges counts: the light it gets leaves. */
                sum += (double)(whole - (a <= b ? b + 1 - a : 0));
                if (a <= b) {
                    const uint32_t *count = landing_row(job, y);
                    sum += h->hidden ? (double)(b + 1 - a)
                                     : (double)(count[b + 1 - job->bx0] - count[a - job->bx0]);
                }
            }
            const int steps = rim_steps(&row);
            for (int k = 1; k <= steps; k++)
                for (int side = -1; side <= 1; side += 2) {
                    int x;
                    float w;
                    const rim_place place = rim_pixel(job, h, &row, k, side, &x, &w);
                    if (place == RIM_NONE)
                        continue;
                    if (place == RIM_OFF || !row_inside)
                        sum += w; /* no weight, or past the frame's edges */
                    else if (h->hidden ||
                             lands(r, job->coc_signed, job->threshold, (uint32_t)x, (uint32_t)y))
                        sum += w;
                }
        }
        /* The centre always lands (its own CoC passes its class's rule), so sum > 0; a hidden
         * part's disc counts every pixel of the frame it covers. Past the frame's edges every
         * pixel counts, as the lens's disc goes on there: a light near the edge puts part of
         * its light outside the frame, which the pass does not fold back in. */
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
                    int x;
                    float w;
                    if (rim_pixel(job, h, &row, k, side, &x, &w) == RIM_ON) {
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
