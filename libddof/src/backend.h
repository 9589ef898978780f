/* SPDX-License-Identifier: MIT */
/* backend.h - the seam between the core and a diffusion backend (the GL plugin).
 *
 * The planner and the layers decide *what* to simulate and issue ADI requests (adi.h); a
 * backend decides *how* to run one. The CPU backend is adi.c and reference_f64.c. The GL
 * backends live in the plugin library libddof_gl, which the core loads with
 * dlopen(RTLD_LOCAL) and asks for one table through the symbol DDOF_BACKEND_ENTRY_SYMBOL.
 * The plugin is built from this tree, but the two libraries can still be mixed up on disk, so
 * the table carries an ABI number and its size, checked before use.
 *
 * This header is shared by libddof and plugin/gl only; it is not installed.
 */
#ifndef DDOF_BACKEND_H
#define DDOF_BACKEND_H

#include "adi.h"

/* ---- the core's side (backend.c) ---------------------------------------------------------- */

/* Runs one diffusion on the context's backend: the double reference and the CPU solvers here,
 * everything else on the loaded device. */
ddof_status ddof_run_adi(ddof_context *context, const adi_request *request, adi_report *report);

/* Whether the disc kernel runs with this solver on the context's backend: on the CPU with
 * Thomas (lens_adi.c), on a device whose table says so with Thomas, and with REFERENCE_F64
 * everywhere (the core runs the reference itself). */
int ddof_backend_runs_disc(const ddof_context *context, ddof_solver solver);

/* DDOF_OK when the context's backend can run this solver/precision, else a failure recorded
 * in the context (before any output is written). */
ddof_status ddof_check_backend_supports(ddof_context *context, ddof_solver solver,
                                        ddof_precision precision);

/* Releases the loaded plugin and device (context teardown). */
void ddof_backend_release(ddof_context *context);

#endif
