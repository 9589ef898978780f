/* SPDX-License-Identifier: MIT */
/* gl_resident.c - one diffusion whose images already lie in device buffers (gl_layers.c's
 * maps and layers): pack.comp reads them at an offset with their strides, as it reads an
 * upload, the ADI driver (gl_heat.c or gl_lens.c, libddof/src/adi/gl) runs on the packed
 * images, and unpack.comp writes the result at an offset of another (or the same) buffer. Nothing crosses to the host
 * but the analysis' counters and, for the disc kernel, its clamp range (range.comp), a few
 * bytes each. */
#include "gl_layers.h"

#include "gl_adi.h"

#include <float.h>
#include <stdio.h>
#include <string.h>

static int pack(ddof_device *device, const gl_resident *q, float in_focus, char *message,
                size_t size)
{
    const gl_functions *gl = &device->gl;
    const uint64_t pixels = (uint64_t)q->width * q->height;
    GLuint dummy = gl_need(device, GL_BUF_DUMMY, 16, message, size);
    GLuint image = gl_need(device, GL_BUF_IMAGE_A, pixels * 16, message, size);
    GLuint coc = gl_need(device, GL_BUF_COC, pixels * 4, message, size);
    GLuint gamma = q->gamma.buffer ? gl_need(device, GL_BUF_GAMMA, pixels * 4, message, size)
                                   : dummy;
    GLuint prog = gl_programs_get(gl, &device->programs, GL_PROG_PACK, message, size);
    if (!dummy || !image || !coc || !gamma || !prog)
        return 0;
    gl_bind(gl, 0, coc);
    gl_bind(gl, 1, gamma);
    gl_bind(gl, 4, image);
    gl_bind_ref(gl, 5, &q->color, dummy);
    gl_bind_ref(gl, 6, &q->coc, dummy);
    gl_bind_ref(gl, 7, &q->gamma, dummy);
    gl_uniform_u(gl, prog, "u_width", q->width);
    gl_uniform_u(gl, prog, "u_height", q->height);
    gl_uniform_u(gl, prog, "u_channels", q->channels);
    gl_uniform_u(gl, prog, "u_color_offset", q->color.offset);
    gl_uniform_u(gl, prog, "u_color_stride", q->color.stride);
    gl_uniform_u(gl, prog, "u_has_coc", q->coc.buffer != 0);
    gl_uniform_f(gl, prog, "u_uniform_coc", q->uniform_coc);
    gl_uniform_u(gl, prog, "u_coc_offset", q->coc.offset);
    gl_uniform_u(gl, prog, "u_coc_stride", q->coc.stride);
    gl_uniform_u(gl, prog, "u_coc_channels", q->coc.step);
    gl_uniform_f(gl, prog, "u_in_focus", in_focus);
    gl_uniform_u(gl, prog, "u_has_gamma", q->gamma.buffer != 0);
    gl_uniform_u(gl, prog, "u_gamma_offset", q->gamma.offset);
    gl_uniform_u(gl, prog, "u_gamma_stride", q->gamma.stride);
    gl_uniform_u(gl, prog, "u_gamma_channels", q->gamma.step);
    if (!gl_largest_reset(device, message, size))
        return 0;
    gl->UseProgram(prog);
    gl_dispatch(gl, pixels, 256);
    return 1;
}

/* The key range.comp orders floats by, and back. */
static float from_ordered(GLuint key)
{
    const GLuint bits = key & 0x80000000u ? key & 0x7fffffffu : ~key;
    float f;
    memcpy(&f, &bits, sizeof f);
    return f;
}

/* gl_lens_input_range of the packed (masked) colour in IMAGE_A. */
static int input_range(ddof_device *device, const gl_resident *q, float lo[4], float hi[4],
                       char *message, size_t size)
{
    const gl_functions *gl = &device->gl;
    GLuint range = gl_need(device, GL_BUF_RANGE, 32, message, size);
    GLuint prog = gl_programs_get(gl, &device->programs, GL_PROG_RANGE, message, size);
    if (!range || !prog)
        return 0;
    GLuint keys[8] = {UINT32_MAX, UINT32_MAX, UINT32_MAX, UINT32_MAX, 0, 0, 0, 0};
    gl->BindBuffer(GL_SHADER_STORAGE_BUFFER, range);
    gl->BufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof keys, keys);
    gl_bind(gl, 3, device->buffers.name[GL_BUF_IMAGE_A]);
    gl_bind(gl, 6, range);
    gl_uniform_u(gl, prog, "u_pixels", q->width * q->height);
    gl_uniform_u(gl, prog, "u_channels", q->channels);
    gl->UseProgram(prog);
    gl_dispatch(gl, (uint64_t)q->width * q->height, 256);
    gl->MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    gl->BindBuffer(GL_SHADER_STORAGE_BUFFER, range);
    gl->GetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof keys, keys);
    for (uint32_t c = 0; c < 4; c++) {
        lo[c] = c < q->channels ? from_ordered(keys[c]) : -FLT_MAX;
        hi[c] = c < q->channels ? from_ordered(keys[4 + c]) : FLT_MAX;
    }
    return 1;
}

static int unpack(ddof_device *device, const gl_resident *q, char *message, size_t size)
{
    const gl_functions *gl = &device->gl;
    GLuint prog = gl_programs_get(gl, &device->programs, GL_PROG_UNPACK, message, size);
    if (!prog)
        return 0;
    gl_bind(gl, 3, device->buffers.name[GL_BUF_IMAGE_A]);
    gl_bind_ref(gl, 7, &q->out, q->out.buffer);
    gl_uniform_u(gl, prog, "u_width", q->width);
    gl_uniform_u(gl, prog, "u_height", q->height);
    gl_uniform_u(gl, prog, "u_channels", q->channels);
    gl_uniform_u(gl, prog, "u_out_offset", q->out.offset);
    gl_uniform_u(gl, prog, "u_out_stride", q->out.stride);
    gl->UseProgram(prog);
    gl_dispatch(gl, (uint64_t)q->width * q->height, 256);
    return 1;
}

ddof_status gl_resident_diffuse(ddof_device *device, const adi_request *settings,
                                const gl_resident *q, adi_report *report, char *message,
                                size_t size)
{
    gl_diffusion d = {q->width, q->height, q->channels, settings->solver, settings->precision,
                      q->substeps, settings->jacobi_iterations, settings->beta_scale,
                      settings->pixel_aspect, q->gamma.buffer != 0, q->progress,
                      q->progress_user, q->disc, {0}, {0}};
    /* The in-focus threshold as the CPU's solvers apply it (libddof cuts the CoC itself only
     * for a request that comes up from the host). */
    if (!pack(device, q, settings->in_focus_px, message, size))
        return DDOF_ERROR_BACKEND_FAILED;
    if (d.disc && !input_range(device, q, d.lo, d.hi, message, size))
        return DDOF_ERROR_BACKEND_FAILED;
    const ddof_status status = d.disc ? gl_lens_diffuse(device, &d, report, message, size)
                                      : gl_diffuse(device, &d, report, message, size);
    /* Cancelled: IMAGE_A holds the masked input or the last finished substep, both finite. */
    if ((status == DDOF_OK || status == DDOF_ERROR_CANCELLED) && !unpack(device, q, message, size))
        return DDOF_ERROR_BACKEND_FAILED;
    return status;
}
