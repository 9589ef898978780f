/* solver_pcr.c - parallel cyclic reduction (Zhang, Cohen, Owens 2010).
 *
 * At step k every equation eliminates its neighbours at distance s = 2^k, which couples it to the
 * unknowns at distance 2s instead. After ceil(log2 n) steps the distance exceeds the line and
 * every equation stands alone: y = u. O(n log n) work against cyclic reduction's O(n), but no
 * back-substitution and every step is one independent pass over all equations (what a GPU
 * wants); here it mainly exists to be compared. Steps are double-buffered: an equation must see
 * its neighbours as they were before the step.
 *
 * Row storage and arithmetic are those of solver_cr.c (read its header): per equation, for all
 * lanes, links A and C, excess E (diagonal = E + A + C, never formed by subtraction) and the
 * source value u (right-hand side = E u), updated as u + w * (v - u) with w >= 0.
 */
#include "solver.h"

#include <float.h>

enum { L = DDOF_LANES };

/* A row that does not exist: no links, no excess, value 0 (so every weight on it is 0). */
static _Alignas(64) const float zero_row[(3 + 4) * L] = {0.0f};

static DDOF_ALWAYS_INLINE size_t row_floats(const uint32_t channels)
{
    return (size_t)(3 + channels) * L;
}
#define ROW_A(r) ((r))
#define ROW_C(r) ((r) + L)
#define ROW_E(r) ((r) + 2 * L)
#define ROW_U(r) ((r) + 3 * L) /* [channels][L] */

/* num / den for a share num of a sum den of non-negatives, 0 for 0 / 0; branch-free so it
 * vectorises (see solver_cr.c). */
static DDOF_ALWAYS_INLINE float ratio(float num, float den)
{
    return num / ddof_maxf(den, FLT_TRUE_MIN);
}

/* out = row + alpha * lo + g * hi with alpha, g chosen to cancel row's links to lo and hi. */
static DDOF_ALWAYS_INLINE void eliminate(float *restrict out, const float *restrict row,
                                         const float *restrict lo, const float *restrict hi,
                                         const uint32_t ch)
{
    const float *u = ROW_U(row), *ulo = ROW_U(lo), *uhi = ROW_U(hi);
    float *uo = ROW_U(out);
    for (int l = 0; l < L; l++) {
        /* row's A is lo's C (the same link, up to rounding), a share of lo's diagonal; where
         * that diagonal is 0 alpha only ever multiplies zeros. Likewise g with hi. */
        const float alpha = ratio(ROW_A(row)[l], ROW_E(lo)[l] + ROW_A(lo)[l] + ROW_C(lo)[l]);
        const float g = ratio(ROW_C(row)[l], ROW_E(hi)[l] + ROW_A(hi)[l] + ROW_C(hi)[l]);
        const float elo = alpha * ROW_E(lo)[l], ehi = g * ROW_E(hi)[l];
        const float e = ROW_E(row)[l] + elo + ehi;
        ROW_A(out)[l] = alpha * ROW_A(lo)[l];
        ROW_C(out)[l] = g * ROW_C(hi)[l];
        ROW_E(out)[l] = e;
        /* e u' = E u + elo u_lo + ehi u_hi, written as steps from u */
        const float wlo = ratio(elo, e), whi = ratio(ehi, e);
        for (uint32_t c = 0; c < ch; c++) {
            const size_t k = c * L + l;
            uo[k] = u[k] + wlo * (ulo[k] - u[k]) + whi * (uhi[k] - u[k]);
        }
    }
}

static size_t pcr_scratch_floats(uint32_t n, uint32_t channels)
{
    return 2 * (size_t)n * row_floats(channels);
}

static DDOF_ALWAYS_INLINE void pcr_solve_channels(const line_batch *batch, const uint32_t ch)
{
    const size_t rf = row_floats(ch);
    const uint32_t n = batch->n;
    float *src = batch->scratch, *dst = batch->scratch + n * rf;

    /* The original rows: links beta_{i-1}, beta_i (0 past either end), excess gamma_i, value
     * x_i transposed to [channel][lane]. */
    for (uint32_t i = 0; i < n; i++) {
        float *row = src + i * rf;
        const float *beta = batch->beta + (size_t)i * L, *gamma = batch->gamma + (size_t)i * L;
        const float *left = i > 0 ? beta - L : zero_row, *right = i + 1 < n ? beta : zero_row;
        const float *x = batch->x + (size_t)i * L * ch;
        for (int l = 0; l < L; l++) ROW_A(row)[l] = left[l];
        for (int l = 0; l < L; l++) ROW_C(row)[l] = right[l];
        for (int l = 0; l < L; l++) ROW_E(row)[l] = gamma[l];
        for (uint32_t c = 0; c < ch; c++)
            for (int l = 0; l < L; l++) ROW_U(row)[c * L + l] = x[l * ch + c];
    }

    for (uint64_t s = 1; s < n; s *= 2) {
        for (uint32_t i = 0; i < n; i++) {
            const float *lo = i >= s ? src + (i - s) * rf : zero_row;
            const float *hi = i + s < n ? src + (i + s) * rf : zero_row;
            eliminate(dst + i * rf, src + i * rf, lo, hi, ch);
        }
        float *t = src;
        src = dst;
        dst = t;
    }

    /* Every row is decoupled now (A = C = 0: its neighbours at distance >= n do not exist), so
     * its source value is its solution. */
    for (uint32_t i = 0; i < n; i++) {
        const float *u = ROW_U(src + i * rf);
        float *x = batch->x + (size_t)i * L * ch;
        for (int l = 0; l < L; l++)
            for (uint32_t c = 0; c < ch; c++) x[l * ch + c] = u[c * L + l];
    }
}

/* One copy of the solver per channel count, so every inner loop has a constant trip count. */
static void pcr_solve(const line_batch *batch)
{
    switch (batch->channels) {
    case 1: pcr_solve_channels(batch, 1); break;
    case 2: pcr_solve_channels(batch, 2); break;
    case 3: pcr_solve_channels(batch, 3); break;
    case 4: pcr_solve_channels(batch, 4); break;
    default: break;
    }
}

const solver_ops ddof_solver_pcr = {"pcr", pcr_scratch_floats, pcr_solve};
