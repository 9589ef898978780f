/* SPDX-License-Identifier: MIT */
/* stub_backend.c - a backend plugin built for tests/test_backend_tables.c: a whole table (or,
 * with STUB_PARTIAL, one whose render_cards is missing) whose device does nothing but draw
 * cards as a flat marker colour, and only when opened as EGL; opened as OSMESA it says it does
 * not draw them, so the core must hand them to the CPU's table. It runs no diffusion. */
#include "ddof_backend_seam.h"

#include <stdio.h>
#include <stdlib.h>

/* What the stub's cards draw everywhere (premultiplied RGBA). */
#define STUB_MARK 0.25f

struct ddof_device {
    ddof_backend_kind kind;
};

static ddof_device *stub_open(ddof_backend_kind kind, int require_hardware, char *message,
                              size_t size)
{
    (void)require_hardware;
    ddof_device *d = malloc(sizeof *d);
    if (!d)
        snprintf(message, size, "no memory for the stub device");
    else
        d->kind = kind;
    return d;
}

static void stub_close(ddof_device *device)
{
    free(device);
}

static void stub_describe(const ddof_device *device, ddof_device_info *info)
{
    info->hardware = 0;
    snprintf(info->renderer, sizeof info->renderer, "stub (%s)",
             device->kind == DDOF_BACKEND_EGL ? "draws cards" : "no cards");
}

static int stub_supports(const ddof_device *device, ddof_solver solver, ddof_precision precision)
{
    (void)device;
    (void)solver;
    (void)precision;
    return 0;
}

static ddof_status stub_run(ddof_device *device, const adi_request *request, adi_report *report,
                            char *message, size_t size)
{
    (void)device;
    (void)request;
    (void)report;
    snprintf(message, size, "the stub runs no diffusion");
    return DDOF_ERROR_UNSUPPORTED;
}

static int stub_supports_disc(const ddof_device *device)
{
    (void)device;
    return 0;
}

static ddof_status stub_run_layers(ddof_device *device, const adi_layers_request *request,
                                   adi_layers_report *report, char *message, size_t size)
{
    (void)device;
    (void)request;
    (void)report;
    snprintf(message, size, "the stub runs no layers");
    return DDOF_ERROR_UNSUPPORTED;
}

static ddof_status stub_split_near(ddof_device *device, const adi_near_request *request,
                                   adi_near_split *split, adi_report *report, char *message,
                                   size_t size)
{
    (void)device;
    (void)request;
    (void)split;
    (void)report;
    snprintf(message, size, "the stub splits no near layer");
    return DDOF_ERROR_UNSUPPORTED;
}

static int stub_supports_cards(const ddof_device *device)
{
    return device->kind == DDOF_BACKEND_EGL;
}

static ddof_status stub_render_cards(ddof_device *device, const adi_cards_request *r,
                                     char *message, size_t size)
{
    (void)device;
    (void)message;
    (void)size;
    for (uint32_t y = 0; y < r->height; y++)
        for (uint32_t x = 0; x < (size_t)r->width * 4; x++)
            r->out[y * r->out_stride + x] = STUB_MARK;
    return DDOF_OK;
}

static const ddof_backend_table table = {
    .abi = DDOF_BACKEND_ABI,
    .table_size = sizeof(ddof_backend_table),
    .open = stub_open,
    .close = stub_close,
    .describe = stub_describe,
    .supports = stub_supports,
    .run = stub_run,
    .supports_disc = stub_supports_disc,
    .run_layers = stub_run_layers,
    .supports_cards = stub_supports_cards,
#ifndef STUB_PARTIAL
    .render_cards = stub_render_cards,
#endif
    .split_near = stub_split_near,
};

__attribute__((visibility("default"))) const ddof_backend_table *ddof_gl_backend_table(void);

const ddof_backend_table *ddof_gl_backend_table(void)
{
#ifdef STUB_PARTIAL
    (void)stub_render_cards;
#endif
    return &table;
}
