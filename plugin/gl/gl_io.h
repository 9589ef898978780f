/* SPDX-License-Identifier: MIT */
/* gl_io.h - host-memory images in and out of the GPU (gl_io.c). */
#ifndef DDOF_GL_IO_H
#define DDOF_GL_IO_H

#include "gl_solve.h"

/* Uploads the request's colour, CoC and gamma (one mapped write) and packs them (IMAGE_A,
 * COC, GAMMA). */
int gl_io_upload(ddof_device *device, const adi_request *request, char *message, size_t size);
/* IMAGE_A into request->out in its layout. */
int gl_io_download(ddof_device *device, const adi_request *request, char *message, size_t size);

#endif
