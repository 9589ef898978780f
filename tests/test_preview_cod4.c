/* SPDX-License-Identifier: MIT */
/* test_preview_cod4.c - the CoD4 post-process preview (params.method = DDOF_METHOD_COD4_PREVIEW,
 * GPU Gems 3 ch. 28): invariants on random images and CoC (huge CoC included), identities,
 * in place, sizes and channels, what it blurs (near spread, edge width growing with the CoC),
 * the saturation at the large level's cap (the public entry points, the foreground element it
 * refuses, cancellation and running out of memory: test_preview_cod4_calls.c).
 *
 * Readings of ddof.h / preview_cod4.h this test relies on:
 *  - every output value is a convex combination of inputs, so it lies in the per-channel range
 *    of the whole input image (checked exactly: the preview clamps its float rounding to it);
 *  - CoC 0 everywhere gives the input back bit for bit; out == colour (in place) gives exactly
 *    what a separate output gets, whatever the thread count;
 *  - the large level's size is min(largest |CoC|, max(width, height) / 4): any CoC beyond that
 *    cap blurs like the cap (preview_cod4.c documents this);
 *  - the preview ignores the solver and the layer fields, and refuses a foreground element
 *    (DDOF_ERROR_UNSUPPORTED). */
#include "preview_cod4_test.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static int verbose;

static const uint32_t sizes[][2] = {{1, 1},  {1, 37},  {37, 1},  {2, 3},   {5, 5},
                                    {7, 13}, {16, 16}, {33, 18}, {1, 150}, {150, 1},
                                    {61, 131}, {130, 67}};
#define N_SIZES (sizeof sizes / sizeof sizes[0])

/* ---------------------------------------------------------------------------------------- */

static void test_range_random(ddof_context *ctx)
{
    const double maxima[] = {3.0, 40.0, 1000.0, 100000.0};
    for (size_t s = 0; s < N_SIZES; s++)
        for (uint32_t ch = 1; ch <= 4; ch++)
            for (size_t m = 0; m < sizeof maxima / sizeof maxima[0]; m++)
                for (int sgn = 0; sgn < 2; sgn++) {
                    const uint32_t w = sizes[s][0], h = sizes[s][1];
                    test_rng rng = {1000 + s * 97 + ch * 13 + m * 5 + (size_t)sgn};
                    test_image im = image_alloc(w, h, ch);
                    fill_hdr(im.color, im.n, &rng);
                    fill_signed_coc(im.coc, im.px, &rng, maxima[m], 0.2, sgn ? 0.4 : 0.0);
                    fill_const(im.out, im.n, NAN);
                    ddof_stats st;
                    ddof_status status = preview(ctx, sgn, im.color, im.coc, im.out, w, h, ch, &st);
                    CHECK_MSG(status == DDOF_OK, "%ux%u x%u, CoC to %g: status %d (%s)", w, h, ch,
                              maxima[m], (int)status, ddof_context_last_error(ctx));
                    const size_t bad = outside_range(im.color, im.out, im.px, ch);
                    CHECK_MSG(bad == 0, "%ux%u x%u, CoC to %g, signed %d: %zu values outside the "
                              "input's range", w, h, ch, maxima[m], sgn, bad);
                    float max_coc = 0.0f;
                    for (size_t i = 0; i < im.px; i++)
                        max_coc = fmaxf(max_coc, fabsf(im.coc[i]));
                    CHECK_MSG(st.max_coc_px == max_coc, "stats max CoC %g, want %g",
                              (double)st.max_coc_px, (double)max_coc);
                    image_free(&im);
                }
}

/* CoC 0 everywhere: the input bit for bit (negative zero CoC too, signed or not). */
static void test_zero_coc_identity(ddof_context *ctx)
{
    for (size_t s = 0; s < N_SIZES; s++)
        for (uint32_t ch = 1; ch <= 4; ch++)
            for (int sgn = 0; sgn < 2; sgn++) {
                const uint32_t w = sizes[s][0], h = sizes[s][1];
                test_rng rng = {77 + s + ch};
                test_image im = image_alloc(w, h, ch);
                fill_hdr(im.color, im.n, &rng);
                fill_const(im.coc, im.px, sgn ? -0.0f : 0.0f);
                fill_const(im.out, im.n, NAN);
                ddof_stats st;
                CHECK_EQ_INT(preview(ctx, sgn, im.color, im.coc, im.out, w, h, ch, &st), DDOF_OK);
                CHECK_MSG(!memcmp(im.color, im.out, im.n * sizeof(float)),
                          "%ux%u x%u: CoC 0 changed the image", w, h, ch);
                CHECK(st.max_coc_px == 0.0f);
                /* in place too */
                memcpy(im.out, im.color, im.n * sizeof(float));
                CHECK_EQ_INT(preview(ctx, sgn, im.out, im.coc, im.out, w, h, ch, NULL), DDOF_OK);
                CHECK(!memcmp(im.color, im.out, im.n * sizeof(float)));
                image_free(&im);
            }
}

/* A constant image stays exactly constant under any CoC. */
static void test_constant_image(ddof_context *ctx)
{
    const float values[] = {0.3f, 0.7f, -2.5f, 12345.678f};
    for (size_t s = 0; s < N_SIZES; s++)
        for (uint32_t ch = 1; ch <= 4; ch++) {
            const uint32_t w = sizes[s][0], h = sizes[s][1];
            test_rng rng = {300 + s * 7 + ch};
            test_image im = image_alloc(w, h, ch);
            for (size_t i = 0; i < im.px; i++)
                for (uint32_t c = 0; c < ch; c++)
                    im.color[i * ch + c] = values[c];
            fill_signed_coc(im.coc, im.px, &rng, 5000.0, 0.1, 0.5);
            CHECK_EQ_INT(preview(ctx, 1, im.color, im.coc, im.out, w, h, ch, NULL), DDOF_OK);
            CHECK_MSG(!memcmp(im.color, im.out, im.n * sizeof(float)),
                      "%ux%u x%u: a constant image changed", w, h, ch);
            image_free(&im);
        }
}

/* In place gives bit for bit what a separate output gets, for 1, 2 and 3 threads; padded
 * strides give what tight images give. */
static void test_in_place_threads_strides(void)
{
    ddof_context *ctxs[3] = {make_context(1), make_context(2), make_context(3)};
    const uint32_t big[][2] = {{200, 150}, {67, 300}, {301, 65}, {130, 67}};
    for (size_t s = 0; s < N_SIZES + 4; s++)
        for (uint32_t ch = 1; ch <= 4; ch++) {
            const uint32_t w = s < N_SIZES ? sizes[s][0] : big[s - N_SIZES][0];
            const uint32_t h = s < N_SIZES ? sizes[s][1] : big[s - N_SIZES][1];
            if (test_quick() && (size_t)w * h > 20000)
                continue;
            test_rng rng = {500 + s * 11 + ch};
            test_image im = image_alloc(w, h, ch);
            block_texture(im.color, w, h, ch, 600 + s, -0.5, 2.0);
            fill_signed_coc(im.coc, im.px, &rng, 60.0, 0.3, 0.5);
            CHECK_EQ_INT(preview(ctxs[1], 1, im.color, im.coc, im.out, w, h, ch, NULL), DDOF_OK);
            float *work = alloc_f(im.n);
            for (int t = 0; t < 3; t++) {
                memcpy(work, im.color, im.n * sizeof(float));
                CHECK_EQ_INT(preview(ctxs[t], 1, work, im.coc, work, w, h, ch, NULL), DDOF_OK);
                CHECK_MSG(!memcmp(work, im.out, im.n * sizeof(float)),
                          "%ux%u x%u, %d threads: in place differs from out of place "
                          "(max diff %g)", w, h, ch, t + 1, max_abs_diff_ff(work, im.out, im.n));
                fill_const(work, im.n, NAN);
                CHECK_EQ_INT(preview(ctxs[t], 1, im.color, im.coc, work, w, h, ch, NULL), DDOF_OK);
                CHECK_MSG(!memcmp(work, im.out, im.n * sizeof(float)),
                          "%ux%u x%u: %d threads differ from 2", w, h, ch, t + 1);
            }
            free(work);

            /* Padded rows: colour +3 floats, CoC with 2 channels (the first is read) and +1
             * float, output +5 floats; the padding must stay as it was. */
            const size_t cs = (size_t)w * ch + 3, zs = (size_t)w * 2 + 1, os = (size_t)w * ch + 5;
            float *pc = alloc_f(cs * h), *pz = alloc_f(zs * h), *po = alloc_f(os * h);
            fill_const(pc, cs * h, 9.0f);
            fill_const(pz, zs * h, -1.0f);
            fill_const(po, os * h, 7.0f);
            for (uint32_t y = 0; y < h; y++) {
                memcpy(pc + y * cs, im.color + (size_t)y * w * ch, (size_t)w * ch * sizeof(float));
                for (uint32_t x = 0; x < w; x++)
                    pz[y * zs + 2 * x] = im.coc[(size_t)y * w + x];
            }
            ddof_params p = preview_params(1);
            ddof_image_in ci = {pc, w, h, ch, cs * sizeof(float)};
            ddof_image_in zi = {pz, w, h, 2, zs * sizeof(float)};
            ddof_image oi = {po, w, h, ch, os * sizeof(float)};
            CHECK_EQ_INT(ddof_diffuse(ctxs[1], &p, &ci, &zi, &oi, NULL), DDOF_OK);
            CHECK_MSG(padded_rows_differ(po, os, im.out, (size_t)w * ch, h) == 0,
                      "%ux%u x%u: padded layout differs from tight", w, h, ch);
            CHECK(padding_changed(po, os, (size_t)w * ch, h, 7.0f) == 0);
            free(pc);
            free(pz);
            free(po);
            image_free(&im);
        }
    for (int t = 0; t < 3; t++)
        ddof_context_free(ctxs[t]);
}

/* Each channel is blurred alike and on its own: channel c of a C-channel call equals the
 * 1-channel call on channel c alone. */
static void test_channels_independent(ddof_context *ctx)
{
    const uint32_t w = 45, h = 38;
    test_rng rng = {4242};
    test_image im = image_alloc(w, h, 4);
    fill_hdr(im.color, im.n, &rng);
    fill_signed_coc(im.coc, im.px, &rng, 30.0, 0.2, 0.5);
    float *one = alloc_f(im.px), *one_out = alloc_f(im.px);
    for (uint32_t ch = 2; ch <= 4; ch++) {
        float *color = alloc_f(im.px * ch), *out = alloc_f(im.px * ch);
        for (size_t i = 0; i < im.px; i++)
            for (uint32_t c = 0; c < ch; c++)
                color[i * ch + c] = im.color[i * 4 + c];
        CHECK_EQ_INT(preview(ctx, 1, color, im.coc, out, w, h, ch, NULL), DDOF_OK);
        for (uint32_t c = 0; c < ch; c++) {
            for (size_t i = 0; i < im.px; i++)
                one[i] = color[i * ch + c];
            CHECK_EQ_INT(preview(ctx, 1, one, im.coc, one_out, w, h, 1, NULL), DDOF_OK);
            double worst = 0.0;
            for (size_t i = 0; i < im.px; i++)
                worst = max_diff_step(worst, (double)out[i * ch + c] - one_out[i]);
            CHECK_MSG(worst <= 1e-5 * 1000.0, "%u channels, channel %u vs alone: %g", ch, c,
                      worst);
        }
        free(color);
        free(out);
    }
    free(one);
    free(one_out);
    image_free(&im);
}

/* ---------------------------------------------------------------------------------------- */
/* What it blurs                                                                              */

/* A blurred near square (CoC -20, colour 1) over a sharp striped background (CoC 0, colour in
 * {0, 0.2}): with signed CoC the square's soft edge spreads over the background just outside
 * its silhouette, towards the square's colour; far from it the background is untouched. With
 * unsigned CoC (no near field) the background keeps every pixel. */
static void test_near_spread(ddof_context *ctx)
{
    const uint32_t w = 160, h = 120, ch = 3;
    const uint32_t x0 = 60, x1 = 100, y0 = 40, y1 = 80; /* the square [x0, x1) x [y0, y1) */
    test_image im = image_alloc(w, h, ch);
    float *plain = alloc_f(im.n);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            const size_t i = (size_t)y * w + x;
            const int in = x >= x0 && x < x1 && y >= y0 && y < y1;
            for (uint32_t c = 0; c < ch; c++)
                im.color[i * ch + c] = in ? 1.0f : ((x / 3) % 2 ? 0.2f : 0.0f);
            im.coc[i] = in ? -20.0f : 0.0f;
        }
    ddof_stats st;
    CHECK_EQ_INT(preview(ctx, 1, im.color, im.coc, im.out, w, h, ch, &st), DDOF_OK);
    /* Just outside each side of the silhouette the pixels change, towards the square's colour
     * (the background is at most 0.2, the square 1): a near CoC of 20 px reaches about 10 px
     * beyond the silhouette, the more the closer. */
    const uint32_t probes[][3] = {{x0 - 2, 60, 2}, {x0 - 4, 60, 4}, {x1 + 1, 60, 2},
                                  {x1 + 3, 60, 4}, {80, y0 - 2, 2}, {80, y0 - 4, 4},
                                  {80, y1 + 1, 2}, {80, y1 + 3, 4}};
    for (size_t k = 0; k < sizeof probes / sizeof probes[0]; k++) {
        const size_t i = (size_t)probes[k][1] * w + probes[k][0];
        const float before = im.color[i * ch], after = im.out[i * ch];
        const float want = probes[k][2] <= 2 ? 0.3f : before + 0.05f;
        CHECK_MSG(after > before + 0.05f && after > want,
                  "near spread: pixel (%u, %u), %u px outside the square, went %g -> %g",
                  probes[k][0], probes[k][1], probes[k][2], (double)before, (double)after);
    }
    /* Far away (more than a CoC beyond the square, and beyond the block and upsampling reach)
     * the sharp background is exactly as it was. */
    size_t changed_far = 0;
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            const int far = x + 40 < x0 || x >= x1 + 40 || y + 40 < y0 || y >= y1 + 40;
            const size_t i = (size_t)y * w + x;
            if (far && memcmp(&im.out[i * ch], &im.color[i * ch], ch * sizeof(float)))
                changed_far++;
        }
    CHECK_MSG(changed_far == 0, "near spread: %zu sharp pixels far from the square changed",
              changed_far);
    /* The square's own interior near its edge is softened too (it is blurred). */
    {
        const size_t i = (size_t)60 * w + x0;
        CHECK_MSG(im.out[i * ch] < 0.99f, "the blurred square's edge pixel stayed %g",
                  (double)im.out[i * ch]);
    }
    if (verbose) {
        printf("near spread, row 60 around the left edge:");
        for (uint32_t x = x0 - 16; x < x0 + 4; x++)
            printf(" %.3f", (double)im.out[((size_t)60 * w + x) * ch]);
        printf("\n");
    }

    /* Unsigned: the same magnitudes, no near field: pixels with CoC 0 keep their value. */
    for (size_t i = 0; i < im.px; i++)
        im.coc[i] = fabsf(im.coc[i]);
    CHECK_EQ_INT(preview(ctx, 0, im.color, im.coc, plain, w, h, ch, NULL), DDOF_OK);
    size_t changed = 0;
    for (size_t i = 0; i < im.px; i++)
        if (im.coc[i] == 0.0f && memcmp(&plain[i * ch], &im.color[i * ch], ch * sizeof(float)))
            changed++;
    CHECK_MSG(changed == 0, "unsigned CoC: %zu in-focus pixels changed", changed);
    free(plain);
    image_free(&im);
}

/* The 10%-90% width of the rising edge in row y of a 1-channel image (0 left, 1 right). */
static double edge_width(const float *out, uint32_t w, uint32_t y)
{
    const float *row = out + (size_t)y * w;
    double x10 = -1.0, x90 = -1.0;
    for (uint32_t x = 1; x < w; x++) {
        const double a = row[x - 1], b = row[x];
        if (x10 < 0 && a < 0.1 && b >= 0.1)
            x10 = (x - 1) + (0.1 - a) / (b - a);
        if (a < 0.9 && b >= 0.9)
            x90 = (x - 1) + (0.9 - a) / (b - a);
    }
    return x10 < 0 || x90 < 0 ? -1.0 : x90 - x10;
}

/* A vertical step edge under a uniform CoC d: the 10-90% width grows with d, and roughly in
 * proportion once the large level carries the blur (a Gaussian of the disk's variance d^2/16
 * has a 10-90% width of 2.56 d / 4 = 0.64 d). */
static void test_edge_width(ddof_context *ctx)
{
    const uint32_t w = 512, h = 48;
    const double ds[] = {1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0};
    const size_t nd = sizeof ds / sizeof ds[0];
    double width[2][sizeof ds / sizeof ds[0]];
    test_image im = image_alloc(w, h, 1);
    for (int shift = 0; shift < 2; shift++) { /* the edge on a block boundary, and off it */
        const uint32_t edge = 256 + (uint32_t)shift * 2 + (uint32_t)shift;
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++)
                im.color[(size_t)y * w + x] = x < edge ? 0.0f : 1.0f;
        for (size_t k = 0; k < nd; k++) {
            fill_const(im.coc, im.px, (float)ds[k]);
            CHECK_EQ_INT(preview(ctx, 0, im.color, im.coc, im.out, w, h, 1, NULL), DDOF_OK);
            width[shift][k] = edge_width(im.out, w, h / 2);
            /* monotone across the edge: nothing rings */
            int monotone = 1;
            for (uint32_t x = 1; x < w; x++)
                monotone &= im.out[(size_t)(h / 2) * w + x] >= im.out[(size_t)(h / 2) * w + x - 1];
            CHECK_MSG(monotone, "edge, d = %g: the profile is not monotone", ds[k]);
        }
        if (verbose) {
            printf("edge at x = %u, 10-90%% widths:", edge);
            for (size_t k = 0; k < nd; k++)
                printf(" d=%g: %.2f", ds[k], width[shift][k]);
            printf("\n");
        }
        for (size_t k = 0; k < nd; k++) {
            CHECK_MSG(width[shift][k] > 0.0, "edge, d = %g: no 10-90%% width", ds[k]);
            if (k > 0)
                CHECK_MSG(width[shift][k] >= width[shift][k - 1] - 0.05,
                          "edge width not monotone: d = %g: %g, d = %g: %g", ds[k - 1],
                          width[shift][k - 1], ds[k], width[shift][k]);
            if (ds[k] >= 16.0) { /* roughly proportional: 0.64 d for a Gaussian */
                const double ratio = width[shift][k] / ds[k];
                CHECK_MSG(ratio > 0.45 && ratio < 0.85, "edge, d = %g: width %g = %.3f d",
                          ds[k], width[shift][k], ratio);
            }
            if (ds[k] >= 32.0) {
                const double growth = width[shift][k] / width[shift][k - 1];
                CHECK_MSG(growth > 1.6 && growth < 2.4,
                          "edge: doubling d from %g grew the width %.3f times", ds[k - 1], growth);
            }
        }
    }
    image_free(&im);
}

/* At the small level's own size (the disk with the pinwheel's variance, 4 sqrt(24/17) px) the
 * output is the small level alone: the mean of the pixel and the 2x2 blocks with top-left
 * corners (x, y-2), (x-2, y-1), (x-1, y+1), (x+1, y), of the pixels inside the image. */
static void test_small_level(ddof_context *ctx)
{
    const uint32_t dims[][2] = {{1, 1}, {1, 7}, {6, 1}, {3, 4}, {19, 13}};
    const float d_small = (float)(4.0 * sqrt(24.0 / 17.0));
    const int blocks[4][2] = {{0, -2}, {-2, -1}, {-1, 1}, {1, 0}};
    for (size_t s = 0; s < sizeof dims / sizeof dims[0]; s++) {
        const uint32_t w = dims[s][0], h = dims[s][1], ch = 2;
        test_rng rng = {700 + s};
        test_image im = image_alloc(w, h, ch);
        fill_uniform(im.color, im.n, &rng, 0.0, 1.0);
        fill_const(im.coc, im.px, d_small);
        CHECK_EQ_INT(preview(ctx, 0, im.color, im.coc, im.out, w, h, ch, NULL), DDOF_OK);
        double worst = 0.0;
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++)
                for (uint32_t c = 0; c < ch; c++) {
                    double sum = im.color[((size_t)y * w + x) * ch + c];
                    int count = 1;
                    for (int k = 0; k < 4; k++)
                        for (int j = 0; j < 2; j++)
                            for (int i = 0; i < 2; i++) {
                                const long xx = (long)x + blocks[k][0] + i;
                                const long yy = (long)y + blocks[k][1] + j;
                                if (xx < 0 || yy < 0 || xx >= (long)w || yy >= (long)h)
                                    continue;
                                sum += im.color[((size_t)yy * w + (size_t)xx) * ch + c];
                                count++;
                            }
                    worst = max_diff_step(worst, im.out[((size_t)y * w + x) * ch + c] - sum / count);
                }
        CHECK_MSG(worst <= 1e-5, "%ux%u: the small level differs from the pinwheel by %g", w, h,
                  worst);
        image_free(&im);
    }
}

/* Bilinear weights at quarter resolution for full-resolution coordinate v (pixel centres of
 * the quarter image at 4 i + 1.5), clamped to [0, n - 1]. */
static void quarter_coord(uint32_t v, uint32_t n, uint32_t *i0, uint32_t *i1, double *w)
{
    const double u = ((double)v - 1.5) / 4.0;
    if (u <= 0.0) {
        *i0 = *i1 = 0;
        *w = 0.0;
        return;
    }
    *i0 = (uint32_t)u;
    *w = u - *i0;
    *i1 = *i0 + 1;
    if (*i1 >= n) {
        *i0 = *i1 = n - 1;
        *w = 0.0;
    }
}

/* At the medium level's own size (4 sqrt(15/12 + 16 * 2/3 + 16/6) px, below which no large
 * level is built) the output is the medium level alone: 4x4 block means (partial blocks: what
 * they hold), a 3x3 box over them (what lies inside), sampled bilinearly. */
static void test_medium_level(ddof_context *ctx)
{
    const uint32_t dims[][2] = {{1, 10}, {5, 7}, {13, 9}, {16, 12}, {30, 21}};
    const float d_medium = (float)(4.0 * sqrt(15.0 / 12.0 + 16.0 * 2.0 / 3.0 + 16.0 / 6.0));
    for (size_t s = 0; s < sizeof dims / sizeof dims[0]; s++) {
        const uint32_t w = dims[s][0], h = dims[s][1], ch = 1;
        const uint32_t qw = (w + 3) / 4, qh = (h + 3) / 4;
        test_rng rng = {800 + s};
        test_image im = image_alloc(w, h, ch);
        fill_uniform(im.color, im.n, &rng, 0.0, 1.0);
        fill_const(im.coc, im.px, d_medium);
        CHECK_EQ_INT(preview(ctx, 0, im.color, im.coc, im.out, w, h, ch, NULL), DDOF_OK);
        double *q = malloc((size_t)qw * qh * sizeof(double)), *m = malloc((size_t)qw * qh * sizeof(double));
        if (!q || !m)
            exit(2);
        for (uint32_t j = 0; j < qh; j++)
            for (uint32_t i = 0; i < qw; i++) {
                double sum = 0;
                int count = 0;
                for (uint32_t y = 4 * j; y < 4 * j + 4 && y < h; y++)
                    for (uint32_t x = 4 * i; x < 4 * i + 4 && x < w; x++) {
                        sum += im.color[(size_t)y * w + x];
                        count++;
                    }
                q[(size_t)j * qw + i] = sum / count;
            }
        for (uint32_t j = 0; j < qh; j++)
            for (uint32_t i = 0; i < qw; i++) {
                double sum = 0;
                int count = 0;
                for (long jj = (long)j - 1; jj <= (long)j + 1; jj++)
                    for (long ii = (long)i - 1; ii <= (long)i + 1; ii++)
                        if (jj >= 0 && ii >= 0 && jj < (long)qh && ii < (long)qw) {
                            sum += q[(size_t)jj * qw + (size_t)ii];
                            count++;
                        }
                m[(size_t)j * qw + i] = sum / count;
            }
        double worst = 0.0;
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++) {
                uint32_t x0, x1, y0, y1;
                double wx, wy;
                quarter_coord(x, qw, &x0, &x1, &wx);
                quarter_coord(y, qh, &y0, &y1, &wy);
                const double top = (1 - wx) * m[(size_t)y0 * qw + x0] + wx * m[(size_t)y0 * qw + x1];
                const double bottom = (1 - wx) * m[(size_t)y1 * qw + x0] + wx * m[(size_t)y1 * qw + x1];
                worst = max_diff_step(worst, im.out[(size_t)y * w + x] - ((1 - wy) * top + wy * bottom));
            }
        CHECK_MSG(worst <= 1e-5, "%ux%u: the medium level differs from its definition by %g", w,
                  h, worst);
        free(q);
        free(m);
        image_free(&im);
    }
}

/* Thin images blur along their one dimension: a step along a 1 x N column and an N x 1 row. */
static void test_thin_images(ddof_context *ctx)
{
    for (int vertical = 0; vertical < 2; vertical++) {
        const uint32_t n = 400, w = vertical ? 1 : n, h = vertical ? n : 1;
        test_image im = image_alloc(w, h, 2);
        for (uint32_t i = 0; i < n; i++) {
            im.color[2 * i] = i < n / 2 ? 0.0f : 1.0f;
            im.color[2 * i + 1] = 0.5f;
            im.coc[i] = 24.0f;
        }
        CHECK_EQ_INT(preview(ctx, 0, im.color, im.coc, im.out, w, h, 2, NULL), DDOF_OK);
        int monotone = 1;
        for (uint32_t i = 1; i < n; i++)
            monotone &= im.out[2 * i] >= im.out[2 * (i - 1)];
        CHECK_MSG(monotone, "%ux%u step: not monotone", w, h);
        CHECK_MSG(im.out[2 * (n / 2 - 3)] > 0.05f && im.out[2 * (n / 2 + 2)] < 0.95f,
                  "%ux%u step with CoC 24: not blurred (%g, %g)", w, h,
                  (double)im.out[2 * (n / 2 - 3)], (double)im.out[2 * (n / 2 + 2)]);
        CHECK(im.out[0] == 0.0f && im.out[2 * (n - 1)] == 1.0f);
        size_t constant_kept = 0;
        for (uint32_t i = 0; i < n; i++)
            constant_kept += im.out[2 * i + 1] == 0.5f;
        CHECK_EQ_INT(constant_kept, n);
        image_free(&im);
    }
}

/* A CoC beyond the cap (a quarter of the larger dimension) blurs exactly like the cap, and the
 * largest CoC the library accepts works on the smallest images. */
static void test_saturation(ddof_context *ctx)
{
    const uint32_t w = 96, h = 64, ch = 4;
    test_image im = image_alloc(w, h, ch);
    float *capped = alloc_f(im.n);
    block_texture(im.color, w, h, ch, 31, 0.0, 1.0);
    const float cap = (float)(w > h ? w : h) / 4.0f;
    fill_const(im.coc, im.px, DDOF_MAX_COC_PX);
    CHECK_EQ_INT(preview(ctx, 0, im.color, im.coc, im.out, w, h, ch, NULL), DDOF_OK);
    fill_const(im.coc, im.px, cap);
    CHECK_EQ_INT(preview(ctx, 0, im.color, im.coc, capped, w, h, ch, NULL), DDOF_OK);
    CHECK_MSG(!memcmp(im.out, capped, im.n * sizeof(float)),
              "CoC %g and the cap %g differ by %g", (double)DDOF_MAX_COC_PX, (double)cap,
              max_abs_diff_ff(im.out, capped, im.n));
    /* and the blur is strong: much less of the texture's variance is left than after a small
     * blur (CoC 4 px) */
    float *small = alloc_f(im.n);
    fill_const(im.coc, im.px, 4.0f);
    CHECK_EQ_INT(preview(ctx, 0, im.color, im.coc, small, w, h, ch, NULL), DDOF_OK);
    double var_in = 0, var_out = 0, var_small = 0, mean = 0;
    for (size_t i = 0; i < im.px; i++)
        mean += im.color[i * ch];
    mean /= (double)im.px;
    for (size_t i = 0; i < im.px; i++) {
        var_in += (im.color[i * ch] - mean) * (im.color[i * ch] - mean);
        var_out += (im.out[i * ch] - mean) * (im.out[i * ch] - mean);
        var_small += (small[i * ch] - mean) * (small[i * ch] - mean);
    }
    if (verbose)
        printf("texture variance: input %g, CoC 4: %g, CoC at the cap (%g): %g\n", var_in,
               var_small, (double)cap, var_out);
    CHECK_MSG(var_out < 0.3 * var_in && var_out < 0.5 * var_small,
              "CoC at the cap: variance %g of %g left (CoC 4: %g)", var_out, var_in, var_small);
    free(small);
    /* Huge near CoC on tiny images. */
    for (size_t s = 0; s < 6; s++) {
        test_image t = image_alloc(sizes[s][0], sizes[s][1], 3);
        test_rng rng = {99 + s};
        fill_uniform(t.color, t.n, &rng, 0.0, 1.0);
        fill_const(t.coc, t.px, -DDOF_MAX_COC_PX);
        CHECK_EQ_INT(preview(ctx, 1, t.color, t.coc, t.out, t.w, t.h, 3, NULL), DDOF_OK);
        CHECK(outside_range(t.color, t.out, t.px, 3) == 0);
        image_free(&t);
    }
    free(capped);
    image_free(&im);
}

int main(int argc, char **argv)
{
    verbose = argc > 1 && !strcmp(argv[1], "-v");
    ddof_context *ctx = make_context(2);
    test_range_random(ctx);
    test_zero_coc_identity(ctx);
    test_constant_image(ctx);
    test_in_place_threads_strides();
    test_channels_independent(ctx);
    test_near_spread(ctx);
    test_edge_width(ctx);
    test_small_level(ctx);
    test_medium_level(ctx);
    test_thin_images(ctx);
    test_saturation(ctx);
    ddof_context_free(ctx);
    return test_report("test_preview_cod4");
}
