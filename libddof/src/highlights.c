/* SPDX-License-Identifier: MIT */
/* highlights.c - the highlight pass (highlights.h): find, take out, scatter as discs. */
#include "highlights.h"

#include "parallel_rows.h"

#include <math.h>
#include <string.h>

/* Brightness classes, a quarter octave each: a highlight of brightness L is in class
 * floor(4 log2(L / threshold)), so raising the threshold by 2^(k/4) drops the classes below k. */
#define CLASSES_PER_OCTAVE 4
#define CLASSES 128

typedef struct class_count {
    uint32_t count[CLASSES];
    double area[CLASSES];
} class_count;

typedef struct find_job {
    const adi_request *r;
    float threshold; /* the user's                                  */
    uint32_t first_class;  /* the classes kept (after the budget)   */
    int coc_signed;
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
    return fmaxf(px[0], fmaxf(px[1], px[2]));
}

/* The pixels an anti-aliased disc of this CoC touches (its bounding ellipse's area). */
static double disc_area(float coc, float aspect)
{
    const double r = 0.5 * fabs((double)coc) + 0.5;
    return 3.14159265358979 * r * r * (double)aspect + 1.0;
}

/* The class of a pixel, or -1 when it is no highlight. */
static int highlight_class(const find_job *job, const float *px, float coc)
{
    const float l = brightness(px);
    if (!(l > job->threshold) || !(fabsf(coc) >= DDOF_HIGHLIGHT_MIN_COC_PX))
        return -1;
    const int k = (int)floorf(CLASSES_PER_OCTAVE * log2f(l / job->threshold));
    return k < 0 ? 0 : k >= CLASSES ? CLASSES - 1 : k;
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
            const float coc = coc_at(r, x, y);
            const int k = highlight_class(job, row + (size_t)x * r->channels, coc);
            if (k >= 0) {
                c->count[k]++;
                c->area[k] += disc_area(coc, r->pixel_aspect);
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
            const float coc = coc_at(r, x, y);
            float *px = out + (size_t)x * r->channels;
            const int k = highlight_class(job, px, coc);
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

/* Whether a highlight of CoC `from` lands on a pixel of CoC `to`: everything behind a near
 * highlight, and for a far one what is at least half as blurred on the far side. */
static int lands_on(float from, float to, int coc_signed)
{
    if (coc_signed && from < 0.0f)
        return 1;
    return (coc_signed ? to : fabsf(to)) >= 0.5f * fabsf(from);
}

/* The disc's weight at (dx, dy) pixels from its centre: anti-aliased by the distance to the
 * rim, rows scaled by the pixel aspect. */
static float disc_weight(float radius, float aspect, int dx, int dy)
{
    const float u = (float)dx, v = (float)dy / aspect;
    const float w = radius + 0.5f - sqrtf(u * u + v * v);
    return w <= 0.0f ? 0.0f : w >= 1.0f ? 1.0f : w;
}

typedef struct disc_extent {
    int x0, x1, y0, y1; /* inclusive, within the image */
    float radius;
} disc_extent;

static disc_extent extent_of(const adi_request *r, const highlight *h)
{
    const float radius = 0.5f * fabsf(h->coc);
    const int rx = (int)ceilf(radius + 0.5f), ry = (int)ceilf((radius + 0.5f) * r->pixel_aspect);
    const int x = (int)h->x, y = (int)h->y;
    return (disc_extent){x - rx < 0 ? 0 : x - rx,
                         x + rx >= (int)r->width ? (int)r->width - 1 : x + rx,
                         y - ry < 0 ? 0 : y - ry,
                         y + ry >= (int)r->height ? (int)r->height - 1 : y + ry, radius};
}

typedef struct scatter_job {
    const adi_request *r;
    int coc_signed;
    highlight *items;
    uint32_t count;
    int reach_rows; /* the largest disc's half height */
} scatter_job;

/* Per highlight: 1 / its weights' sum over the pixels it lands on (the centre always counts). */
static void weigh_items(void *user, uint32_t i0, uint32_t i1, uint32_t chunk)
{
    (void)chunk;
    const scatter_job *job = user;
    const adi_request *r = job->r;
    for (uint32_t i = i0; i < i1; i++) {
        highlight *h = &job->items[i];
        const disc_extent e = extent_of(r, h);
        double sum = 0.0;
        for (int y = e.y0; y <= e.y1; y++)
            for (int x = e.x0; x <= e.x1; x++)
                if (lands_on(h->coc, coc_at(r, (uint32_t)x, (uint32_t)y), job->coc_signed))
                    sum += disc_weight(e.radius, r->pixel_aspect, x - (int)h->x, y - (int)h->y);
        h->weight = sum > 0.0 ? (float)(1.0 / sum) : 0.0f;
    }
}

/* The output rows [y0, y1): every disc that reaches them, added. */
static void scatter_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const scatter_job *job = user;
    const adi_request *r = job->r;
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
        const disc_extent e = extent_of(r, h);
        const int ya = e.y0 > (int)y0 ? e.y0 : (int)y0;
        const int yb = e.y1 < (int)y1 - 1 ? e.y1 : (int)y1 - 1;
        for (int y = ya; y <= yb; y++) {
            float *row = r->out + (size_t)y * r->out_stride;
            for (int x = e.x0; x <= e.x1; x++) {
                if (!lands_on(h->coc, coc_at(r, (uint32_t)x, (uint32_t)y), job->coc_signed))
                    continue;
                const float w =
                    h->weight * disc_weight(e.radius, r->pixel_aspect, x - (int)h->x,
                                            y - (int)h->y);
                float *px = row + (size_t)x * r->channels;
                for (int c = 0; c < 3; c++)
                    px[c] += w * h->excess[c];
            }
        }
    }
}

ddof_status ddof_find_highlights(ddof_context *context, const adi_request *r, float threshold,
                                 int coc_signed, float *base, highlight_set *set)
{
    memset(set, 0, sizeof *set);
    set->threshold = threshold;
    const uint32_t chunks = ddof_row_chunks(r->height);
    class_count *counts = ddof_scratch_get(context, DDOF_SCRATCH_HIGHLIGHT_COUNTS,
                                           chunks * (sizeof *counts + sizeof(uint32_t)));
    if (!counts)
        return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                         "could not allocate the highlight pass's counts");
    find_job job = {.r = r, .threshold = threshold, .coc_signed = coc_signed, .counts = counts,
                    .offsets = (uint32_t *)(counts + chunks), .base = base};
    ddof_parallel_rows(context, r->height, count_rows, &job);

    /* The brightest classes that fit the budget. */
    double area[CLASSES] = {0};
    uint64_t count[CLASSES] = {0};
    for (uint32_t c = 0; c < chunks; c++)
        for (int k = 0; k < CLASSES; k++) {
            area[k] += counts[c].area[k];
            count[k] += counts[c].count[k];
        }
    const double budget = DDOF_HIGHLIGHT_BUDGET * (double)r->width * r->height;
    double kept_area = 0.0;
    uint64_t kept = 0;
    int first = CLASSES;
    while (first > 0 && kept_area + area[first - 1] <= budget) {
        first--;
        kept_area += area[first];
        kept += count[first];
    }
    if (kept == 0)
        return DDOF_OK;
    job.first_class = (uint32_t)first;
    for (uint32_t c = 0, at = 0; c < chunks; c++) {
        job.offsets[c] = at;
        for (int k = first; k < CLASSES; k++)
            at += counts[c].count[k];
    }
    highlight *items =
        ddof_scratch_get(context, DDOF_SCRATCH_HIGHLIGHTS, (size_t)kept * sizeof *items);
    if (!items)
        return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                         "could not allocate the highlight pass's %llu highlights",
                         (unsigned long long)kept);
    job.items = items;
    ddof_parallel_rows(context, r->height, fill_rows, &job);
    *set = (highlight_set){items, (uint32_t)kept,
                           threshold * exp2f((float)first / CLASSES_PER_OCTAVE),
                           (uint64_t)kept_area};
    return DDOF_OK;
}

void ddof_scatter_highlights(ddof_context *context, const adi_request *r, int coc_signed,
                             const highlight_set *set)
{
    if (!set->count)
        return;
    scatter_job job = {r, coc_signed, set->items, set->count, 0};
    for (uint32_t i = 0; i < set->count; i++) {
        const disc_extent e = extent_of(r, &set->items[i]);
        const int reach = (int)set->items[i].y - e.y0 > e.y1 - (int)set->items[i].y
                              ? (int)set->items[i].y - e.y0
                              : e.y1 - (int)set->items[i].y;
        job.reach_rows = reach > job.reach_rows ? reach : job.reach_rows;
    }
    ddof_parallel_rows(context, set->count, weigh_items, &job);
    ddof_parallel_rows(context, r->height, scatter_rows, &job);
}
