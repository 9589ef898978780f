/* SPDX-License-Identifier: MIT */
/* solver_jacobi.c - batch->iterations Jacobi sweeps, starting from y = x.
 *
 *     y_i <- (gamma_i x_i + A_i y_{i-1} + C_i y_{i+1}) / (gamma_i + A_i + C_i)
 *
 * with A_i = beta_{i-1}, C_i = beta_i. Approximate by design: it exists to show what an
 * approximate solver costs in accuracy (the error shrinks by about 2 beta / (gamma + 2 beta) per
 * sweep, so large CoCs need very many). Every sweep reads only the previous sweep's values
 * (double-buffered, Jacobi rather than Gauss-Seidel): each unknown is independent within a sweep,
 * as it would be on a GPU.
 *
 * The update is written y_i <- x_i + wlo (y_{i-1} - x_i) + whi (y_{i+1} - x_i) with
 * wlo = A / (gamma + A + C), whi = C / (gamma + A + C): the diagonal is a sum of non-negatives
 * (never a difference), the weights are computed once, and with no links the output is x bit for
 * bit (gamma x / gamma would not be).
 */
#include "solver.h"

#include <float.h>
#include <string.h>

enum { L = DDOF_LANES };

/* The links past either end of the line: none. */
static _Alignas(64) const float zero_links[L] = {0.0f};

static size_t jacobi_scratch_floats(uint32_t n, uint32_t channels)
{
    return (size_t)n * 2 * L + ((size_t)n + 2 * ((size_t)n + 2)) * channels * L;
}

/* The first guess in a hole (gamma = 0, its own value unread) is the nearest value along the
 * line that holds heat, not the 0 the hole was given: starting from 0 an unconverged Jacobi
 * would pull its neighbours out of the input's range. Only the start changes, not the answer. */
static DDOF_ALWAYS_INLINE void fill_holes(float *y, const float *gamma, uint32_t n,
                                          const uint32_t ch)
{
    const size_t vf = (size_t)ch * L;
    for (int l = 0; l < L; l++) {
        long last = -1; /* the last element holding heat, going forward */
        for (uint32_t i = 0; i < n; i++) {
            if (gamma[(size_t)i * L + l] > 0.0f)
                last = (long)i;
            else if (last >= 0)
                for (uint32_t c = 0; c < ch; c++)
                    y[i * vf + c * L + l] = y[(size_t)last * vf + c * L + l];
        }
        long first = -1; /* leading holes take the first element holding heat */
        for (uint32_t i = 0; i < n && first < 0; i++)
            if (gamma[(size_t)i * L + l] > 0.0f)
                first = (long)i;
        for (long i = 0; i < first; i++)
            for (uint32_t c = 0; c < ch; c++)
                y[(size_t)i * vf + c * L + l] = y[(size_t)first * vf + c * L + l];
    }
}

static DDOF_ALWAYS_INLINE void jacobi_solve_channels(const line_batch *batch, const uint32_t ch)
{
    const uint32_t n = batch->n;
    const size_t vf = (size_t)ch * L; /* floats per unknown, all lanes */
    float *w = batch->scratch;
    float *src = w + (size_t)n * 2 * L;
    float *cur = src + n * vf, *next = cur + (n + 2) * vf;

    for (uint32_t i = 0; i < n; i++) {
        const float *beta = batch->beta + (size_t)i * L, *gamma = batch->gamma + (size_t)i * L;
        const float *left = i > 0 ? beta - L : zero_links, *right = i + 1 < n ? beta : zero_links;
        const float *x = batch->x + i * batch_x_stride(batch);
        float *wlo = w + (2 * i) * L, *whi = wlo + L, *s = src + i * vf;
        for (int l = 0; l < L; l++) {
            const float b = gamma[l] + left[l] + right[l];
            wlo[l] = solver_share(left[l], b);
            whi[l] = solver_share(right[l], b);
            for (uint32_t c = 0; c < ch; c++) s[c * L + l] = x[l * ch + c];
        }
    }
    memcpy(cur + vf, src, n * vf * sizeof(float));
    fill_holes(cur + vf, batch->gamma, n, ch);
    memset(cur, 0, vf * sizeof(float));
    memset(cur + (n + 1) * vf, 0, vf * sizeof(float));
    memset(next, 0, vf * sizeof(float));
    memset(next + (n + 1) * vf, 0, vf * sizeof(float));

    for (uint32_t it = 0; it < batch->iterations; it++) {
        for (uint32_t i = 0; i < n; i++) {
            const float *wlo = w + (2 * i) * L, *whi = w + (2 * i + 1) * L;
            const float *s = src + i * vf, *ylo = cur + i * vf, *yhi = cur + (i + 2) * vf;
            float *restrict y = next + (i + 1) * vf; /* never one of the buffers read */
            for (uint32_t c = 0; c < ch; c++)
                for (int l = 0; l < L; l++) {
                    const size_t k = c * L + l;
                    y[k] = s[k] + wlo[l] * (ylo[k] - s[k]) + whi[l] * (yhi[k] - s[k]);
                }
        }
        float *t = cur;
        cur = next;
        next = t;
    }

    for (uint32_t i = 0; i < n; i++) {
        const float *y = cur + (i + 1) * vf;
        float *x = batch->x + i * batch_x_stride(batch);
        for (int l = 0; l < L; l++)
            for (uint32_t c = 0; c < ch; c++) x[l * ch + c] = y[c * L + l];
    }
}

DDOF_MULTIVERSION static void jacobi_solve(const line_batch *batch)
{
    DDOF_SOLVE_PER_CHANNEL_COUNT(jacobi_solve_channels, batch);
}

const solver_ops ddof_solver_jacobi = {"jacobi", jacobi_scratch_floats, jacobi_solve};
