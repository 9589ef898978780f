/* SPDX-License-Identifier: MIT */
/* gl_adi.h - the ADI drivers on the GPU, over the packed images of gl_solve.h: the heat kernel
 * (gl_heat.c) and the disc kernel (gl_lens.c), each with the CPU driver's semantics. */
#ifndef DDOF_GL_ADI_H
#define DDOF_GL_ADI_H

#include "gl_solve.h"

/* The heat kernel on the packed images, the result in IMAGE_A (gl_heat.c). */
ddof_status gl_diffuse(ddof_device *device, const gl_diffusion *d, adi_report *report,
                       char *message, size_t message_size);

/* The range per channel of the request's input as the disc reads it (0 where gamma is 0),
 * which the disc kernel clamps its result to (libddof/src/adi/lens_adi.c); unused channels get
 * the whole float range. */
void gl_lens_input_range(const adi_request *r, float lo[4], float hi[4]);

/* The disc kernel (d->disc, Thomas only) on the same packed images, the result again in
 * IMAGE_A (gl_lens.c). */
ddof_status gl_lens_diffuse(ddof_device *device, const gl_diffusion *d, adi_report *report,
                            char *message, size_t message_size);

#endif
