/* SPDX-License-Identifier: MIT */
/* far_field_gather.c - the far field's gather (far_field.h, far_field_internal.h).
 *
 * With the CoC locally linear, rho(q) = rho + g . (q - p) (a plane's CoC is affine in 1 / Z,
 * which is affine in the image), the points whose disc covers p are those with
 * |q - p| < rho + g . (q - p): a conic with p at a focus, one span on each row. A row's span is
 * a difference of two prefix sums (each pixel a unit box), weighted by 1 / rho(q)^2 (the light
 * a point puts on each pixel of its disc; rho(q) taken mid-span) and normalised by the weights.
 * The rows of a disc of radius below TWO_TAPS_BELOW are sampled at two Gauss points
 * (+-1 / (2 sqrt 3) of a row), so its top and bottom rows weigh what they cover; a larger one's
 * at their centres (measured on the study's receding plane: two points everywhere 40.80 dB,
 * one 40.47, two below a radius of 4 pixels 40.96).
 *
 * A pixel whose disc is wider than FAR_LEVEL_RADIUS pixels interpolates (bilinearly) samples taken
 * at the pixel centres of level k of the frame (boxes of 2^k pixels), the level whose pixels are
 * an eighth to a quarter of the radius apart, where the blurred image is smooth; each sample
 * reads level k - 1 (twice finer: its boxes blur the disc's rim less; the radius shrunk by the
 * box's variance so the spread stays the disc's). So a pixel costs O(FAR_LEVEL_RADIUS) rows at any
 * CoC, and a large blur far less. */
#include "far_field_internal.h"
#include "far_layer_sink.h"

#include "runtime/float_ops.h"
#include "runtime/parallel_rows.h"

#include <math.h>
#include <string.h>

#define GRADIENT_MAX 0.5f
#define RAMP_TOLERANCE 0.25f /* the two halves' slopes may differ by this share */
#define GAUSS_POINT 0.28867513f /* 1 / (2 sqrt 3) */
#define TWO_TAPS_BELOW 4.0f      /* level pixels of radius */
#define GATHER_BLOCK 16u         /* row taps whose spans are computed together */

static uint32_t level_of(const far_gather *g, float rho)
{
    const float extent = rho * ddof_maxf(1.0f, g->r->pixel_aspect);
    uint32_t k = 0;
    while (k + 1 < g->level_count && extent > FAR_LEVEL_RADIUS * (float)(1u << k))
        k++;
    return k;
}

/* ---- levels -------------------------------------------------------------------------------- */

/* Level k from level k - 1: means of 2 x 2 boxes (the last row or column repeated). */
static void downsample_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const far_gather *g = user;
    const far_level *s = &g->levels[g->level - 1], *t = &g->levels[g->level];
    const uint32_t channels = g->r->channels;
    for (uint32_t y = y0; y < y1; y++) {
        const float *a = s->image + (size_t)(2 * y) * s->stride;
        const float *b = s->image + (size_t)(2 * y + 1 < s->height ? 2 * y + 1 : 2 * y) * s->stride;
        float *o = (float *)t->image + (size_t)y * t->stride;
        for (uint32_t x = 0; x < t->width; x++) {
            const size_t x0 = (size_t)(2 * x) * channels;
            const size_t x1 = (size_t)(2 * x + 1 < s->width ? 2 * x + 1 : 2 * x) * channels;
            for (uint32_t c = 0; c < channels; c++)
                o[(size_t)x * channels + c] =
                    0.25f * (a[x0 + c] + a[x1 + c] + b[x0 + c] + b[x1 + c]);
        }
    }
}

static void prefix_row(const float *in, uint32_t width, uint32_t channels, float *p)
{
    for (uint32_t c = 0; c < channels; c++)
        p[c] = 0.0f;
    for (uint32_t x = 0; x < width; x++)
        for (uint32_t c = 0; c < channels; c++)
            p[(size_t)(x + 1) * channels + c] =
                p[(size_t)x * channels + c] + in[(size_t)x * channels + c];
}

static void prefix_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const far_gather *g = user;
    const far_level *l = &g->levels[g->level];
    const uint32_t channels = g->r->channels;
    for (uint32_t y = y0; y < y1; y++)
        prefix_row(l->image + (size_t)y * l->stride, l->width, channels,
                   l->prefix + (size_t)y * (l->width + 1) * channels);
}

/* The mean of `count` pixels `step` floats apart from `first`, the last one repeated past
 * `available`. */
static void mean_of(const float *first, size_t step, uint32_t count, uint32_t available,
                    uint32_t channels, float *out)
{
    for (uint32_t c = 0; c < channels; c++) {
        double sum = 0.0;
        for (uint32_t i = 0; i < count; i++)
            sum += first[(size_t)(i < available ? i : available - 1) * step + c];
        out[c] = (float)(sum / count);
    }
}

/* Level k's continuation: the frame's top and bottom rows reduced by 2^k along the row, its
 * left and right columns along the column, and the corners. `row`: scratch of width * channels
 * floats. */
static void level_edges(const far_gather *g, uint32_t k, float *row)
{
    const adi_request *r = g->r;
    const far_level *l = &g->levels[k];
    const uint32_t channels = r->channels, s = 1u << k;
    for (int bottom = 0; bottom < 2; bottom++) {
        const float *edge = g->color + (size_t)(bottom ? r->height - 1 : 0) * g->color_stride;
        for (uint32_t x = 0; x < l->width; x++) {
            const uint32_t x0 = x * s < r->width ? x * s : r->width - 1;
            mean_of(edge + (size_t)x0 * channels, channels, s, r->width - x0, channels,
                    row + (size_t)x * channels);
        }
        const size_t index = (size_t)l->height + (size_t)bottom;
        prefix_row(row, l->width, channels, l->prefix + index * (l->width + 1) * channels);
        float *side = l->sides + index * 2 * channels;
        memcpy(side, edge, channels * sizeof(float));
        memcpy(side + channels, edge + (size_t)(r->width - 1) * channels,
               channels * sizeof(float));
    }
    for (uint32_t y = 0; y < l->height; y++) {
        const uint32_t y0 = y * s < r->height ? y * s : r->height - 1;
        const float *start = g->color + (size_t)y0 * g->color_stride;
        float *side = l->sides + (size_t)y * 2 * channels;
        mean_of(start, g->color_stride, s, r->height - y0, channels, side);
        mean_of(start + (size_t)(r->width - 1) * channels, g->color_stride, s, r->height - y0,
                channels, side + channels);
    }
}

/* Floats of level k's prefix sums and sides, and of its image and samples (k >= 1). */
static size_t prefix_floats(uint32_t w, uint32_t h, uint32_t channels)
{
    return ((size_t)(w + 1) * (h + 2) + (size_t)(h + 2) * 2) * channels;
}

static size_t image_floats(uint32_t k, uint32_t w, uint32_t h, uint32_t channels)
{
    return k ? 2 * (size_t)w * h * channels : 0;
}

static ddof_status build_levels(ddof_context *context, far_gather *g, float largest)
{
    const adi_request *r = g->r;
    const uint32_t channels = r->channels;
    const uint32_t count = ddof_far_level_count(largest, r->pixel_aspect, r->width, r->height);
    uint32_t w = r->width, h = r->height;
    size_t floats = (size_t)r->width * channels, bytes = 0; /* the edge rows' scratch */
    for (uint32_t k = 0; k < count; k++) {
        floats += prefix_floats(w, h, channels) + image_floats(k, w, h, channels);
        bytes += k ? (size_t)w * h : 0;
        w = (w + 1) / 2;
        h = (h + 1) / 2;
    }
    float *f = ddof_scratch_get(context, DDOF_SCRATCH_FAR_FIELD_LEVELS,
                                floats * sizeof(float) + bytes);
    if (!f)
        return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                         "could not allocate the far field's %u image levels", count);
    uint8_t *needed = (uint8_t *)(f + floats);
    memset(needed, 0, bytes);
    float *edge_row = f;
    f += (size_t)r->width * channels;
    g->level_count = count;
    w = r->width;
    h = r->height;
    for (uint32_t k = 0; k < count; k++) {
        far_level *l = &g->levels[k];
        *l = (far_level){.width = w, .height = h, .prefix = f};
        f += (size_t)(w + 1) * (h + 2) * channels;
        l->sides = f;
        f += (size_t)(h + 2) * 2 * channels;
        g->level = k;
        if (k == 0) {
            l->image = g->color;
            l->stride = g->color_stride;
        } else {
            l->image = f;
            l->stride = (size_t)w * channels;
            f += (size_t)w * h * channels;
            l->samples = f;
            f += (size_t)w * h * channels;
            l->needed = needed;
            needed += (size_t)w * h;
            ddof_parallel_rows(context, h, downsample_rows, g);
        }
        ddof_parallel_rows(context, h, prefix_rows, g);
        level_edges(g, k, edge_row);
        w = (w + 1) / 2;
        h = (h + 1) / 2;
    }
    return DDOF_OK;
}

/* ---- the gather ---------------------------------------------------------------------------- */

/* The integral of level row `row` (each pixel a unit box, continued by its side values
 * beyond the frame; row < 0: the frame's top row continued upwards, >= height: its bottom row)
 * from the frame's left edge to t, t in the level's pixel coordinates (pixel x spans x +- 0.5),
 * added into sum[c] times `scale`. */
static inline void add_integral(const far_level *l, uint32_t channels, int64_t row, float t,
                                float scale, float *sum)
{
    const size_t index = row < 0                     ? (size_t)l->height
                         : row >= (int64_t)l->height ? (size_t)l->height + 1
                                                     : (size_t)row;
    const float *p = l->prefix + index * (l->width + 1) * channels;
    const float u = t + 0.5f;
    if (u <= 0.0f) {
        const float *side = l->sides + index * 2 * channels;
        for (uint32_t c = 0; c < channels; c++)
            sum[c] += scale * u * side[c];
    } else if (u >= (float)l->width) {
        const float *side = l->sides + index * 2 * channels + channels;
        const float *end = p + (size_t)l->width * channels;
        for (uint32_t c = 0; c < channels; c++)
            sum[c] += scale * (end[c] + (u - (float)l->width) * side[c]);
    } else {
        const size_t i = (size_t)u;
        const float f = u - (float)i;
        const float *x0 = p + i * channels, *x1 = x0 + channels;
        for (uint32_t c = 0; c < channels; c++)
            sum[c] += scale * (x0[c] + f * (x1[c] - x0[c]));
    }
}

/* The slope of rho along a line through a pixel from the values `left` pixels before it and
 * `right` after it: the CoC's slope across the disc when it is a ramp there (the two halves'
 * slopes agree within RAMP_TOLERANCE), 0 when it is a step (a tree's crown before the sky, both
 * far: a conic tilted by a step spreads the nearer side too far). Measured on the daylight
 * scene (480x270): the neighbours' differences 43.79 dB, the disc's span 43.98, with the step
 * test 44.24; the receding plane 40.96 / 40.98 / 41.03. */
static float linear_slope(float before, float here, float after, uint32_t left, uint32_t right)
{
    if (!left || !right)
        return left + right ? (after - before) / (float)(left + right) : 0.0f;
    const float a = (here - before) / (float)left, b = (after - here) / (float)right;
    /* A step (one side flat, the other steep) is no ramp: no slope. */
    if (fabsf(a - b) > RAMP_TOLERANCE * ddof_maxf(fabsf(a), fabsf(b)) + 1e-3f)
        return 0.0f;
    return (after - before) / (float)(left + right);
}

/* d rho / dx and d rho / dy at a frame pixel, over rho pixels each side (fewer at the frame's
 * edges). */
static void radius_gradient(const far_gather *g, uint32_t x, uint32_t y, float *gx, float *gy)
{
    const uint32_t w = g->r->width, h = g->r->height;
    const float *rho = g->radius;
    const float here = rho[(size_t)y * w + x];
    const float reach = ddof_maxf(1.0f, here);
    const uint32_t span = reach < (float)DDOF_MAX_DIMENSION ? (uint32_t)reach : DDOF_MAX_DIMENSION;
    const uint32_t xa = x > span ? x - span : 0, xb = w - 1 - x > span ? x + span : w - 1;
    const uint32_t ya = y > span ? y - span : 0, yb = h - 1 - y > span ? y + span : h - 1;
    *gx = linear_slope(rho[(size_t)y * w + xa], here, rho[(size_t)y * w + xb], x - xa, xb - x);
    *gy = linear_slope(rho[(size_t)ya * w + x], here, rho[(size_t)yb * w + x], y - ya, yb - y);
}

/* The gather on level k centred at (u0, v0) (the level's pixel coordinates) of radius rho and
 * radius gradient (gx, gy) (both in frame pixels) into out[channels]; inlined per channel
 * count. */
static inline void conic_gather(const far_gather *g, uint32_t channels, uint32_t k, float u0,
                                float v0, float rho, float gx, float gy, float *out)
{
    const far_level *l = &g->levels[k];
    const float aspect = g->r->pixel_aspect, inv_aspect = 1.0f / aspect;
    const float s = (float)(1u << k);
    /* The level's box adds (s^2 - 1) / 12 to each axis's variance, a disc has rho^2 / 4. */
    const float shrunk = rho * rho - (s * s - 1.0f) / 3.0f;
    const float radius = sqrtf(ddof_maxf(shrunk, 0.25f * s * s)) / s;
    float bx = gx, bv = gy * aspect; /* per unit of the shape's x and y (rows / aspect) */
    const float g2 = bx * bx + bv * bv;
    if (g2 > GRADIENT_MAX * GRADIENT_MAX) {
        const float f = GRADIENT_MAX / sqrtf(g2);
        bx *= f;
        bv *= f;
    }
    /* At the shape's height v the span is where a X^2 - 2 bx b X + v^2 - b^2 < 0,
     * b = radius + bv v: it exists for v within radius (bv -+ sqrt a) / (1 - |g|^2). */
    const float a = 1.0f - bx * bx, inv_a = 1.0f / a, root_a = sqrtf(a), q = a - bv * bv;
    const float top = radius * (bv - root_a) / q, bottom = radius * (bv + root_a) / q;
    const int64_t j0 = (int64_t)ceilf(v0 + top * aspect - 0.5f);
    const int64_t j1 = (int64_t)floorf(v0 + bottom * aspect + 0.5f);
    float sum[FAR_FIELD_MAX_CHANNELS] = {0.0f}, weights = 0.0f;
    /* A small disc's rows are sampled at two Gauss points, a large one's at its centre. */
    const int taps = radius < TWO_TAPS_BELOW ? 2 : 1;
    const float offset = taps == 2 ? GAUSS_POINT : 0.0f, share = 1.0f / (float)taps;
    /* Each block of row taps in two passes: their spans and weights, a loop without branches
     * that runs in SIMD (the square roots and divisions, most of the work); then their sums,
     * in the order of the rows and taps. Row numbers are whole floats (exact: a level is under
     * 2^24 rows), so v is what (float)j gives. */
    const uint32_t shift = (uint32_t)taps - 1u; /* a tap's row: e >> shift, which: e & shift */
    const int64_t count = (j1 - j0 + 1) * taps;
    const float first_row = (float)j0;
    for (int64_t done = 0; done < count; done += GATHER_BLOCK) {
        const uint32_t n =
            count - done < GATHER_BLOCK ? (uint32_t)(count - done) : GATHER_BLOCK;
        float lo[GATHER_BLOCK], hi[GATHER_BLOCK], weight[GATHER_BLOCK], bs[GATHER_BLOCK],
            ds[GATHER_BLOCK];
        for (uint32_t e = 0; e < n; e++) {
            const int32_t t = (int32_t)done + (int32_t)e;
            const float row = first_row + (float)(t >> shift);
            /* +offset for the second tap, -offset for the first (-0 with one tap: exact) */
            const float side = offset * (float)(2 * (t & (int32_t)shift) - 1);
            const float v = (row + side - v0) * inv_aspect;
            const float b = radius + bv * v, d = b * b - a * v * v;
            /* A tap outside the conic (b <= 0 or d <= 0) computes NaN or inf here, unread. */
            const float root = sqrtf(d);
            bs[e] = b;
            ds[e] = d;
            lo[e] = (bx * b - root) * inv_a;
            hi[e] = (bx * b + root) * inv_a;
            /* 1 / rho(q)^2, rho(q) = b / a mid-span */
            weight[e] = share * (a * a) / (b * b);
        }
        for (uint32_t e = 0; e < n; e++) {
            if (bs[e] <= 0.0f || ds[e] <= 0.0f)
                continue;
            const int64_t j = j0 + (int64_t)(((uint32_t)done + e) >> shift);
            add_integral(l, channels, j, u0 + hi[e], weight[e], sum);
            add_integral(l, channels, j, u0 + lo[e], -weight[e], sum);
            weights += weight[e] * (hi[e] - lo[e]);
        }
    }
    if (weights <= 0.0f) {
        /* A disc thinner than a row (rows squeezed by the aspect): its centre's row. */
        const float lo = (bx * radius - radius) * inv_a, hi = (bx * radius + radius) * inv_a;
        const int64_t j = (int64_t)floorf(v0 + 0.5f);
        add_integral(l, channels, j, u0 + hi, 1.0f, sum);
        add_integral(l, channels, j, u0 + lo, -1.0f, sum);
        weights = hi - lo;
    }
    for (uint32_t c = 0; c < channels; c++)
        out[c] = sum[c] / weights;
}

/* A frame pixel's position on level k (s = 2^k): the level's pixel coordinates. */
static float on_level(uint32_t x, float s)
{
    return ((float)x + 0.5f) / s - 0.5f;
}

/* The four samples frame pixel (x, y) interpolates on level k (s = 2^k): their indices (upper
 * left, upper right, lower left, lower right; clamped at the level's last row and column) and
 * the weights along the row and the column. */
typedef struct sample_cell {
    size_t index[4];
    float fu, fv;
} sample_cell;

static sample_cell cell_of(const far_level *l, uint32_t x, uint32_t y, float s)
{
    const float cu = ddof_minf(ddof_maxf(on_level(x, s), 0.0f), (float)(l->width - 1));
    const float cv = ddof_minf(ddof_maxf(on_level(y, s), 0.0f), (float)(l->height - 1));
    const uint32_t i0 = (uint32_t)cu, j0 = (uint32_t)cv;
    const uint32_t i1 = i0 + 1 < l->width ? i0 + 1 : i0;
    const uint32_t j1 = j0 + 1 < l->height ? j0 + 1 : j0;
    const size_t row0 = (size_t)j0 * l->width, row1 = (size_t)j1 * l->width;
    return (sample_cell){.index = {row0 + i0, row0 + i1, row1 + i0, row1 + i1},
                         .fu = cu - (float)i0,
                         .fv = cv - (float)j0};
}

/* Marks the samples the frame's pixels interpolate (one thread: each pixel marks four). */
static void mark_samples(far_gather *g)
{
    const adi_request *r = g->r;
    for (uint32_t y = 0; y < r->height; y++)
        for (uint32_t x = 0; x < r->width; x++) {
            const size_t i = (size_t)y * r->width + x;
            const uint32_t k = g->weight[i] > 0.0f ? level_of(g, g->radius[i]) : 0;
            if (!k)
                continue;
            const far_level *l = &g->levels[k];
            const sample_cell cell = cell_of(l, x, y, (float)(1u << k));
            for (int corner = 0; corner < 4; corner++)
                l->needed[cell.index[corner]] = 1;
        }
}

/* The gather at the needed samples of one level: each at its centre, with the radius and
 * gradient of the frame pixel there. */
static void sample_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const far_gather *g = user;
    const adi_request *r = g->r;
    const uint32_t k = g->level, channels = r->channels, s = 1u << k;
    const far_level *l = &g->levels[k];
    for (uint32_t j = y0; j < y1; j++)
        for (uint32_t i = 0; i < l->width; i++) {
            if (!l->needed[(size_t)j * l->width + i])
                continue;
            /* The centre in frame pixels, and the frame pixel nearest it inside the frame. */
            const float cx = ((float)i + 0.5f) * (float)s - 0.5f;
            const float cy = ((float)j + 0.5f) * (float)s - 0.5f;
            const uint32_t x = (uint32_t)ddof_minf(cx + 0.5f, (float)(r->width - 1));
            const uint32_t y = (uint32_t)ddof_minf(cy + 0.5f, (float)(r->height - 1));
            float gx, gy;
            radius_gradient(g, x, y, &gx, &gy);
            const float rho = g->radius[(size_t)y * r->width + x] + gx * (cx - (float)x) +
                              gy * (cy - (float)y);
            /* Read from the level below the grid's (twice finer: a radius of up to twice
             * FAR_LEVEL_RADIUS of its pixels), so that its boxes blur the disc's rim less. */
            const float f = (float)(1u << (k - 1));
            conic_gather(g, channels, k - 1, (cx + 0.5f) / f - 0.5f, (cy + 0.5f) / f - 0.5f, rho,
                         gx, gy, l->samples + ((size_t)j * l->width + i) * channels);
        }
}

static inline void blend_row(const far_gather *g, uint32_t channels, uint32_t y)
{
    const adi_request *r = g->r;
    float *out = r->out + (size_t)y * r->out_stride;
    for (uint32_t x = 0; x < r->width; x++) {
        const size_t i = (size_t)y * r->width + x;
        const float weight = g->weight[i];
        if (weight <= 0.0f)
            continue;
        const float rho = g->radius[i];
        const uint32_t k = level_of(g, rho);
        float v[FAR_FIELD_MAX_CHANNELS] = {0.0f};
        if (k == 0) {
            float gx, gy;
            radius_gradient(g, x, y, &gx, &gy);
            conic_gather(g, channels, 0, (float)x, (float)y, rho, gx, gy, v);
        } else {
            const far_level *l = &g->levels[k];
            const sample_cell cell = cell_of(l, x, y, (float)(1u << k));
            const float *s00 = l->samples + cell.index[0] * channels;
            const float *s01 = l->samples + cell.index[1] * channels;
            const float *s10 = l->samples + cell.index[2] * channels;
            const float *s11 = l->samples + cell.index[3] * channels;
            for (uint32_t c = 0; c < channels; c++) {
                const float top = s00[c] + cell.fu * (s01[c] - s00[c]);
                const float bottom = s10[c] + cell.fu * (s11[c] - s10[c]);
                v[c] = top + cell.fv * (bottom - top);
            }
        }
        if (g->sink) {
            ddof_far_layer_take(g->sink, i, v);
            continue;
        }
        float *o = out + (size_t)x * channels;
        for (uint32_t c = 0; c < channels; c++)
            o[c] += weight * (v[c] - o[c]);
    }
}

static void blend_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const far_gather *g = user;
    for (uint32_t y = y0; y < y1; y++)
        switch (g->r->channels) {
        case 5: blend_row(g, 5, y); break;
        case 4: blend_row(g, 4, y); break;
        case 3: blend_row(g, 3, y); break;
        default: blend_row(g, g->r->channels, y); break;
        }
}

ddof_status ddof_far_field_gather(ddof_context *context, far_gather *g, float largest)
{
    const ddof_status status = build_levels(context, g, largest);
    if (status != DDOF_OK)
        return status;
    if (g->level_count > 1)
        mark_samples(g);
    for (uint32_t k = 1; k < g->level_count; k++) {
        g->level = k;
        ddof_parallel_rows(context, g->levels[k].height, sample_rows, g);
    }
    ddof_parallel_rows(context, g->r->height, blend_rows, g);
    return DDOF_OK;
}
