/* SPDX-License-Identifier: MIT */
/* silhouettes.c - the mixed pixels of in-focus silhouettes over a blurred background
 * (silhouettes.h).
 *
 * A silhouette pair is a sharp pixel p (|CoC| below the in-focus threshold) and a 4-neighbour q
 * behind it with CoC of DDOF_SILHOUETTE_MIN_COC_PX or more. Across it, along the pair's
 * direction d, the object's colour O is p - d's (or p's, where p - d is not sharp) and the
 * background's B is q + d's (or q's): the pixels one step away are the likeliest unmixed. A
 * pixel x of the pair is the mixture x = a O + (1 - a) B; its object share a is the projection
 * of x - B on O - B, clamped to [0, 1] (skipped where O and B are too alike to tell). Where p
 * is thin (one pixel across along d: O is p, itself a mixture), p's share is
 * DDOF_THIN_OBJECT_SHARE and q's at most DDOF_THIN_NEIGHBOUR_SHARE of O, and q takes O with O's
 * background share blurred.
 *  - q (its depth says background): the diffusion blurred the object's share away with the
 *    background; it is put back sharp: out(q) = a O + (1 - a) out(q).
 *  - p (its depth says object): its background share stayed sharp; it becomes the blurred
 *    background beside it: out(p) += (1 - a) (out(q) - B).
 * With an object matte (Cryptomatte) a is the share of x not covered by the background's
 * object (the id of rank 0 at the background's pixel, or the world, what no object covers,
 * where that covers more of it), and O is solved from p itself where the object covers at
 * least DDOF_MATTE_SOLVE_SHARE of it: O = (p - (1 - a_p) B) / a_p (a strand of 1-2 px has no
 * pixel wholly inside it). A pixel in several pairs takes the mean over them.
 * Every change is computed from the result before any is applied (a delta image), so rows can
 * run on any thread. Colour channels only; alpha keeps the layers' value. */
#include "silhouettes.h"

#include "runtime/float_ops.h"
#include "runtime/parallel_rows.h"

#include <math.h>
#include <string.h>

typedef struct split_job {
    const adi_request *r;
    const object_matte *matte;
    const float *color;
    size_t color_stride;
    float *delta;          /* width x height x 3: what each pixel's colour changes by */
    float *cleaned;        /* the colour to diffuse (ddof_clean_silhouettes)           */
    uint64_t *chunk_pixels;
} split_job;

static const int step_x[4] = {-1, 1, 0, 0}, step_y[4] = {0, 0, -1, 1};

static int inside(const adi_request *r, int64_t x, int64_t y)
{
    return x >= 0 && y >= 0 && x < (int64_t)r->width && y < (int64_t)r->height;
}

static int is_sharp(const adi_request *r, float c)
{
    return fabsf(c) < r->in_focus_px || c == 0.0f;
}

static int is_blurred_behind(float c)
{
    return c >= DDOF_SILHOUETTE_MIN_COC_PX;
}

static const float *color_at(const split_job *job, int64_t x, int64_t y)
{
    return job->color + (size_t)y * job->color_stride + (size_t)x * job->r->channels;
}

static const float *out_at(const adi_request *r, int64_t x, int64_t y)
{
    return r->out + (size_t)y * r->out_stride + (size_t)x * r->channels;
}

static uint32_t matte_bits(const float *pair, uint32_t rank)
{
    uint32_t bits;
    memcpy(&bits, pair + 2 * rank, sizeof bits);
    return bits;
}

static const float *matte_pairs(const object_matte *m, int64_t x, int64_t y)
{
    return m->pairs + (size_t)y * m->stride + (size_t)x * 2 * m->ranks;
}

/* The coverage of object `id` at a pixel, 0..1. */
static float matte_coverage(const object_matte *m, int64_t x, int64_t y, uint32_t id)
{
    const float *pair = matte_pairs(m, x, y);
    double sum = 0.0;
    for (uint32_t k = 0; k < m->ranks; k++)
        if (matte_bits(pair, k) == id)
            sum += pair[2 * k + 1];
    return (float)(sum < 0.0 ? 0.0 : sum > 1.0 ? 1.0 : sum);
}

/* The coverage of every object at a pixel, 0..1 (the rest is the world's). */
static float matte_coverage_sum(const object_matte *m, int64_t x, int64_t y)
{
    const float *pair = matte_pairs(m, x, y);
    double sum = 0.0;
    for (uint32_t k = 0; k < m->ranks; k++)
        sum += pair[2 * k + 1];
    return (float)(sum < 0.0 ? 0.0 : sum > 1.0 ? 1.0 : sum);
}

/* The share of pixel (x, y) that the background pixel (bx, by) shows: its dominant object
 * (rank 0), or the world where no object covers most of it (the sky: Cryptomatte has no id for
 * what no object covers, only coverages that sum below 1). */
static float background_coverage(const object_matte *m, int64_t x, int64_t y, int64_t bx,
                                 int64_t by)
{
    const float *pair = matte_pairs(m, bx, by);
    const float world = 1.0f - matte_coverage_sum(m, bx, by);
    if (world > pair[1])
        return 1.0f - matte_coverage_sum(m, x, y);
    return matte_coverage(m, x, y, matte_bits(pair, 0));
}

/* The pair (sharp p, blurred q = p + d): the object's and the background's colours, and the
 * object's share of pixel (xx, xy), one of the two. 0 when the two colours are too alike to
 * split by and no matte tells. */
static int pair_colors(const split_job *job, int64_t px, int64_t py, int dir, int64_t xx,
                       int64_t xy, float object[3], float background[3], float *share,
                       float *object_share)
{
    const adi_request *r = job->r;
    const int64_t dx = step_x[dir], dy = step_y[dir];
    int64_t ox = px - dx, oy = py - dy;
    const int64_t bx = px + 2 * dx, by = py + 2 * dy;
    /* p is thin where the pixel behind it along d is in the frame and not sharp. */
    const int behind_inside = inside(r, ox, oy);
    const int thin = behind_inside && !is_sharp(r, adi_request_coc(r, ox, oy));
    if (thin || !behind_inside) {
        ox = px;
        oy = py;
    }
    int64_t bgx = px + dx, bgy = py + dy;
    if (inside(r, bx, by) && is_blurred_behind(adi_request_coc(r, bx, by))) {
        bgx = bx;
        bgy = by;
    }
    const float *o = color_at(job, ox, oy), *b = color_at(job, bgx, bgy);
    const float *x = color_at(job, xx, xy);
    for (int c = 0; c < 3; c++) {
        object[c] = o[c];
        background[c] = b[c];
    }
    const object_matte *m = job->matte;
    *object_share = 1.0f;
    if (m && m->ranks) {
        /* The object's share: all that is not the background's (its pixel's rank 0, or the
         * world), so that strands crossing at a pixel count together. */
        *share = 1.0f - background_coverage(m, xx, xy, bgx, bgy);
        const float at_p = 1.0f - background_coverage(m, px, py, bgx, bgy);
        if (at_p >= DDOF_MATTE_SOLVE_SHARE) {
            const float *p = color_at(job, px, py);
            for (int c = 0; c < 3; c++)
                object[c] = (p[c] - (1.0f - at_p) * b[c]) / at_p;
        }
        return 1;
    }
    double dot = 0.0, norm = 0.0, size = 0.0;
    for (int c = 0; c < 3; c++) {
        const double v = (double)o[c] - b[c];
        dot += ((double)x[c] - b[c]) * v;
        norm += v * v;
        size += (double)o[c] * o[c] + (double)b[c] * b[c];
    }
    /* Colours within 1% of each other say nothing of the share. */
    if (!(norm > 1e-4 * size) || !(norm > 1e-20))
        return 0;
    double a = dot / norm;
    if (thin) {
        *object_share = DDOF_THIN_OBJECT_SHARE;
        a = xx == px && xy == py
                ? DDOF_THIN_OBJECT_SHARE
                : (a < DDOF_THIN_NEIGHBOUR_SHARE ? a : DDOF_THIN_NEIGHBOUR_SHARE);
    }
    *share = (float)(a < 0.0 ? 0.0 : a > 1.0 ? 1.0 : a);
    return 1;
}

/* A blurred pixel q next to sharp ones: the mean over its pairs of the object share a, of
 * a O and of a B. */
typedef struct shares {
    double a, object[3], background[3];
    double mixed, mixed_background[3]; /* of a (1 - the object's share of O), and of that B */
} shares;

static int blurred_shares(const split_job *job, int64_t x, int64_t y, shares *s)
{
    const adi_request *r = job->r;
    memset(s, 0, sizeof *s);
    int pairs = 0;
    for (int dir = 0; dir < 4; dir++) {
        const int64_t px = x - step_x[dir], py = y - step_y[dir];
        float object[3], background[3], a, o;
        if (!inside(r, px, py) || !is_sharp(r, adi_request_coc(r, px, py)) ||
            !pair_colors(job, px, py, dir, x, y, object, background, &a, &o))
            continue;
        s->a += a;
        s->mixed += (double)a * (1.0 - o);
        for (int c = 0; c < 3; c++) {
            s->object[c] += (double)a * object[c];
            s->background[c] += (double)a * background[c];
            s->mixed_background[c] += (double)a * (1.0 - o) * background[c];
        }
        pairs++;
    }
    if (pairs) {
        s->a /= pairs;
        s->mixed /= pairs;
        for (int c = 0; c < 3; c++) {
            s->object[c] /= pairs;
            s->background[c] /= pairs;
            s->mixed_background[c] /= pairs;
        }
    }
    return pairs;
}

/* The change of a blurred pixel q next to sharp ones: its object share put back sharp (a O, and
 * where O is a thin pixel, a (1 - its object share) (out - B): O's background blurred). */
static int blurred_side(const split_job *job, int64_t x, int64_t y, float delta[3])
{
    const float *out = out_at(job->r, x, y);
    shares s;
    const int pairs = blurred_shares(job, x, y, &s);
    for (int c = 0; c < 3; c++)
        delta[c] = pairs ? (float)(s.object[c] + (s.mixed - s.a) * out[c] -
                                   s.mixed_background[c])
                         : 0.0f;
    return pairs;
}

/* The change of a sharp pixel p next to blurred ones: its background share blurred. */
static int sharp_side(const split_job *job, int64_t x, int64_t y, float delta[3])
{
    const adi_request *r = job->r;
    double sum[3] = {0.0, 0.0, 0.0};
    int pairs = 0;
    for (int dir = 0; dir < 4; dir++) {
        const int64_t qx = x + step_x[dir], qy = y + step_y[dir];
        float object[3], background[3], a, o;
        if (!inside(r, qx, qy) || !is_blurred_behind(adi_request_coc(r, qx, qy)) ||
            !pair_colors(job, x, y, dir, x, y, object, background, &a, &o))
            continue;
        const float *blurred = out_at(r, qx, qy);
        for (int c = 0; c < 3; c++)
            sum[c] += (1.0 - (double)a) * ((double)blurred[c] - background[c]);
        pairs++;
    }
    for (int c = 0; c < 3; c++)
        delta[c] = pairs ? (float)(sum[c] / pairs) : 0.0f;
    return pairs;
}

static void delta_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    split_job *job = user;
    const adi_request *r = job->r;
    uint64_t pixels = 0;
    for (uint32_t y = y0; y < y1; y++)
        for (uint32_t x = 0; x < r->width; x++) {
            float *delta = job->delta + ((size_t)y * r->width + x) * 3;
            const float c = adi_request_coc(r, x, y);
            int pairs = 0;
            if (is_blurred_behind(c))
                pairs = blurred_side(job, x, y, delta);
            else if (is_sharp(r, c))
                pairs = sharp_side(job, x, y, delta);
            else
                delta[0] = delta[1] = delta[2] = 0.0f;
            pixels += pairs > 0;
        }
    job->chunk_pixels[chunk] = pixels;
}

static void apply_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    const split_job *job = user;
    const adi_request *r = job->r;
    if (!job->chunk_pixels[chunk])
        return; /* no pair in these rows: their deltas are all 0 */
    for (uint32_t y = y0; y < y1; y++) {
        float *out = r->out + (size_t)y * r->out_stride;
        const float *delta = job->delta + (size_t)y * r->width * 3;
        for (uint32_t x = 0; x < r->width; x++)
            for (int c = 0; c < 3; c++)
                out[(size_t)x * r->channels + (size_t)c] += delta[(size_t)x * 3 + (size_t)c];
    }
}

/* The colour the layers diffuse: each blurred pixel's object share replaced by the background
 * (x + a (B - O), which is B for x = a O + (1 - a) B), so that the object is not smeared into
 * the blur and its light is not counted twice when the split puts it back. */
static void clean_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    split_job *job = user;
    const adi_request *r = job->r;
    uint64_t pixels = 0;
    for (uint32_t y = y0; y < y1; y++) {
        const float *in = job->color + (size_t)y * job->color_stride;
        float *out = job->cleaned + (size_t)y * r->width * r->channels;
        memcpy(out, in, (size_t)r->width * r->channels * sizeof(float));
        for (uint32_t x = 0; x < r->width; x++) {
            shares s;
            if (!is_blurred_behind(adi_request_coc(r, x, y)) || !blurred_shares(job, x, y, &s))
                continue;
            for (int c = 0; c < 3; c++)
                out[(size_t)x * r->channels + (size_t)c] +=
                    (float)(s.background[c] - s.object[c]);
            pixels++;
        }
    }
    job->chunk_pixels[chunk] = pixels;
}

/* Whether rows [y0, y1) hold a blurred pixel behind a sharp 4-neighbour, from the CoC alone. */
static int rows_have_pair(const adi_request *r, uint32_t y0, uint32_t y1)
{
    for (uint32_t y = y0; y < y1; y++)
        for (uint32_t x = 0; x < r->width; x++) {
            if (!is_blurred_behind(adi_request_coc(r, x, y)))
                continue;
            for (int dir = 0; dir < 4; dir++) {
                const int64_t px = (int64_t)x - step_x[dir], py = (int64_t)y - step_y[dir];
                if (inside(r, px, py) && is_sharp(r, adi_request_coc(r, px, py)))
                    return 1;
            }
        }
    return 0;
}

/* The scan before the split: chunk_pixels[chunk] is 1 when the chunk's rows hold a pair, else
 * 0; only whether the frame has one matters, so a chunk stops at its first. */
static void pair_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    split_job *job = user;
    job->chunk_pixels[chunk] = (uint64_t)rows_have_pair(job->r, y0, y1);
}

ddof_status ddof_clean_silhouettes(ddof_context *context, const adi_request *r,
                                   const object_matte *matte, const float **color,
                                   size_t *color_stride, int *pairs)
{
    *pairs = 0;
    if (r->channels < 3)
        return DDOF_OK;
    const uint32_t chunks = ddof_row_chunks(r->height);
    /* A frame without a pair pays one read of its CoC: no copy, no split. */
    uint64_t counts[(DDOF_MAX_DIMENSION + DDOF_ROWS_PER_CHUNK - 1) / DDOF_ROWS_PER_CHUNK];
    split_job scan = {.r = r, .chunk_pixels = counts};
    ddof_parallel_rows(context, r->height, pair_rows, &scan);
    for (uint32_t c = 0; c < chunks && !*pairs; c++)
        *pairs = counts[c] > 0;
    if (!*pairs)
        return DDOF_OK;
    const size_t floats = (size_t)r->width * r->height * r->channels;
    uint64_t *chunk_pixels = ddof_scratch_get(context, DDOF_SCRATCH_SILHOUETTE_COLOR,
                                              chunks * sizeof(uint64_t) + floats * sizeof(float));
    if (!chunk_pixels)
        return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                         "could not allocate the silhouettes' %ux%u colour", r->width,
                         r->height);
    split_job job = {.r = r, .matte = matte, .color = *color, .color_stride = *color_stride,
                     .cleaned = (float *)(void *)(chunk_pixels + chunks),
                     .chunk_pixels = chunk_pixels};
    ddof_parallel_rows(context, r->height, clean_rows, &job);
    uint64_t pixels = 0;
    for (uint32_t c = 0; c < chunks; c++)
        pixels += chunk_pixels[c];
    if (pixels) {
        *color = job.cleaned;
        *color_stride = (size_t)r->width * r->channels;
    }
    return DDOF_OK;
}

/* The split's scratch: per-chunk pixel counts, then the delta image (width x height x 3). */
static uint64_t *split_scratch(ddof_context *context, const adi_request *r, float **delta)
{
    const uint32_t chunks = ddof_row_chunks(r->height);
    const size_t pixels = (size_t)r->width * r->height;
    uint64_t *chunk_pixels = ddof_scratch_get(
        context, DDOF_SCRATCH_SILHOUETTES, chunks * sizeof(uint64_t) + 3 * pixels * sizeof(float));
    *delta = chunk_pixels ? (float *)(void *)(chunk_pixels + chunks) : NULL;
    return chunk_pixels;
}

float *ddof_silhouettes_scratch(ddof_context *context, const adi_request *r)
{
    float *delta;
    split_scratch(context, r, &delta);
    return delta;
}

ddof_status ddof_split_silhouettes(ddof_context *context, const adi_request *r,
                                   const object_matte *matte, const float *color,
                                   size_t color_stride, silhouette_report *report)
{
    memset(report, 0, sizeof *report);
    if (r->channels < 3)
        return DDOF_OK;
    const uint32_t chunks = ddof_row_chunks(r->height);
    float *delta;
    uint64_t *chunk_pixels = split_scratch(context, r, &delta);
    if (!chunk_pixels)
        return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                         "could not allocate the silhouettes' %ux%u image", r->width, r->height);
    split_job job = {.r = r, .matte = matte, .color = color, .color_stride = color_stride,
                     .delta = delta, .chunk_pixels = chunk_pixels};
    ddof_parallel_rows(context, r->height, delta_rows, &job);
    for (uint32_t c = 0; c < chunks; c++)
        report->pixels += chunk_pixels[c];
    if (report->pixels)
        ddof_parallel_rows(context, r->height, apply_rows, &job);
    return DDOF_OK;
}
