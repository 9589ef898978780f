/* SPDX-License-Identifier: MIT */
/* solver.h - the tridiagonal line solvers behind one table of function pointers.
 *
 * A solver works on a batch of DDOF_LANES independent lines of n unknowns each, solving per lane
 *
 *     gamma_i (y_i - x_i) = beta_i (y_{i+1} - y_i) - beta_{i-1} (y_i - y_{i-1})
 *
 * i.e. the unnormalised system a_i = -beta_{i-1}, b_i = gamma_i + beta_{i-1} + beta_i,
 * c_i = -beta_i, rhs_i = gamma_i x_i, with beta_{-1} = beta_{n-1} = 0 (insulated ends).
 *
 * Layout: element i of lane l is at [i * DDOF_LANES + l] for the coefficients and at
 * [i * x_stride + l * channels + c] for the values (x_stride = DDOF_LANES * channels when
 * packed). This is the image's own memory order for a column pass (lanes = neighbouring columns,
 * x_stride = the row stride: solved in place) and a gather away for a row pass (lanes =
 * neighbouring rows), and lets every inner loop run across lanes (and channels) in SIMD.
 *
 * Numerical contract (all solvers): never form b_i - (something) by subtraction. Keep each row's
 * *excess* e_i = b_i + a_i + c_i (its row sum, >= 0) and build diagonals as sums of non-negative
 * terms; row operations of elimination add rows with non-negative weights, so the excess of a
 * combined row is the same combination of excesses. This keeps beta ~ 1e8 exact enough in float
 * (1 + 2e8 would otherwise drop the 1) and makes every output a convex combination of inputs.
 * A diagonal that is exactly 0 (gamma = 0 with no conductive neighbour) must not produce NaN or
 * Inf: treat the division as giving weight 0.
 */
#ifndef DDOF_SOLVER_H
#define DDOF_SOLVER_H

#include "runtime/float_ops.h"

#include <float.h>
#include <stddef.h>
#include <stdint.h>

/* Lines solved together. 16 floats = one AVX-512 register, two AVX2 registers. */
#define DDOF_LANES 16

/* beta / gamma up to which Thomas's running values stay in float: a memory of 256 pixels
 * (solver_thomas.c says why). */
#define DDOF_FLOAT_RUNNING_MAX_MEMORY 65536.0f

/* Whether lines whose largest link is beta_max and smallest positive heat capacity gamma_min
 * keep Thomas's running values in float: the one rule for a row batch and a column pass. */
static inline int ddof_float_running_suffices(float beta_max, float gamma_min)
{
    return beta_max <= DDOF_FLOAT_RUNNING_MAX_MEMORY * gamma_min;
}

/* A heat capacity as the smallest positive one is looked for: 0 (no heat held) lifted out of
 * the minimum by adding FLT_MAX, branch-free so that the loops vectorise. */
static inline float ddof_positive_or_lifted(float gamma)
{
    return gamma + (float)(gamma <= 0.0f) * FLT_MAX;
}

/* Thomas's running values: chosen by the batch's own memory (a partition of lines that does not
 * change between calls, the row pass's), or given for a whole pass (the column pass, whose
 * blocks follow the output's alignment: a per-batch choice would make a line's result depend
 * on where the caller's buffer lies). */
typedef enum line_running {
    LINE_RUNNING_BY_BATCH = 0,
    LINE_RUNNING_FLOAT,
    LINE_RUNNING_DOUBLE
} line_running;

typedef struct line_batch {
    uint32_t n;          /* unknowns per line, >= 1                                            */
    uint32_t channels;   /* values per unknown, 1..4                                           */
    const float *beta;   /* [n][LANES] link i -> i+1, >= 0, finite; beta[n-1][*] is 0          */
    const float *gamma;  /* [n][LANES] >= 0, finite (1 for plain diffusion)                    */
    float *x;            /* [n][x_stride] finite input in, solution y out                      */
    float *scratch;      /* scratch_floats(n, channels) floats, 64-byte aligned, uninitialised */
    uint32_t iterations; /* Jacobi sweeps (>= 1); ignored by exact solvers                     */
    size_t x_stride;     /* floats from element i to i + 1; 0 means packed (LANES * channels)  */
    line_running running; /* Thomas: its running values' precision (solver_thomas.c)         */
} line_batch;

/* The distance between consecutive elements of x. */
static inline size_t batch_x_stride(const line_batch *batch)
{
    return batch->x_stride ? batch->x_stride : (size_t)DDOF_LANES * batch->channels;
}

typedef struct solver_ops {
    const char *name;
    size_t (*scratch_floats)(uint32_t n, uint32_t channels);
    void (*solve)(const line_batch *batch);
} solver_ops;

/* num / den for a share num of a sum den of non-negatives (num <= den), and 0 for 0 / 0: the
 * diagonal of a row with no excess and no links. Clamping den to the smallest subnormal keeps
 * every positive den exact, and unlike a `den > 0 ? ... : 0` select (which GCC will not
 * if-convert under the default -ftrapping-math) the loop stays branch-free and vectorises. */
static inline float solver_share(float num, float den)
{
    return num / ddof_maxf(den, FLT_TRUE_MIN);
}

/* The body of a solver's solve(): solve_channels(batch, C) with C a constant 1..4 (any other
 * count solves nothing), one copy per channel count, so that every inner loop has a constant
 * trip count. */
#define DDOF_SOLVE_PER_CHANNEL_COUNT(solve_channels, batch)                                    \
    do {                                                                                        \
        switch ((batch)->channels) {                                                            \
        case 1: solve_channels((batch), 1); break;                                              \
        case 2: solve_channels((batch), 2); break;                                              \
        case 3: solve_channels((batch), 3); break;                                              \
        case 4: solve_channels((batch), 4); break;                                              \
        default: break;                                                                         \
        }                                                                                       \
    } while (0)

extern const solver_ops ddof_solver_thomas;
extern const solver_ops ddof_solver_cr;
extern const solver_ops ddof_solver_pcr;
extern const solver_ops ddof_solver_jacobi;

#endif
