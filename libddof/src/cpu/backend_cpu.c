/* SPDX-License-Identifier: MIT */
/* backend_cpu.c - the CPU as a backend: the core's solvers and layers behind the seam's table,
 * as the GL plugin's are, every entry filled, so that backends/backend.c has one dispatch for
 * both. Its device is the context itself (its threads and scratch); it opens nothing. It runs
 * the double references too, on every backend: those are the core's measure of the others;
 * and it draws the cards where the context's device does not. */
#include "backend_cpu.h"

#include "adi/adi.h"
#include "cards/cards.h"
#include "layers/layers.h"
#include "passes/near_layer.h"
#include "planner/planner.h"

#include <stdio.h>
#include <string.h>

static ddof_context *context_of(const ddof_device *device)
{
    return (ddof_context *)device;
}

/* The context is the CPU's device, held from its creation (backend.c): nothing to open. */
static ddof_device *cpu_open(ddof_backend_kind kind, int require_hardware, char *message,
                             size_t message_size)
{
    (void)kind;
    (void)require_hardware;
    snprintf(message, message_size, "the CPU opens no device: its device is the context");
    return NULL;
}

static void cpu_close(ddof_device *device)
{
    (void)device; /* the context, freed by ddof_context_free */
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
    if (request->all_in_focus && request->coc) {
        ddof_adi_copy_in_focus(context, request, report, request->known_max_coc);
        return DDOF_OK;
    }
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

/* The near layer's split (passes/near_layer.c) in the context's scratch, and the rest's
 * analysis by the planner's rules; failures are recorded in the context by the split. */
static ddof_status cpu_split_near(ddof_device *device, const adi_near_request *request,
                                  adi_near_split *out, adi_report *report, char *message,
                                  size_t message_size)
{
    (void)message;
    (void)message_size;
    ddof_context *context = context_of(device);
    const adi_request *r = &request->base;
    memset(report, 0, sizeof *report);
    near_split split;
    const ddof_status status = ddof_split_near(context, r, request->threshold, &split);
    if (status != DDOF_OK)
        return status;
    ddof_params rules;
    ddof_params_init(&rules);
    rules.background_threshold_px = request->background_threshold_px;
    rules.background_ramp_start_px = request->background_ramp_start_px;
    coc_analysis rest;
    ddof_analyse_coc(context, split.rest_coc, r->width, 1, r->width, r->height, &rules, &rest);
    *out = (adi_near_split){.rest = split.rest,
                            .rest_coc = split.rest_coc,
                            .element = split.element,
                            .element_coc = split.element_coc,
                            .carried_alpha = split.carried_alpha,
                            .box = split.box,
                            .max_coc = split.max_coc,
                            .element_pixels = split.element_pixels,
                            .holes = split.holes,
                            .filled = (uint32_t)split.filled,
                            .rest_background_box = rest.background_box,
                            .rest_near_box = rest.near_box};
    return DDOF_OK;
}

static int cpu_supports_cards(const ddof_device *device)
{
    (void)device;
    return 1;
}

/* The core's drawing (cards_draw.c); failures are recorded in the context. */
static ddof_status cpu_render_cards(ddof_device *device, const adi_cards_request *request,
                                    char *message, size_t message_size)
{
    (void)message;
    (void)message_size;
    return ddof_draw_cards_on_cpu(context_of(device), request);
}

const ddof_backend_table ddof_cpu_backend = {
    .abi = DDOF_BACKEND_ABI,
    .table_size = sizeof(ddof_backend_table),
    .open = cpu_open,
    .close = cpu_close,
    .describe = cpu_describe,
    .supports = cpu_supports,
    .run = cpu_run,
    .supports_disc = cpu_supports_disc,
    .run_layers = cpu_run_layers,
    .supports_cards = cpu_supports_cards,
    .render_cards = cpu_render_cards,
    .split_near = cpu_split_near,
};
