/* SPDX-License-Identifier: MIT */
/* point_spread.h - what a kernel draws around one bright pixel, measured against the disc a lens
 * draws: shared by test_disc_kernel.c (which asserts it) and ddof-bench (which prints it).
 *
 * One pixel of value 1 in the middle of a w x w image (w = 3 d + 9, odd, so the kernel's tails
 * stay inside the insulated borders) on a pedestal of 0.001, uniform CoC d, one ddof_diffuse call;
 * the output minus the pedestal is the kernel. (The disc kernels clamp their output to the
 * input's range, which on black would cut the kernel's negative ring: so the top-left pixel is
 * an in-focus 0, which widens the range, is left as it is and takes no part.) Kernel SNR is
 * -20 log10(|K - D| / |D|) with D the anti-aliased uniform disc of diameter d (8 x 8 samples a
 * pixel) and both normalised to unit sum.
 * point_spread_measure_bright does the same with an RGB point of 100 through the frame call:
 * what the default preset draws of an HDR highlight (the highlight pass's disc over the rest,
 * which the diffusion carries). */
#ifndef DDOF_POINT_SPREAD_H
#define DDOF_POINT_SPREAD_H

#include "ddof.h"

#include <math.h>
#include <stdlib.h>

#define POINT_SPREAD_PEDESTAL 0.001 /* small: float keeps the kernel's digits on it */

typedef struct point_spread {
    ddof_status status;
    double snr_db;      /* kernel SNR against the disc                                 */
    double energy;      /* sum of the output (1 = kept)                                */
    double ring;        /* most negative output / the disc's height (0: none)          */
    double max_abs_err; /* unused by callers that only print; largest |K - D| / height */
} point_spread;

static inline uint32_t point_spread_size(float d)
{
    return ((uint32_t)(3.0f * d) + 9u) | 1u;
}

/* The disc's coverage of pixel (x, y) around the centre c, 8 x 8 samples. */
static inline double point_spread_disc(int x, int y, int c, double d)
{
    int inside = 0;
    for (int sy = 0; sy < 8; sy++)
        for (int sx = 0; sx < 8; sx++) {
            const double px = x - c + (sx + 0.5) / 8.0 - 0.5, py = y - c + (sy + 0.5) / 8.0 - 0.5;
            inside += px * px + py * py <= 0.25 * d * d;
        }
    return inside / 64.0;
}

/* One pixel of `value` above the pedestal, `channels` colour channels (the kernel is read from
 * the first); `layered` runs ddof_diffuse_layers (the frame call, highlight pass included) where
 * ddof_diffuse runs the diffusion alone. */
static inline point_spread point_spread_run(ddof_context *ctx, const ddof_params *params, float d,
                                            uint32_t channels, float value, int layered)
{
    point_spread r = {DDOF_ERROR_OUT_OF_MEMORY, 0, 0, 0, 0};
    const uint32_t w = point_spread_size(d);
    const int c = (int)w / 2;
    const size_t n = (size_t)w * w;
    float *color = malloc(n * channels * sizeof *color), *coc = malloc(n * sizeof *coc);
    float *out = malloc(n * channels * sizeof *out);
    double *disc = malloc(n * sizeof *disc);
    if (!color || !coc || !out || !disc)
        goto done;
    for (size_t i = 0; i < n; i++) {
        coc[i] = d;
        for (uint32_t k = 0; k < channels; k++)
            color[i * channels + k] = POINT_SPREAD_PEDESTAL;
    }
    for (uint32_t k = 0; k < channels; k++) {
        color[((size_t)c * w + (size_t)c) * channels + k] += value;
        color[k] = 0.0f;
    }
    coc[0] = 0.0f;
    ddof_image_in ci = {color, w, w, channels, 0}, zi = {coc, w, w, 1, 0};
    ddof_image oi = {out, w, w, channels, 0};
    r.status = layered ? ddof_diffuse_layers(ctx, params, &ci, &zi, NULL, &oi, NULL)
                       : ddof_diffuse(ctx, params, &ci, &zi, &oi, NULL);
    if (r.status != DDOF_OK)
        goto done;
    /* The first channel, as a kernel of unit weight (in place: i * channels >= i). */
    for (size_t i = 0; i < n; i++)
        out[i] = (float)(((double)out[i * channels] - POINT_SPREAD_PEDESTAL) / value);
    double disc_sum = 0, height = 0;
    for (uint32_t y = 0; y < w; y++)
        for (uint32_t x = 0; x < w; x++) {
            disc[(size_t)y * w + x] = point_spread_disc((int)x, (int)y, c, d);
            disc_sum += disc[(size_t)y * w + x];
        }
    double err2 = 0, ref2 = 0, lowest = 0;
    out[0] = 0.0f; /* the range-widening pixel: no part of the kernel */
    for (size_t i = 0; i < n; i++) {
        const double k = (double)out[i], dd = disc[i] / disc_sum;
        r.energy += k;
        height = dd > height ? dd : height;
        lowest = k < lowest ? k : lowest;
        err2 += (k - dd) * (k - dd);
        ref2 += dd * dd;
    }
    for (size_t i = 0; i < n; i++) {
        const double e = fabs((double)out[i] - disc[i] / disc_sum) / height;
        r.max_abs_err = e > r.max_abs_err ? e : r.max_abs_err;
    }
    /* The kernel's own sum is ~1; normalising it too would hide an energy error in the SNR. */
    r.snr_db = -10.0 * log10(err2 / ref2);
    r.ring = lowest / height;
done:
    free(color);
    free(coc);
    free(out);
    free(disc);
    return r;
}

/* The diffusion's own kernel: a pixel of 1 in a one-channel image (no highlight pass). */
static inline point_spread point_spread_measure(ddof_context *ctx, const ddof_params *params,
                                                float d)
{
    return point_spread_run(ctx, params, d, 1, 1.0f, 0);
}

/* What the frame call draws of a bright RGB point (`value` above the pedestal, above
 * the highlight threshold): the highlight pass's disc over the diffused rest. */
static inline point_spread point_spread_measure_bright(ddof_context *ctx,
                                                       const ddof_params *params, float d,
                                                       float value)
{
    return point_spread_run(ctx, params, d, 3, value, 1);
}

#endif
