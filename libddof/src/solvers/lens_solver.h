/* SPDX-License-Identifier: MIT */
/* lens_solver.h - the complex tridiagonal solve behind the disc kernel, DDOF_LANES lines at once.
 *
 * One step of the disc kernel is an implicit step with a complex conductance beta = kappa * b:
 * b >= 0 is the link's real conductance (the smaller CoC of its two pixels, squared) and kappa
 * is the step's complex constant with Re(kappa) > 0. Per lane it solves
 *
 *     gamma_i (y_i - x_i) = beta_i (y_{i+1} - y_i) - beta_{i-1} (y_i - y_{i-1})
 *
 * with complex y and x, by the same weighted-mean elimination as the real Thomas solver
 * (solver_thomas.c): e_i = gamma_i + q_{i-1}, s_i = q_{i-1} / e_i, w_i = beta_i / (beta_i + e_i),
 * q_i = e_i w_i. Every beta of one solve has kappa's phase and gamma is real and >= 0, so e, q
 * and beta all lie in the sector between the real axis and kappa's direction (the reciprocal of
 * a sum of reciprocals stays in it): sums never cancel, |w| <= 1 and |s| <= 1, and no pivoting
 * is needed. beta = 0 still decouples exactly (s = 0 behind it, w = 0 before it).
 *
 * A pixel without links comes out exactly as it went in (s = w = 0 there), so a chain of solves
 * keeps it bit for bit. y may be the very same array as x (then x_stride = LANES * channels).
 */
#ifndef DDOF_LENS_SOLVER_H
#define DDOF_LENS_SOLVER_H

#include "ddof_backend_seam.h"
#include "solver.h"

typedef struct complex_batch {
    uint32_t n;            /* unknowns per line, >= 1                                        */
    uint32_t channels;     /* values per unknown, 1..4                                       */
    const float *b;        /* [n][LANES] real link conductance i -> i+1, 0 or >= the minimum  */
    const float *gamma;    /* [n][LANES] heat capacity, >= 0                                 */
    const float *x_re;     /* [n][x_stride] input, real part                                 */
    const float *x_im;     /* imaginary part with the same layout; NULL: a real input        */
    size_t x_stride;       /* floats from element i to i + 1                                 */
    float *y_re;           /* [n][LANES * channels] the solution                            */
    float *y_im;
    float *scratch;        /* lens_solver_scratch_floats(n, channels) floats                 */
} complex_batch;

size_t ddof_lens_solver_scratch_floats(uint32_t n, uint32_t channels);

/* y = the solution for the conductances kappa * b. */
void ddof_lens_solve(const complex_batch *batch, float kappa_re, float kappa_im);

#endif
