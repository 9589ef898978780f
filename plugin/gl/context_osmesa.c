/* SPDX-License-Identifier: MIT */
/* context_osmesa.c - Mesa's off-screen software renderer (llvmpipe) as a context backend.
 *
 * libOSMesa is dlopen()ed (DDOF_GL_OSMESA_LIBRARY names another file; a path that does not
 * load simulates a machine without it). The context renders nothing to its 1x1 colour buffer:
 * the solver works in its own buffers; OSMesaMakeCurrent only wants somewhere to point. */
#include "gl_context.h"

#include <GL/osmesa.h>
#include <stdlib.h>
#include <stdio.h>

typedef OSMesaContext (*osmesa_create_fn)(const int *attribs, OSMesaContext share);
typedef GLboolean (*osmesa_make_current_fn)(OSMesaContext, void *, GLenum, GLsizei, GLsizei);
typedef void (*osmesa_destroy_fn)(OSMesaContext);
typedef OSMESAproc (*osmesa_get_proc_fn)(const char *);

typedef struct osmesa_context {
    gl_context base;
    OSMesaContext context;
    osmesa_make_current_fn make_current;
    osmesa_destroy_fn destroy;
    osmesa_get_proc_fn get_proc;
    unsigned char pixel[4]; /* the 1x1 RGBA colour buffer */
} osmesa_context;

static const char *const osmesa_names[] = {"libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so",
                                           NULL};

static gl_context *osmesa_create(int require_hardware, char *message, size_t size)
{
    (void)require_hardware;
    void *library = gl_library_open("DDOF_GL_OSMESA_LIBRARY", osmesa_names, message, size);
    if (!library)
        return NULL;
    osmesa_create_fn create = (osmesa_create_fn)gl_library_symbol(library,
                                                                  "OSMesaCreateContextAttribs");
    osmesa_context *c = calloc(1, sizeof *c);
    if (!c) {
        snprintf(message, size, "out of memory");
        return NULL;
    }
    c->make_current = (osmesa_make_current_fn)gl_library_symbol(library, "OSMesaMakeCurrent");
    c->destroy = (osmesa_destroy_fn)gl_library_symbol(library, "OSMesaDestroyContext");
    c->get_proc = (osmesa_get_proc_fn)gl_library_symbol(library, "OSMesaGetProcAddress");
    if (!create || !c->make_current || !c->destroy || !c->get_proc)
        return gl_context_fail(c, message, size,
                               "libOSMesa lacks OSMesaCreateContextAttribs (Mesa 11.2 or later "
                               "is needed for a core profile)");
    const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA,
                           OSMESA_DEPTH_BITS, 0,
                           OSMESA_STENCIL_BITS, 0,
                           OSMESA_ACCUM_BITS, 0,
                           OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION, 4,
                           OSMESA_CONTEXT_MINOR_VERSION, 5,
                           0};
    c->context = create(attribs, NULL);
    if (!c->context)
        return gl_context_fail(c, message, size, "OSMesa could not create a GL 4.5 core context");
    c->base.ops = &gl_context_osmesa;
    return &c->base;
}

static int osmesa_make_current(gl_context *context)
{
    osmesa_context *c = (osmesa_context *)context;
    return c->make_current(c->context, c->pixel, GL_UNSIGNED_BYTE, 1, 1) == GL_TRUE;
}

static void osmesa_release(gl_context *context)
{
    osmesa_context *c = (osmesa_context *)context;
    c->make_current(NULL, NULL, 0, 0, 0); /* Mesa: no context and no buffer unbinds */
}

static gl_proc osmesa_get_proc(gl_context *context, const char *name)
{
    osmesa_context *c = (osmesa_context *)context;
    return (gl_proc)c->get_proc(name);
}

static void osmesa_destroy(gl_context *context)
{
    osmesa_context *c = (osmesa_context *)context;
    if (!c)
        return;
    c->destroy(c->context);
    free(c);
}

const gl_context_ops gl_context_osmesa = {"osmesa", osmesa_create, osmesa_make_current,
                                          osmesa_release, osmesa_get_proc, osmesa_destroy};
