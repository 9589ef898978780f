/* SPDX-License-Identifier: MIT */
/* adi.h - alternating-direction implicit diffusion of an image: rows, then columns, n times. */
#ifndef DDOF_ADI_H
#define DDOF_ADI_H

#include "ddof_backend_seam.h"
#include "runtime/internal.h"

#include <math.h>

/* A request with nothing out of focus (largest |CoC| max_coc): its colour copied to its out,
 * every line counted as skipped, as a run would have (in_focus_copy.c). */
void ddof_adi_copy_in_focus(ddof_context *context, const adi_request *r, adi_report *report,
                            float max_coc);

/* The float solvers (Thomas, CR, PCR, Jacobi), multi-threaded. */
ddof_status ddof_adi_run(ddof_context *context, const adi_request *request, adi_report *report);

/* The double-precision reference: whole image in double, textbook Thomas, one thread. */
ddof_status ddof_adi_reference(ddof_context *context, const adi_request *request,
                               adi_report *report);

/* The disc kernel (request->disc set): lens_adi.c in float on the context's threads, and its
 * double-precision reference (lens_reference_f64.c). Same contract as ddof_adi_run, except
 * that the output is no longer a convex combination of the input. */
ddof_status ddof_lens_run(ddof_context *context, const adi_request *request, adi_report *report);
ddof_status ddof_lens_reference(ddof_context *context, const adi_request *request,
                                adi_report *report);

#endif
