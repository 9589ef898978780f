/* SPDX-License-Identifier: MIT */
/* solver_thomas.c - Thomas (LU) elimination in weighted-mean form, DDOF_LANES lines at once.
 *
 * Textbook Thomas divides by b_i - a_i c'_{i-1}, which at beta ~ 1e8 in float cancels away the
 * gamma term that makes the system non-singular. Instead carry the *excess* of the eliminated
 * row, q_{i-1} = e_{i-1} beta_{i-1} / (beta_{i-1} + e_{i-1}), which only ever adds
 * non-negative numbers:
 *
 *   e_i = gamma_i + q_{i-1}                               (row i's excess after elimination)
 *   D_i = x_i + s_i (D_{i-1} - x_i),   s_i = q_{i-1} / e_i             (forward: running mean)
 *   y_i = D_i + w_i (y_{i+1} - D_i),   w_i = beta_i / (beta_i + e_i)   (back substitution)
 *
 * Each step is a lerp with one weight in [0, 1]: every value is a convex combination of inputs
 * (no overshoot), and the implied complementary weight is exactly 1 - k, so no normalisation
 * error can build up along the line. Behind an insulating link s = 0, and at beta = 0 w = 0, so a
 * CoC-0 pixel keeps its input bit for bit.
 *
 * The running value (D going forward, y coming back) is carried in double and rounded to float
 * only when stored. With huge beta each sweep is a moving average whose memory is longer than
 * the line, and rounding it to float at every step compounds: 1.8e-5 on a 4096-pixel line at
 * CoC 1e4 against 6.6e-7 in double (tests/test_hard_cases.c), for ~10% more time.
 *
 * Where gamma = 0 and nothing conducts in from the left, e = 0: s = 0 (D takes x as a
 * placeholder) and w = 1 (the pixel takes its right neighbour), which is the exact solution when
 * the run holds heat further right and a finite constant when it holds none. */
#include "solver.h"

#include <float.h>

#define L DDOF_LANES

/* a + k (b - a): exactly a for k = 0 and (b - a being exact in double) b for k = 1. */
static inline double lerp(double a, double b, float k)
{
    return a + (double)k * (b - a);
}

static size_t thomas_scratch_floats(uint32_t n, uint32_t channels)
{
    (void)channels;
    return (size_t)n * L; /* the back-substitution weights w */
}

/* Instantiated once per channel count so the inner loops have constant trip counts. */
static DDOF_ALWAYS_INLINE void thomas_solve_channels(const line_batch *batch, const uint32_t C)
{
    const uint32_t n = batch->n;
    const size_t xs = batch_x_stride(batch);
    float *restrict x = batch->x;
    float *restrict w_all = batch->scratch; /* [n][L] */
    const float *restrict beta = batch->beta;
    const float *restrict gamma = batch->gamma;
    /* A column block solved in place: element i is a row of the image of its own, in a page of
     * its own, which the hardware prefetchers do not follow (perf: the forward sweep's loads
     * of x were a third of the solver's time). Ask for the rows a few elements ahead. */
    const int strided = xs > (size_t)L * C;
    enum { ahead = 8 };
    float q[L] = {0}; /* nothing comes in from the left of element 0 */
    double run[L * 4];
    for (uint32_t k = 0; k < L * C; k++)
        run[k] = x[k]; /* D_0 = x_0 */

    for (uint32_t i = 0; i < n; i++) {
        const float *restrict bi = beta + (size_t)i * L;
        const float *restrict gi = gamma + (size_t)i * L;
        float *restrict wi = w_all + (size_t)i * L;
        float s[L];
        for (uint32_t l = 0; l < L; l++) {
            const float e = gi[l] + q[l];
            s[l] = q[l] / ddof_maxf(e, FLT_MIN);
            const float w = bi[l] / ddof_maxf(bi[l] + e, FLT_MIN);
            wi[l] = w;
            q[l] = e * w;
        }
        if (strided && i + ahead < n)
            for (uint32_t k = 0; k < L * C; k += 16)
                DDOF_PREFETCH(x + (size_t)(i + ahead) * xs + k, 1);
        if (i == 0)
            continue;
        float *restrict xi = x + (size_t)i * xs;
        for (uint32_t l = 0; l < L; l++)
            for (uint32_t c = 0; c < C; c++) {
                const double d = lerp(xi[l * C + c], run[l * C + c], s[l]);
                run[l * C + c] = d;
                xi[l * C + c] = (float)d;
            }
    }
    /* run now holds D_{n-1} = y_{n-1} unrounded. */
    for (uint32_t i = n - 1; i-- > 0;) {
        if (strided && i >= ahead) /* what the forward sweep read may have left the caches */
            for (uint32_t k = 0; k < L * C; k += 16)
                DDOF_PREFETCH(x + (size_t)(i - ahead) * xs + k, 1);
        float *restrict xi = x + (size_t)i * xs;
        const float *restrict wi = w_all + (size_t)i * L;
        for (uint32_t l = 0; l < L; l++)
            for (uint32_t c = 0; c < C; c++) {
                const double y = lerp(xi[l * C + c], run[l * C + c], wi[l]);
                run[l * C + c] = y;
                xi[l * C + c] = (float)y;
            }
    }
}

DDOF_MULTIVERSION static void thomas_solve(const line_batch *batch)
{
    switch (batch->channels) {
    case 1: thomas_solve_channels(batch, 1); break;
    case 2: thomas_solve_channels(batch, 2); break;
    case 3: thomas_solve_channels(batch, 3); break;
    default: thomas_solve_channels(batch, 4); break;
    }
}

const solver_ops ddof_solver_thomas = {"thomas", thomas_scratch_floats, thomas_solve};
