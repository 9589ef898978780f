/* solver_cr.c - cyclic reduction (Kass, Lefohn, Owens 2006, fig. 5).
 *
 * Level k+1 keeps the odd equations of level k; each one absorbs its two even neighbours, which
 * leaves a tridiagonal system of half the size coupling every other unknown. After floor(log2 n)
 * levels one equation with no neighbours is left and its solution is read off. Going back down
 * the pyramid, the odd unknowns of a level are known from the level above and each even unknown
 * follows from its own equation. Works for any n >= 1: a level of m equations has m / 2 above it.
 *
 * Every equation of every level is stored for all lanes as one block of (3 + channels) * LANES
 * floats (see ROW_* below). Rows are in the form the numerical contract of solver.h asks for:
 *
 *     (E + A + C) y_i - A y_lo - C y_hi = E u_i         A, C, E >= 0
 *
 * A and C are the links to the neighbours at this level's distance, E the row's excess (gamma at
 * level 0). Instead of the right-hand side r = E u we keep the *source value* u (x at level 0, a
 * convex combination of x's above) and write every update as u + w * (v - u). Then an equation
 * whose weights are 0 returns its u bit for bit: in float, (gamma * x) / gamma differs from x for
 * about one value in ten, and "a pixel cut off from its neighbours is untouched" is a test.
 */
#include "solver.h"

#include <float.h>
#include <string.h>

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

/* num / den for a share num of a sum den of non-negatives (num <= den), and 0 for 0 / 0: the
 * diagonal of a row with no excess and no links. Clamping den to the smallest subnormal keeps
 * every positive den exact, and unlike a `den > 0 ? ... : 0` select (which GCC will not
 * if-convert under the default -ftrapping-math) the loop stays branch-free and vectorises. */
static DDOF_ALWAYS_INLINE float ratio(float num, float den)
{
    return num / ddof_maxf(den, FLT_TRUE_MIN);
}

/* Level-0 row i from the batch: links beta_{i-1}, beta_i (0 past either end), excess gamma_i. */
static DDOF_ALWAYS_INLINE void load_row(float *restrict row, const line_batch *batch, uint32_t i,
                                        const uint32_t ch)
{
    const float *beta = batch->beta + (size_t)i * L, *gamma = batch->gamma + (size_t)i * L;
    const float *left = i > 0 ? beta - L : zero_row, *right = i + 1 < batch->n ? beta : zero_row;
    const float *x = batch->x + (size_t)i * L * ch;
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

/* Solves row for its unknown in place (u becomes y), given the solutions of its neighbours:
 * y = u + (A (y_lo - u) + C (y_hi - u)) / (E + A + C). */
static DDOF_ALWAYS_INLINE void substitute(float *restrict row, const float *restrict ylo,
                                          const float *restrict yhi, const uint32_t ch)
{
    float *u = ROW_U(row);
    for (int l = 0; l < L; l++) {
        const float b = ROW_E(row)[l] + ROW_A(row)[l] + ROW_C(row)[l];
        const float wlo = ratio(ROW_A(row)[l], b), whi = ratio(ROW_C(row)[l], b);
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

    for (uint32_t i = 0; i < batch->n; i++) {
        const float *u = ROW_U(level[0] + i * rf);
        float *x = batch->x + (size_t)i * L * ch;
        for (int l = 0; l < L; l++)
            for (uint32_t c = 0; c < ch; c++) x[l * ch + c] = u[c * L + l];
    }
}

/* One copy of the solver per channel count, so every inner loop has a constant trip count. */
static void cr_solve(const line_batch *batch)
{
    switch (batch->channels) {
    case 1: cr_solve_channels(batch, 1); break;
    case 2: cr_solve_channels(batch, 2); break;
    case 3: cr_solve_channels(batch, 3); break;
    case 4: cr_solve_channels(batch, 4); break;
    default: break;
    }
}

const solver_ops ddof_solver_cr = {"cr", cr_scratch_floats, cr_solve};
