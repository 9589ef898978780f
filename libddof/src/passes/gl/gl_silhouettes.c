/* SPDX-License-Identifier: MIT */
/* gl_silhouettes.c - ../silhouettes.c on the device (gl_passes.h): silhouettes.comp's steps on
 * device-resident images; the host reads only the count of the pixels split. */
#include "gl_passes.h"

#include <stdio.h>

/* A silhouettes.comp step with its bindings and uniforms; 0 on failure. */
static GLuint step(ddof_device *device, gl_program_id id, const gl_silhouettes_request *q,
                   GLuint out, GLuint cleaned, char *message, size_t size)
{
    const gl_functions *gl = &device->gl;
    GLuint prog = gl_programs_get(gl, &device->programs, id, message, size);
    GLuint delta = gl_need(device, GL_BUF_SIL_DELTA,
                           (uint64_t)q->width * q->height * 3 * sizeof(float), message, size);
    GLuint counts = gl_need(device, GL_BUF_SIL_COUNTS, 2 * sizeof(GLuint), message, size);
    GLuint dummy = gl_need(device, GL_BUF_DUMMY, 16, message, size);
    if (!prog || !delta || !counts || !dummy)
        return 0;
    gl_bind_ref(gl, 0, &q->coc, dummy);
    gl_bind_ref(gl, 1, &q->color, dummy);
    gl_bind(gl, 2, out ? out : dummy);
    gl_bind_ref(gl, 3, &q->matte, dummy);
    gl_bind(gl, 4, cleaned ? cleaned : dummy);
    gl_bind(gl, 5, delta);
    gl_bind(gl, 6, counts);
    gl_uniform_u(gl, prog, "u_width", q->width);
    gl_uniform_u(gl, prog, "u_height", q->height);
    gl_uniform_u(gl, prog, "u_channels", q->channels);
    gl_uniform_ref(gl, prog, "u_coc", &q->coc);
    gl_uniform_ref(gl, prog, "u_color", &q->color);
    gl_uniform_ref(gl, prog, "u_matte", &q->matte);
    gl_uniform_f(gl, prog, "u_in_focus", q->in_focus_px);
    gl_uniform_u(gl, prog, "u_ranks", q->matte.buffer ? q->ranks : 0u);
    gl->UseProgram(prog);
    return prog;
}

static void reset_counts(ddof_device *device)
{
    const gl_functions *gl = &device->gl;
    const GLuint zero[2] = {0, 0};
    gl->BindBuffer(GL_SHADER_STORAGE_BUFFER, device->buffers.name[GL_BUF_SIL_COUNTS]);
    gl->BufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof zero, zero);
}

int gl_clean_silhouettes(ddof_device *device, const gl_silhouettes_request *q, GLuint cleaned,
                         char *message, size_t size)
{
    if (!step(device, GL_PROG_SIL_CLEAN, q, 0, cleaned, message, size))
        return 0;
    reset_counts(device);
    gl_dispatch(&device->gl, (uint64_t)q->width * q->height, 256);
    return 1;
}

int gl_split_silhouettes(ddof_device *device, const gl_silhouettes_request *q, GLuint out,
                         uint64_t *pixels, char *message, size_t size)
{
    const gl_functions *gl = &device->gl;
    const uint64_t invocations = (uint64_t)q->width * q->height;
    if (!step(device, GL_PROG_SIL_DELTA, q, out, 0, message, size))
        return 0;
    reset_counts(device);
    gl_dispatch(gl, invocations, 256);
    if (!step(device, GL_PROG_SIL_APPLY, q, out, 0, message, size))
        return 0;
    gl_dispatch(gl, invocations, 256);
    GLuint counts[2];
    gl->MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    gl->BindBuffer(GL_SHADER_STORAGE_BUFFER, device->buffers.name[GL_BUF_SIL_COUNTS]);
    gl->GetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof counts, counts);
    *pixels = counts[1];
    return 1;
}
