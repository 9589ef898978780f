/* SPDX-License-Identifier: MIT */
/* layers_test.h - what the tests of ddof_diffuse_layers' layers share (test_layers_*.c): the
 * frame (160x120, 64x48 with DDOF_TEST_QUICK), the context, the scenes (bars over a blurred
 * background, a disc in the middle) and the measures.
 *
 * References (all computed with DDOF_SOLVER_REFERENCE_F64 through ddof_diffuse):
 *  - bars over a blurred background: the background alone (known: the scene is synthetic)
 *    diffused with its uniform CoC, the sharp bars pasted on top;
 *  - a near blurred object over a sharp background: the object layer alone (premultiplied
 *    colour + alpha; alpha 1 inside, 0 outside) diffused with its uniform CoC, composited over
 *    the sharp background: out = F + (1 - F.a) bg.
 * Errors are RMSE over the colour channels in a band around the bars / the silhouette; the
 * measured values are printed. Margins were set from the measured values (see the constants).
 *
 * Readings of ddof.h these tests rely on:
 *  - ddof_diffuse_layers accepts out == color (in place) as ddof_diffuse does ("ddof_diffuse
 *    with the layers"), and row strides / CoC channels as ddof_diffuse does;
 *  - a pixel with CoC 0 keeps its input exactly when only the background layer runs: its matte
 *    is 0, so out = (1 - 0) mid + 0 * background = mid = input;
 *  - the foreground element's CoC where its alpha is 0 is not used (gamma = alpha = 0 there);
 *  - bad foreground channel counts (3-channel element, 1- or 2-channel colour with an element):
 *    DDOF_ERROR_BAD_CHANNELS or DDOF_ERROR_SIZE_MISMATCH (the header names neither);
 *  - ddof_depth_of_field uses signed CoC whatever params.coc_signed says. */
#ifndef DDOF_LAYERS_TEST_H
#define DDOF_LAYERS_TEST_H

#include "ddof.h"
#include "test_images.h"
#include "test_util.h"

#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static uint32_t W = 160, H = 120;
#define CH 4u

static ddof_context *ctx;
static int verbose;

static const ddof_solver all_solvers[] = {DDOF_SOLVER_THOMAS, DDOF_SOLVER_CYCLIC_REDUCTION,
                                          DDOF_SOLVER_PCR, DDOF_SOLVER_JACOBI,
                                          DDOF_SOLVER_REFERENCE_F64};
#define N_SOLVERS (sizeof all_solvers / sizeof all_solvers[0])

#include "test_frame_calls.h"

/* ---------------------------------------------------------------------------------------- */
/* Helpers                                                                                  */

/* ddof_diffuse on the frame (one layer), without stats. */
static inline ddof_status single(const ddof_params *p, const float *color, const float *coc,
                                 float *out, uint32_t ch)
{
    ddof_image_in ci = {color, W, H, ch, 0};
    ddof_image_in zi = {coc, W, H, 1, 0};
    ddof_image oi = {out, W, H, ch, 0};
    return ddof_diffuse(ctx, p, &ci, &zi, &oi, NULL);
}

/* RMSE over channels 0..2 of the pixels where mask[i] != 0. */
static inline double rmse_rgb(const float *a, const float *b, const unsigned char *mask,
                              uint32_t ch)
{
    double sum = 0;
    size_t count = 0;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        if (!mask[i])
            continue;
        for (uint32_t c = 0; c < 3; c++) {
            double d = (double)a[i * ch + c] - (double)b[i * ch + c];
            sum += d * d;
            count++;
        }
    }
    return count ? sqrt(sum / count) : 0.0;
}

/* Per-channel [lo, hi] of an image. */
static inline void channel_range(const float *p, uint32_t ch, float *lo, float *hi)
{
    for (uint32_t c = 0; c < ch; c++) {
        lo[c] = INFINITY;
        hi[c] = -INFINITY;
    }
    for (size_t i = 0; i < (size_t)W * H; i++)
        for (uint32_t c = 0; c < ch; c++) {
            lo[c] = fminf(lo[c], p[i * ch + c]);
            hi[c] = fmaxf(hi[c], p[i * ch + c]);
        }
}

/* Outputs finite and each channel within [lo, hi] (+- tol); returns the number of bad values
 * and the worst excursion in *worst. */
static inline size_t out_of_range(const float *out, uint32_t ch, const float *lo, const float *hi,
                                  double tol, double *worst)
{
    size_t bad = 0;
    *worst = 0;
    for (size_t i = 0; i < (size_t)W * H; i++)
        for (uint32_t c = 0; c < ch; c++) {
            float v = out[i * ch + c];
            if (!isfinite(v)) {
                bad++;
                *worst = INFINITY;
                continue;
            }
            double e = fmax((double)lo[c] - v, (double)v - hi[c]);
            if (e > tol) {
                bad++;
                *worst = fmax(*worst, e);
            }
        }
    return bad;
}

/* Blocky random texture (8x8 blocks) in [0.05, 0.55] (darker than the bars and the object);
 * channel 3 (alpha) 1. */
static inline void texture(float *color, uint32_t ch, unsigned long long seed)
{
    block_texture(color, W, H, ch, seed, 0.05, 0.55);
}

/* Per-pixel noise: channel c uniform in [0.2 + 0.05 c, 0.7 + 0.05 c] (alpha, c = 3, in
 * [0.35, 0.85]), so that a stray 0 or 1 is out of range in every channel. */
static inline void noise(float *color, uint32_t ch, unsigned long long seed)
{
    test_rng rng = {seed};
    for (size_t i = 0; i < (size_t)W * H; i++)
        for (uint32_t c = 0; c < ch; c++)
            color[i * ch + c] = (float)(0.2 + 0.05 * c + 0.5 * test_uniform(&rng));
}

/* ---------------------------------------------------------------------------------------- */
/* Bars over a blurred background                                                           */

static inline int is_bar(uint32_t x)
{
    uint32_t k = x / 16, off = x % 16, width = (k & 1) ? 3 : 2;
    return off >= 8 && off < 8 + width;
}

/* Bars run vertically (full columns) or horizontally (full rows). */
static int bars_horizontal;

static inline int is_bar_xy(long x, long y)
{
    if (x < 0 || y < 0 || x >= (long)W || y >= (long)H)
        return 0;
    return is_bar((uint32_t)(bars_horizontal ? y : x));
}

static inline void bars_coc(float *coc, float blur)
{
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++)
            coc[(size_t)y * W + x] = is_bar_xy(x, y) ? 0.0f : blur;
}

static inline void paste_bars(float *img)
{
    static const float bar[4] = {0.95f, 0.9f, 0.85f, 1.0f};
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++)
            if (is_bar_xy(x, y))
                memcpy(&img[((size_t)y * W + x) * CH], bar, sizeof bar);
}

/* ---------------------------------------------------------------------------------------- */
/* A disc in the middle                                                                     */

static inline double disc_dist(uint32_t x, uint32_t y)
{
    double dx = x + 0.5 - W / 2.0, dy = y + 0.5 - H / 2.0;
    return sqrt(dx * dx + dy * dy);
}

static inline double disc_radius(void) { return H / 5.0; }

/* The frame's size, DDOF_TEST_VERBOSE, the context. */
static inline void layers_test_begin(void)
{
    verbose = getenv("DDOF_TEST_VERBOSE") && atoi(getenv("DDOF_TEST_VERBOSE"));
    if (test_quick()) {
        W = 64;
        H = 48;
    }
    ctx = make_context(2);
}

/* Frees the context; the exit status. */
static inline int layers_test_end(const char *name)
{
    ddof_context_free(ctx);
    return test_report(name);
}

#endif
