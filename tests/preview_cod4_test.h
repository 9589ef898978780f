/* SPDX-License-Identifier: MIT */
/* preview_cod4_test.h - what test_preview_cod4.c and test_preview_cod4_calls.c share: the
 * preview's params and call, the range check and the random CoC and HDR fills. */
#ifndef PREVIEW_COD4_TEST_H
#define PREVIEW_COD4_TEST_H

#include "ddof.h"
#include "test_images.h"
#include "test_util.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>

static inline ddof_params preview_params(int coc_signed)
{
    ddof_params p;
    ddof_params_init(&p);
    p.method = DDOF_METHOD_COD4_PREVIEW;
    p.coc_signed = (uint32_t)coc_signed;
    return p;
}

/* The preview of colour (w x h x ch) with CoC (w x h) into out. */
static inline ddof_status preview(ddof_context *ctx, int coc_signed, const float *color,
                                  const float *coc, float *out, uint32_t w, uint32_t h, uint32_t ch, ddof_stats *st)
{
    ddof_params p = preview_params(coc_signed);
    if (st)
        *st = stats_init();
    return diffuse(ctx, &p, color, coc, out, w, h, ch, st);
}

/* Values outside the per-channel range of `in` (or not finite). */
static inline size_t outside_range(const float *in, const float *out, size_t px, uint32_t ch)
{
    float lo[4], hi[4];
    for (uint32_t c = 0; c < ch; c++) {
        lo[c] = INFINITY;
        hi[c] = -INFINITY;
    }
    for (size_t i = 0; i < px; i++)
        for (uint32_t c = 0; c < ch; c++) {
            lo[c] = fminf(lo[c], in[i * ch + c]);
            hi[c] = fmaxf(hi[c], in[i * ch + c]);
        }
    size_t bad = 0;
    for (size_t i = 0; i < px; i++)
        for (uint32_t c = 0; c < ch; c++) {
            const float v = out[i * ch + c];
            bad += !(v >= lo[c] && v <= hi[c]);
        }
    return bad;
}

/* Random signed CoC: a fraction `zeros` exactly 0, the rest |CoC| log-uniform in [0.1, max],
 * negative (near) with probability `near`. */
static inline void fill_signed_coc(float *coc, size_t n, test_rng *rng, double max, double zeros,
                            double near)
{
    for (size_t i = 0; i < n; i++) {
        if (test_uniform(rng) < zeros) {
            coc[i] = 0.0f;
            continue;
        }
        const double v = 0.1 * pow(max / 0.1, test_uniform(rng));
        coc[i] = (float)(test_uniform(rng) < near ? -v : v);
        if (fabsf(coc[i]) > DDOF_MAX_COC_PX)
            coc[i] = coc[i] < 0 ? -DDOF_MAX_COC_PX : DDOF_MAX_COC_PX;
    }
}

/* HDR-ish colour: mostly [0, 1], some large values, a few negative. */
static inline void fill_hdr(float *p, size_t n, test_rng *rng)
{
    for (size_t i = 0; i < n; i++) {
        const double u = test_uniform(rng);
        p[i] = (float)(u < 0.05 ? 1000.0 * test_uniform(rng)
                                : (u < 0.08 ? -test_uniform(rng) : test_uniform(rng)));
    }
}

/* The sizes most tests run on: odd, not divisible by 4, thin, one pixel, and one that spans
 * several bands of the last pass (64 rows each). */

#endif
