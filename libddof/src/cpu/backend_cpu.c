/* SPDX-License-Identifier: MIT */
/* backend_cpu.c - the CPU as a backend: the core's solvers and layers behind the seam's table,
 * as the GL plugin's are, so that backends/backend.c has one dispatch for both. Its device is
 * the context itself (its threads and scratch); it opens nothing. It runs the double
 * references too, on every backend: those are the core's measure of the others. */
#include "backend_cpu.h"

#include "adi/adi.h"
#include "layers/layers.h"

#include <stdio.h>

static ddof_context *context_of(const ddof_device *device)
{
    return (ddof_context *)device;
}

static void cpu_describe(const ddof_device *device, ddof_device_info *info)
{
    const uint32_t threads = context_of(device)->thread_count;
    info->hardware = 0;
    snprintf(info->renderer, sizeof info->renderer, "CPU, %u thread%s", threads,
             threads == 1 ? "" : "s");
}

static int cpu_supports(const ddof_device *device, ddof_solver solver, ddof_precision precision)
{
    (void)device;
    if (solver == DDOF_SOLVER_REFERENCE_F64)
        return precision == DDOF_PRECISION_FLOAT;
    return solver != DDOF_SOLVER_GRUEN && precision == DDOF_PRECISION_FLOAT;
}

/* Failures are recorded in the context by the solvers themselves. */
static ddof_status cpu_run(ddof_device *device, const adi_request *request, adi_report *report,
                           char *message, size_t message_size)
{
    (void)message;
    (void)message_size;
    ddof_context *context = context_of(device);
    if (request->solver == DDOF_SOLVER_REFERENCE_F64)
        return request->disc ? ddof_lens_reference(context, request, report)
                             : ddof_adi_reference(context, request, report);
    return request->disc ? ddof_lens_run(context, request, report)
                         : ddof_adi_run(context, request, report);
}

/* The disc kernel with Thomas (lens_adi.c; backend.c asks for the solver). */
static int cpu_supports_disc(const ddof_device *device)
{
    (void)device;
    return 1;
}

/* The layers' steps of layers.c, each diffusion through the dispatch (on the CPU, or on the
 * context's device one request at a time where it takes the request); failures are recorded
 * in the context by the steps themselves. */
static ddof_status cpu_run_layers(ddof_device *device, const adi_layers_request *request,
                                  adi_layers_report *report, char *message, size_t message_size)
{
    (void)message;
    (void)message_size;
    return ddof_run_layers_on_cpu(context_of(device), request, report);
}

const ddof_backend_table ddof_cpu_backend = {
    .abi = DDOF_BACKEND_ABI,
    .table_size = sizeof(ddof_backend_table),
    .open = NULL, /* the context is its device */
    .close = NULL,
    .describe = cpu_describe,
    .supports = cpu_supports,
    .run = cpu_run,
    .supports_disc = cpu_supports_disc,
    .run_layers = cpu_run_layers,
    .render_cards = NULL, /* the core draws the cards itself (cards_draw.c) */
};
