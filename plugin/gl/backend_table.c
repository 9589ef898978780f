/* SPDX-License-Identifier: MIT */
/* backend_table.c - the plugin's one exported symbol: the table libddof/src/backends/backend.c
 * loads (open, close, describe, supports, run, supports_disc, run_layers, supports_cards,
 * render_cards, split_near), and run() itself: upload, ADI (heat or disc kernel), read back,
 * with the device's context current only for the call; run_layers, render_cards and
 * split_near the same bracket around gl_layers.c, gl_cards.c and gl_near_layer.c. */
#include "gl_adi.h"
#include "gl_cards.h"
#include "gl_io.h"
#include "gl_layers.h"
#include "gl_passes.h"
#include "gl_solvers.h"

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

/* llvmpipe (and Mesa's other software renderers) end a shader invocation's loops after
 * 65,535 iterations in all, silently: thomas.comp solves a line in one invocation (2n - 1
 * iterations), lens_thomas.comp a line's chain of `steps` complex steps (steps x (2n + 1)).
 * Measured with tests/gl/test_gl_long_lines.c on llvmpipe: Thomas right at 32,000 px and
 * wrong from 32,768 (6 values: the count is not exact, so the budget keeps a margin); the
 * 2x2 disc right at 16,000 and wrong at 16,384. Such a line is refused, never solved wrong; a
 * hardware driver runs loops to their end. */
#define SOFTWARE_LOOP_LIMIT 65000u

static ddof_status check_line_length(const ddof_device *device, const adi_request *r,
                                     char *message, size_t size)
{
    if (device->info.hardware || r->solver != DDOF_SOLVER_THOMAS)
        return DDOF_OK;
    const uint64_t n = r->width > r->height ? r->width : r->height;
    const uint64_t steps = r->disc ? r->disc->steps : 0;
    const uint64_t iterations = r->disc ? steps * (2 * n + 1) : 2 * n - 1;
    if (iterations <= SOFTWARE_LOOP_LIMIT)
        return DDOF_OK;
    const uint64_t longest = r->disc ? (SOFTWARE_LOOP_LIMIT / steps - 1) / 2
                                     : (SOFTWARE_LOOP_LIMIT + 1) / 2;
    /* n > longest here, and every length up to it is solved right (test_gl_long_lines). */
    snprintf(message, size,
             "lines of %llu pixels are longer than this software renderer can solve with %s "
             "(at most %llu pixels: its shader loops stop after 65,535 iterations); use the CPU "
             "backend, or the cyclic reduction solver with the heat kernel",
             (unsigned long long)n, r->disc ? "the disc kernel" : "the Thomas solver",
             (unsigned long long)longest);
    return DDOF_ERROR_UNSUPPORTED;
}

/* What every request must be for this device, checked before the device is touched. */
static ddof_status check_request(const ddof_device *device, const adi_request *r, char *message,
                                 size_t size)
{
    if (!gl_solver_supported(r->solver, r->precision)) {
        snprintf(message, size, "solver %d is not available on the GPU", (int)r->solver);
        return DDOF_ERROR_UNSUPPORTED;
    }
    if (r->disc && (r->solver != DDOF_SOLVER_THOMAS || r->precision != DDOF_PRECISION_FLOAT)) {
        snprintf(message, size, "the disc kernel runs with the Thomas solver only");
        return DDOF_ERROR_UNSUPPORTED;
    }
    return check_line_length(device, r, message, size);
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
    ddof_status status = check_request(device, r, message, size);
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
    ddof_status status = check_request(device, &q->base, message, size);
    if (status != DDOF_OK)
        return status;
    if (!begin_call(device, message, size))
        return DDOF_ERROR_BACKEND_FAILED;
    status = gl_layers_run(device, q, report, message, size);
    return end_call(device, &q->base, status, &report->adi, message, size);
}

/* Not on the host's own context: drawing sets a framebuffer, blending, the viewport and
 * texture units that the host's renderer owns (the CPU's table draws there). */
static int table_supports_cards(const ddof_device *device)
{
    return device->kind != DDOF_BACKEND_HOST_GL;
}

/* The cards (gl_cards.c), bracketed as run() is. */
static ddof_status table_render_cards(ddof_device *device, const adi_cards_request *q,
                                      char *message, size_t size)
{
    if (!begin_call(device, message, size))
        return DDOF_ERROR_BACKEND_FAILED;
    const adi_request none = {0}; /* no progress to report */
    adi_report report;
    ddof_status status = gl_cards_render(device, q, message, size);
    return end_call(device, &none, status, &report, message, size);
}

/* The near layer's split (gl_near_layer.c), bracketed as run() is; the images stay on the
 * device for the layers' run that follows. */
static ddof_status table_split_near(ddof_device *device, const adi_near_request *q,
                                    adi_near_split *split, adi_report *report, char *message,
                                    size_t size)
{
    if (!begin_call(device, message, size))
        return DDOF_ERROR_BACKEND_FAILED;
    int declined = 0;
    ddof_status status = gl_split_near(device, q, split, &declined, message, size)
                             ? DDOF_OK
                             : declined ? DDOF_ERROR_UNSUPPORTED : DDOF_ERROR_BACKEND_FAILED;
    const adi_request none = {0}; /* its progress is the layers' run's */
    return end_call(device, &none, status, report, message, size);
}

static const ddof_backend_table table = {
    DDOF_BACKEND_ABI, sizeof(ddof_backend_table), table_open, gl_device_close, table_describe,
    table_supports, table_run, table_supports_disc, table_run_layers, table_supports_cards,
    table_render_cards, table_split_near,
};

DDOF_GL_EXPORT const ddof_backend_table *ddof_gl_backend_table(void);

const ddof_backend_table *ddof_gl_backend_table(void)
{
    return &table;
}
