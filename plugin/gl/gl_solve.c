/* SPDX-License-Identifier: MIT */
/* gl_solve.c - the ADI driver on the GPU: rows then columns, `substeps` times, with the CPU
 * path's semantics (libddof/src/adi.c): beta from the smaller |CoC| of a link, scaled by
 * k / substeps (columns also by pixel_aspect^2), insulated borders, singular runs kept,
 * progress between passes. The CoC and gamma do not change between substeps, so one analysis
 * per direction up front finds the conductive lines (the report), the largest CoC and the
 * singular runs, and a call with nothing conductive solves nothing. */
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

/* Runs analyse.comp over one direction. */
static void analyse(ddof_device *device, GLuint program, const gl_diffusion *d,
                    const gl_pass *pass, GLuint counter)
{
    const gl_functions *gl = &device->gl;
    gl_uniform_u(gl, program, "u_n", pass->n);
    gl_uniform_u(gl, program, "u_lines", pass->lines);
    gl_uniform_u(gl, program, "u_along", pass->along);
    gl_uniform_u(gl, program, "u_across", pass->across);
    gl_uniform_f(gl, program, "u_scale", pass->scale);
    gl_uniform_u(gl, program, "u_has_gamma", (GLuint)d->has_gamma);
    gl_uniform_u(gl, program, "u_flag_bit", pass->flag_bit);
    gl_uniform_u(gl, program, "u_counter", counter);
    gl->UseProgram(program);
    gl_dispatch(gl, pass->lines, 64);
}

int gl_analyse(ddof_device *device, gl_program_id id, const gl_diffusion *d,
               const gl_pass *rows, const gl_pass *columns, gl_analysis *result, char *message,
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
    const GLuint zero[4] = {0, 0, 0, 0};
    gl->BindBuffer(GL_SHADER_STORAGE_BUFFER, counters);
    gl->BufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof zero, zero);
    gl_bind(gl, 0, device->buffers.name[GL_BUF_COC]);
    gl_bind(gl, 1, d->has_gamma ? device->buffers.name[GL_BUF_GAMMA] : dummy);
    gl_bind(gl, 2, flags);
    gl_bind(gl, 6, counters);
    analyse(device, program, d, rows, 0);
    analyse(device, program, d, columns, 1);
    gl->MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    GLuint counted[4];
    gl->BindBuffer(GL_SHADER_STORAGE_BUFFER, counters);
    gl->GetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof counted, counted);
    result->rows = counted[0];
    result->columns = counted[1];
    memcpy(&result->max_coc, &counted[2], sizeof result->max_coc);
    return 1;
}

ddof_status gl_diffuse(ddof_device *device, const gl_diffusion *d, adi_report *report,
                       char *message, size_t message_size)
{
    const gl_functions *gl = &device->gl;
    const uint32_t w = d->width, h = d->height;
    const uint64_t pixels = (uint64_t)w * h;
    GLuint image_a = device->buffers.name[GL_BUF_IMAGE_A];
    GLuint image_b = gl_need(device, GL_BUF_IMAGE_B, pixels * 16, message, message_size);
    if (!image_b)
        return DDOF_ERROR_BACKEND_FAILED;

    const float row_scale = d->beta_scale / (float)d->substeps;
    const float column_scale = row_scale * d->pixel_aspect * d->pixel_aspect;
    const uint32_t flag_rows = d->has_gamma ? 1u : 0u, flag_columns = d->has_gamma ? 2u : 0u;
    const gl_pass rows = {w, h, 1, w, row_scale, flag_rows, image_a, image_b};
    const gl_pass columns = {h, w, w, 1, column_scale, flag_columns, image_b, image_a};

    gl_analysis found;
    if (!gl_analyse(device, GL_PROG_ANALYSE, d, &rows, &columns, &found, message,
                    message_size))
        return DDOF_ERROR_BACKEND_FAILED;
    const uint64_t active = (uint64_t)found.rows + found.columns;
    *report = (adi_report){.threads = 1, .max_coc = found.max_coc};
    if (active == 0) { /* nothing conducts: the (masked) input is the answer */
        report->lines_skipped = (uint64_t)w + h;
        return DDOF_OK;
    }

    const uint32_t passes = 2 * d->substeps;
    for (uint32_t step = 0; step < d->substeps; step++) {
        for (int axis = 0; axis < 2; axis++) {
            const float fraction = (float)(2 * step + (uint32_t)axis) / (float)passes;
            if (d->progress && d->progress(d->progress_user, fraction)) {
                snprintf(message, message_size, "cancelled by the progress callback");
                return DDOF_ERROR_CANCELLED;
            }
            const double t0 = gl_seconds();
            if (!gl_solve_pass(device, d, axis == 0 ? &rows : &columns, message,
                               message_size))
                return DDOF_ERROR_BACKEND_FAILED;
            gl->Finish(); /* so that the pass's time is its own */
            const double t = gl_seconds() - t0;
            if (axis == 0)
                report->seconds_rows += t;
            else
                report->seconds_columns += t;
        }
        report->lines_solved += active;
        report->lines_skipped += (uint64_t)w + h - active;
        report->substeps_run++;
    }
    return DDOF_OK;
}
