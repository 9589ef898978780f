/* SPDX-License-Identifier: MIT */
/* gl_device.c - opening a backend's context, checking it is GL 4.5 core with compute, and
 * the begin/end bracket every call runs in (its context current only for the call). */
#include "gl_device.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const gl_context_ops *context_ops(ddof_backend_kind kind)
{
    switch (kind) {
    case DDOF_BACKEND_EGL: return &gl_context_egl;
    case DDOF_BACKEND_OSMESA: return &gl_context_osmesa;
    case DDOF_BACKEND_HOST_GL: return &gl_context_host;
    default: return NULL;
    }
}

/* Reads what the device is and its limits; 0 when the context is below GL 4.5. */
static int inspect(ddof_device *d, char *message, size_t size)
{
    const gl_functions *gl = &d->gl;
    GLint major = 0, minor = 0;
    gl->GetIntegerv(GL_MAJOR_VERSION, &major);
    gl->GetIntegerv(GL_MINOR_VERSION, &minor);
    const char *renderer = (const char *)gl->GetString(GL_RENDERER);
    const char *version = (const char *)gl->GetString(GL_VERSION);
    if (!renderer || !version || major * 10 + minor < 45) {
        snprintf(message, size, "the %s context is GL %d.%d (%s); 4.5 is needed",
                 d->context->ops->name, (int)major, (int)minor, renderer ? renderer : "?");
        return 0;
    }
    snprintf(d->info.renderer, sizeof d->info.renderer, "%s, %s", renderer, version);
    d->info.hardware = !gl_renderer_is_software(renderer);
    GLint64 block = 0;
    gl->GetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &block);
    d->max_buffer_bytes = block > 0 ? (uint64_t)block : 0;
    GLint align = 0;
    gl->GetIntegerv(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, &align);
    d->buffer_alignment = align > 0 ? (uint64_t)align : 256;
    return 1;
}

/* Destroys the device's context and frees the device: close's last step, and a failed open's
 * once the context exists. NULL, for open to return. */
static ddof_device *device_destroy(ddof_device *d)
{
    d->context->ops->destroy(d->context);
    free(d);
    return NULL;
}

ddof_device *gl_device_open(ddof_backend_kind kind, int require_hardware, char *message,
                            size_t size)
{
    const gl_context_ops *ops = context_ops(kind);
    if (!ops) {
        snprintf(message, size, "the GL plugin does not open backend %d", (int)kind);
        return NULL;
    }
    ddof_device *d = calloc(1, sizeof *d);
    if (!d) {
        snprintf(message, size, "out of memory");
        return NULL;
    }
    d->kind = kind;
    d->context = ops->create(require_hardware, message, size);
    if (!d->context) {
        free(d);
        return NULL;
    }
    if (!ops->make_current(d->context)) {
        snprintf(message, size, "the %s context could not be made current", ops->name);
        return device_destroy(d);
    }
    int ok = gl_functions_load(&d->gl, d->context, message, size) && inspect(d, message, size);
    ops->release(d->context);
    return ok ? d : device_destroy(d);
}

void gl_device_close(ddof_device *d)
{
    if (!d)
        return;
    /* GL objects go with their context, but a host's context lives on: delete ours. */
    if (d->context->ops->make_current(d->context)) {
        gl_programs_free(&d->gl, &d->programs);
        if (d->cards_program)
            d->gl.DeleteProgram(d->cards_program);
        gl_buffers_free(&d->gl, &d->buffers);
        d->context->ops->release(d->context);
    }
    device_destroy(d);
}

int gl_device_begin(ddof_device *d, char *message, size_t size)
{
    if (d->context->ops->make_current(d->context))
        return 1;
    snprintf(message, size, d->kind == DDOF_BACKEND_HOST_GL
                                ? "the host's GL context is no longer current on this thread"
                                : "the GL context could not be made current");
    return 0;
}

void gl_device_end(ddof_device *d)
{
    d->gl.UseProgram(0);
    d->context->ops->release(d->context);
}
