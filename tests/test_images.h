/* SPDX-License-Identifier: MIT */
/* test_images.h - image helpers shared by the tests that run the library on whole images
 * (test_invariants, test_hard_cases, test_coc, test_bad_input): allocation, fills, the call on
 * tightly packed images, error measures, padded-layout comparisons and the independent double
 * ADI step that the solvers are checked against. The generic CHECK macros and the RNG stay in
 * test_util.h, which this header includes.
 *
 * Everything is static inline so a test that does not use a helper does not warn about it. */
#ifndef DDOF_TEST_IMAGES_H
#define DDOF_TEST_IMAGES_H

#include "ddof.h"
#include "test_util.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------------------------------------- */
/* Buffers and contexts: a failure here is the test machine's, not the library's, so exit(2)  */
/* (what ctest shows as a crash of the test) rather than count a check.                       */

static inline float *alloc_f(size_t n)
{
    float *p = malloc((n ? n : 1) * sizeof(float));
    if (!p) {
        fprintf(stderr, "out of memory in the test\n");
        exit(2);
    }
    return p;
}

static inline ddof_context *make_context(uint32_t threads)
{
    ddof_context_options options;
    ddof_context_options_init(&options);
    options.thread_count = threads;
    ddof_context *ctx = NULL;
    ddof_status s = ddof_context_create(&options, &ctx);
    if (s != DDOF_OK || !ctx) {
        fprintf(stderr, "ddof_context_create failed: %d\n", (int)s);
        exit(2);
    }
    return ctx;
}

/* Scratch memory handed out full of one byte (carried in the allocator's user pointer): 0xff
 * is a NaN in every float, so a result that reads scratch it never wrote shows. */
static inline void *patterned_alloc(void *user, size_t size)
{
    void *p = malloc(size);
    if (p)
        memset(p, (int)(uintptr_t)user, size);
    return p;
}

static inline void patterned_free(void *user, void *p)
{
    (void)user;
    free(p);
}

/* A one-thread context whose scratch arrives filled with `byte`; NULL if it cannot be made. */
static inline ddof_context *patterned_context(unsigned char byte)
{
    const ddof_allocator a = {patterned_alloc, patterned_free, (void *)(uintptr_t)byte};
    ddof_context_options o;
    ddof_context_options_init(&o);
    o.thread_count = 1;
    o.allocator = &a;
    ddof_context *c = NULL;
    return ddof_context_create(&o, &c) == DDOF_OK ? c : NULL;
}

/* One case's tightly packed images: colour and output w x h x ch, CoC w x h (one channel).
 * Most cases need exactly these three buffers; image_free() releases them together. */
typedef struct test_image {
    uint32_t w, h, ch;
    size_t px, n; /* pixels; floats in the colour and the output */
    float *color, *coc, *out;
} test_image;

static inline test_image image_alloc(uint32_t w, uint32_t h, uint32_t ch)
{
    test_image im;
    im.w = w;
    im.h = h;
    im.ch = ch;
    im.px = (size_t)w * h;
    im.n = im.px * ch;
    im.color = alloc_f(im.n);
    im.coc = alloc_f(im.px);
    im.out = alloc_f(im.n);
    return im;
}

static inline void image_free(test_image *im)
{
    free(im->color);
    free(im->coc);
    free(im->out);
    im->color = im->coc = im->out = NULL;
}

/* Default parameters with the given solver and substep count. */
static inline ddof_params params_for(ddof_solver solver, uint32_t substeps)
{
    ddof_params p;
    heat_params_init(&p);
    p.solver = solver;
    p.substeps = substeps;
    /* The k whose kernel variance the tests derive (2 beta = d^2 / 16), not the default
     * preset's measured one, which the accuracy study may change. */
    p.beta_scale = DDOF_MOMENT_BETA_SCALE;
    return p;
}

/* Stats to be filled in: zeroed, struct_size set. */
static inline ddof_stats stats_init(void)
{
    ddof_stats st;
    memset(&st, 0, sizeof st);
    st.struct_size = sizeof st;
    return st;
}

/* ddof_diffuse on tightly packed images (row_stride 0): colour and output w x h x c, CoC
 * w x h x 1. stats may be NULL. */
static inline ddof_status diffuse(ddof_context *ctx, const ddof_params *params,
                                  const float *color, const float *coc, float *out, uint32_t w,
                                  uint32_t h, uint32_t c, ddof_stats *stats)
{
    ddof_image_in ci = {color, w, h, c, 0};
    ddof_image_in zi = {coc, w, h, 1, 0};
    ddof_image oi = {out, w, h, c, 0};
    return ddof_diffuse(ctx, params, &ci, &zi, &oi, stats);
}

/* ddof_diffuse_layers on tightly packed images, as diffuse() above; fg may be NULL. */
static inline ddof_status diffuse_layers(ddof_context *ctx, const ddof_params *params,
                                         const float *color, const float *coc,
                                         const ddof_foreground *fg, float *out, uint32_t w,
                                         uint32_t h, uint32_t c, ddof_stats *stats)
{
    ddof_image_in ci = {color, w, h, c, 0};
    ddof_image_in zi = {coc, w, h, 1, 0};
    ddof_image oi = {out, w, h, c, 0};
    return ddof_diffuse_layers(ctx, params, &ci, &zi, fg, &oi, stats);
}

/* Blocky random texture (8x8 blocks) in [lo, hi) on channels 0..2; channel 3 (alpha) is 1. */
static inline void block_texture(float *color, uint32_t w, uint32_t h, uint32_t ch,
                                 unsigned long long seed, double lo, double hi)
{
    test_rng rng = {seed};
    const uint32_t bw = (w + 7) / 8, bh = (h + 7) / 8;
    float *blocks = alloc_f((size_t)bw * bh * 3);
    for (size_t i = 0; i < (size_t)bw * bh * 3; i++)
        blocks[i] = (float)(lo + (hi - lo) * test_uniform(&rng));
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++)
            for (uint32_t c = 0; c < ch; c++)
                color[((size_t)y * w + x) * ch + c] =
                    c == 3 ? 1.0f : blocks[((size_t)(y / 8) * bw + x / 8) * 3 + c];
    free(blocks);
}

/* The layers' call on an RGBA frame (w x h, its RGBA result in out, colour overwritten) gives
 * the same RGB bit for bit as on its RGB channels alone, and in place the same as out of
 * place. */
static inline void check_rgb_and_in_place(ddof_context *ctx, const ddof_params *params,
                                          float *color, const float *coc, const float *out,
                                          uint32_t w, uint32_t h)
{
    const size_t pixels = (size_t)w * h;
    float *rgb = alloc_f(pixels * 3), *out3 = alloc_f(pixels * 3);
    for (size_t i = 0; i < pixels; i++)
        memcpy(rgb + i * 3, color + i * 4, 3 * sizeof(float));
    CHECK_EQ_INT(diffuse_layers(ctx, params, rgb, coc, NULL, out3, w, h, 3, NULL), DDOF_OK);
    double worst = 0.0;
    for (size_t i = 0; i < pixels; i++)
        for (int c = 0; c < 3; c++)
            worst = fmax(worst, fabs((double)out3[i * 3 + c] - out[i * 4 + (size_t)c]));
    CHECK_MSG(worst == 0.0, "3 and 4 channels differ by %.3g", worst);
    CHECK_EQ_INT(diffuse_layers(ctx, params, color, coc, NULL, color, w, h, 4, NULL), DDOF_OK);
    CHECK(memcmp(color, out, pixels * 4 * sizeof(float)) == 0);
    free(rgb);
    free(out3);
}

/* ddof_diffuse of im->color with im->coc into im->out. */
static inline ddof_status image_diffuse(ddof_context *ctx, const ddof_params *params,
                                        test_image *im, ddof_stats *stats)
{
    return diffuse(ctx, params, im->color, im->coc, im->out, im->w, im->h, im->ch, stats);
}

/* An artist curve: near_blur px up to near_start, falling to 0 at near_end, 0 up to far_start,
 * rising to far_blur px at far_end; every other field at its default. */
static inline ddof_curve curve_of(double near_blur, double near_start, double near_end,
                                  double far_start, double far_end, double far_blur)
{
    ddof_curve cv;
    ddof_curve_init(&cv);
    cv.near_blur_px = near_blur;
    cv.near_start = near_start;
    cv.near_end = near_end;
    cv.far_start = far_start;
    cv.far_end = far_end;
    cv.far_blur_px = far_blur;
    return cv;
}

/* ---------------------------------------------------------------------------------------- */
/* Fills. Each draws from the RNG in a fixed order, so a case's data depend only on its seed. */

/* Uniform in [lo, hi). */
static inline void fill_uniform(float *p, size_t n, test_rng *rng, double lo, double hi)
{
    for (size_t i = 0; i < n; i++)
        p[i] = (float)(lo + (hi - lo) * test_uniform(rng));
}

/* CoC in [0, max) with a fraction `zeros` of exact zeros. */
static inline void fill_coc(float *p, size_t n, test_rng *rng, double max, double zeros)
{
    for (size_t i = 0; i < n; i++)
        p[i] = test_uniform(rng) < zeros ? 0.0f : (float)(max * test_uniform(rng));
}

static inline void fill_const(float *p, size_t n, float v)
{
    for (size_t i = 0; i < n; i++)
        p[i] = v;
}

/* ---------------------------------------------------------------------------------------- */
/* Measures                                                                                   */

/* The larger of m and |d|, where a NaN counts as an infinite difference (fmax would drop it,
 * and a NaN output would compare as equal). */
static inline double max_diff_step(double m, double d)
{
    d = fabs(d);
    return d <= m ? m : isnan(d) ? INFINITY : d;
}

static inline double max_abs_diff_fd(const float *a, const double *b, size_t n)
{
    double m = 0;
    for (size_t i = 0; i < n; i++)
        m = max_diff_step(m, (double)a[i] - b[i]);
    return m;
}

static inline double max_abs_diff_ff(const float *a, const float *b, size_t n)
{
    double m = 0;
    for (size_t i = 0; i < n; i++)
        m = max_diff_step(m, (double)a[i] - (double)b[i]);
    return m;
}

static inline int all_finite(const float *p, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite(p[i]))
            return 0;
    return 1;
}

/* Padded layouts: `stride` is the padded row length in floats, `row` the floats of pixels in a
 * row (width * channels). Both compare bitwise, so a NaN sentinel or fill works. */

/* How many of the h padded rows differ from the tightly packed rows of `tight`. */
static inline size_t padded_rows_differ(const float *padded, size_t stride, const float *tight,
                                        size_t row, uint32_t h)
{
    size_t differ = 0;
    for (uint32_t y = 0; y < h; y++)
        if (memcmp(padded + y * stride, tight + (size_t)y * row, row * sizeof(float)))
            differ++;
    return differ;
}

/* How many padding floats (past `row` in each of the h rows) no longer hold `fill`. */
static inline size_t padding_changed(const float *padded, size_t stride, size_t row, uint32_t h,
                                     float fill)
{
    size_t changed = 0;
    for (uint32_t y = 0; y < h; y++)
        for (size_t i = row; i < stride; i++)
            if (memcmp(&padded[y * stride + i], &fill, sizeof fill))
                changed++;
    return changed;
}

/* ---------------------------------------------------------------------------------------- */
/* An independent double-precision ADI step (docs/design.md section 1), written from the formulas:
 * per line a_i = -beta_{i-1}, b_i = 1 + beta_{i-1} + beta_i, c_i = -beta_i, rhs_i = x_i, with
 * beta_i = k * min(d_i, d_{i+1})^2 / n (columns: d * pixel_aspect) and 0 at the borders, and 0
 * where min(d_i, d_{i+1}) is below the in-focus threshold (ddof_params.in_focus_threshold_px).
 * Thomas elimination keeps each row's excess (b + a + c) so nothing is formed by subtraction.
 * It shares no code with the library, so agreement with it checks the library's formulas. */

static inline void ref_line(uint32_t n, const double *beta, double *v, double *m, double *dp)
{
    double e = 0, w;
    for (uint32_t i = 0; i < n; i++) {
        w = i ? beta[i - 1] / m[i - 1] : 0.0;
        e = 1.0 + w * e;
        m[i] = e + beta[i];
        dp[i] = v[i] + (i ? w * dp[i - 1] : 0.0);
    }
    v[n - 1] = dp[n - 1] / m[n - 1];
    for (uint32_t i = n - 1; i-- > 0;)
        v[i] = (dp[i] + beta[i] * v[i + 1]) / m[i];
}

/* `substeps` ADI steps of beta / substeps on img (w x h x ch, in place): each step solves
 * every row, then every column. */
static inline void ref_adi(double *img, const float *coc, uint32_t w, uint32_t h, uint32_t ch,
                           double k, double aspect, uint32_t substeps, float in_focus)
{
    uint32_t nmax = w > h ? w : h;
    double *beta = malloc(nmax * sizeof(double)), *v = malloc(nmax * sizeof(double));
    double *m = malloc(nmax * sizeof(double)), *dp = malloc(nmax * sizeof(double));
    for (uint32_t s = 0; s < substeps; s++) {
        for (int columns = 0; columns < 2; columns++) {
            const uint32_t lines = columns ? w : h, len = columns ? h : w;
            const size_t step = columns ? w : 1;         /* to the next pixel on the line */
            const double scale = columns ? aspect : 1.0; /* column links use d * aspect */
            for (uint32_t l = 0; l < lines; l++) {
                const size_t first = columns ? l : (size_t)l * w;
                for (uint32_t i = 0; i < len; i++) {
                    const size_t p = first + i * step;
                    const float m = i + 1 < len ? fminf(coc[p], coc[p + step]) : 0.0f;
                    const double d = m >= in_focus ? m * scale : 0.0;
                    beta[i] = k * d * d / substeps;
                }
                for (uint32_t c = 0; c < ch; c++) {
                    for (uint32_t i = 0; i < len; i++)
                        v[i] = img[(first + i * step) * ch + c];
                    ref_line(len, beta, v, m, dp);
                    for (uint32_t i = 0; i < len; i++)
                        img[(first + i * step) * ch + c] = v[i];
                }
            }
        }
    }
    free(beta);
    free(v);
    free(m);
    free(dp);
}

#endif
