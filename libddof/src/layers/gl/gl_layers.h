/* SPDX-License-Identifier: MIT */
/* gl_layers.h - the layered frame on the device (gl_layers.c) and the diffusion of images that
 * already lie in device buffers, which it is built from (gl_resident.c). */
#ifndef DDOF_GL_LAYERS_H
#define DDOF_GL_LAYERS_H

#include "gl_solve.h"

/* One diffusion of device-resident images, with adi_request's meaning for each field. */
typedef struct gl_resident {
    uint32_t width, height, channels;
    gl_image_ref color;
    gl_image_ref coc;   /* none: every pixel has uniform_coc */
    gl_image_ref gamma; /* none: 1 everywhere                */
    gl_image_ref out;   /* may be color (in place)           */
    float uniform_coc;
    uint32_t substeps;
    const struct disc_kernel *disc;
    ddof_progress_fn progress;
    void *progress_user;
} gl_resident;

/* Runs q with settings' solver, precision, Jacobi iterations, beta scale and pixel aspect. */
ddof_status gl_resident_diffuse(ddof_device *device, const adi_request *settings,
                                const gl_resident *q, adi_report *report, char *message,
                                size_t message_size);

/* The seam's run_layers, with the device's context current. */
ddof_status gl_layers_run(ddof_device *device, const adi_layers_request *q,
                          adi_layers_report *report, char *message, size_t message_size);

#endif
