/* SPDX-License-Identifier: MIT */
/* highlights_find.c - the highlight pass's finding (highlights.h): the brightest blurred pixels
 * within the budget, taken out of the colour, and the parts of them sharp occluders hide;
 * highlights_draw.c draws them. */
#include "highlights.h"
#include "highlights_classes.h"

#include "runtime/parallel_rows.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define CLASSES DDOF_HIGHLIGHT_CLASSES

_Static_assert(DDOF_HIGHLIGHT_CHUNK_ROWS == DDOF_ROWS_PER_CHUNK,
               "a device's find sums the costs in the CPU's row chunks");

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
    highlight_owner owner;
} find_job;

/* Pixel px as the search sees it: the frame's as it is, an element's premultiplied as its
 * steps premultiply it (into `tmp`). */
static const float *seen(const find_job *job, const float *px, float tmp[4])
{
    if (job->owner == HIGHLIGHTS_OF_FRAME)
        return px;
    ddof_element_pixel(px, job->owner == HIGHLIGHTS_OF_ELEMENT, tmp);
    return tmp;
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
    return adi_request_coc(r, bx, by);
}

static double disc_cost(float coc, float aspect, int area)
{
    return ddof_highlight_disc_cost(coc, aspect, area);
}

/* The class of pixel (x, y) of colour px, or -1 when it is no highlight; *coc gets the CoC its
 * light is drawn with. */
static int highlight_class(const find_job *job, const float *px, uint32_t x, uint32_t y,
                           float *coc)
{
    const float l = brightness(px);
    /* Its own CoC too: a pixel the diffusion leaves in focus is never taken from. */
    if (!ddof_is_highlight(l, adi_request_coc(job->r, x, y), job->threshold))
        return -1;
    *coc = highlight_coc(job->r, x, y);
    if (!(fabsf(*coc) >= DDOF_HIGHLIGHT_MIN_COC_PX))
        return -1;
    return ddof_highlight_brightness_class(l, job->threshold);
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
            float coc, tmp[4];
            const int k =
                highlight_class(job, seen(job, row + (size_t)x * r->channels, tmp), x, y, &coc);
            if (k >= 0) {
                c->count[k]++;
                c->cost[k] += disc_cost(coc, r->pixel_aspect, job->area_cost);
            }
        }
    }
}

/* Rows [y0, y1) of base: the colour's, less the excess of each of `items` (in row order, all
 * on those rows) that is not a hidden part. */
static void take_out_rows(const adi_request *r, const highlight *items, uint32_t count,
                          uint32_t y0, uint32_t y1, float *base)
{
    const size_t row_floats = (size_t)r->width * r->channels;
    for (uint32_t y = y0; y < y1; y++)
        memcpy(base + (size_t)y * row_floats, r->color + (size_t)y * r->color_stride,
               row_floats * sizeof *base);
    for (uint32_t i = 0; i < count; i++) {
        if (items[i].hidden)
            continue;
        float *px = base + (size_t)items[i].y * row_floats + (size_t)items[i].x * r->channels;
        for (int c = 0; c < 3; c++)
            px[c] -= items[i].excess[c];
    }
}

typedef struct take_out_job {
    const adi_request *r;
    const highlight *items;
    uint32_t count;
    float *base;
} take_out_job;

static void take_out_chunk(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const take_out_job *job = user;
    /* The items on rows [y0, y1): they are in row order. */
    uint32_t a = 0, b = job->count;
    while (a < b) {
        const uint32_t mid = a + (b - a) / 2;
        if (job->items[mid].y < y0)
            a = mid + 1;
        else
            b = mid;
    }
    uint32_t end = a;
    while (end < job->count && job->items[end].y < y1)
        end++;
    take_out_rows(job->r, job->items + a, end - a, y0, y1, job->base);
}

void ddof_take_out_highlights(ddof_context *context, const adi_request *r,
                              const highlight *items, uint32_t count, float *base)
{
    take_out_job job = {r, items, count, base};
    ddof_parallel_rows(context, r->height, take_out_chunk, &job);
}

/* Writes the chunk's highlights (in row order) and, with a base, its rows of base. */
static void fill_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    const find_job *job = user;
    const adi_request *r = job->r;
    const float kept = ddof_highlight_kept_threshold(job->threshold, job->first_class);
    highlight *item = job->items + job->offsets[chunk];
    for (uint32_t y = y0; y < y1; y++) {
        const float *row = r->color + (size_t)y * r->color_stride;
        for (uint32_t x = 0; x < r->width; x++) {
            float coc, tmp[4];
            const float *px = seen(job, row + (size_t)x * r->channels, tmp);
            const int k = highlight_class(job, px, x, y, &coc);
            if (k < (int)job->first_class)
                continue;
            /* The part above the kept threshold, hue kept: px * (1 - t / L). */
            const float keep = kept / brightness(px);
            *item = (highlight){.x = x, .y = y, .coc = coc};
            for (int c = 0; c < 3; c++)
                item->excess[c] = px[c] * (1.0f - keep);
            item++;
        }
    }
    if (!job->base)
        return;
    const highlight *first = job->items + job->offsets[chunk];
    take_out_rows(r, first, (uint32_t)(item - first), y0, y1, job->base);
}

const double *ddof_aperture_sums(ddof_context *context, const highlight_aperture *a)
{
    if (!a->image)
        return NULL;
    const uint32_t w = a->image_width, h = a->image_height;
    double *sums = ddof_scratch_get(context, DDOF_SCRATCH_APERTURE_SUMS,
                                    (size_t)(w + 1) * (h + 1) * sizeof *sums);
    if (!sums) {
        ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                  "could not allocate the aperture image's table");
        return NULL;
    }
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
    return fabsf(adi_request_coc(r, (uint32_t)x, (uint32_t)y)) < DDOF_HIGHLIGHT_SHARP_PX;
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
        ddof_highlight_kept_threshold(job->threshold, job->first_class) / brightness(px);
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

/* Memory for `count` highlights as a set holds them: the list twice (found, then sorted into
 * size classes), their weights, and the per-row landing counts of one size class at a time
 * (landing_bytes). NULL, with the error recorded, when there is none. */
static highlight *highlight_memory(ddof_context *context, int slot, uint64_t count,
                                   size_t landing_bytes)
{
    highlight *items = ddof_scratch_get(context, slot,
                                        2 * (size_t)count * sizeof *items +
                                            (size_t)count * sizeof(float) + landing_bytes);
    if (!items)
        ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                  "could not allocate the highlight pass's %llu highlights",
                  (unsigned long long)count);
    return items;
}

highlight_set ddof_highlight_set_of(const highlight *items, uint32_t count,
                                    const double *aperture_sums)
{
    /* highlight_memory's layout; the scatter writes its sorted copy after the items. */
    highlight *all = (highlight *)(uintptr_t)items;
    float *weights = (float *)(void *)(all + 2 * (size_t)count);
    return (highlight_set){.items = all, .count = count, .weights = weights,
                           .landing = (uint32_t *)(weights + count),
                           .aperture_sums = aperture_sums};
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
    highlight *all = highlight_memory(context, DDOF_SCRATCH_HIGHLIGHTS, total, landing_bytes);
    if (!all)
        return DDOF_ERROR_OUT_OF_MEMORY;
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
                                 int coc_signed, const double *sums, highlight_owner owner,
                                 float *base, highlight_set *set)
{
    memset(set, 0, sizeof *set);
    set->threshold = threshold;
    const int image = sums != NULL;
    const uint32_t chunks = ddof_row_chunks(r->height);
    class_count *counts = ddof_scratch_get(context, DDOF_SCRATCH_HIGHLIGHT_COUNTS,
                                           chunks * (sizeof *counts + sizeof(uint32_t)));
    if (!counts)
        return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                         "could not allocate the highlight pass's counts");
    find_job job = {.r = r, .threshold = threshold, .coc_signed = coc_signed,
                    .area_cost = image, .counts = counts,
                    .offsets = (uint32_t *)(counts + chunks), .base = base,
                    .owner = owner};
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
    const ddof_highlight_choice choice = ddof_highlight_choose(count, cost, budget, threshold);
    double kept_cost = choice.kept_cost;
    uint64_t kept = choice.kept;
    const int first = (int)choice.first;
    if (kept == 0) {
        set->over_budget = choice.over_budget;
        set->threshold = choice.threshold;
        return DDOF_OK;
    }
    job.first_class = (uint32_t)first;
    for (uint32_t c = 0, at = 0; c < chunks; c++) {
        job.offsets[c] = at;
        for (int k = first; k < CLASSES; k++)
            at += counts[c].count[k];
    }
    const size_t landing_bytes = (size_t)(r->width + 1) * r->height * sizeof(uint32_t);
    highlight *items = highlight_memory(context,
                                        owner == HIGHLIGHTS_OF_FRAME
                                            ? DDOF_SCRATCH_HIGHLIGHTS
                                            : DDOF_SCRATCH_ELEMENT_HIGHLIGHTS,
                                        kept, landing_bytes);
    if (!items)
        return DDOF_ERROR_OUT_OF_MEMORY;
    job.items = items;
    ddof_parallel_rows(context, r->height, fill_rows, &job);
    uint32_t hidden = 0;
    if (owner == HIGHLIGHTS_OF_FRAME) {
        const ddof_status status = add_hidden_parts(context, &job, landing_bytes, budget,
                                                    &items, &kept, &kept_cost, &hidden);
        if (status != DDOF_OK)
            return status;
    }
    *set = (highlight_set){items, (uint32_t)kept, choice.threshold,
                           (uint64_t)kept_cost, 0, (float *)(items + 2 * kept),
                           (uint32_t *)((float *)(items + 2 * kept) + kept), sums, hidden};
    return DDOF_OK;
}
