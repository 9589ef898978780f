/* SPDX-License-Identifier: MIT */
/* solver_cr.c - cyclic reduction (Kass, Lefohn, Owens 2006, fig. 5).
 *
 * Level k+1 keeps the odd equations of level k; each one absorbs its two even neighbours, which
 * leaves a tridiagonal system of half the size coupling every other unknown. After floor(log2 n)
 * levels one equation with no neighbours is left and its solution is read off. Going back down
 * the pyramid, the odd unknowns of a level are known from the level above and each even unknown
 * follows from its own equation. Works for any n >= 1: a level of m equations has m / 2 above it.
 *
 * The rows and how they are combined are in reduction_rows.h.
 */
#include "reduction_rows.h"

#include <string.h>

/* Solves row for its unknown in place (u becomes y), given the solutions of its neighbours:
 * y = u + (A (y_lo - u) + C (y_hi - u)) / (E + A + C). */
static DDOF_ALWAYS_INLINE void substitute(float *restrict row, const float *restrict ylo,
                                          const float *restrict yhi, const uint32_t ch)
{
    float *u = ROW_U(row);
    for (int l = 0; l < L; l++) {
        const float b = ROW_E(row)[l] + ROW_A(row)[l] + ROW_C(row)[l];
        const float wlo = solver_share(ROW_A(row)[l], b), whi = solver_share(ROW_C(row)[l], b);
        for (uint32_t c = 0; c < ch; c++) {
            const size_t k = c * L + l;
            u[k] += wlo * (ylo[k] - u[k]) + whi * (yhi[k] - u[k]);
        }
    }
}

static size_t cr_scratch_floats(uint32_t n, uint32_t channels)
{
    size_t rows = 0;
    for (uint32_t m = n;; m /= 2) {
        rows += m;
        if (m <= 1) break;
    }
    return rows * row_floats(channels);
}

static DDOF_ALWAYS_INLINE void cr_solve_channels(const line_batch *batch, const uint32_t ch)
{
    const size_t rf = row_floats(ch);
    float *level[33];  /* first row of each level; n < 2^32 gives at most 33 levels */
    uint32_t count[33];
    int top = 0;

    level[0] = batch->scratch;
    count[0] = batch->n;
    for (uint32_t i = 0; i < batch->n; i++) load_row(level[0] + i * rf, batch, i, ch);

    /* Reduce: row j of level k+1 is row 2j+1 of level k with rows 2j and 2j+2 eliminated. */
    while (count[top] > 1) {
        const float *cur = level[top];
        const uint32_t m = count[top];
        float *next = level[top] + (size_t)m * rf;
        for (uint32_t j = 0; j < m / 2; j++) {
            const float *hi = 2 * j + 2 < m ? cur + (2 * j + 2) * rf : zero_row;
            eliminate(next + j * rf, cur + (2 * j + 1) * rf, cur + 2 * j * rf, hi, ch);
        }
        level[top + 1] = next;
        count[top + 1] = m / 2;
        top++;
    }

    /* The top row has no neighbours left (A = C = 0), so its u already is its y. Walk down:
     * odd rows copy their y from the level above, even rows solve with those as neighbours. */
    for (int k = top - 1; k >= 0; k--) {
        const float *up = level[k + 1];
        const uint32_t m = count[k];
        for (uint32_t j = 0; j < m; j++) {
            float *row = level[k] + j * rf;
            if (j & 1) {
                memcpy(ROW_U(row), ROW_U(up + (j / 2) * rf), ch * L * sizeof(float));
            } else {
                const float *ylo = j > 0 ? ROW_U(up + (j / 2 - 1) * rf) : zero_row;
                const float *yhi = j + 1 < m ? ROW_U(up + (j / 2) * rf) : zero_row;
                substitute(row, ylo, yhi, ch);
            }
        }
    }

    for (uint32_t i = 0; i < batch->n; i++) store_values(batch, i, level[0] + i * rf, ch);
}

DDOF_MULTIVERSION static void cr_solve(const line_batch *batch)
{
    DDOF_SOLVE_PER_CHANNEL_COUNT(cr_solve_channels, batch);
}

const solver_ops ddof_solver_cr = {"cr", cr_scratch_floats, cr_solve};
