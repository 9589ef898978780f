/* SPDX-License-Identifier: MIT */
/* context_host.c - the GL context a host application (a DCC viewport) has made current on the
 * calling thread. ddof never makes anything current or releases it here; it only needs a way
 * to look GL functions up, found in whichever GL library the process already has loaded
 * (RTLD_NOLOAD: loading one ourselves could not have the host's context current anyway). */
#include "gl_context.h"

#include <stdio.h>
#include <stdlib.h>

typedef void *(*current_context_fn)(void);
typedef gl_proc (*get_proc_fn)(const char *name);

typedef struct host_context {
    gl_context base;
    current_context_fn current;
    get_proc_fn get_proc;
    void *context; /* the host's context when it was adopted */
} host_context;

/* Each window-system library: its names, its "current context" and "get proc" functions. */
typedef struct host_library {
    const char *const *names;
    const char *current;
    const char *get_proc;
} host_library;

static const char *const osmesa_names[] = {"libOSMesa.so.8", "libOSMesa.so.6", NULL};
static const char *const egl_names[] = {"libEGL.so.1", NULL};
static const char *const glx_names[] = {"libGLX.so.0", "libGL.so.1", NULL};

static const host_library host_libraries[] = {
    {osmesa_names, "OSMesaGetCurrentContext", "OSMesaGetProcAddress"},
    {egl_names, "eglGetCurrentContext", "eglGetProcAddress"},
    {glx_names, "glXGetCurrentContext", "glXGetProcAddressARB"},
};

static gl_context *host_create(int require_hardware, char *message, size_t size)
{
    (void)require_hardware;
    for (size_t i = 0; i < sizeof host_libraries / sizeof *host_libraries; i++) {
        void *library = gl_library_find_loaded(host_libraries[i].names);
        if (!library)
            continue;
        current_context_fn current =
            (current_context_fn)gl_library_symbol(library, host_libraries[i].current);
        get_proc_fn get_proc =
            (get_proc_fn)gl_library_symbol(library, host_libraries[i].get_proc);
        void *context = current && get_proc ? current() : NULL;
        if (!context)
            continue;
        host_context *c = calloc(1, sizeof *c);
        if (!c) {
            snprintf(message, size, "out of memory");
            return NULL;
        }
        *c = (host_context){{&gl_context_host}, current, get_proc, context};
        return &c->base;
    }
    snprintf(message, size, "no GL context is current on this thread (looked through OSMesa, "
                            "EGL and GLX)");
    return NULL;
}

static int host_make_current(gl_context *context)
{
    host_context *c = (host_context *)context;
    return c->current() == c->context;
}

static void host_release(gl_context *context)
{
    (void)context; /* the host's context stays current */
}

static gl_proc host_get_proc(gl_context *context, const char *name)
{
    host_context *c = (host_context *)context;
    return c->get_proc(name);
}

static void host_destroy(gl_context *context)
{
    free(context);
}

const gl_context_ops gl_context_host = {"host", host_create, host_make_current, host_release,
                                        host_get_proc, host_destroy};
