/* SPDX-License-Identifier: MIT */
/* gl_solve.c - what the GPU's ADI drivers (libddof/src/adi/gl) and the line solvers
 * (libddof/src/solvers/gl) share: binding and dispatch, buffers, a pass's uniforms, the
 * largest |CoC| the packing measures, the analysis of both directions up front (the
 * conductive lines and the singular runs: the CoC and gamma do not change between substeps),
 * cancelling and timing a pass. */
#include "gl_solve.h"

#include <stdio.h>
#include <string.h>
#include <time.h>

double gl_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

void gl_bind(const gl_functions *gl, GLuint index, GLuint buffer)
{
    gl->BindBufferBase(GL_SHADER_STORAGE_BUFFER, index, buffer);
}

void gl_dispatch(const gl_functions *gl, uint64_t invocations, uint32_t local)
{
    const uint64_t groups = (invocations + local - 1) / local;
    if (groups == 0)
        return;
    const uint64_t gx = groups < 65535 ? groups : 65535;
    gl->DispatchCompute((GLuint)gx, (GLuint)((groups + gx - 1) / gx), 1);
    gl->MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

void gl_bind_ref(const gl_functions *gl, GLuint index, const gl_image_ref *ref, GLuint fallback)
{
    if (!ref->buffer)
        gl_bind(gl, index, fallback);
    else if (ref->bytes)
        gl->BindBufferRange(GL_SHADER_STORAGE_BUFFER, index, ref->buffer, (GLintptr)ref->at,
                            (GLsizeiptr)ref->bytes);
    else
        gl_bind(gl, index, ref->buffer);
}

void gl_uniform_ref(const gl_functions *gl, GLuint program, const char *prefix,
                    const gl_image_ref *ref)
{
    static const char *const fields[3] = {"base", "stride", "step"};
    const GLuint values[3] = {ref->offset, ref->stride, ref->step};
    for (int i = 0; i < 3; i++) {
        char name[64];
        snprintf(name, sizeof name, "%s_%s", prefix, fields[i]);
        gl_uniform_u(gl, program, name, values[i]);
    }
}

GLuint gl_need(ddof_device *device, gl_buffer_slot slot, uint64_t bytes, char *message,
               size_t message_size)
{
    if (bytes > device->max_buffer_bytes) {
        snprintf(message, message_size,
                 "the image needs a %llu-byte buffer, more than this renderer's "
                 "GL_MAX_SHADER_STORAGE_BLOCK_SIZE (%llu)",
                 (unsigned long long)bytes, (unsigned long long)device->max_buffer_bytes);
        return 0;
    }
    GLuint name = gl_buffers_get(&device->gl, &device->buffers, slot, bytes);
    if (!name)
        snprintf(message, message_size, "out of GPU memory (%llu-byte buffer)",
                 (unsigned long long)bytes);
    return name;
}

/* d's two directions (gl_directions), their lines not analysed yet. */
static void lay_out(const ddof_device *device, const gl_diffusion *d, float row_scale,
                    gl_directions *directions)
{
    const uint32_t w = d->width, h = d->height;
    const GLuint a = device->buffers.name[GL_BUF_IMAGE_A];
    const GLuint b = device->buffers.name[GL_BUF_IMAGE_B];
    const float column_scale = row_scale * d->pixel_aspect * d->pixel_aspect;
    directions->along[0] = (gl_pass){w, h, 1, w, row_scale, d->has_gamma ? 1u : 0u, a, b};
    directions->along[1] = (gl_pass){h, w, w, 1, column_scale, d->has_gamma ? 2u : 0u, b, a};
    directions->active = 0;
}

void gl_pass_uniforms(const gl_functions *gl, GLuint program, const gl_pass *pass,
                      int has_gamma)
{
    gl_uniform_u(gl, program, "u_n", pass->n);
    gl_uniform_u(gl, program, "u_lines", pass->lines);
    gl_uniform_u(gl, program, "u_along", pass->along);
    gl_uniform_u(gl, program, "u_across", pass->across);
    gl_uniform_f(gl, program, "u_scale", pass->scale);
    gl_uniform_u(gl, program, "u_has_gamma", (GLuint)has_gamma);
    gl_uniform_u(gl, program, "u_flag_bit", pass->flag_bit);
}

int gl_largest_reset(ddof_device *device, char *message, size_t message_size)
{
    const gl_functions *gl = &device->gl;
    GLuint counters = gl_need(device, GL_BUF_COUNTERS, 16, message, message_size);
    if (!counters)
        return 0;
    const GLuint zero = 0;
    gl->BindBuffer(GL_SHADER_STORAGE_BUFFER, counters);
    gl->BufferSubData(GL_SHADER_STORAGE_BUFFER, 2 * sizeof zero, sizeof zero, &zero);
    gl_bind(gl, 3, counters);
    return 1;
}

/* Runs analyse.comp over one direction. */
static void analyse(ddof_device *device, GLuint program, const gl_diffusion *d,
                    const gl_pass *pass, GLuint counter)
{
    const gl_functions *gl = &device->gl;
    gl_pass_uniforms(gl, program, pass, d->has_gamma);
    gl_uniform_u(gl, program, "u_counter", counter);
    gl->UseProgram(program);
    gl_dispatch(gl, pass->lines, 64);
}

int gl_analyse(ddof_device *device, gl_program_id id, const gl_diffusion *d, float row_scale,
               gl_directions *directions, adi_report *report, char *message,
               size_t message_size)
{
    const gl_functions *gl = &device->gl;
    const uint64_t pixels = (uint64_t)d->width * d->height;
    GLuint dummy = gl_need(device, GL_BUF_DUMMY, 16, message, message_size);
    GLuint counters = gl_need(device, GL_BUF_COUNTERS, 16, message, message_size);
    GLuint flags = d->has_gamma ? gl_need(device, GL_BUF_FLAGS, pixels * 4, message,
                                          message_size)
                                : dummy;
    GLuint program = gl_programs_get(gl, &device->programs, id, message, message_size);
    if (!dummy || !counters || !flags || !program)
        return 0;
    lay_out(device, d, row_scale, directions);
    const GLuint zero[2] = {0, 0}; /* [2] is the packing's (gl_largest_reset) */
    gl->BindBuffer(GL_SHADER_STORAGE_BUFFER, counters);
    gl->BufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof zero, zero);
    gl_bind(gl, 0, device->buffers.name[GL_BUF_COC]);
    gl_bind(gl, 1, d->has_gamma ? device->buffers.name[GL_BUF_GAMMA] : dummy);
    gl_bind(gl, 2, flags);
    gl_bind(gl, 6, counters);
    analyse(device, program, d, &directions->along[0], 0);
    analyse(device, program, d, &directions->along[1], 1);
    gl->MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    /* conductive rows, conductive columns, the largest |CoC|'s bits before the in-focus cut
     * (the packing's: the report's, as the CPU's solvers measure it) */
    GLuint counted[3];
    gl->BindBuffer(GL_SHADER_STORAGE_BUFFER, counters);
    gl->GetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof counted, counted);
    float max_coc;
    memcpy(&max_coc, &counted[2], sizeof max_coc);
    *report = (adi_report){.threads = 1, .max_coc = max_coc};
    directions->active = (uint64_t)counted[0] + counted[1];
    return 1;
}

int gl_pass_cancelled(const gl_diffusion *d, uint32_t done, uint32_t passes, char *message,
                      size_t message_size)
{
    if (d->progress && d->progress(d->progress_user, (float)done / (float)passes)) {
        snprintf(message, message_size, "cancelled by the progress callback");
        return 1;
    }
    return 0;
}

void gl_pass_timed(const gl_functions *gl, adi_report *report, int axis, double t0)
{
    gl->Finish(); /* so that the pass's time is its own */
    const double t = gl_seconds() - t0;
    if (axis == 0)
        report->seconds_rows += t;
    else
        report->seconds_columns += t;
}
