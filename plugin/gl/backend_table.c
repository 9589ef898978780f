/* SPDX-License-Identifier: MIT */
/* backend_table.c - the plugin's one exported symbol: the table libddof/src/backend.c loads
 * (open, close, describe, supports, run, supports_disc, run_layers), and run() itself: upload,
 * ADI (heat or disc kernel), read back, with the device's context current only for the call;
 * run_layers the same bracket around gl_layers.c. */
#include "gl_io.h"
#include "gl_layers.h"

#include <stdio.h>
#include <string.h>

#define DDOF_GL_EXPORT __attribute__((visibility("default")))

static ddof_device *table_open(ddof_backend_kind kind, int require_hardware, char *message,
                               size_t size)
{
    return gl_device_open(kind, require_hardware, message, size);
}

static void table_describe(const ddof_device *device, ddof_device_info *info)
{
    *info = device->info;
}

static int table_supports(const ddof_device *device, ddof_solver solver,
                          ddof_precision precision)
{
    (void)device;
    return gl_solver_supported(solver, precision);
}

/* The disc kernel needs nothing beyond what every device has (float storage buffers). */
static int table_supports_disc(const ddof_device *device)
{
    (void)device;
    return 1;
}

/* What every request must be for this device, checked before the device is touched. */
static ddof_status check_request(const adi_request *r, char *message, size_t size)
{
    if (!gl_solver_supported(r->solver, r->precision)) {
        snprintf(message, size, "solver %d is not available on the GPU", (int)r->solver);
        return DDOF_ERROR_UNSUPPORTED;
    }
    if (r->disc && (r->solver != DDOF_SOLVER_THOMAS || r->precision != DDOF_PRECISION_FLOAT)) {
        snprintf(message, size, "the disc kernel runs with the Thomas solver only");
        return DDOF_ERROR_UNSUPPORTED;
    }
    return DDOF_OK;
}

/* Opens a call: the device's context current, the host's GL errors cleared (they are not
 * ours), the buffers' and transfers' counts reset. 0 when the context cannot be had. */
static int begin_call(ddof_device *device, char *message, size_t size)
{
    if (!gl_device_begin(device, message, size))
        return 0;
    const gl_functions *gl = &device->gl;
    while (gl->GetError() != GL_NO_ERROR) {
    }
    gl_buffers_begin(&device->buffers);
    device->uploads = device->readbacks = 0;
    return 1;
}

/* Closes a call: a GL error turns success into a failure; the report gets the peak memory
 * and the transfers; the last progress report when it succeeded. */
static ddof_status end_call(ddof_device *device, const adi_request *r, ddof_status status,
                            adi_report *report, char *message, size_t size)
{
    const GLenum error = device->gl.GetError();
    if (status == DDOF_OK && error != GL_NO_ERROR) {
        snprintf(message, size, error == GL_OUT_OF_MEMORY ? "out of GPU memory"
                                                          : "GL error 0x%x", (unsigned)error);
        status = DDOF_ERROR_BACKEND_FAILED;
    }
    report->device_bytes = gl_buffers_used(&device->buffers);
    report->uploads = device->uploads;
    report->readbacks = device->readbacks;
    gl_device_end(device);
    if (status == DDOF_OK && r->progress)
        r->progress(r->progress_user, 1.0f);
    return status;
}

static ddof_status table_run(ddof_device *device, const adi_request *r, adi_report *report,
                             char *message, size_t size)
{
    ddof_status status = check_request(r, message, size);
    if (status != DDOF_OK)
        return status;
    if (!begin_call(device, message, size))
        return DDOF_ERROR_BACKEND_FAILED;
    gl_diffusion d = {r->width, r->height, r->channels, r->solver, r->precision,
                      r->substeps, r->jacobi_iterations, r->beta_scale, r->pixel_aspect,
                      r->gamma != NULL, r->progress, r->progress_user, r->disc, {0}, {0}};
    if (d.disc)
        gl_lens_input_range(r, d.lo, d.hi);
    status = DDOF_ERROR_BACKEND_FAILED;
    if (gl_io_upload(device, r, message, size))
        status = d.disc ? gl_lens_diffuse(device, &d, report, message, size)
                        : gl_diffuse(device, &d, report, message, size);
    /* Cancelled: IMAGE_A holds the masked input or the last finished substep, both finite. */
    if ((status == DDOF_OK || status == DDOF_ERROR_CANCELLED) &&
        !gl_io_download(device, r, message, size))
        status = DDOF_ERROR_BACKEND_FAILED;
    return end_call(device, r, status, report, message, size);
}

/* The whole layered frame (gl_layers.c), bracketed as run() is. */
static ddof_status table_run_layers(ddof_device *device, const adi_layers_request *q,
                                    adi_layers_report *report, char *message, size_t size)
{
    ddof_status status = check_request(&q->base, message, size);
    if (status != DDOF_OK)
        return status;
    if (!begin_call(device, message, size))
        return DDOF_ERROR_BACKEND_FAILED;
    status = gl_layers_run(device, q, report, message, size);
    return end_call(device, &q->base, status, &report->adi, message, size);
}

static const ddof_backend_table table = {
    DDOF_BACKEND_ABI, sizeof(ddof_backend_table), table_open, gl_device_close, table_describe,
    table_supports, table_run, table_supports_disc, table_run_layers,
};

DDOF_GL_EXPORT const ddof_backend_table *ddof_gl_backend_table(void);

const ddof_backend_table *ddof_gl_backend_table(void)
{
    return &table;
}
