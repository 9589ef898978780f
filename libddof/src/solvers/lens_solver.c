/* SPDX-License-Identifier: MIT */
/* lens_solver.c - complex Thomas elimination in weighted-mean form (see lens_solver.h).
 *
 * Real and imaginary parts live in separate arrays, so every inner loop runs across the
 * DDOF_LANES lanes (and channels) in SIMD exactly as the real solver's do. Values are carried
 * in float: |s|, |w| <= 1 and each step is a complex lerp, so rounding stays at the level of the
 * inputs (tests/test_disc_kernel.c measures it against the double reference on the hard cases).
 */
#include "lens_solver.h"

#include <float.h>

#define L DDOF_LANES

size_t ddof_lens_solver_scratch_floats(uint32_t n, uint32_t channels)
{
    /* s and w (complex) per element and lane, the forward values D (complex) per channel. */
    return (size_t)n * L * 4 + (size_t)n * L * channels * 2;
}

/* The forward and back weights of one term: s_i = q_{i-1} / e_i and w_i = beta_i / (beta_i +
 * e_i), both as num * conj(den) / |den|^2; a zero den has a zero num (the sector argument), and
 * clamping |den|^2 makes that 0 / tiny = 0 without a branch. */
static DDOF_ALWAYS_INLINE void lens_weights(const complex_batch *batch, float kr, float ki,
                                            float *restrict s_re, float *restrict s_im,
                                            float *restrict w_re, float *restrict w_im)
{
    float q_re[L] = {0}, q_im[L] = {0};
    for (uint32_t i = 0; i < batch->n; i++) {
        const float *restrict bi = batch->b + (size_t)i * L;
        const float *restrict gi = batch->gamma + (size_t)i * L;
        const size_t o = (size_t)i * L;
        for (uint32_t l = 0; l < L; l++) {
            const float er = gi[l] + q_re[l], ei = q_im[l];
            /* One division per denominator, not per part (a division costs about ten
             * multiplies; disc-2x2 at 1080p measured 2-3% faster). */
            const float inv_e2 = 1.0f / ddof_maxf(er * er + ei * ei, FLT_MIN);
            s_re[o + l] = (q_re[l] * er + q_im[l] * ei) * inv_e2;
            s_im[o + l] = (q_im[l] * er - q_re[l] * ei) * inv_e2;
            const float br = kr * bi[l], bim = ki * bi[l];
            const float tr = br + er, ti = bim + ei;
            const float inv_t2 = 1.0f / ddof_maxf(tr * tr + ti * ti, FLT_MIN);
            const float wr = (br * tr + bim * ti) * inv_t2, wi = (bim * tr - br * ti) * inv_t2;
            w_re[o + l] = wr;
            w_im[o + l] = wi;
            q_re[l] = er * wr - ei * wi;
            q_im[l] = er * wi + ei * wr;
        }
    }
}

static DDOF_ALWAYS_INLINE void lens_solve_channels(const complex_batch *batch, float kr,
                                                   float ki, const uint32_t C,
                                                   const int real_input)
{
    const uint32_t n = batch->n;
    const size_t xs = batch->x_stride, nl = (size_t)n * L;
    float *restrict s_re = batch->scratch;
    float *restrict s_im = s_re + nl;
    float *restrict w_re = s_im + nl;
    float *restrict w_im = w_re + nl;
    float *restrict d_re = w_im + nl; /* [n][L * C] */
    float *restrict d_im = d_re + nl * C;
    lens_weights(batch, kr, ki, s_re, s_im, w_re, w_im);

    /* Forward: D_i = x_i + s_i (D_{i-1} - x_i), D_0 = x_0 (s_0 = 0). A column block's first
     * step reads the complex image where it lies, a row a page apart: prefetched ahead, as
     * the hardware prefetchers do not follow that stride. */
    enum { ahead = 8 };
    const int strided = xs > (size_t)L * C;
    for (uint32_t i = 0; i < n; i++) {
        if (strided && i + ahead < n)
            for (uint32_t k = 0; k < L * C; k += 16) {
                DDOF_PREFETCH(batch->x_re + (size_t)(i + ahead) * xs + k, 0);
                if (!real_input)
                    DDOF_PREFETCH(batch->x_im + (size_t)(i + ahead) * xs + k, 0);
            }
        const float *restrict xr = batch->x_re + (size_t)i * xs;
        const float *restrict xi = real_input ? xr : batch->x_im + (size_t)i * xs;
        float *restrict dr = d_re + (size_t)i * L * C, *restrict di = d_im + (size_t)i * L * C;
        if (i == 0) {
            for (uint32_t k = 0; k < L * C; k++) {
                dr[k] = xr[k];
                di[k] = real_input ? 0.0f : xi[k];
            }
            continue;
        }
        const float *restrict pr = dr - L * C, *restrict pi = di - L * C;
        const float *restrict sr = s_re + (size_t)i * L, *restrict si = s_im + (size_t)i * L;
        for (uint32_t l = 0; l < L; l++)
            for (uint32_t c = 0; c < C; c++) {
                const uint32_t k = l * C + c;
                const float x_i = real_input ? 0.0f : xi[k];
                const float hr = pr[k] - xr[k], hi = pi[k] - x_i;
                dr[k] = xr[k] + sr[l] * hr - si[l] * hi;
                di[k] = x_i + sr[l] * hi + si[l] * hr;
            }
    }
    /* Back: y_{n-1} = D_{n-1}, y_i = D_i + w_i (y_{i+1} - D_i). The last element is peeled
     * off: a condition on i inside the lane loop kept it scalar for 3 and 4 channels. */
    float yr[L * 4], yi[L * 4];
    {
        const size_t last = (size_t)(n - 1) * L * C;
        for (uint32_t k = 0; k < L * C; k++) {
            yr[k] = d_re[last + k];
            yi[k] = d_im[last + k];
            batch->y_re[last + k] = yr[k];
            batch->y_im[last + k] = yi[k];
        }
    }
    for (uint32_t i = n - 1; i-- > 0;) {
        const float *restrict dr = d_re + (size_t)i * L * C, *restrict di = d_im + (size_t)i * L * C;
        const float *restrict wr = w_re + (size_t)i * L, *restrict wi = w_im + (size_t)i * L;
        float *restrict outr = batch->y_re + (size_t)i * L * C;
        float *restrict outi = batch->y_im + (size_t)i * L * C;
        for (uint32_t l = 0; l < L; l++)
            for (uint32_t c = 0; c < C; c++) {
                const uint32_t k = l * C + c;
                const float vr = dr[k], vi = di[k];
                const float hr = yr[k] - vr, hi = yi[k] - vi;
                yr[k] = vr + (wr[l] * hr - wi[l] * hi);
                yi[k] = vi + (wr[l] * hi + wi[l] * hr);
                outr[k] = yr[k];
                outi[k] = yi[k];
            }
    }
}

#define LENS_CASE(C)                                                                           \
    case C:                                                                                    \
        if (batch->x_im)                                                                       \
            lens_solve_channels(batch, kr, ki, C, 0);                           \
        else                                                                                   \
            lens_solve_channels(batch, kr, ki, C, 1);                           \
        break;

DDOF_MULTIVERSION void ddof_lens_solve(const complex_batch *batch, float kr, float ki)
{
    switch (batch->channels) {
        LENS_CASE(1)
        LENS_CASE(2)
        LENS_CASE(3)
    default:
        if (batch->x_im)
            lens_solve_channels(batch, kr, ki, 4, 0);
        else
            lens_solve_channels(batch, kr, ki, 4, 1);
        break;
    }
}
