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
 * The running value (D going forward, y coming back) is a moving average whose memory is about
 * sqrt(beta / gamma) pixels. Rounded to float at every step its error grows with that memory:
 * 1.2e-5 on a 4096-pixel line at CoC 1e4 and beta_scale 1 (tests/test_hard_cases.c), against
 * 6.6e-7 when it is carried in double and rounded only when stored. Double cost the whole 1080p
 * step 18.4 ms against 12.8 ms in float, since every value is widened and narrowed and every
 * weight is spread over the channels in double lanes. So a batch whose memory is short (largest
 * beta / smallest positive gamma <= DDOF_FLOAT_RUNNING_MAX_MEMORY, a memory of 256 pixels) runs in
 * float, where the error stays at the level of the double path (test_hard_cases measures both
 * sides of the switch), and only longer ones pay for double. The switch depends on the CoC and
 * the heat capacities alone, never on the colour.
 *
 * Where gamma = 0 and nothing conducts in from the left, e = 0: s = 0 (D takes x as a
 * placeholder) and w = 1 (the pixel takes its right neighbour), which is the exact solution when
 * the run holds heat further right and a finite constant when it holds none. */
#include "solver.h"

#include <float.h>

#define L DDOF_LANES

/* a + k (b - a): exactly a for k = 0 and (b - a being exact in double) b for k = 1. */
static inline double lerp_double(double a, double b, float k)
{
    return a + (double)k * (b - a);
}

/* The same in float: exactly a for k = 0 (a CoC-0 pixel keeps its value bit for bit). */
static inline float lerp_float(float a, float b, float k)
{
    return a + k * (b - a);
}

/* Whether every line of the batch has a short memory: largest beta <= the bound times the
 * smallest positive gamma (gamma 0 holds no heat: its pixels pass the running value on). */
static DDOF_ALWAYS_INLINE int short_memory(const line_batch *batch)
{
    /* Per lane, element-wise (a loop the compiler vectorises; a float min reduction it would
     * not). */
    float beta_max[L] = {0}, gamma_min[L];
    for (uint32_t l = 0; l < L; l++)
        gamma_min[l] = FLT_MAX;
    for (uint32_t i = 0; i < batch->n; i++) {
        const float *restrict b = batch->beta + (size_t)i * L;
        const float *restrict g = batch->gamma + (size_t)i * L;
        for (uint32_t l = 0; l < L; l++) {
            beta_max[l] = ddof_maxf(beta_max[l], b[l]);
            gamma_min[l] = ddof_minf(gamma_min[l], ddof_positive_or_lifted(g[l]));
        }
    }
    int all = 1;
    for (uint32_t l = 0; l < L; l++)
        all &= ddof_float_running_suffices(beta_max[l], gamma_min[l]);
    return all;
}

static size_t thomas_scratch_floats(uint32_t n, uint32_t channels)
{
    (void)channels;
    return (size_t)n * L; /* the back-substitution weights w */
}

/* One element of the sweeps: each value becomes x + k (run - x) with its lane's weight k, and
 * the running value follows it; the running value is kept in double when `wide`, else float. */
static DDOF_ALWAYS_INLINE void lerp_values(float *restrict xi, double *restrict run_d,
                                           float *restrict run_f, const float *restrict k,
                                           const uint32_t C, const int wide)
{
    for (uint32_t l = 0; l < L; l++)
        for (uint32_t c = 0; c < C; c++) {
            if (wide) {
                const double v = lerp_double(xi[l * C + c], run_d[l * C + c], k[l]);
                run_d[l * C + c] = v;
                xi[l * C + c] = (float)v;
            } else {
                const float v = lerp_float(xi[l * C + c], run_f[l * C + c], k[l]);
                run_f[l * C + c] = v;
                xi[l * C + c] = v;
            }
        }
}

/* Instantiated once per channel count so the inner loops have constant trip counts, and once
 * per running precision. */
static DDOF_ALWAYS_INLINE void thomas_solve_channels(const line_batch *batch, const uint32_t C,
                                                     const int wide)
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
    double run_d[L * 4];
    float run_f[L * 4];
    for (uint32_t k = 0; k < L * C; k++) {
        if (wide)
            run_d[k] = x[k]; /* D_0 = x_0 */
        else
            run_f[k] = x[k];
    }

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
        if (i > 0)
            lerp_values(x + (size_t)i * xs, run_d, run_f, s, C, wide);
    }
    /* The running value now holds D_{n-1} = y_{n-1}. */
    for (uint32_t i = n - 1; i-- > 0;) {
        if (strided && i >= ahead) /* what the forward sweep read may have left the caches */
            for (uint32_t k = 0; k < L * C; k += 16)
                DDOF_PREFETCH(x + (size_t)(i - ahead) * xs + k, 1);
        lerp_values(x + (size_t)i * xs, run_d, run_f, w_all + (size_t)i * L, C, wide);
    }
}

DDOF_MULTIVERSION static void thomas_solve(const line_batch *batch)
{
    const int in_float = batch->running == LINE_RUNNING_BY_BATCH
                             ? short_memory(batch)
                             : batch->running == LINE_RUNNING_FLOAT;
    if (in_float) {
        switch (batch->channels) {
        case 1: thomas_solve_channels(batch, 1, 0); break;
        case 2: thomas_solve_channels(batch, 2, 0); break;
        case 3: thomas_solve_channels(batch, 3, 0); break;
        default: thomas_solve_channels(batch, 4, 0); break;
        }
    } else {
        switch (batch->channels) {
        case 1: thomas_solve_channels(batch, 1, 1); break;
        case 2: thomas_solve_channels(batch, 2, 1); break;
        case 3: thomas_solve_channels(batch, 3, 1); break;
        default: thomas_solve_channels(batch, 4, 1); break;
        }
    }
}

const solver_ops ddof_solver_thomas = {"thomas", thomas_scratch_floats, thomas_solve};
