/* SPDX-License-Identifier: MIT */
/* gl_io.c - an adi_request's images in host memory to the GPU and the result back.
 *
 * The caller's images are uploaded as they lie (strided rows, 1..4 channels, CoC and gamma as
 * the first of several channels: one copy each, no reformatting on the CPU), one after the
 * other in one mapped write, and pack.comp turns them into the working layout; unpack.comp writes the result in the caller's layout into the
 * raw buffer, which is mapped and copied row by row (the padding between rows is the caller's
 * and is never written). */
#include "gl_io.h"

#include <stdio.h>
#include <string.h>

uint64_t gl_span_floats(uint32_t width, uint32_t height, size_t stride, uint32_t step,
                        uint32_t used)
{
    return (uint64_t)(height - 1) * stride + (uint64_t)(width - 1) * step + used;
}

int gl_io_upload_sections(ddof_device *device, gl_buffer_slot slot, int count,
                          const void *const *source, const uint64_t *floats, uint64_t *at,
                          uint64_t *bytes, char *message, size_t size)
{
    const uint64_t align = device->buffer_alignment;
    uint64_t total = 0;
    for (int i = 0; i < count; i++) {
        at[i] = (total + align - 1) / align * align;
        bytes[i] = floats[i] * sizeof(float);
        total = at[i] + bytes[i];
        if (bytes[i] > device->max_buffer_bytes || floats[i] > UINT32_MAX) {
            snprintf(message, size,
                     "an image needs a %llu-byte buffer, more than this renderer's "
                     "GL_MAX_SHADER_STORAGE_BLOCK_SIZE (%llu)",
                     (unsigned long long)bytes[i], (unsigned long long)device->max_buffer_bytes);
            return 0;
        }
    }
    if (total == 0)
        return 1;
    const gl_functions *gl = &device->gl;
    GLuint buffer = gl_buffers_get(gl, &device->buffers, slot, total);
    if (!buffer) {
        snprintf(message, size, "out of GPU memory (%llu-byte buffer)", (unsigned long long)total);
        return 0;
    }
    gl->BindBuffer(GL_SHADER_STORAGE_BUFFER, buffer);
    unsigned char *mapped = gl->MapBufferRange(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)total,
                                               GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_BUFFER_BIT);
    if (!mapped) {
        snprintf(message, size, "the frame's buffer could not be mapped for writing");
        return 0;
    }
    device->uploads++;
    for (int i = 0; i < count; i++)
        if (bytes[i] && source[i])
            memcpy(mapped + at[i], source[i], bytes[i]);
    if (!gl->UnmapBuffer(GL_SHADER_STORAGE_BUFFER)) {
        snprintf(message, size, "the frame's upload was lost (buffer unmapped)");
        return 0;
    }
    return 1;
}

int gl_io_upload(ddof_device *device, const adi_request *r, char *message, size_t size)
{
    const gl_functions *gl = &device->gl;
    const uint32_t w = r->width, h = r->height, C = r->channels;
    const uint64_t pixels = (uint64_t)w * h;
    const uint64_t color_span = gl_span_floats(w, h, r->color_stride, C, C);
    const uint64_t out_span = gl_span_floats(w, h, r->out_stride, C, C);
    const uint64_t coc_span = r->coc ? gl_span_floats(w, h, r->coc_stride, r->coc_channels, 1) : 0;
    const uint64_t gamma_span =
        r->gamma ? gl_span_floats(w, h, r->gamma_stride, r->gamma_channels, 1) : 0;
    /* One buffer, one mapped write: colour, CoC and gamma one after the other; the result
     * comes back through the same buffer. */
    const uint64_t in_floats = color_span + coc_span + gamma_span;
    const uint64_t raw_floats = in_floats > out_span ? in_floats : out_span;
    if (raw_floats > UINT32_MAX) {
        snprintf(message, size, "the request's images exceed 2^32 floats");
        return 0;
    }
    const GLuint coc_at = (GLuint)color_span, gamma_at = (GLuint)(color_span + coc_span);

    GLuint raw = gl_need(device, GL_BUF_RAW_COLOR, raw_floats * 4, message, size);
    GLuint dummy = gl_need(device, GL_BUF_DUMMY, 16, message, size);
    GLuint image = gl_need(device, GL_BUF_IMAGE_A, pixels * 16, message, size);
    GLuint coc = gl_need(device, GL_BUF_COC, pixels * 4, message, size);
    GLuint gamma = r->gamma ? gl_need(device, GL_BUF_GAMMA, pixels * 4, message, size) : dummy;
    GLuint pack = gl_programs_get(gl, &device->programs, GL_PROG_PACK, message, size);
    if (!raw || !dummy || !image || !coc || !gamma || !pack)
        return 0;

    gl->BindBuffer(GL_SHADER_STORAGE_BUFFER, raw);
    float *mapped = gl->MapBufferRange(GL_SHADER_STORAGE_BUFFER, 0,
                                       (GLsizeiptr)(in_floats * sizeof(float)),
                                       GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_RANGE_BIT);
    if (!mapped) {
        snprintf(message, size, "the upload buffer could not be mapped for writing");
        return 0;
    }
    device->uploads++;
    memcpy(mapped, r->color, color_span * sizeof(float));
    if (r->coc)
        memcpy(mapped + coc_at, r->coc, coc_span * sizeof(float));
    if (r->gamma)
        memcpy(mapped + gamma_at, r->gamma, gamma_span * sizeof(float));
    if (!gl->UnmapBuffer(GL_SHADER_STORAGE_BUFFER)) {
        snprintf(message, size, "the upload was lost (buffer unmapped)");
        return 0;
    }

    gl_bind(gl, 0, coc);
    gl_bind(gl, 1, gamma);
    gl_bind(gl, 4, image);
    gl_bind(gl, 5, raw);
    gl_bind(gl, 6, r->coc ? raw : dummy);
    gl_bind(gl, 7, r->gamma ? raw : dummy);
    gl_uniform_u(gl, pack, "u_width", w);
    gl_uniform_u(gl, pack, "u_height", h);
    gl_uniform_u(gl, pack, "u_channels", C);
    gl_uniform_u(gl, pack, "u_color_offset", 0);
    gl_uniform_u(gl, pack, "u_coc_offset", coc_at);
    gl_uniform_u(gl, pack, "u_gamma_offset", gamma_at);
    gl_uniform_u(gl, pack, "u_color_stride", (GLuint)r->color_stride);
    gl_uniform_u(gl, pack, "u_has_coc", r->coc != NULL);
    gl_uniform_f(gl, pack, "u_uniform_coc", r->uniform_coc);
    gl_uniform_u(gl, pack, "u_coc_stride", (GLuint)r->coc_stride);
    gl_uniform_u(gl, pack, "u_coc_channels", r->coc_channels);
    gl_uniform_f(gl, pack, "u_in_focus", r->in_focus_px);
    gl_uniform_u(gl, pack, "u_has_gamma", r->gamma != NULL);
    gl_uniform_u(gl, pack, "u_gamma_stride", (GLuint)r->gamma_stride);
    gl_uniform_u(gl, pack, "u_gamma_channels", r->gamma_channels);
    if (!gl_largest_reset(device, message, size))
        return 0;
    gl->UseProgram(pack);
    gl_dispatch(gl, pixels, 256);
    return 1;
}

int gl_io_download(ddof_device *device, const adi_request *r, char *message, size_t size)
{
    const gl_functions *gl = &device->gl;
    const uint32_t w = r->width, h = r->height, C = r->channels;
    const uint64_t out_span = gl_span_floats(w, h, r->out_stride, C, C);
    GLuint unpack = gl_programs_get(gl, &device->programs, GL_PROG_UNPACK, message, size);
    if (!unpack)
        return 0;
    GLuint raw = device->buffers.name[GL_BUF_RAW_COLOR];
    gl_bind(gl, 3, device->buffers.name[GL_BUF_IMAGE_A]);
    gl_bind(gl, 7, raw);
    gl_uniform_u(gl, unpack, "u_width", w);
    gl_uniform_u(gl, unpack, "u_height", h);
    gl_uniform_u(gl, unpack, "u_channels", C);
    gl_uniform_u(gl, unpack, "u_out_offset", 0);
    gl_uniform_u(gl, unpack, "u_out_stride", (GLuint)r->out_stride);
    gl->UseProgram(unpack);
    gl_dispatch(gl, (uint64_t)w * h, 256);
    gl->MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_CLIENT_MAPPED_BUFFER_BARRIER_BIT);

    gl->BindBuffer(GL_SHADER_STORAGE_BUFFER, raw);
    const float *mapped = gl->MapBufferRange(GL_SHADER_STORAGE_BUFFER, 0,
                                             (GLsizeiptr)(out_span * sizeof(float)),
                                             GL_MAP_READ_BIT);
    if (!mapped) {
        snprintf(message, size, "the result buffer could not be mapped for reading");
        return 0;
    }
    device->readbacks++;
    for (uint32_t y = 0; y < h; y++)
        memcpy(r->out + (size_t)y * r->out_stride, mapped + (size_t)y * r->out_stride,
               (size_t)w * C * sizeof(float));
    gl->UnmapBuffer(GL_SHADER_STORAGE_BUFFER);
    return 1;
}
