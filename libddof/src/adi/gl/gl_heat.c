/* SPDX-License-Identifier: MIT */
/* gl_heat.c - the heat kernel's ADI driver on the GPU: rows then columns, `substeps` times,
 * with the CPU path's semantics (libddof/src/adi/heat_adi.c): beta from the smaller |CoC| of a
 * link, scaled by k / substeps (columns also by pixel_aspect^2), insulated borders, singular
 * runs kept, progress between passes. A call with nothing conductive solves nothing. */
#include "gl_adi.h"
#include "gl_solvers.h"

ddof_status gl_diffuse(ddof_device *device, const gl_diffusion *d, adi_report *report,
                       char *message, size_t message_size)
{
    const gl_functions *gl = &device->gl;
    const uint32_t w = d->width, h = d->height;
    const uint64_t pixels = (uint64_t)w * h;
    if (!gl_need(device, GL_BUF_IMAGE_B, pixels * 16, message, message_size))
        return DDOF_ERROR_BACKEND_FAILED;

    const float row_scale = d->beta_scale / (float)d->substeps;
    gl_directions found;
    if (!gl_analyse(device, GL_PROG_ANALYSE, d, row_scale, &found, report, message,
                    message_size))
        return DDOF_ERROR_BACKEND_FAILED;
    if (found.active == 0) { /* nothing conducts: the (masked) input is the answer */
        report->lines_skipped = (uint64_t)w + h;
        return DDOF_OK;
    }

    const uint32_t passes = 2 * d->substeps;
    for (uint32_t step = 0; step < d->substeps; step++) {
        for (int axis = 0; axis < 2; axis++) {
            if (gl_pass_cancelled(d, 2 * step + (uint32_t)axis, passes, message, message_size))
                return DDOF_ERROR_CANCELLED;
            const double t0 = gl_seconds();
            if (!gl_solve_pass(device, d, &found.along[axis], message, message_size))
                return DDOF_ERROR_BACKEND_FAILED;
            gl_pass_timed(gl, report, axis, t0);
        }
        report->lines_solved += found.active;
        report->lines_skipped += (uint64_t)w + h - found.active;
        report->substeps_run++;
    }
    return DDOF_OK;
}
