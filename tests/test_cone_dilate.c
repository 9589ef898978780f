/* SPDX-License-Identifier: MIT */
/* test_cone_dilate.c - the near spread's cone dilation (libddof/src/passes/cone_dilate.c) against a
 * brute-force double-precision evaluation of its definition, max over q of v(q) - slope d(p, q)
 * with d the 8-connected chamfer distance, on sparse random maps of odd sizes, 1xN and Nx1 and
 * a padded stride; plus the octagon of a single peak and the padding left untouched. */
#include "passes/cone_dilate.h"
#include "test_util.h"

#include <math.h>
#include <stdlib.h>

/* The chamfer distance of steps 1 and sqrt 2. */
static double chamfer(long dx, long dy)
{
    const double a = (double)labs(dx), b = (double)labs(dy);
    return fmax(a, b) + (sqrt(2.0) - 1.0) * fmin(a, b);
}

/* Largest |dilated - brute force| over the map; the padding must stay as it was. */
static double check_against_brute_force(uint32_t w, uint32_t h, size_t stride, float slope,
                                        double density, test_rng *rng, int *padding_ok)
{
    float *map = malloc(stride * h * sizeof *map);
    double *in = malloc((size_t)w * h * sizeof *in);
    for (size_t i = 0; i < stride * h; i++)
        map[i] = -7.0f; /* padding sentinel */
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            const double v = test_uniform(rng) < density ? 60.0 * test_uniform(rng) : 0.0;
            in[(size_t)y * w + x] = (float)v;
            map[(size_t)y * stride + x] = (float)v;
        }
    ddof_cone_dilate(map, w, h, stride, slope);
    double worst = 0.0;
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            double expect = -INFINITY;
            for (uint32_t qy = 0; qy < h; qy++)
                for (uint32_t qx = 0; qx < w; qx++)
                    expect = fmax(expect, in[(size_t)qy * w + qx] -
                                              slope * chamfer((long)x - qx, (long)y - qy));
            worst = fmax(worst, fabs(map[(size_t)y * stride + x] - expect));
        }
    *padding_ok = 1;
    for (uint32_t y = 0; y < h; y++)
        for (size_t x = w; x < stride; x++)
            *padding_ok &= map[(size_t)y * stride + x] == -7.0f;
    free(map);
    free(in);
    return worst;
}

static void test_brute_force(void)
{
    static const struct { uint32_t w, h; size_t stride; float slope; double density; } cases[] = {
        {1, 1, 1, 4.0f, 1.0},    {1, 17, 1, 4.0f, 0.2},   {17, 1, 17, 4.0f, 0.2},
        {23, 19, 23, 4.0f, 0.03}, {40, 31, 45, 2.5f, 0.01}, {31, 40, 31, 8.0f, 0.05},
        {37, 29, 40, 4.0f, 0.6},
    };
    test_rng rng = {0x5eedULL};
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        int padding_ok;
        const double err = check_against_brute_force(cases[i].w, cases[i].h, cases[i].stride,
                                                     cases[i].slope, cases[i].density, &rng,
                                                     &padding_ok);
        /* Float steps of slope from values up to 60: a few ulps per step, under 40 steps. */
        CHECK_MSG(err <= 2e-4, "%ux%u stride %zu slope %g: max |error| %.3g", cases[i].w,
                  cases[i].h, cases[i].stride, (double)cases[i].slope, err);
        CHECK_MSG(padding_ok, "%ux%u stride %zu: the padding was written", cases[i].w, cases[i].h,
                  cases[i].stride);
    }
}

/* One peak of 40 at (10, 10) on 0: the cone reaches 10 px along the axes and 40 / (4 sqrt 2)
 * = 7.07 px along the diagonals, and never goes below the map's own values. */
static void test_single_peak(void)
{
    enum { n = 21 };
    float map[n * n] = {0};
    map[10 * n + 10] = 40.0f;
    ddof_cone_dilate(map, n, n, n, 4.0f);
    CHECK_NEAR(map[10 * n + 10], 40.0, 0.0);
    CHECK_NEAR(map[10 * n + 15], 20.0, 1e-5);               /* 5 px right                 */
    CHECK_NEAR(map[0 * n + 10], 0.0, 1e-5);                 /* 10 px up: the cone's edge  */
    CHECK_NEAR(map[13 * n + 14], 40.0 - 4.0 * (4.0 + 3.0 * (sqrt(2.0) - 1.0)), 1e-4);
    CHECK_NEAR(map[2 * n + 2], 0.0, 0.0);                   /* 8 diagonal steps: beyond   */
    CHECK_NEAR(map[17 * n + 17], 40.0 - 4.0 * 7.0 * sqrt(2.0), 1e-4);
}

int main(void)
{
    test_brute_force();
    test_single_peak();
    return test_report("test_cone_dilate");
}
