/* SPDX-License-Identifier: MIT */
/* backend.h - the core's side of the backend seam (backend.c): running a request on the
 * context's backend, and what the planner asks of it. What crosses the seam (the request, the
 * report, the backend's table) is in ddof_backend_seam.h, which the GL plugin includes alone.
 * Every backend is a table of that shape: the GL plugin's, loaded at run time, and the CPU's
 * (cpu/backend_cpu.c: the solvers, the layers and the double references), which the context
 * holds (context->cpu), so one dispatch serves both. */
#ifndef DDOF_BACKEND_H
#define DDOF_BACKEND_H

#include "adi/adi.h"

/* Runs one diffusion on the backend that takes it: the context's loaded device, else the CPU
 * (the double reference always, and a disc kernel the device does not run). */
ddof_status ddof_run_adi(ddof_context *context, const adi_request *request, adi_report *report);

/* The disc kernel's table when the context's backend runs `kernel` with this solver, else NULL:
 * the heat kernel runs (ddof_stats.kernel says which ran). A disc kernel has a complex form of
 * the Thomas solver only (on the CPU and on a device that runs it) and the double reference. */
const disc_kernel *ddof_backend_disc_kernel(const ddof_context *context, ddof_solver solver,
                                            ddof_kernel kernel);

/* DDOF_OK when the context's backend can run this solver/precision, else a failure recorded
 * in the context (before any output is written). */
ddof_status ddof_check_backend_supports(ddof_context *context, ddof_solver solver,
                                        ddof_precision precision);

/* Whether the context's backend runs this request's whole layered frame (run_layers): a
 * solver it runs, the disc kernel only where it runs it, a CoC image; else the CPU's table. */
int ddof_backend_runs_layers(const ddof_context *context, const adi_request *request);

/* The near layer's split, on the context's device where it runs the frame's layers (the images
 * then stay there: ADI_ON_DEVICE), else, or where the device declines the frame, on the CPU's
 * table; a failure is recorded in the context. report: the device's memory and transfers. */
ddof_status ddof_backend_split_near(ddof_context *context, const adi_near_request *request,
                                    adi_near_split *split, adi_report *report);

/* The whole layered frame on the context's backend (on_backend: where the planner put it,
 * which ddof_backend_runs_layers allowed), else on the CPU's table; a failure is recorded in
 * the context. */
ddof_status ddof_backend_run_layers(ddof_context *context, int on_backend,
                                    const adi_layers_request *request,
                                    adi_layers_report *report);

/* The cards (ddof_render_cards) on the context's backend where its device draws them, else
 * on the CPU's table; a failure is recorded in the context. */
ddof_status ddof_backend_render_cards(ddof_context *context, const adi_cards_request *request);

/* Whether every entry of t is filled (a loaded table with one missing is refused). */
int ddof_backend_table_whole(const ddof_backend_table *t);

/* The CPU as the new context's backend (context creation). */
void ddof_backend_start(ddof_context *context);

/* Releases the loaded plugin and device (context teardown). */
void ddof_backend_release(ddof_context *context);

#endif
