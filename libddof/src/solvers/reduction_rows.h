/* SPDX-License-Identifier: MIT */
/* reduction_rows.h - the equation rows that cyclic reduction (solver_cr.c) and parallel cyclic
 * reduction (solver_pcr.c) store and combine.
 *
 * Every equation is stored for all lanes as one block of (3 + channels) * LANES floats, in the
 * form the numerical contract of solver.h asks for:
 *
 *     (E + A + C) y_i - A y_lo - C y_hi = E u_i         A, C, E >= 0
 *
 * A and C are the links to the neighbours at the current distance, E the row's excess (gamma at
 * level 0). Instead of the right-hand side r = E u we keep the *source value* u (x at level 0, a
 * convex combination of x's later) and write every update as u + w * (v - u). Then an equation
 * whose weights are 0 returns its u bit for bit: in float, (gamma * x) / gamma differs from x for
 * about one value in ten, and "a pixel cut off from its neighbours is untouched" is a test.
 */
#ifndef DDOF_REDUCTION_ROWS_H
#define DDOF_REDUCTION_ROWS_H

#include "solver.h"

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

/* Level-0 row i from the batch: links beta_{i-1}, beta_i (0 past either end), excess gamma_i. */
static DDOF_ALWAYS_INLINE void load_row(float *restrict row, const line_batch *batch, uint32_t i,
                                        const uint32_t ch)
{
    const float *beta = batch->beta + (size_t)i * L, *gamma = batch->gamma + (size_t)i * L;
    const float *left = i > 0 ? beta - L : zero_row, *right = i + 1 < batch->n ? beta : zero_row;
    const float *x = batch->x + (size_t)i * batch_x_stride(batch);
    for (int l = 0; l < L; l++) ROW_A(row)[l] = left[l];
    for (int l = 0; l < L; l++) ROW_C(row)[l] = right[l];
    for (int l = 0; l < L; l++) ROW_E(row)[l] = gamma[l];
    for (uint32_t c = 0; c < ch; c++)
        for (int l = 0; l < L; l++) ROW_U(row)[c * L + l] = x[l * ch + c];
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
        const float alpha = solver_share(ROW_A(row)[l], ROW_E(lo)[l] + ROW_A(lo)[l] + ROW_C(lo)[l]);
        const float g = solver_share(ROW_C(row)[l], ROW_E(hi)[l] + ROW_A(hi)[l] + ROW_C(hi)[l]);
        const float elo = alpha * ROW_E(lo)[l], ehi = g * ROW_E(hi)[l];
        const float e = ROW_E(row)[l] + elo + ehi;
        ROW_A(out)[l] = alpha * ROW_A(lo)[l];
        ROW_C(out)[l] = g * ROW_C(hi)[l];
        ROW_E(out)[l] = e;
        /* e u' = E u + elo u_lo + ehi u_hi, written as steps from u */
        const float wlo = solver_share(elo, e), whi = solver_share(ehi, e);
        for (uint32_t c = 0; c < ch; c++) {
            const size_t k = c * L + l;
            uo[k] = u[k] + wlo * (ulo[k] - u[k]) + whi * (uhi[k] - u[k]);
        }
    }
}

/* Row i's source values back into the batch: the solution once the row stands alone. */
static DDOF_ALWAYS_INLINE void store_values(const line_batch *batch, uint32_t i,
                                            const float *restrict row, const uint32_t ch)
{
    const float *u = ROW_U(row);
    float *x = batch->x + (size_t)i * batch_x_stride(batch);
    for (int l = 0; l < L; l++)
        for (uint32_t c = 0; c < ch; c++) x[l * ch + c] = u[c * L + l];
}

#endif
