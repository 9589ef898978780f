/* SPDX-License-Identifier: MIT */
/* far_layers.c - the far field's depth slices (far_layers.h).
 *
 * Where a tree's crown meets the sky, both blurred, a lens draws each surface with its own disc,
 * and the nearer covers the farther by the share of the disc it fills; the farther shows
 * through where the nearer thins out. The diffusion draws a soft blob there, and the far
 * field's plain gather (far_field_gather.c) would spread either side over the other.
 *
 * The frame is cut into depth slices by its signed CoC (the nearer, the smaller), at the values
 * that separate the most pairs of 4-neighbours across edges between blurred surfaces (at most
 * FAR_LAYERS_MAX_SLICES - 1 cuts, each separating at least FAR_MIN_SEPARATED pairs not separated
 * yet). Each slice is an image of premultiplied colour and coverage (1 on its pixels, 0
 * elsewhere), gathered as the far field gathers, with the radius the pixel's own on the slice
 * and the mean of the slice's radii around it elsewhere. Nearest first, a slice of coverage A
 * covers what lies behind it by A / (1 - H), H the nearer slices' coverage: in the pinhole image
 * the nearer slices hide what lies behind them, so the slice's share is counted among what they
 * leave. The farthest slice with any coverage is normalised to cover the rest: it is the
 * background, continued under the nearer ones from what it shows (as Kraus and Strengert 2007
 * fill a layer's hidden part). A slice's colour is its premultiplied gather over its coverage,
 * so where two surfaces of one radius meet, the composite is the plain gather of both. */
#include "far_layers.h"

#include "far_field_internal.h"
#include "far_layer_sink.h"
#include "runtime/float_ops.h"
#include "runtime/parallel_rows.h"

#include <math.h>
#include <string.h>

#define NO_SLICE 255u

typedef struct edge_pair {
    float lo, hi; /* the nearer side's signed CoC and the farther's */
} edge_pair;

typedef struct slicing {
    const adi_request *r;
    const float *color;
    size_t color_stride;
    const float *radius, *share;
    uint8_t *slice;     /* per pixel: its slice, or NO_SLICE where it does not blur */
    uint32_t current;   /* the slice being gathered                                 */
    float *image;       /* its premultiplied colour and coverage                    */
    float *box;         /* 2 per pixel: row box sums of coverage, coverage x radius  */
    float *slice_radius;
    uint32_t reach;     /* the box's half-width                                     */
    struct far_layer_sink sink;
} slicing;

/* Whether the pair (a, b) is an edge between two blurred surfaces (far_field.c's edges whose
 * two sides blur). */
static int blurred_edge(float a, float b)
{
    return fabsf(a - b) >= FAR_EDGE_STEP_PX && ddof_minf(fabsf(a), fabsf(b)) >= FAR_BLURRED_PX;
}

/* The frame's edges between blurred surfaces, into `pairs` (NULL: only counted). */
static size_t collect_pairs(const adi_request *r, edge_pair *pairs)
{
    size_t n = 0;
    for (size_t y = 0; y < r->height; y++)
        for (size_t x = 0; x < r->width; x++) {
            const float c = adi_request_coc(r, x, y);
            const float right = x + 1 < r->width ? adi_request_coc(r, x + 1, y) : c;
            const float down = y + 1 < r->height ? adi_request_coc(r, x, y + 1) : c;
            const float next[2] = {right, down};
            for (int k = 0; k < 2; k++)
                if (blurred_edge(c, next[k])) {
                    if (pairs)
                        pairs[n] = (edge_pair){ddof_minf(c, next[k]), ddof_maxf(c, next[k])};
                    n++;
                }
        }
    return n;
}

/* The cuts, ascending: each in turn the bin edge that separates the most pairs the earlier
 * ones left together (a difference array over the bins each pair spans). `runs`:
 * FAR_MAX_BINS + 2 counters. */
static uint32_t choose_cuts(const edge_pair *pairs, size_t count, int64_t *runs, float *cuts)
{
    if (!count)
        return 0;
    float lo = pairs[0].lo, hi = pairs[0].hi;
    for (size_t i = 1; i < count; i++) {
        lo = ddof_minf(lo, pairs[i].lo);
        hi = ddof_maxf(hi, pairs[i].hi);
    }
    float width;
    const uint32_t bins = ddof_far_bins(lo, hi, &width);
    uint32_t n = 0;
    while (n < FAR_LAYERS_MAX_SLICES - 1) {
        memset(runs, 0, (size_t)(bins + 2) * sizeof *runs);
        for (size_t i = 0; i < count; i++) {
            const edge_pair *p = &pairs[i];
            if (ddof_far_separated(p->lo, p->hi, cuts, n))
                continue;
            uint32_t b0, b1;
            ddof_far_pair_bins(p->lo, p->hi, lo, width, bins, &b0, &b1);
            if (b0 <= b1) {
                runs[b0]++;
                runs[b1 + 1]--;
            }
        }
        const uint32_t more = ddof_far_take_cut(runs, bins, lo, width, cuts, n);
        if (more == n)
            break;
        n = more;
    }
    return n;
}

/* ---- one slice ------------------------------------------------------------------------------ */

/* The slice's image (premultiplied colour, coverage) and its rows' box sums of coverage and
 * coverage x radius. */
static void image_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const slicing *s = user;
    const adi_request *r = s->r;
    const uint32_t w = r->width, channels = r->channels, out = channels + 1;
    const int64_t reach = s->reach;
    for (uint32_t y = y0; y < y1; y++) {
        const float *in = s->color + (size_t)y * s->color_stride;
        float *o = s->image + (size_t)y * w * out;
        const uint8_t *slice = s->slice + (size_t)y * w;
        for (uint32_t x = 0; x < w; x++) {
            const float a = slice[x] == s->current ? 1.0f : 0.0f;
            for (uint32_t c = 0; c < channels; c++)
                o[(size_t)x * out + c] = a * in[(size_t)x * channels + c];
            o[(size_t)x * out + channels] = a;
        }
        /* Running sums over [x - reach, x + reach]. */
        const float *rho = s->radius + (size_t)y * w;
        float *box = s->box + (size_t)y * w * 2;
        double cover = 0.0, weighted = 0.0;
        for (int64_t x = -reach - 1; x < (int64_t)w; x++) {
            const int64_t enter = x + reach, leave = x - reach - 1;
            if (enter >= 0 && enter < (int64_t)w && slice[enter] == s->current) {
                cover += 1.0;
                weighted += rho[enter];
            }
            if (leave >= 0 && slice[leave] == s->current) {
                cover -= 1.0;
                weighted -= rho[leave];
            }
            if (x >= 0) {
                box[2 * x] = (float)cover;
                box[2 * x + 1] = (float)weighted;
            }
        }
    }
}

/* The slice's radius map: the pixel's own on the slice, else the mean of the slice's radii
 * within the box (its mean over the frame where the box holds none). One thread: a running sum
 * down the columns. Returns the largest radius a pixel with a share takes. */
static float slice_radii(slicing *s, double *column, float mean)
{
    const adi_request *r = s->r;
    const uint32_t w = r->width, h = r->height;
    const int64_t reach = s->reach;
    float largest = 0.0f;
    memset(column, 0, (size_t)w * 2 * sizeof *column);
    for (int64_t y = -reach - 1; y < (int64_t)h; y++) {
        const int64_t enter = y + reach, leave = y - reach - 1;
        if (enter >= 0 && enter < (int64_t)h) {
            const float *b = s->box + (size_t)enter * w * 2;
            for (uint32_t i = 0; i < 2 * w; i++)
                column[i] += b[i];
        }
        if (leave >= 0) {
            const float *b = s->box + (size_t)leave * w * 2;
            for (uint32_t i = 0; i < 2 * w; i++)
                column[i] -= b[i];
        }
        if (y < 0)
            continue;
        const size_t row = (size_t)y * w;
        for (uint32_t x = 0; x < w; x++) {
            const size_t i = row + x;
            float rho = s->radius[i];
            if (s->slice[i] != s->current)
                rho = column[2 * x] > 0.5 ? (float)(column[2 * x + 1] / column[2 * x]) : mean;
            s->slice_radius[i] = rho;
            if (s->share[i] > 0.0f)
                largest = ddof_maxf(largest, rho);
        }
    }
    return largest;
}

/* The composite into the layers' result: the slices so far, the farthest covering what is
 * left. */
static void blend_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const slicing *s = user;
    const adi_request *r = s->r;
    const uint32_t channels = r->channels;
    const struct far_layer_sink *sink = &s->sink;
    for (uint32_t y = y0; y < y1; y++) {
        float *out = r->out + (size_t)y * r->out_stride;
        for (uint32_t x = 0; x < r->width; x++) {
            const size_t i = (size_t)y * r->width + x;
            const uint32_t slot = sink->slot[i];
            if (slot == NOT_TAKEN || !(sink->state[(size_t)slot * 2 + 1] > 0.0f))
                continue;
            const float share = s->share[i], left = sink->state[(size_t)slot * 2];
            const float *acc = sink->acc + (size_t)slot * channels;
            const float *last = sink->last + (size_t)slot * channels;
            float *o = out + (size_t)x * channels;
            for (uint32_t c = 0; c < channels; c++)
                o[c] += share * (acc[c] + left * last[c] - o[c]);
        }
    }
}

ddof_status ddof_far_layers(ddof_context *context, const adi_request *r, const float *color,
                            size_t color_stride, const float *radius, const float *share,
                            float largest, far_layers_report *report)
{
    memset(report, 0, sizeof *report);
    const uint32_t w = r->width, h = r->height, channels = r->channels;
    const size_t pixels = (size_t)w * h;
    const size_t pair_count = collect_pairs(r, NULL);
    size_t taken = 0;
    for (size_t i = 0; i < pixels; i++)
        taken += share[i] > 0.0f;
    if (!pair_count || !taken)
        return DDOF_OK;

    /* One block: the pairs, the cuts' counters, the slots, the slice indices, the slice's
     * image, box sums and radii, the columns' running sums, and the composite's arrays. */
    const size_t image_floats = pixels * (channels + 1);
    const size_t bytes = pair_count * sizeof(edge_pair) + (FAR_MAX_BINS + 2) * sizeof(int64_t) +
                         (size_t)w * 2 * sizeof(double) + pixels * sizeof(uint32_t) +
                         (image_floats + 3 * pixels) * sizeof(float) +
                         taken * (2 * channels + 2) * sizeof(float) + pixels;
    uint8_t *block = ddof_scratch_get(context, DDOF_SCRATCH_FAR_LAYERS, bytes);
    if (!block)
        return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                         "could not allocate the far field's %ux%u depth slices", w, h);
    edge_pair *pairs = (edge_pair *)(void *)block;
    int64_t *runs = (int64_t *)(void *)(pairs + pair_count);
    double *column = (double *)(void *)(runs + FAR_MAX_BINS + 2);
    uint32_t *slot = (uint32_t *)(void *)(column + (size_t)w * 2);
    float *floats = (float *)(void *)(slot + pixels);
    slicing s = {.r = r, .color = color, .color_stride = color_stride, .radius = radius,
                 .share = share, .image = floats, .box = floats + image_floats,
                 .slice_radius = floats + image_floats + 2 * pixels};
    float *sink_floats = s.slice_radius + pixels;
    s.sink = (struct far_layer_sink){.channels = channels, .slot = slot, .acc = sink_floats,
                                     .last = sink_floats + taken * channels,
                                     .state = sink_floats + 2 * taken * channels};
    s.slice = (uint8_t *)(void *)(s.sink.state + 2 * taken);

    collect_pairs(r, pairs);
    float cuts[FAR_LAYERS_MAX_SLICES - 1];
    const uint32_t cut_count = choose_cuts(pairs, pair_count, runs, cuts);
    if (!cut_count)
        return DDOF_OK;
    const uint32_t slices = cut_count + 1;

    double radius_sum[FAR_LAYERS_MAX_SLICES] = {0.0};
    uint64_t members[FAR_LAYERS_MAX_SLICES] = {0};
    size_t next = 0;
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            const size_t i = (size_t)y * w + x;
            uint8_t k = NO_SLICE;
            if (radius[i] > 0.0f) {
                const float c = adi_request_coc(r, x, y);
                k = 0;
                while (k < cut_count && cuts[k] <= c)
                    k++;
                radius_sum[k] += radius[i];
                members[k]++;
            }
            s.slice[i] = k;
            if (share[i] > 0.0f) {
                slot[i] = (uint32_t)next;
                float *state = s.sink.state + next * 2;
                state[0] = 1.0f;
                state[1] = 0.0f;
                next++;
            } else {
                slot[i] = NOT_TAKEN;
            }
        }
    memset(s.sink.acc, 0, 2 * taken * channels * sizeof(float));
    s.reach = (uint32_t)ddof_minf(ceilf(largest) + 1.0f, (float)DDOF_MAX_DIMENSION);

    adi_request sliced = *r;
    sliced.channels = channels + 1;
    sliced.color = s.image;
    sliced.color_stride = (size_t)w * (channels + 1);
    for (uint32_t k = 0; k < slices; k++) {
        if (!members[k])
            continue;
        s.current = k;
        ddof_parallel_rows(context, h, image_rows, &s);
        const float reach = slice_radii(&s, column, (float)(radius_sum[k] / (double)members[k]));
        far_gather g = {.r = &sliced, .color = s.image, .color_stride = sliced.color_stride,
                        .radius = s.slice_radius, .weight = share, .sink = &s.sink};
        const ddof_status status = ddof_far_field_gather(context, &g, reach);
        if (status != DDOF_OK)
            return status;
    }
    ddof_parallel_rows(context, h, blend_rows, &s);
    report->pixels = taken;
    report->slices = slices;
    return DDOF_OK;
}
