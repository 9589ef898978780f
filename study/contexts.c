/* SPDX-License-Identifier: MIT */
/* contexts.c - the context a configuration runs in: a fresh CPU context each time, or the GL
 * backend's, probed once and kept for the whole run. */
#include "study.h"

#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

const ddof_backend_kind study_gl_backend_kinds[STUDY_GL_BACKEND_COUNT] = {DDOF_BACKEND_OSMESA,
                                                                          DDOF_BACKEND_EGL};

/* Probed on first use and kept until study_gl_free: one context per GL backend for the run. */
static study_gl_backend gl_backends[STUDY_GL_BACKEND_COUNT] = {{.kind = DDOF_BACKEND_OSMESA},
                                                               {.kind = DDOF_BACKEND_EGL}};

ddof_status study_cpu_context(const study_options *o, ddof_context **ctx)
{
    ddof_context_options co;
    ddof_context_options_init(&co);
    co.thread_count = o->threads;
    return ddof_context_create(&co, ctx);
}

static const char *plugin_path(const study_options *o)
{
    if (o->gl_plugin)
        return o->gl_plugin;
    if (getenv("DDOF_GL_PLUGIN"))
        return NULL; /* the library reads it */
#ifdef DDOF_STUDY_GL_PLUGIN
    if (access(DDOF_STUDY_GL_PLUGIN, R_OK) == 0)
        return DDOF_STUDY_GL_PLUGIN;
#endif

    return NULL;
}

study_gl_backend *study_gl_get(const study_options *o, ddof_backend_kind kind)
{
    study_gl_backend *b = NULL;
    for (int i = 0; i < STUDY_GL_BACKEND_COUNT; i++)
        if (gl_backends[i].kind == kind)
            b = &gl_backends[i];
    if (!b || b->probed)
        return b;
    b->probed = 1;
    if (o->no_gl) {
        snprintf(b->why, sizeof b->why, "GL not probed (--no-gl)");
        return b;
    }
    ddof_context *ctx;
    if (study_cpu_context(o, &ctx) != DDOF_OK) {
        snprintf(b->why, sizeof b->why, "no context");
        return b;
    }
    ddof_status st = ddof_context_set_backend(ctx, kind, plugin_path(o));
    if (st != DDOF_OK) {
        snprintf(b->why, sizeof b->why, "%s", ddof_context_last_error(ctx));
        ddof_context_free(ctx);
        return b;
    }
    ddof_backend_info info = {.struct_size = sizeof info};
    ddof_context_backend_info(ctx, &info);
    snprintf(b->renderer, sizeof b->renderer, "%s", info.renderer);
    b->hardware = (int)info.hardware;
    if (kind == DDOF_BACKEND_EGL && !b->hardware && !o->egl_software) {
        /* Without a GPU, EGL runs Mesa's software renderer, which OSMesa measures already. */
        snprintf(b->why, sizeof b->why,
                 "EGL found no GPU, only the software renderer %s, which the osmesa "
                 "configurations measure (--egl-software measures it anyway)", b->renderer);
        ddof_context_free(ctx);
        return b;
    }
    b->ctx = ctx;
    return b;
}

/* A context for one configuration: a fresh CPU context (so host_bytes is this configuration's
 * own), or the GL backend's. NULL with *why when the backend is unavailable. */
ddof_context *study_context_for(const study_options *o, const study_config *cfg, int *owned,
                                const char **why, const char **renderer)
{
    *owned = 0;
    *why = NULL;
    *renderer = "";
    if (cfg->kind == STUDY_DIFFUSION && cfg->backend != DDOF_BACKEND_CPU) {
        study_gl_backend *b = study_gl_get(o, cfg->backend);
        if (!b || !b->ctx) {
            *why = b ? b->why : "unknown backend";
            return NULL;
        }
        *renderer = b->renderer;
        return b->ctx;
    }
    ddof_context *ctx;
    if (study_cpu_context(o, &ctx) != DDOF_OK) {
        *why = "ddof_context_create failed";
        return NULL;
    }
    *owned = 1;
    return ctx;
}

void study_gl_free(void)
{
    for (int i = 0; i < STUDY_GL_BACKEND_COUNT; i++)
        ddof_context_free(gl_backends[i].ctx);
}
