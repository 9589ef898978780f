/* SPDX-License-Identifier: MIT */
/* highlights_draw.c - the highlight pass's drawing (highlights.h): each highlight's excess
 * scattered as its disc or the aperture's shape, anti-aliased, over the pixels its light may
 * land on. */
#include "aperture.h"
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

typedef struct scatter_job {
    const adi_request *r;
    aperture_shape shape;
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
static void interior_span(const adi_request *r, const highlight *h, const aperture_row *row, int *a,
                          int *b)
{
    *a = (int)h->x + row->inner_l < 0 ? 0 : (int)h->x + row->inner_l;
    *b = (int)h->x + row->inner_r >= (int)r->width ? (int)r->width - 1
                                                    : (int)h->x + row->inner_r;
}

/* What the k-th rim column on `side` of a row (aperture_rim_column) is to the image. */
typedef enum rim_place {
    RIM_NONE,   /* the row has no such column                                 */
    RIM_OFF,    /* weight *w, but 0 or past the frame's left or right edge     */
    RIM_ON      /* image column *x, weight *w > 0                              */
} rim_place;

static rim_place rim_pixel(const scatter_job *job, const highlight *h, const aperture_row *row,
                           int k, int side, int *x, float *w)
{
    const int dx = aperture_rim_column(row, k, side);
    if (dx == INT_MIN)
        return RIM_NONE;
    *w = aperture_rim_weight(&job->shape, h, row, dx);
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
        const int reach = aperture_half_height(&job->shape, h);
        double sum = 0.0;
        for (int dy = -reach; dy <= reach; dy++) {
            const int y = (int)h->y + dy;
            aperture_row row;
            if (!aperture_row_at(&job->shape, h, dy, &row))
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
            const int steps = aperture_rim_steps(&row);
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
        const int reach = aperture_half_height(&job->shape, h);
        for (int dy = -reach; dy <= reach; dy++) {
            const int y = (int)h->y + dy;
            aperture_row row;
            if (y < (int)y0 || y >= (int)y1 ||
                !aperture_row_at(&job->shape, h, dy, &row))
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
            const int steps = aperture_rim_steps(&row);
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
                       .shape = aperture_shape_of(aperture, set->aperture_sums, r->pixel_aspect),
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
            const int reach = aperture_half_height(&job.shape, h);
            const int reach_x = ddof_highlight_reach_x(radius_of(h));
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

void ddof_draw_highlights(ddof_context *context, const adi_request *r, const adi_highlights *h,
                          float *scratch)
{
    const highlight_aperture aperture = {
        .blades = h->blades, .rotation_rad = h->rotation_rad, .catseye = h->catseye,
        .centre_x = h->centre_x, .centre_y = h->centre_y, .half_width = h->half_width,
        .half_height = h->half_height, .image_width = h->image_width,
        .image_height = h->image_height};
    const highlight_set set = ddof_highlight_set_of(h->items, h->count, h->image_sums);
    ddof_scatter_highlights(context, r, (int)h->coc_signed, &aperture, &set, scratch);
}
