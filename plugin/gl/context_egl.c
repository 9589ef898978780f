/* SPDX-License-Identifier: MIT */
/* context_egl.c - EGL without a window: a GPU when there is one, Mesa's surfaceless platform
 * (llvmpipe) otherwise.
 *
 * With EGL_EXT_device_enumeration every GPU is its own device; Mesa's software device carries
 * EGL_MESA_device_software, and a device whose renderer still turns out to be llvmpipe,
 * softpipe or swrast counts as software too. The first hardware device wins; without one,
 * require_hardware fails (so AUTO picks the CPU rather than software GL) and otherwise
 * EGL_PLATFORM_SURFACELESS_MESA is used. Contexts are GL 4.5 core, config-less
 * (EGL_KHR_no_config_context) and surfaceless (EGL_KHR_surfaceless_context): the solver only
 * touches its own buffers. libEGL is dlopen()ed (DDOF_GL_EGL_LIBRARY names another file).
 *
 * Displays are never terminated: EGL displays are per process and not reference-counted, so
 * eglTerminate would pull the display from under any other ddof context (or the host) using it.
 */
#define EGL_EGL_PROTOTYPES 0
#include "gl_context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct egl_api {
    PFNEGLGETPROCADDRESSPROC GetProcAddress;
    PFNEGLQUERYSTRINGPROC QueryString;
    PFNEGLGETERRORPROC GetError;
    PFNEGLINITIALIZEPROC Initialize;
    PFNEGLBINDAPIPROC BindAPI;
    PFNEGLCREATECONTEXTPROC CreateContext;
    PFNEGLDESTROYCONTEXTPROC DestroyContext;
    PFNEGLMAKECURRENTPROC MakeCurrent;
    PFNEGLGETCURRENTCONTEXTPROC GetCurrentContext;
    PFNEGLGETCURRENTDISPLAYPROC GetCurrentDisplay;
    PFNEGLGETCURRENTSURFACEPROC GetCurrentSurface;
    PFNEGLQUERYAPIPROC QueryAPI;
    PFNEGLGETPLATFORMDISPLAYEXTPROC GetPlatformDisplayEXT;
    PFNEGLQUERYDEVICESEXTPROC QueryDevicesEXT;
    PFNEGLQUERYDEVICESTRINGEXTPROC QueryDeviceStringEXT;
} egl_api;

typedef struct egl_context {
    gl_context base;
    egl_api egl;
    EGLDisplay display;
    EGLContext context;
    /* What was current on the calling thread before a call (a host's EGL context, say), put
     * back by release so that running ddof does not pull the host's context from under it. */
    EGLenum saved_api;
    EGLDisplay saved_display;
    EGLSurface saved_draw, saved_read;
    EGLContext saved_context;
} egl_context;

static const char *const egl_names[] = {"libEGL.so.1", "libEGL.so", NULL};

static int has_extension(const char *list, const char *name)
{
    const size_t n = strlen(name);
    for (const char *p = list; p && (p = strstr(p, name)); p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0'))
            return 1;
    return 0;
}

static gl_proc egl_proc(void *library, const egl_api *egl, const char *name)
{
    gl_proc p = gl_library_symbol(library, name);
    return p ? p : (egl->GetProcAddress ? (gl_proc)egl->GetProcAddress(name) : NULL);
}

static int load_api(void *library, egl_api *egl)
{
    egl->GetProcAddress = (PFNEGLGETPROCADDRESSPROC)gl_library_symbol(library,
                                                                      "eglGetProcAddress");
    egl->QueryString = (PFNEGLQUERYSTRINGPROC)egl_proc(library, egl, "eglQueryString");
    egl->GetError = (PFNEGLGETERRORPROC)egl_proc(library, egl, "eglGetError");
    egl->Initialize = (PFNEGLINITIALIZEPROC)egl_proc(library, egl, "eglInitialize");
    egl->BindAPI = (PFNEGLBINDAPIPROC)egl_proc(library, egl, "eglBindAPI");
    egl->CreateContext = (PFNEGLCREATECONTEXTPROC)egl_proc(library, egl, "eglCreateContext");
    egl->DestroyContext = (PFNEGLDESTROYCONTEXTPROC)egl_proc(library, egl, "eglDestroyContext");
    egl->MakeCurrent = (PFNEGLMAKECURRENTPROC)egl_proc(library, egl, "eglMakeCurrent");
    egl->GetCurrentContext = (PFNEGLGETCURRENTCONTEXTPROC)egl_proc(library, egl,
                                                                   "eglGetCurrentContext");
    egl->GetCurrentDisplay = (PFNEGLGETCURRENTDISPLAYPROC)egl_proc(library, egl,
                                                                   "eglGetCurrentDisplay");
    egl->GetCurrentSurface = (PFNEGLGETCURRENTSURFACEPROC)egl_proc(library, egl,
                                                                   "eglGetCurrentSurface");
    egl->QueryAPI = (PFNEGLQUERYAPIPROC)egl_proc(library, egl, "eglQueryAPI");
    /* Extensions: only through eglGetProcAddress. */
    egl->GetPlatformDisplayEXT = (PFNEGLGETPLATFORMDISPLAYEXTPROC)egl_proc(
        library, egl, "eglGetPlatformDisplayEXT");
    egl->QueryDevicesEXT = (PFNEGLQUERYDEVICESEXTPROC)egl_proc(library, egl,
                                                               "eglQueryDevicesEXT");
    egl->QueryDeviceStringEXT = (PFNEGLQUERYDEVICESTRINGEXTPROC)egl_proc(
        library, egl, "eglQueryDeviceStringEXT");
    return egl->GetProcAddress && egl->QueryString && egl->GetError && egl->Initialize &&
           egl->BindAPI && egl->CreateContext && egl->DestroyContext && egl->MakeCurrent &&
           egl->GetCurrentContext && egl->GetCurrentDisplay && egl->GetCurrentSurface &&
           egl->QueryAPI;
}

/* A GL 4.5 core context on an initialised display, or EGL_NO_CONTEXT. */
static EGLContext core_context(const egl_api *egl, EGLDisplay display)
{
    EGLint major, minor;
    if (!egl->Initialize(display, &major, &minor))
        return EGL_NO_CONTEXT;
    const char *ext = egl->QueryString(display, EGL_EXTENSIONS);
    if (!has_extension(ext, "EGL_KHR_no_config_context") ||
        !has_extension(ext, "EGL_KHR_surfaceless_context") || !egl->BindAPI(EGL_OPENGL_API))
        return EGL_NO_CONTEXT;
    const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4,
                              EGL_CONTEXT_MINOR_VERSION, 5,
                              EGL_CONTEXT_OPENGL_PROFILE_MASK,
                              EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                              EGL_NONE};
    return egl->CreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
}

/* Whether the context (made current here, released again) renders in software. */
static int context_is_software(const egl_api *egl, EGLDisplay display, EGLContext context)
{
    if (!egl->MakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context))
        return 1;
    PFNGLGETSTRINGPROC get_string = (PFNGLGETSTRINGPROC)egl->GetProcAddress("glGetString");
    const char *renderer = get_string ? (const char *)get_string(GL_RENDERER) : NULL;
    int software = !renderer || gl_renderer_is_software(renderer);
    egl->MakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    return software;
}

/* The first hardware device's display and context; counts the devices seen. */
static int pick_hardware(const egl_api *egl, EGLDisplay *display, EGLContext *context,
                         int *devices_seen)
{
    EGLDeviceEXT devices[16];
    EGLint count = 0;
    *devices_seen = 0;
    if (!egl->QueryDevicesEXT || !egl->GetPlatformDisplayEXT ||
        !egl->QueryDevicesEXT(16, devices, &count))
        return 0;
    *devices_seen = count;
    for (EGLint i = 0; i < count; i++) {
        const char *ext = egl->QueryDeviceStringEXT
                              ? egl->QueryDeviceStringEXT(devices[i], EGL_EXTENSIONS)
                              : NULL;
        if (has_extension(ext, "EGL_MESA_device_software"))
            continue;
        EGLDisplay d = egl->GetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[i], NULL);
        EGLContext c = d != EGL_NO_DISPLAY ? core_context(egl, d) : EGL_NO_CONTEXT;
        if (c == EGL_NO_CONTEXT)
            continue;
        if (!context_is_software(egl, d, c)) {
            *display = d;
            *context = c;
            return 1;
        }
        egl->DestroyContext(d, c);
    }
    return 0;
}

static gl_context *egl_create(int require_hardware, char *message, size_t size)
{
    void *library = gl_library_open("DDOF_GL_EGL_LIBRARY", egl_names, message, size);
    if (!library)
        return NULL;
    egl_context *c = calloc(1, sizeof *c);
    if (!c) {
        snprintf(message, size, "out of memory");
        return NULL;
    }
    if (!load_api(library, &c->egl))
        return gl_context_fail(c, message, size, "libEGL lacks EGL 1.4 entry points");
    const egl_api *egl = &c->egl;
    const char *client = egl->QueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    int devices = 0;
    int found = has_extension(client, "EGL_EXT_device_enumeration") &&
                pick_hardware(egl, &c->display, &c->context, &devices);
    if (!found && require_hardware)
        return gl_context_fail(c, message, size, "EGL found no GPU (%d device%s, all software)",
                               devices, devices == 1 ? "" : "s");
    if (!found) {
        if (!has_extension(client, "EGL_MESA_platform_surfaceless") ||
            !egl->GetPlatformDisplayEXT)
            return gl_context_fail(c, message, size,
                                   "EGL has neither a GPU device nor Mesa's surfaceless "
                                   "platform");
        c->display = egl->GetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA,
                                                EGL_DEFAULT_DISPLAY, NULL);
        c->context = c->display != EGL_NO_DISPLAY ? core_context(egl, c->display)
                                                  : EGL_NO_CONTEXT;
        if (c->context == EGL_NO_CONTEXT)
            return gl_context_fail(c, message, size,
                                   "EGL (surfaceless) could not create a GL 4.5 core context "
                                   "(EGL error 0x%x)", (unsigned)egl->GetError());
    }
    c->base.ops = &gl_context_egl;
    return &c->base;
}

static int egl_make_current(gl_context *context)
{
    egl_context *c = (egl_context *)context;
    const egl_api *egl = &c->egl;
    c->saved_api = egl->QueryAPI();
    c->saved_context = egl->GetCurrentContext();
    c->saved_display = egl->GetCurrentDisplay();
    c->saved_draw = egl->GetCurrentSurface(EGL_DRAW);
    c->saved_read = egl->GetCurrentSurface(EGL_READ);
    if (egl->BindAPI(EGL_OPENGL_API) &&
        egl->MakeCurrent(c->display, EGL_NO_SURFACE, EGL_NO_SURFACE, c->context))
        return 1;
    egl->BindAPI(c->saved_api);
    return 0;
}

static void egl_release(gl_context *context)
{
    egl_context *c = (egl_context *)context;
    const egl_api *egl = &c->egl;
    if (c->saved_context != EGL_NO_CONTEXT && c->saved_display != EGL_NO_DISPLAY) {
        egl->BindAPI(c->saved_api);
        egl->MakeCurrent(c->saved_display, c->saved_draw, c->saved_read, c->saved_context);
    } else {
        egl->MakeCurrent(c->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        egl->BindAPI(c->saved_api);
    }
}

static gl_proc egl_get_proc(gl_context *context, const char *name)
{
    egl_context *c = (egl_context *)context;
    return (gl_proc)c->egl.GetProcAddress(name);
}

static void egl_destroy(gl_context *context)
{
    egl_context *c = (egl_context *)context;
    if (!c)
        return;
    c->egl.DestroyContext(c->display, c->context);
    free(c);
}

const gl_context_ops gl_context_egl = {"egl", egl_create, egl_make_current, egl_release,
                                       egl_get_proc, egl_destroy};

gl_context *gl_context_fail(void *partial, char *message, size_t message_size,
                            const char *format, ...)
{
    va_list args;
    va_start(args, format);
    vsnprintf(message, message_size, format, args);
    va_end(args);
    free(partial);
    return NULL;
}

int gl_renderer_is_software(const char *renderer)
{
    return strstr(renderer, "llvmpipe") || strstr(renderer, "softpipe") ||
           strstr(renderer, "swrast") || strstr(renderer, "Software Rasterizer");
}
