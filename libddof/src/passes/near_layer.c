/* SPDX-License-Identifier: MIT */
/* near_layer.c - the near field of one image split off as a foreground element, and the fill of
 * what it hid (near_layer.h).
 *
 * A hole pixel's fill is the mean of two guesses, each a weighted mean of sources (so the fill
 * is NaN-free, within the sources' range, and a frame without any source says so: split->filled
 * = 0, and the rest keeps the input there):
 *  - pull-push (Gortler et al. 1996, "The Lumigraph"): the sources' values averaged down a
 *    pyramid of halved images, each coarse pixel's weight the sum of its children's clamped to
 *    1, and pushed back up, each pixel keeping its own value by its weight and taking the rest
 *    from the coarser level, bilinearly. Fills a hole of any size in time linear in the frame,
 *    smoothly, but blends everything around a large hole;
 *  - across the hole: along its row, its column and both diagonals, linear between the sources
 *    at the two ends of each run, the shorter runs dominating (weight 1 / length^2). Across a
 *    thin near object the two sides it separates are the best guess of what it hides, and of
 *    four directions one runs nearly across any object; a single line streaks, so its end
 *    values are 2x2 means of sources (the pyramid's first level). Pull-push fills only what no
 *    line reaches (a hole whose every line ends at the frame's edge).
 * Then near_offsets_fill.c copies from where the frame repeats itself, where its surroundings say
 * that it does. Measured on the study's near scenes (docs/accuracy.md, the near layer). */
#include "near_layer.h"

#include "near_offsets.h"
#include "runtime/parallel_rows.h"

#include <math.h>
#include <string.h>

/* Colour channels (at most 4) plus the signed CoC. */
#define MAX_VALUES 5

/* The pyramid level whose means are the line fill's end values (2x2 pixels: one texel of a
 * textured surface no longer streaks across a run; coarser levels measured no better). */
#define END_LEVEL DDOF_NEAR_END_LEVEL

typedef struct level {
    uint32_t width, height;
    float *values; /* `count` values per pixel, the weighted mean of its sources */
    float *weight; /* in [0, 1]                                                  */
} level;

enum { MAX_LEVELS = 32 };

typedef struct pyramid {
    level levels[MAX_LEVELS]; /* levels[0] is the frame itself, read through the request */
    uint32_t count;           /* levels, the frame included                              */
    uint32_t values;          /* values per pixel: channels + 1                          */
} pyramid;

typedef struct split_job {
    const adi_request *r;
    float threshold;
    pyramid *p;
    uint32_t from; /* pull: the level read; push: the level written */
    int32_t diagonal_dx; /* fill_diagonals: down and right (1) or down and left (-1) */
    float *rest, *rest_coc, *element;
    float *carried;     /* the matte times the input's alpha (4 channels)              */
    float *line_weight; /* the line fill's summed weights per pixel (0: no line reached) */
    float *source;      /* each pixel's weight as a source of the fill (0: none)       */
    float *matte;       /* each pixel's share in the element                            */
    float *element_coc; /* the element's |CoC|                                          */
    float *fringe;      /* 1 where a fringe pixel was split (matte_rows wrote it)       */
    near_split *chunks; /* finish: one per row chunk */
} split_job;

/* The element's fringe. A pinhole render's depth is not anti-aliased: the pixels around a near
 * object hold some of its colour with the depth behind it. Where the object is much brighter
 * than what lies behind (a light: its rim holds much of its light), such a pixel C (matte 0,
 * beside a pixel of matte 1) is split as a matte would: its near neighbour F (the one of
 * largest |CoC|) and the pixel on the far side of it, B (mirrored through C), give C's share of
 * F, a = (C - B).(F - B) / |F - B|^2 in [0, 0.95] and no more than C / F in any channel; the
 * element takes a F (premultiplied, alpha a, F's CoC) and the rest (C - a F) / (1 - a) >= 0, so
 * that the composite gives C back where nothing blurs. Left whole in the rest, a light's rim is blurred with the
 * background's CoC and fills the light's own hole: on the study's highlights scene the near
 * layer lost 4.4 dB without the split. Where the object is not FRINGE_CONTRAST times brighter
 * than B the split is not made: there the first sample's depth already divides a silhouette's
 * mixed pixels about evenly, and splitting them too made the element heavier (near_railing
 * -0.45 dB). Returns whether the pixel was split (its element and rest written). */
#define FRINGE_CONTRAST DDOF_NEAR_FRINGE_CONTRAST
#define FRINGE_MAX_SHARE DDOF_NEAR_FRINGE_MAX_SHARE

static int split_fringe(const split_job *j, uint32_t x, uint32_t y)
{
    const adi_request *r = j->r;
    const uint32_t C = r->channels;
    float near = 0.0f;
    uint32_t fx = 0, fy = 0;
    for (uint32_t ny = y ? y - 1 : 0; ny <= y + 1 && ny < r->height; ny++)
        for (uint32_t nx = x ? x - 1 : 0; nx <= x + 1 && nx < r->width; nx++) {
            const float nc = adi_request_coc(r, nx, ny);
            if (ddof_near_matte(nc, j->threshold) >= 1.0f && -nc > near) {
                near = -nc;
                fx = nx;
                fy = ny;
            }
        }
    if (near <= 0.0f)
        return 0;
    const int64_t bx = 2 * (int64_t)x - fx, by = 2 * (int64_t)y - fy;
    const float *c = r->color + (size_t)y * r->color_stride + (size_t)x * C;
    const float *f = r->color + (size_t)fy * r->color_stride + (size_t)fx * C;
    const float *b = bx >= 0 && by >= 0 && bx < r->width && by < r->height
                         ? r->color + (size_t)by * r->color_stride + (size_t)bx * C
                         : c;
    if (!(ddof_maxf(f[0], ddof_maxf(f[1], f[2])) >
          FRINGE_CONTRAST * ddof_maxf(b[0], ddof_maxf(b[1], b[2]))))
        return 0;
    double num = 0.0, den = 0.0;
    for (uint32_t k = 0; k < 3; k++) {
        num += ((double)c[k] - b[k]) * ((double)f[k] - b[k]);
        den += ((double)f[k] - b[k]) * ((double)f[k] - b[k]);
    }
    float a = den > 1e-12 ? ddof_minf(FRINGE_MAX_SHARE, ddof_maxf(0.0f, (float)(num / den)))
                          : 0.0f;
    for (uint32_t k = 0; k < 3; k++) /* a F <= C in every channel: the rest stays >= 0 */
        if (f[k] > 0.0f && a * f[k] > c[k])
            a = ddof_maxf(0.0f, c[k] / f[k]);
    const size_t i = (size_t)y * r->width + x;
    float *element = j->element + i * 4, *rest = j->rest + i * C;
    for (uint32_t k = 0; k < C; k++) {
        const float e = k < 3 ? a * f[k] : 0.0f;
        rest[k] = k < 3 ? ddof_maxf(0.0f, (c[k] - e) / (1.0f - a)) : c[k];
        if (k < 3)
            element[k] = e;
    }
    element[3] = a;
    j->rest_coc[i] = adi_request_coc(r, x, y);
    j->matte[i] = a;
    j->element_coc[i] = near;
    j->fringe[i] = 1.0f;
    return 1;
}

/* Per pixel: its matte and the element's CoC (a fringe pixel split), and its weight as a
 * source of the fill: outside the element, a near one counting less the more blurred it is
 * (what a near object hides is background, not more of the near field; > 0.5 on this side of
 * threshold / 2), a split fringe pixel by its rest's share. */
static void matte_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const split_job *j = user;
    const adi_request *r = j->r;
    for (uint32_t y = y0; y < y1; y++)
        for (uint32_t x = 0; x < r->width; x++) {
            const size_t i = (size_t)y * r->width + x;
            const float c = adi_request_coc(r, x, y);
            const float m = ddof_near_matte(c, j->threshold);
            j->fringe[i] = 0.0f;
            if (m <= 0.0f && split_fringe(j, x, y)) {
                j->source[i] = 1.0f - j->matte[i];
                continue;
            }
            j->matte[i] = m;
            j->element_coc[i] = fabsf(c);
            j->source[i] = m > 0.0f ? 0.0f : c >= 0.0f ? 1.0f : 1.0f + c / j->threshold;
        }
}

/* The values and weight of pixel (x, y) of level l: level 0 is the request's frame. */
static float fetch(const split_job *j, uint32_t l, uint32_t x, uint32_t y, float *v)
{
    const pyramid *p = j->p;
    if (l == 0) {
        const adi_request *r = j->r;
        const size_t i = (size_t)y * r->width + x;
        if (j->source[i] <= 0.0f)
            return 0.0f;
        /* A split fringe pixel is a source by its rest's part. */
        const float *px = j->fringe[i] > 0.0f
                              ? j->rest + i * r->channels
                              : r->color + (size_t)y * r->color_stride + (size_t)x * r->channels;
        for (uint32_t k = 0; k < r->channels; k++)
            v[k] = px[k];
        v[r->channels] = adi_request_coc(r, x, y);
        return j->source[i];
    }
    const level *lv = &p->levels[l];
    const size_t i = (size_t)y * lv->width + x;
    memcpy(v, lv->values + i * p->values, p->values * sizeof(float));
    return lv->weight[i];
}

/* Pixel (x, y) of level from + 1 from level from: the weighted mean of its (up to 4)
 * children. */
static void pull_pixel(const split_job *j, const level *fine, const level *coarse, uint32_t x,
                       uint32_t y)
{
    const uint32_t n = j->p->values;
    float sum[MAX_VALUES] = {0}, v[MAX_VALUES];
    float total = 0.0f;
    for (uint32_t dy = 0; dy < 2; dy++)
        for (uint32_t dx = 0; dx < 2; dx++) {
            const uint32_t fx = 2 * x + dx, fy = 2 * y + dy;
            if (fx >= fine->width || fy >= fine->height)
                continue;
            const float w = fetch(j, j->from, fx, fy, v);
            if (w <= 0.0f)
                continue;
            total += w;
            for (uint32_t k = 0; k < n; k++)
                sum[k] += w * v[k];
        }
    const size_t i = (size_t)y * coarse->width + x;
    for (uint32_t k = 0; k < n; k++)
        coarse->values[i * n + k] = total > 0.0f ? sum[k] / total : 0.0f;
    coarse->weight[i] = ddof_minf(1.0f, total);
}

/* The coarse level's values at fine pixel (x, y), bilinearly (pixel centres aligned). */
static void upsample(const level *coarse, uint32_t n, uint32_t x, uint32_t y, float *out)
{
    const float u = ddof_maxf(0.0f, 0.5f * (float)x - 0.25f);
    const float t = ddof_maxf(0.0f, 0.5f * (float)y - 0.25f);
    uint32_t x0 = (uint32_t)u, y0 = (uint32_t)t;
    x0 = x0 < coarse->width ? x0 : coarse->width - 1;
    y0 = y0 < coarse->height ? y0 : coarse->height - 1;
    const uint32_t x1 = x0 + 1 < coarse->width ? x0 + 1 : x0;
    const uint32_t y1 = y0 + 1 < coarse->height ? y0 + 1 : y0;
    const float fx = ddof_minf(1.0f, u - (float)x0), fy = ddof_minf(1.0f, t - (float)y0);
    const float *a = coarse->values + ((size_t)y0 * coarse->width + x0) * n;
    const float *b = coarse->values + ((size_t)y0 * coarse->width + x1) * n;
    const float *c = coarse->values + ((size_t)y1 * coarse->width + x0) * n;
    const float *d = coarse->values + ((size_t)y1 * coarse->width + x1) * n;
    for (uint32_t k = 0; k < n; k++) {
        const float top = a[k] + fx * (b[k] - a[k]);
        const float bottom = c[k] + fx * (d[k] - c[k]);
        out[k] = top + fy * (bottom - top);
    }
}

/* Pixel (x, y) of level `from` (>= 1) takes what its weight leaves from level from + 1; its
 * weight becomes 1. */
static void push_pixel(const split_job *j, const level *fine, const level *coarse, uint32_t x,
                       uint32_t y)
{
    const uint32_t n = j->p->values;
    const size_t i = (size_t)y * fine->width + x;
    const float w = fine->weight[i];
    if (w >= 1.0f)
        return;
    float up[MAX_VALUES];
    upsample(coarse, n, x, y, up);
    float *v = fine->values + i * n;
    for (uint32_t k = 0; k < n; k++)
        v[k] = w * v[k] + (1.0f - w) * up[k];
    fine->weight[i] = 1.0f;
}

typedef void (*level_pixel)(const split_job *j, const level *fine, const level *coarse,
                            uint32_t x, uint32_t y);

/* Rows y0..y1 of the level a pull or a push writes (the coarse one, or the fine one), each
 * pixel by `pixel`: the two passes between levels from and from + 1 walk them alike. */
static void level_rows(const split_job *j, uint32_t y0, uint32_t y1, int writes_coarse,
                       level_pixel pixel)
{
    const level *fine = &j->p->levels[j->from];
    const level *coarse = &j->p->levels[j->from + 1];
    const uint32_t width = writes_coarse ? coarse->width : fine->width;
    for (uint32_t y = y0; y < y1; y++)
        for (uint32_t x = 0; x < width; x++)
            pixel(j, fine, coarse, x, y);
}

static void pull_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    level_rows(user, y0, y1, 1, pull_pixel);
}

static void push_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    level_rows(user, y0, y1, 0, push_pixel);
}

static int is_source(const split_job *j, uint32_t x, uint32_t y)
{
    return j->source[(size_t)y * j->r->width + x] > 0.0f;
}

/* A line's end value at source pixel (x, y): its neighbourhood's mean of sources (colour, then
 * CoC, from the pyramid), so that one texel of a textured surface does not streak across the
 * whole run. */
static void end_value(const split_job *j, uint32_t x, uint32_t y, float *v)
{
    const level *lv = &j->p->levels[END_LEVEL];
    const size_t i = (size_t)(y >> END_LEVEL) * lv->width + (x >> END_LEVEL);
    memcpy(v, lv->values + i * j->p->values, j->p->values * sizeof(float));
}

/* Interpolation across a run of non-source pixels [a, b) of one line, from its sources at a - 1
 * and b (either may be missing: the line's end); `step` is the distance between the line's
 * pixels. Writes the value at offset i of the run and returns its weight, 1 / (run length)^2,
 * so that the shortest of a pixel's runs dominates: across a thin near object, the two sides
 * it separates are the best guess of what it hides. A run with a source at one end only is a
 * weaker guess (its length counts twice); one without any, none. */
static float across_run(const float *before, const float *after, uint32_t n, uint32_t a,
                        uint32_t b, uint32_t i, float step, float *out)
{
    const float length = (float)(b - a + 1) * step;
    if (before && after) {
        const float t = (float)(i - a + 1) / (float)(b - a + 1);
        for (uint32_t k = 0; k < n; k++)
            out[k] = before[k] + t * (after[k] - before[k]);
        return 1.0f / (length * length);
    }
    const float *only = before ? before : after;
    if (!only) {
        memset(out, 0, n * sizeof(float)); /* weightless, but added as 0 * value */
        return 0.0f;
    }
    memcpy(out, only, n * sizeof(float));
    return 0.25f / (length * length);
}

/* One line of the frame: `length` pixels from (x, y) in steps of (dx, dy). */
typedef struct line {
    uint32_t x, y, length;
    int32_t dx, dy;
} line;

/* What the walk does with a non-source pixel (x, y): v, its interpolation across the run
 * (colour, then CoC), and the weight across_run gave it. */
typedef void (*run_visit)(const split_job *j, uint32_t x, uint32_t y, const float *v, float w);

/* Calls visit for every non-source pixel of the line, with its run's interpolation. */
static void walk_runs(const split_job *j, line l, run_visit visit)
{
    const uint32_t n = j->r->channels + 1;
    const float step = l.dx && l.dy ? 1.41421356f : 1.0f;
    float before[MAX_VALUES], after[MAX_VALUES], v[MAX_VALUES];
#define AT(k)                                                                                  \
    (uint32_t)((int64_t)l.x + (int64_t)(k) * l.dx), (uint32_t)((int64_t)l.y + (int64_t)(k) * l.dy)
    uint32_t a = 0;
    while (a < l.length) {
        if (is_source(j, AT(a))) {
            a++;
            continue;
        }
        uint32_t b = a;
        while (b < l.length && !is_source(j, AT(b)))
            b++;
        if (a > 0)
            end_value(j, AT(a - 1), before);
        if (b < l.length)
            end_value(j, AT(b), after);
        for (uint32_t i = a; i < b; i++) {
            const float w = across_run(a > 0 ? before : NULL, b < l.length ? after : NULL, n,
                                       a, b, i, step, v);
            visit(j, AT(i), v, w);
        }
        a = b + 1;
    }
#undef AT
}

/* The first direction (rows): the weighted interpolation into the rest (colour and CoC) and
 * its weight, at every non-source pixel (the ramp's are overwritten by finish_rows). */
static void store_line_fill(const split_job *j, uint32_t x, uint32_t y, const float *v, float w)
{
    const uint32_t C = j->r->channels;
    const size_t p = (size_t)y * j->r->width + x;
    j->line_weight[p] = w;
    for (uint32_t k = 0; k < C; k++)
        j->rest[p * C + k] = w * v[k];
    j->rest_coc[p] = w * v[C];
}

/* The other directions: added in, holes only. */
static void add_line_fill(const split_job *j, uint32_t x, uint32_t y, const float *v, float w)
{
    const size_t p = (size_t)y * j->r->width + x;
    if (j->matte[p] < 1.0f || w <= 0.0f)
        return;
    const uint32_t C = j->r->channels;
    j->line_weight[p] += w;
    for (uint32_t k = 0; k < C; k++)
        j->rest[p * C + k] += w * v[k];
    j->rest_coc[p] += w * v[C];
}

static void fill_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const split_job *j = user;
    for (uint32_t y = y0; y < y1; y++)
        walk_runs(j, (line){0, y, j->r->width, 1, 0}, store_line_fill);
}

/* Called over column chunks (after fill_rows). */
static void fill_columns(void *user, uint32_t x0, uint32_t x1, uint32_t chunk)
{
    (void)chunk;
    const split_job *j = user;
    for (uint32_t x = x0; x < x1; x++)
        walk_runs(j, (line){x, 0, j->r->height, 0, 1}, add_line_fill);
}

/* Diagonal number d of width + height - 1, going down and right (dx = 1) or down and left
 * (dx = -1): each starts on the top row, then down the side it comes from. */
static line diagonal(uint32_t width, uint32_t height, uint32_t d, int32_t dx)
{
    const uint32_t x = d < width ? (dx > 0 ? d : width - 1 - d) : (dx > 0 ? 0 : width - 1);
    const uint32_t y = d < width ? 0 : d - width + 1;
    const uint32_t across = dx > 0 ? width - x : x + 1;
    const uint32_t down = height - y;
    return (line){x, y, across < down ? across : down, dx, 1};
}

/* Called over the diagonals (width + height - 1), in the direction j->diagonal_dx. */
static void fill_diagonals(void *user, uint32_t d0, uint32_t d1, uint32_t chunk)
{
    (void)chunk;
    const split_job *j = user;
    for (uint32_t d = d0; d < d1; d++)
        walk_runs(j, diagonal(j->r->width, j->r->height, d, j->diagonal_dx), add_line_fill);
}

/* A hole's line fill: the weighted sum divided by its weight; pull-push where no line reached
 * a source. */
static void settle_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const split_job *j = user;
    const adi_request *r = j->r;
    const uint32_t C = r->channels, n = C + 1;
    for (uint32_t y = y0; y < y1; y++)
        for (uint32_t x = 0; x < r->width; x++) {
            const size_t p = (size_t)y * r->width + x;
            if (j->matte[p] < 1.0f)
                continue;
            float *rest = j->rest + p * C;
            const float w = j->line_weight[p];
            if (w > 0.0f) {
                for (uint32_t k = 0; k < C; k++)
                    rest[k] /= w;
                j->rest_coc[p] /= w;
            } else {
                float pp[MAX_VALUES];
                upsample(&j->p->levels[1], n, x, y, pp);
                memcpy(rest, pp, C * sizeof(float));
                j->rest_coc[p] = pp[C];
            }
        }
}

/* The frame's pixels: the element, and the rest with its holes filled from level 1. */
static void finish_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    const split_job *j = user;
    const adi_request *r = j->r;
    const uint32_t C = r->channels;
    const int filled = j->p->count > 1;
    near_split s = {.box = box_empty()};
    for (uint32_t y = y0; y < y1; y++) {
        const float *in = r->color + (size_t)y * r->color_stride;
        float *rest = j->rest + (size_t)y * r->width * C;
        float *rest_coc = j->rest_coc + (size_t)y * r->width;
        float *element = j->element + (size_t)y * r->width * 4;
        for (uint32_t x = 0; x < r->width; x++) {
            const size_t i = (size_t)y * r->width + x;
            const float c = adi_request_coc(r, x, y);
            const float m = j->matte[i];
            const float *px = in + (size_t)x * C;
            if (C == 4) {
                j->carried[i] = m * px[3];
                s.carried_alpha = m > 0.0f && px[3] != 1.0f ? j->carried : s.carried_alpha;
            }
            if (m > 0.0f) {
                s.element_pixels++;
                box_add(&s.box, x, y);
                s.max_coc = ddof_maxf(s.max_coc, j->element_coc[i]);
            }
            if (j->fringe[i] > 0.0f)
                continue; /* split by matte_rows: element and rest written */
            for (uint32_t k = 0; k < 3; k++)
                element[x * 4 + k] = m * px[k];
            element[x * 4 + 3] = m;
            if (m >= 1.0f && filled) {
                s.holes++; /* filled by fill_rows and fill_columns */
            } else {
                memcpy(rest + (size_t)x * C, px, C * sizeof(float));
                rest_coc[x] = c;
            }
        }
    }
    j->chunks[chunk] = s;
}

/* The pyramid's levels 1.. (halved, rounded up, down to 1 x 1) laid out in one block of
 * scratch memory; returns the floats it needs, and with memory != NULL points the levels
 * into it. */
static size_t lay_out(pyramid *p, uint32_t width, uint32_t height, float *memory)
{
    size_t used = 0;
    p->levels[0] = (level){width, height, NULL, NULL};
    p->count = 1;
    while ((width > 1 || height > 1) && p->count < MAX_LEVELS) {
        width = (width + 1) / 2;
        height = (height + 1) / 2;
        const size_t pixels = (size_t)width * height;
        level *l = &p->levels[p->count++];
        *l = (level){width, height, memory ? memory + used : NULL,
                     memory ? memory + used + pixels * p->values : NULL};
        used += pixels * (p->values + 1);
    }
    return used;
}

ddof_status ddof_split_near(ddof_context *context, const adi_request *r, float threshold,
                            near_split *split)
{
    enum { max_chunks = (DDOF_MAX_DIMENSION + DDOF_ROWS_PER_CHUNK - 1) / DDOF_ROWS_PER_CHUNK };
    const size_t pixels = (size_t)r->width * r->height;
    pyramid p = {.values = r->channels + 1};
    const size_t pyramid_floats = lay_out(&p, r->width, r->height, NULL);
    float *rest = ddof_scratch_get(context, DDOF_SCRATCH_NEAR_REST,
                                   pixels * r->channels * sizeof(float));
    float *rest_coc = ddof_scratch_get(context, DDOF_SCRATCH_NEAR_REST_COC, pixels * sizeof(float));
    float *element = ddof_scratch_get(context, DDOF_SCRATCH_NEAR_ELEMENT,
                                      pixels * 4 * sizeof(float));
    float *levels = ddof_scratch_get(context, DDOF_SCRATCH_NEAR_PYRAMID,
                                     (pyramid_floats + 6 * pixels) * sizeof(float));
    if (!rest || !rest_coc || !element || !levels)
        return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                         "could not allocate the near layer's images for %ux%u", r->width,
                         r->height);
    lay_out(&p, r->width, r->height, levels);

    near_split chunks[max_chunks];
    /* After the pyramid: the line fill's weights, the carried alpha, the source weights, the
     * matte, the element's CoC, the fringe's marks. */
    float *maps = levels + pyramid_floats;
    split_job job = {.r = r,
                     .threshold = threshold,
                     .p = &p,
                     .rest = rest,
                     .rest_coc = rest_coc,
                     .element = element,
                     .line_weight = maps,
                     .carried = maps + pixels,
                     .source = maps + 2 * pixels,
                     .matte = maps + 3 * pixels,
                     .element_coc = maps + 4 * pixels,
                     .fringe = maps + 5 * pixels,
                     .chunks = chunks};
    ddof_parallel_rows(context, r->height, matte_rows, &job);
    for (job.from = 0; job.from + 1 < p.count; job.from++)
        ddof_parallel_rows(context, p.levels[job.from + 1].height, pull_rows, &job);
    /* No source anywhere (every pixel in the element): nothing to fill the holes with. */
    const int filled = p.count > 1 && p.levels[p.count - 1].weight[0] > 0.0f;
    if (!filled)
        p.count = 1;
    for (job.from = p.count > 1 ? p.count - 2 : 0; job.from >= 1; job.from--)
        ddof_parallel_rows(context, p.levels[job.from].height, push_rows, &job);
    if (filled) {
        ddof_parallel_rows(context, r->height, fill_rows, &job);
        ddof_parallel_rows(context, r->width, fill_columns, &job);
        for (job.diagonal_dx = 1; job.diagonal_dx >= -1; job.diagonal_dx -= 2)
            ddof_parallel_rows(context, r->width + r->height - 1, fill_diagonals, &job);
        ddof_parallel_rows(context, r->height, settle_rows, &job);
        const ddof_status st = ddof_fill_from_offsets(
            context, &(offset_fill){.frame = r, .source = job.source, .matte = job.matte,
                                    .rest = rest, .rest_coc = rest_coc});
        if (st != DDOF_OK)
            return st;
    }
    ddof_parallel_rows(context, r->height, finish_rows, &job);

    *split = (near_split){.rest = rest, .rest_coc = rest_coc, .element = element,
                          .element_coc = job.element_coc, .box = box_empty(), .filled = filled};
    for (uint32_t c = 0; c < ddof_row_chunks(r->height); c++) {
        split->box = box_union(split->box, chunks[c].box);
        split->max_coc = ddof_maxf(split->max_coc, chunks[c].max_coc);
        split->element_pixels += chunks[c].element_pixels;
        split->holes += chunks[c].holes;
        split->carried_alpha = chunks[c].carried_alpha ? chunks[c].carried_alpha
                                                       : split->carried_alpha;
    }
    return DDOF_OK;
}
