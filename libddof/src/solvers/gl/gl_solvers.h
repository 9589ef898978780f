/* SPDX-License-Identifier: MIT */
/* gl_solvers.h - the line solvers of one ADI pass on the GPU (gl_solvers.c), over the passes
 * of gl_solve.h. */
#ifndef DDOF_GL_SOLVERS_H
#define DDOF_GL_SOLVERS_H

#include "gl_solve.h"

/* Solves every line of a pass with d->solver; 0 with a sentence in message on failure. */
int gl_solve_pass(ddof_device *device, const gl_diffusion *d, const gl_pass *pass,
                  char *message, size_t message_size);

/* Whether the GPU solvers cover this solver and precision. */
int gl_solver_supported(ddof_solver solver, ddof_precision precision);

#endif
