/* solver_thomas.c - Thomas (LU) elimination in weighted-mean form, DDOF_LANES lines at once.
 *
 * Textbook Thomas divides by b_i - a_i c'_{i-1}, which at beta ~ 1e8 in float cancels away the
 * gamma term that makes the system non-singular. Instead carry the *excess* of the eliminated
 * row, q_{i-1} = e_{i-1} beta_{i-1} / (beta_{i-1} + e_{i-1}), which only ever adds
 * non-negative numbers:
 *
 *   e_i = gamma_i + q_{i-1}                         (row i's excess after elimination)
 *   D_i = t_i x_i + s_i D_{i-1},   t_i = gamma_i / e_i,  s_i = q_{i-1} / e_i     (forward)
 *   y_i = u_i D_i + w_i y_{i+1},   u_i = e_i / (beta_i + e_i),  w_i = beta_i / (beta_i + e_i)
 *
 * Every value is a convex combination of inputs, so there is no overshoot. Both weights of each
 * pair come from their own quotient, never as 1 - (the other), and each step is evaluated as a
 * lerp from the endpoint with the larger weight (a + k (b - a) with k <= 1/2): at beta ~ 1e8
 * the weights are 1 - 1e-4 and 1e-4, and this keeps the rounding of each step to about one ulp
 * of the *correction* rather than of the value. Over 4097 strongly coupled unknowns that is the
 * difference between 7.7e-6 and 3e-7 relative error (tests/test_solvers.c). Behind an insulating
 * link s = 0 and t = 1 exactly, and at beta = 0 w = 0 and u = 1 exactly, so a CoC-0 pixel keeps
 * its input bit for bit.
 * Where gamma = 0 and nothing conducts in from the left, e = 0: D takes x as a placeholder and
 * u = 0, w = 1 (the pixel takes its right neighbour), which is the exact solution when the run
 * holds heat further right and a finite constant when it holds none. */
#include "solver.h"

#include <float.h>

#define L DDOF_LANES

static size_t thomas_scratch_floats(uint32_t n, uint32_t channels)
{
    (void)channels;
    return 2 * (size_t)n * L; /* the back-substitution weights w and u */
}

/* ka * a + kb * b for weights ka + kb = 1 (each computed on its own), as a lerp from the endpoint
 * with the larger weight. When kb is exactly 0 the result is exactly a (b finite), and vice
 * versa. Both candidates are computed and one selected, so it vectorises. */
static inline double lerp_near(double a, float ka, double b, float kb)
{
    const double from_a = a + (double)kb * (b - a);
    const double from_b = b + (double)ka * (a - b);
    return ka >= kb ? from_a : from_b;
}

/* Instantiated once per channel count so the inner loops have constant trip counts. */
static DDOF_ALWAYS_INLINE void thomas_solve_channels(const line_batch *batch, const uint32_t C)
{
    const uint32_t n = batch->n;
    float *restrict x = batch->x;
    float *restrict w_all = batch->scratch;                 /* [n][L] */
    float *restrict u_all = batch->scratch + (size_t)n * L; /* [n][L] */
    const float *restrict beta = batch->beta;
    const float *restrict gamma = batch->gamma;
    float q[L] = {0}; /* nothing comes in from the left of element 0 */
    /* The running value of each lane and channel (D going forward, y coming back) is carried in
     * double and rounded only when stored. With huge beta each sweep is a moving average whose
     * memory is longer than the line; in float its per-step rounding compounds (1.8e-5 on a
     * 4096-pixel line at CoC 1e4), in double it stays at one rounding (1.8e-7). */
    double run[L * 4];
    for (uint32_t k = 0; k < L * C; k++)
        run[k] = x[k]; /* D_0 = x_0 */

    for (uint32_t i = 0; i < n; i++) {
        const float *restrict bi = beta + (size_t)i * L;
        const float *restrict gi = gamma + (size_t)i * L;
        float t[L], s[L];
        for (uint32_t l = 0; l < L; l++) {
            const float e = gi[l] + q[l];
            const float r = 1.0f / ddof_maxf(e, FLT_MIN);
            t[l] = q[l] > 0.0f ? gi[l] * r : 1.0f;
            s[l] = q[l] * r;
            const float b = bi[l] + e;
            const float rb = 1.0f / ddof_maxf(b, FLT_MIN);
            const float w = bi[l] * rb;
            w_all[(size_t)i * L + l] = w;
            u_all[(size_t)i * L + l] = bi[l] > 0.0f ? e * rb : 1.0f;
            q[l] = e * w;
        }
        if (i == 0)
            continue;
        float *restrict xi = x + (size_t)i * L * C;
        for (uint32_t l = 0; l < L; l++)
            for (uint32_t c = 0; c < C; c++) {
                const double d = lerp_near(xi[l * C + c], t[l], run[l * C + c], s[l]);
                run[l * C + c] = d;
                xi[l * C + c] = (float)d;
            }
    }
    /* run now holds D_{n-1} = y_{n-1} unrounded. */
    for (uint32_t i = n - 1; i-- > 0;) {
        float *restrict xi = x + (size_t)i * L * C;
        const float *restrict wi = w_all + (size_t)i * L;
        const float *restrict ui = u_all + (size_t)i * L;
        for (uint32_t l = 0; l < L; l++)
            for (uint32_t c = 0; c < C; c++) {
                const double y = lerp_near(xi[l * C + c], ui[l], run[l * C + c], wi[l]);
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
