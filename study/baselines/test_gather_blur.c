/* SPDX-License-Identifier: MIT */
/* test_gather_blur.c - checks ddof_gather_blur against a brute-force double computation of the
 * disk average on small images, plus its identities (CoC 0, constant image, in place, thread
 * counts), bad arguments, and the bleeding it exists to show. Prints `test_gather_blur: N
 * checks, M failed` and exits 1 on any failure.
 *
 *   cc -std=c11 -O2 -Wall -Wextra -Wpedantic -D_POSIX_C_SOURCE=200809L -Istudy/baselines \
 *      study/baselines/gather_blur.c study/baselines/test_gather_blur.c -lpthread -lm \
 *      -o test_gather_blur */
#include "gather_blur.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int checks, failed;

#define CHECK(cond, ...)                                                                  \
    do {                                                                                  \
        checks++;                                                                         \
        if (!(cond)) {                                                                    \
            failed++;                                                                     \
            fprintf(stderr, "%s:%d: CHECK failed: %s: ", __FILE__, __LINE__, #cond);      \
            fprintf(stderr, __VA_ARGS__);                                                 \
            fputc('\n', stderr);                                                          \
        }                                                                                 \
    } while (0)

static uint64_t rng_state = 88172645463325252ull;

static double uniform(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) * (1.0 / 9007199254740992.0);
}

static float *alloc_f(size_t n)
{
    float *p = malloc((n ? n : 1) * sizeof(float));
    if (!p) {
        fprintf(stderr, "out of memory\n");
        exit(2);
    }
    return p;
}

/* Brute force: every pixel of the image tested against the disk, summed in double. */
static void brute_force(const float *in, const float *coc, uint32_t w, uint32_t h, uint32_t ch,
                        double *out)
{
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            const double r = fabs((double)coc[(size_t)y * w + x]) / 2.0;
            double sum[4] = {0, 0, 0, 0};
            double count = 0;
            for (uint32_t v = 0; v < h; v++)
                for (uint32_t u = 0; u < w; u++) {
                    const double dx = (double)u - x, dy = (double)v - y;
                    if (dx * dx + dy * dy <= r * r) {
                        for (uint32_t c = 0; c < ch; c++)
                            sum[c] += in[((size_t)v * w + u) * ch + c];
                        count++;
                    }
                }
            for (uint32_t c = 0; c < ch; c++)
                out[((size_t)y * w + x) * ch + c] = sum[c] / count;
        }
}

static void test_against_brute_force(void)
{
    const uint32_t sizes[][2] = {{1, 1}, {1, 9}, {9, 1}, {23, 17}, {40, 31}};
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++)
        for (uint32_t ch = 1; ch <= 4; ch++) {
            const uint32_t w = sizes[s][0], h = sizes[s][1];
            const size_t px = (size_t)w * h, n = px * ch;
            float *in = alloc_f(n), *coc = alloc_f(px), *out = alloc_f(n);
            double *want = malloc(n * sizeof(double));
            if (!want)
                exit(2);
            for (size_t i = 0; i < n; i++)
                in[i] = (float)(uniform() < 0.1 ? 50.0 * uniform() : uniform());
            for (size_t i = 0; i < px; i++) {
                const double u = uniform();
                /* zeros, small, exact integer diameters (disk edges through pixel centres),
                 * negative (near field: the sign is ignored), huge */
                coc[i] = u < 0.15 ? 0.0f
                         : u < 0.3 ? (float)(2 * (int)(1 + 5 * uniform()))
                         : u < 0.45 ? -(float)(12.0 * uniform())
                         : u < 0.5 ? 1000.0f
                                   : (float)(12.0 * uniform());
            }
            for (uint32_t threads = 1; threads <= 3; threads += 2) {
                for (size_t i = 0; i < n; i++)
                    out[i] = NAN;
                const int rc = ddof_gather_blur(in, coc, w, h, ch, out, threads);
                CHECK(rc == DDOF_GATHER_OK, "%ux%u x%u: rc %d", w, h, ch, rc);
                brute_force(in, coc, w, h, ch, want);
                double worst = 0;
                size_t worst_i = 0;
                for (size_t i = 0; i < n; i++) {
                    const double e = fabs(out[i] - want[i]) / fmax(1.0, fabs(want[i]));
                    if (!(e <= worst)) {
                        worst = isnan(e) ? INFINITY : e;
                        worst_i = i;
                    }
                }
                CHECK(worst <= 1e-6, "%ux%u x%u, %u threads: worst relative error %g at %zu "
                      "(%g vs %g)", w, h, ch, threads, worst, worst_i, (double)out[worst_i],
                      want[worst_i]);
            }
            free(in);
            free(coc);
            free(out);
            free(want);
        }
}

static void test_identities(void)
{
    const uint32_t w = 37, h = 29, ch = 4;
    const size_t px = (size_t)w * h, n = px * ch;
    float *in = alloc_f(n), *coc = alloc_f(px), *out = alloc_f(n), *work = alloc_f(n);
    for (size_t i = 0; i < n; i++)
        in[i] = (float)uniform();
    /* CoC below 2 px (a disk of radius < 1): only the pixel itself, bit for bit */
    for (size_t i = 0; i < px; i++)
        coc[i] = (float)(1.99 * uniform());
    CHECK(ddof_gather_blur(in, coc, w, h, ch, out, 2) == 0, "rc");
    CHECK(!memcmp(in, out, n * sizeof(float)), "CoC < 2 changed the image");

    /* in place = out of place; 1 thread = 4 threads */
    for (size_t i = 0; i < px; i++)
        coc[i] = (float)(20.0 * uniform());
    CHECK(ddof_gather_blur(in, coc, w, h, ch, out, 1) == 0, "rc");
    memcpy(work, in, n * sizeof(float));
    CHECK(ddof_gather_blur(work, coc, w, h, ch, work, 4) == 0, "rc");
    CHECK(!memcmp(work, out, n * sizeof(float)), "in place or 4 threads differ");

    /* a constant image stays exactly constant */
    for (size_t i = 0; i < n; i++)
        in[i] = 0.7f;
    CHECK(ddof_gather_blur(in, coc, w, h, ch, out, 2) == 0, "rc");
    CHECK(!memcmp(in, out, n * sizeof(float)), "a constant image changed");

    /* bad arguments leave out alone */
    for (size_t i = 0; i < n; i++)
        out[i] = 5.0f;
    CHECK(ddof_gather_blur(NULL, coc, w, h, ch, out, 1) == DDOF_GATHER_BAD_ARGUMENT, "NULL");
    CHECK(ddof_gather_blur(in, coc, 0, h, ch, out, 1) == DDOF_GATHER_BAD_ARGUMENT, "width 0");
    CHECK(ddof_gather_blur(in, coc, w, h, 0, out, 1) == DDOF_GATHER_BAD_ARGUMENT, "0 channels");
    coc[7] = NAN;
    CHECK(ddof_gather_blur(in, coc, w, h, ch, out, 1) == DDOF_GATHER_BAD_ARGUMENT, "NaN CoC");
    coc[7] = INFINITY;
    CHECK(ddof_gather_blur(in, coc, w, h, ch, out, 1) == DDOF_GATHER_BAD_ARGUMENT, "inf CoC");
    size_t touched = 0;
    for (size_t i = 0; i < n; i++)
        touched += out[i] != 5.0f;
    CHECK(touched == 0, "%zu values written on bad arguments", touched);
    free(in);
    free(coc);
    free(out);
    free(work);
}

/* What the baseline exists to show. A sharp bright bar (CoC 0) in front of a dark blurred
 * background (CoC 16): background pixels next to the bar gather it (bleeding; a real lens
 * would not put the in-focus bar's light there). A blurred bright near square (CoC 16) over a
 * sharp dark background (CoC 0): the background keeps its sharp edge against the square (no
 * spread), while the square's own edge pixels gather the background (a dark halo inside). */
static void test_bleeding(void)
{
    const uint32_t w = 64, h = 48, ch = 1;
    const size_t px = (size_t)w * h;
    float *in = alloc_f(px), *coc = alloc_f(px), *out = alloc_f(px);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            const int bar = x >= 30 && x < 34;
            in[(size_t)y * w + x] = bar ? 1.0f : 0.0f;
            coc[(size_t)y * w + x] = bar ? 0.0f : 16.0f;
        }
    CHECK(ddof_gather_blur(in, coc, w, h, ch, out, 2) == 0, "rc");
    CHECK(out[24 * w + 31] == 1.0f, "the sharp bar itself changed: %g", (double)out[24 * w + 31]);
    CHECK(out[24 * w + 27] > 0.1f, "no bleeding next to the bar: %g", (double)out[24 * w + 27]);

    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            const int square = x >= 20 && x < 44 && y >= 12 && y < 36;
            in[(size_t)y * w + x] = square ? 1.0f : 0.0f;
            coc[(size_t)y * w + x] = square ? -16.0f : 0.0f;
        }
    CHECK(ddof_gather_blur(in, coc, w, h, ch, out, 2) == 0, "rc");
    CHECK(out[24 * w + 19] == 0.0f, "the background next to the near square changed: %g",
          (double)out[24 * w + 19]);
    CHECK(out[24 * w + 20] < 0.8f, "no halo inside the near square's edge: %g",
          (double)out[24 * w + 20]);
    free(in);
    free(coc);
    free(out);
}

int main(void)
{
    test_against_brute_force();
    test_identities();
    test_bleeding();
    printf("test_gather_blur: %d checks, %d failed\n", checks, failed);
    return failed ? 1 : 0;
}
