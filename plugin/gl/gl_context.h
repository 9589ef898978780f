/* SPDX-License-Identifier: MIT */
/* gl_context.h - the context backends (EGL, OSMesa, the host's current context) behind one
 * table of function pointers, as GLFW does for its platforms: the solver code never knows
 * which one it runs on. One file per backend: context_egl.c, context_osmesa.c, context_host.c.
 */
#ifndef DDOF_GL_CONTEXT_H
#define DDOF_GL_CONTEXT_H

#include "gl_library.h"

#include <stddef.h>

typedef struct gl_context gl_context;

typedef struct gl_context_ops {
    const char *name;
    /* A GL 4.5 core context, not current on return. require_hardware (EGL): fail unless a
     * GPU device is found. NULL with a sentence in message on failure. */
    gl_context *(*create)(int require_hardware, char *message, size_t message_size);
    /* 1 on success. Host contexts: checks that the host's context is (still) current. */
    int (*make_current)(gl_context *context);
    /* Undoes make_current, so that another backend's context can be made current on this
     * thread afterwards: EGL puts back the EGL context that was current before (usually none);
     * OSMesa makes nothing current; host contexts leave the host's context alone. */
    void (*release)(gl_context *context);
    gl_proc (*get_proc)(gl_context *context, const char *name);
    void (*destroy)(gl_context *context);
} gl_context_ops;

/* Every backend's context starts with this. */
struct gl_context {
    const gl_context_ops *ops;
};

extern const gl_context_ops gl_context_egl;
extern const gl_context_ops gl_context_osmesa;
extern const gl_context_ops gl_context_host;

#if defined(__GNUC__)
#  define GL_CONTEXT_PRINTF __attribute__((format(printf, 4, 5)))
#else
#  define GL_CONTEXT_PRINTF
#endif

/* A create that failed half way: frees `partial` (the backend's context, calloc()ed, nothing
 * in it to release yet), writes the sentence to message and returns NULL for create to return.
 */
gl_context *gl_context_fail(void *partial, char *message, size_t message_size,
                            const char *format, ...) GL_CONTEXT_PRINTF;

/* Whether a GL_RENDERER string names a software rasteriser (llvmpipe, softpipe, swrast). */
int gl_renderer_is_software(const char *renderer);

#endif
