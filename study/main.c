/* SPDX-License-Identifier: MIT */
/* main.c - ddof-study: runs the configurations of the accuracy-vs-cost study on scene folders.
 *
 *   ddof-study run --out DIR [options] SCENE_DIR...     measure; writes DIR/results.jsonl
 *   ddof-study images --out DIR --configs LIST SCENE_DIR...
 *                                                        the images of some configurations
 *   ddof-study list [--configs LIST]                     print the configuration ids
 *
 * study/README.md says what is measured and how; report.py reads the results. */
#include "study.h"

#ifdef DDOF_STUDY_HAVE_GATHER
#include "gather_blur.h"
#endif

#include <cJSON.h>

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/utsname.h>
#include <time.h>
#include <unistd.h>

#ifndef DDOF_STUDY_BUILD_TYPE
#define DDOF_STUDY_BUILD_TYPE "unknown"
#endif

typedef struct options {
    const char *out;
    const char *configs;
    const char *gl_plugin;
    int reps_small, reps_large;
    double budget_small, budget_large; /* seconds of timed calls per configuration and size */
    int large;                         /* time at 1920x1080 when the scene has it           */
    double large_limit;                /* skip a 1080p timing predicted to take longer (s)  */
    int egl_software;                  /* measure EGL on a software renderer too            */
    int no_gl;                         /* never load the GL plugin                          */
    uint32_t threads;
    int append;
    int quiet;
    const char **scenes;
    int scene_count;
} options;

static void usage(FILE *f)
{
    fprintf(f,
            "usage: ddof-study run --out DIR [options] SCENE_DIR...\n"
            "       ddof-study images --out DIR --configs LIST SCENE_DIR...\n"
            "       ddof-study list [--configs LIST]\n"
            "\n"
            "A scene folder holds pinhole.exr, truth.exr, camera.json and optionally fg.exr,\n"
            "pinhole_1080.exr, defocus[-4.2|-5.3].exr + .json (study/scenes/README.md).\n"
            "\n"
            "  --configs LIST     comma-separated ids and lists: full (default), smoke,\n"
            "                     baselines, cpu/thomas/f32/n4/k0.03125/auto, cod4, gather,\n"
            "                     pinhole, defocus, defocus-4.2, defocus-5.3\n"
            "  --out DIR          run: DIR/results.jsonl; images: DIR/<scene>/<id>.npy\n"
            "  --append           add to an existing results.jsonl instead of replacing it\n"
            "  --reps N           timed calls after the warm-up at the scene's size (5)\n"
            "  --large-reps N     the same at 1920x1080 (3)\n"
            "  --no-large         do not time at 1920x1080 (pinhole_1080.exr)\n"
            "  --large-limit S    skip a 1080p timing that the scene-size time predicts to\n"
            "                     take over S seconds per call (5); an estimate is recorded\n"
            "  --egl-software     measure EGL also when it finds no GPU (by default its\n"
            "                     software renderer is the one OSMesa measures already)\n"
            "  --threads N        threads of the CPU contexts (0 = all cores, the default)\n"
            "  --gl-plugin PATH   the libddof_gl to load (default: DDOF_GL_PLUGIN, beside\n"
            "                     libddof, the build tree's)\n"
            "  --no-gl            never load the GL plugin (GL configurations: not available)\n"
            "  -q                 no progress lines\n");
}

/* ---- the machine ------------------------------------------------------------------------- */

static void first_line_value(const char *path, const char *key, char *out, size_t size)
{
    out[0] = '\0';
    FILE *f = fopen(path, "r");
    if (!f)
        return;
    char line[1024];
    const size_t n = strlen(key);
    while (fgets(line, sizeof line, f)) {
        if (strncmp(line, key, n))
            continue;
        const char *v = line + n;
        while (*v == ' ' || *v == '\t' || *v == ':' || *v == '=' || *v == '"')
            v++;
        snprintf(out, size, "%s", v);
        size_t len = strlen(out);
        while (len && (out[len - 1] == '\n' || out[len - 1] == '"' || out[len - 1] == ' '))
            out[--len] = '\0';
        break;
    }
    fclose(f);
}

typedef struct gl_backend {
    ddof_backend_kind kind;
    ddof_context *ctx;   /* NULL when unavailable */
    char renderer[160];
    int hardware;
    char why[512];       /* why unavailable */
    int probed;
} gl_backend;

static gl_backend gl_backends[2] = {{.kind = DDOF_BACKEND_OSMESA}, {.kind = DDOF_BACKEND_EGL}};

static const char *plugin_path(const options *o)
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

static gl_backend *gl_get(const options *o, ddof_backend_kind kind)
{
    gl_backend *b = NULL;
    for (int i = 0; i < 2; i++)
        if (gl_backends[i].kind == kind)
            b = &gl_backends[i];
    if (!b || b->probed)
        return b;
    b->probed = 1;
    if (o->no_gl) {
        snprintf(b->why, sizeof b->why, "GL not probed (--no-gl)");
        return b;
    }
    ddof_context_options co;
    ddof_context_options_init(&co);
    co.thread_count = o->threads;
    ddof_context *ctx;
    if (ddof_context_create(&co, &ctx) != DDOF_OK) {
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

static cJSON *machine_json(const options *o)
{
    cJSON *m = cJSON_CreateObject();
    char buf[512];
    cJSON_AddStringToObject(m, "type", "machine");
    time_t now = time(NULL);
    struct tm tm;
    gmtime_r(&now, &tm);
    strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
    cJSON_AddStringToObject(m, "date_utc", buf);
    first_line_value("/proc/cpuinfo", "model name", buf, sizeof buf);
    cJSON_AddStringToObject(m, "cpu", buf);
    first_line_value("/proc/cpuinfo", "flags", buf, sizeof buf);
    cJSON_AddBoolToObject(m, "avx512", strstr(buf, "avx512f") != NULL);
    cJSON_AddNumberToObject(m, "cores", (double)sysconf(_SC_NPROCESSORS_ONLN));
    first_line_value("/proc/meminfo", "MemTotal", buf, sizeof buf);
    cJSON_AddNumberToObject(m, "memory_bytes", atof(buf) * 1024.0);
    first_line_value("/etc/os-release", "PRETTY_NAME", buf, sizeof buf);
    cJSON_AddStringToObject(m, "os", buf);
    struct utsname u;
    if (uname(&u) == 0) {
        snprintf(buf, sizeof buf, "%s %s %s", u.sysname, u.release, u.machine);
        cJSON_AddStringToObject(m, "kernel", buf);
    }
#ifdef __VERSION__
    cJSON_AddStringToObject(m, "compiler", "cc " __VERSION__);
#endif
    cJSON_AddStringToObject(m, "build_type", DDOF_STUDY_BUILD_TYPE);
    cJSON_AddStringToObject(m, "ddof_version", ddof_version_string());
    ddof_context *ctx;
    ddof_context_options co;
    ddof_context_options_init(&co);
    co.thread_count = o->threads;
    if (ddof_context_create(&co, &ctx) == DDOF_OK) {
        cJSON_AddNumberToObject(m, "threads", ddof_context_thread_count(ctx));
        ddof_context_free(ctx);
    }
    cJSON *opts = cJSON_AddObjectToObject(m, "options");
    cJSON_AddNumberToObject(opts, "reps", o->reps_small);
    cJSON_AddNumberToObject(opts, "large_reps", o->reps_large);
    cJSON_AddNumberToObject(opts, "large_limit_s", o->large_limit);
    cJSON_AddBoolToObject(opts, "large", o->large);
    cJSON *gl = cJSON_AddObjectToObject(m, "gl");
    for (int i = 0; i < 2; i++) {
        gl_backend *b = gl_get(o, gl_backends[i].kind);
        cJSON *e = cJSON_AddObjectToObject(gl, ddof_backend_name(b->kind));
        cJSON_AddBoolToObject(e, "available", b->ctx != NULL);
        if (b->renderer[0])
            cJSON_AddStringToObject(e, "renderer", b->renderer);
        if (!b->ctx)
            cJSON_AddStringToObject(e, "why", b->why);
        if (b->renderer[0])
            cJSON_AddBoolToObject(e, "hardware", b->hardware);
    }
    return m;
}

/* ---- running one configuration ----------------------------------------------------------- */

typedef struct call {
    const study_config *cfg;
    const study_scene *scene;
    const study_frame *frame;
    ddof_context *ctx;
    const float *abs_coc; /* |CoC|, for the gather baseline */
    float *out;
    ddof_stats stats;
    char error[1024];
} call;

static ddof_status run_call(call *c)
{
    const study_frame *f = c->frame;
    const size_t pixels = (size_t)f->width * f->height;
    c->stats = (ddof_stats){.struct_size = sizeof c->stats};
    switch (c->cfg->kind) {
    case STUDY_PINHOLE:
        memcpy(c->out, f->rgba, pixels * 4 * sizeof(float));
        return DDOF_OK;
    case STUDY_DEFOCUS:
        return DDOF_ERROR_UNSUPPORTED;
    case STUDY_GATHER:
#ifdef DDOF_STUDY_HAVE_GATHER
        if (ddof_gather_blur(f->rgba, c->abs_coc, f->width, f->height, 4, c->out,
                             ddof_context_thread_count(c->ctx)) != 0) {
            snprintf(c->error, sizeof c->error, "ddof_gather_blur failed");
            return DDOF_ERROR_BAD_PARAMETER;
        }
        return DDOF_OK;
#else
        snprintf(c->error, sizeof c->error, "study/baselines/gather_blur.c is not built");
        return DDOF_ERROR_UNSUPPORTED;
#endif
    case STUDY_COD4:
    case STUDY_DIFFUSION:
        break;
    }
    const int fg = study_config_uses_fg(c->cfg, f->fg_rgba != NULL);
    /* The paper's layers: the element over the rest of the scene rendered without it. */
    const int rest = fg && c->cfg->layers == LAYERS_FG && f->rest_rgba != NULL;
    ddof_params p;
    study_config_params(c->cfg, fg, &p);
    p.pixel_aspect = (float)c->scene->camera.pixel_aspect;
    ddof_image_in color = {rest ? f->rest_rgba : f->rgba, f->width, f->height, 4, 0};
    ddof_image_in coc = {rest ? f->rest_coc : f->coc, f->width, f->height, 1, 0};
    ddof_image out = {c->out, f->width, f->height, 4, 0};
    ddof_foreground element;
    ddof_foreground_init(&element);
    if (fg) {
        element.color = (ddof_image_in){f->fg_rgba, f->width, f->height, 4, 0};
        element.coc = (ddof_image_in){f->fg_coc, f->width, f->height, 1, 0};
        element.premultiplied = 1;
    }
    ddof_status st = ddof_diffuse_layers(c->ctx, &p, &color, &coc, fg ? &element : NULL, &out,
                                         &c->stats);
    if (st != DDOF_OK)
        snprintf(c->error, sizeof c->error, "%s: %s", ddof_status_string(st),
                 ddof_context_last_error(c->ctx));
    return st;
}

/* A warm-up call, then up to `reps` timed calls while the budget lasts (at least one). A
 * warm-up longer than a second is itself the measurement (its allocations are noise then). */
static ddof_status time_calls(call *c, int reps, double budget, double *runs, int *count)
{
    *count = 0;
    double t0 = study_now();
    ddof_status st = run_call(c);
    double first = study_now() - t0;
    if (st != DDOF_OK)
        return st;
    if (first > 1.0) {
        runs[(*count)++] = first;
        return DDOF_OK;
    }
    double spent = 0.0;
    for (int i = 0; i < reps && (i == 0 || spent < budget); i++) {
        t0 = study_now();
        st = run_call(c);
        const double t = study_now() - t0;
        if (st != DDOF_OK)
            return st;
        runs[(*count)++] = t;
        spent += t;
    }
    return DDOF_OK;
}

/* The double-precision reference of a diffusion configuration, cached by its settings. */
typedef struct ref_entry {
    char key[96];
    char scene[128];
    float *image;
    uint64_t used;
} ref_entry;

#define REF_CACHE 24
static ref_entry ref_cache[REF_CACHE];
static uint64_t ref_clock;
static double ref_seconds; /* spent computing references (the sweep's overhead) */

static void ref_cache_clear(void)
{
    for (int i = 0; i < REF_CACHE; i++) {
        free(ref_cache[i].image);
        memset(&ref_cache[i], 0, sizeof ref_cache[i]);
    }
}

static const float *reference_image(ddof_context *ctx, const study_scene *scene,
                                    const study_config *cfg, char *error, size_t size)
{
    study_config r = *cfg;
    r.backend = DDOF_BACKEND_CPU;
    r.solver = DDOF_SOLVER_REFERENCE_F64;
    r.precision = DDOF_PRECISION_FLOAT;
    r.jacobi_iterations = 50;
    study_config_make_id(&r);
    ref_entry *slot = &ref_cache[0];
    for (int i = 0; i < REF_CACHE; i++) {
        ref_entry *e = &ref_cache[i];
        if (e->image && !strcmp(e->key, r.id) && !strcmp(e->scene, scene->name)) {
            e->used = ++ref_clock;
            return e->image;
        }
        if (!e->image || e->used < slot->used)
            slot = e;
        if (!e->image)
            break;
    }
    const size_t pixels = (size_t)scene->small.width * scene->small.height;
    if (!slot->image)
        slot->image = malloc(pixels * 4 * sizeof(float));
    if (!slot->image) {
        snprintf(error, size, "out of memory");
        return NULL;
    }
    call c = {.cfg = &r, .scene = scene, .frame = &scene->small, .ctx = ctx,
              .out = slot->image};
    const double t0 = study_now();
    ddof_status st = run_call(&c);
    ref_seconds += study_now() - t0;
    if (st != DDOF_OK) {
        snprintf(error, size, "reference: %s", c.error);
        free(slot->image);
        memset(slot, 0, sizeof *slot);
        return NULL;
    }
    snprintf(slot->key, sizeof slot->key, "%s", r.id);
    snprintf(slot->scene, sizeof slot->scene, "%s", scene->name);
    slot->used = ++ref_clock;
    return slot->image;
}

static const char *layer_mode_name(ddof_layer_mode m)
{
    return m == DDOF_LAYER_ON ? "on" : m == DDOF_LAYER_OFF ? "off" : "auto";
}

static const char *kind_name(study_kind k)
{
    static const char *const names[] = {"diffusion", "cod4", "gather", "pinhole", "defocus"};
    return names[k];
}

static void add_number_or_null(cJSON *o, const char *key, double v)
{
    if (isfinite(v))
        cJSON_AddNumberToObject(o, key, v);
    else if (v > 0)
        cJSON_AddStringToObject(o, key, "inf");
    else
        cJSON_AddNullToObject(o, key);
}

static void add_effects(cJSON *o, const ddof_stats *s)
{
    cJSON *e = cJSON_AddArrayToObject(o, "effects");
    static const struct {
        unsigned bit;
        const char *name;
    } bits[] = {{DDOF_EFFECT_MIDGROUND, "midground"},
                {DDOF_EFFECT_BACKGROUND, "background"},
                {DDOF_EFFECT_FOREGROUND, "foreground"},
                {DDOF_EFFECT_NEAR_SPREAD, "near spread"}};
    for (size_t i = 0; i < sizeof bits / sizeof *bits; i++)
        if (s->effects & bits[i].bit)
            cJSON_AddItemToArray(e, cJSON_CreateString(bits[i].name));
}

/* A context for one configuration: a fresh CPU context (so host_bytes is this configuration's
 * own), or the GL backend's. NULL with *why when the backend is unavailable. */
static ddof_context *context_for(const options *o, const study_config *cfg, int *owned,
                                 const char **why, const char **renderer)
{
    *owned = 0;
    *why = NULL;
    *renderer = "";
    if (cfg->kind == STUDY_DIFFUSION && cfg->backend != DDOF_BACKEND_CPU) {
        gl_backend *b = gl_get(o, cfg->backend);
        if (!b || !b->ctx) {
            *why = b ? b->why : "unknown backend";
            return NULL;
        }
        *renderer = b->renderer;
        return b->ctx;
    }
    ddof_context_options co;
    ddof_context_options_init(&co);
    co.thread_count = o->threads;
    ddof_context *ctx;
    if (ddof_context_create(&co, &ctx) != DDOF_OK) {
        *why = "ddof_context_create failed";
        return NULL;
    }
    *owned = 1;
    return ctx;
}

/* Measures one configuration on one scene; returns its JSON record. */
static cJSON *measure(const options *o, ddof_context *shared, const study_scene *scene,
                      const study_config *cfg, float *out_small, float *out_large,
                      const float *abs_small, const float *abs_large, char *summary,
                      size_t summary_size)
{
    cJSON *r = cJSON_CreateObject();
    char label[128];
    study_config_label(cfg, label, sizeof label);
    cJSON_AddStringToObject(r, "type", "result");
    cJSON_AddStringToObject(r, "scene", scene->name);
    cJSON_AddStringToObject(r, "id", cfg->id);
    cJSON_AddStringToObject(r, "label", label);
    cJSON_AddStringToObject(r, "sweeps", cfg->sweeps);
    cJSON_AddStringToObject(r, "kind", kind_name(cfg->kind));
    const int fg = study_config_uses_fg(cfg, scene->small.fg_rgba != NULL);
    if (cfg->kind == STUDY_DIFFUSION) {
        ddof_params p;
        study_config_params(cfg, fg, &p);
        char solver[32];
        snprintf(solver, sizeof solver, "%s", ddof_solver_name(cfg->solver));
        cJSON_AddStringToObject(r, "backend", ddof_backend_name(cfg->backend));
        cJSON_AddStringToObject(r, "solver", solver);
        cJSON_AddNumberToObject(r, "jacobi_iterations", cfg->jacobi_iterations);
        cJSON_AddStringToObject(r, "precision",
                                cfg->solver == DDOF_SOLVER_REFERENCE_F64 ? "double"
                                : cfg->precision == DDOF_PRECISION_PACKED_HALF ? "packed half"
                                                                                : "float");
        cJSON_AddNumberToObject(r, "substeps", cfg->substeps);
        cJSON_AddNumberToObject(r, "beta_scale", (double)cfg->beta_scale);
        cJSON_AddStringToObject(r, "layers", study_layers_name(cfg->layers));
        cJSON_AddStringToObject(r, "kernel", ddof_kernel_name(cfg->kernel));
        cJSON_AddStringToObject(r, "background", layer_mode_name(p.background));
        cJSON_AddNumberToObject(r, "background_levels", p.background_levels);
        cJSON_AddStringToObject(r, "near_spread", layer_mode_name(p.near_spread));
        cJSON_AddStringToObject(r, "near_layer", layer_mode_name(p.near_layer));
        cJSON_AddStringToObject(r, "far_field", layer_mode_name(p.far_field));
        cJSON_AddStringToObject(r, "silhouettes", layer_mode_name(p.silhouettes));
    } else {
        cJSON_AddStringToObject(r, "backend",
                                cfg->kind == STUDY_DEFOCUS ? "blender" : "cpu");
    }
    cJSON_AddBoolToObject(r, "fg_element", fg);
    cJSON_AddBoolToObject(r, "rest_image", fg && cfg->layers == LAYERS_FG &&
                                               scene->small.rest_rgba != NULL);

    const size_t pixels = (size_t)scene->small.width * scene->small.height;
    double runs[16];
    int count = 0;
    int available = 1;
    char note[1100] = "";
    const float *image = NULL;
    double ms = NAN, ms_large = NAN;

    if (cfg->kind == STUDY_DEFOCUS) {
        const study_node *node = &scene->nodes[cfg->node];
        if (!node->image) {
            available = 0;
            snprintf(note, sizeof note, "no %s.exr in the scene folder",
                     study_node_names[cfg->node]);
        } else {
            image = node->image;
            ms = node->seconds >= 0 ? node->seconds * 1e3 : NAN;
            ms_large = node->seconds_large >= 0 ? node->seconds_large * 1e3 : NAN;
            cJSON_AddStringToObject(r, "blender_version", node->blender);
        }
        cJSON_AddNumberToObject(r, "width", scene->small.width);
        cJSON_AddNumberToObject(r, "height", scene->small.height);
        add_number_or_null(r, "ms", ms);
        if (scene->large.width) {
            cJSON_AddNumberToObject(r, "large_width", scene->large.width);
            cJSON_AddNumberToObject(r, "large_height", scene->large.height);
        }
        add_number_or_null(r, "ms_large", ms_large);
    } else {
        int owned;
        const char *why, *renderer;
        ddof_context *ctx = context_for(o, cfg, &owned, &why, &renderer);
        if (renderer[0])
            cJSON_AddStringToObject(r, "renderer", renderer);
        if (!ctx) {
            available = 0;
            snprintf(note, sizeof note, "not available: %s", why);
        } else {
            call c = {.cfg = cfg, .scene = scene, .frame = &scene->small, .ctx = ctx,
                      .abs_coc = abs_small, .out = out_small};
            ddof_status st = time_calls(&c, o->reps_small, o->budget_small, runs, &count);
            if (st != DDOF_OK) {
                available = 0;
                snprintf(note, sizeof note, "%s%s",
                         st == DDOF_ERROR_UNSUPPORTED || st == DDOF_ERROR_BACKEND_UNAVAILABLE
                             ? "not available: "
                             : "failed: ",
                         c.error);
            } else {
                image = out_small;
                ms = 0.0;
                cJSON *arr = cJSON_AddArrayToObject(r, "ms_runs");
                for (int i = 0; i < count; i++)
                    cJSON_AddItemToArray(arr, cJSON_CreateNumber(runs[i] * 1e3));
                ms = study_median(runs, (size_t)count) * 1e3;
                cJSON_AddNumberToObject(r, "host_bytes", (double)c.stats.host_bytes);
                cJSON_AddNumberToObject(r, "device_bytes", (double)c.stats.device_bytes);
                add_effects(r, &c.stats);
                cJSON_AddStringToObject(r, "plan", c.stats.plan);
                cJSON_AddNumberToObject(r, "threads", c.stats.threads);
            }
            cJSON_AddNumberToObject(r, "width", scene->small.width);
            cJSON_AddNumberToObject(r, "height", scene->small.height);
            add_number_or_null(r, "ms", ms);
            const double ratio = scene->large.width
                                     ? (double)scene->large.width * scene->large.height /
                                           ((double)scene->small.width * scene->small.height)
                                     : 0.0;
            if (available && o->large && scene->large.width &&
                ms * ratio > o->large_limit * 1e3) {
                /* The cost is linear in the pixel count: a prediction, recorded as such. */
                cJSON_AddNumberToObject(r, "large_width", scene->large.width);
                cJSON_AddNumberToObject(r, "large_height", scene->large.height);
                cJSON_AddNullToObject(r, "ms_large");
                cJSON_AddNumberToObject(r, "ms_large_estimate", ms * ratio);
                snprintf(note, sizeof note,
                         "1920x1080 not timed: %.0f ms at %ux%u predicts %.0f s per call "
                         "(over --large-limit %g s)",
                         ms, scene->small.width, scene->small.height, ms * ratio * 1e-3,
                         o->large_limit);
            } else if (available && o->large && scene->large.width) {
                /* A fresh CPU context for the large frame too: its host_bytes is then the
                 * large frame's. */
                if (owned) {
                    ddof_context_free(ctx);
                    ctx = context_for(o, cfg, &owned, &why, &renderer);
                }
                call L = {.cfg = cfg, .scene = scene, .frame = &scene->large, .ctx = ctx,
                          .abs_coc = abs_large, .out = out_large};
                st = ctx ? time_calls(&L, o->reps_large, o->budget_large, runs, &count)
                         : DDOF_ERROR_OUT_OF_MEMORY;
                cJSON_AddNumberToObject(r, "large_width", scene->large.width);
                cJSON_AddNumberToObject(r, "large_height", scene->large.height);
                if (st == DDOF_OK) {
                    cJSON *arr = cJSON_AddArrayToObject(r, "ms_large_runs");
                    for (int i = 0; i < count; i++)
                        cJSON_AddItemToArray(arr, cJSON_CreateNumber(runs[i] * 1e3));
                    ms_large = study_median(runs, (size_t)count) * 1e3;
                    cJSON_AddNumberToObject(r, "host_bytes_large", (double)L.stats.host_bytes);
                    cJSON_AddNumberToObject(r, "device_bytes_large",
                                            (double)L.stats.device_bytes);
                } else {
                    snprintf(note, sizeof note, "1920x1080 failed: %s", L.error);
                }
                add_number_or_null(r, "ms_large", ms_large);
            }
            if (owned)
                ddof_context_free(ctx);
        }
    }
    cJSON_AddBoolToObject(r, "available", available);
    cJSON_AddStringToObject(r, "note", note);

    double psnr = NAN, band = NAN, smooth = NAN;
    if (image) {
        psnr = study_psnr(image, scene->truth, pixels, NULL);
        band = study_psnr(image, scene->truth, pixels, scene->band);
        double max_abs, rms;
        study_linear_diff(image, scene->truth, pixels, &max_abs, &rms);
        add_number_or_null(r, "psnr", psnr);
        add_number_or_null(r, "psnr_band", band);
        smooth = study_psnr(image, scene->truth, pixels, scene->smooth);
        add_number_or_null(r, "psnr_smooth", smooth);
        add_number_or_null(r, "psnr_silhouette",
                           study_psnr(image, scene->truth, pixels, scene->silhouette));
        add_number_or_null(r, "rmse_linear", rms);
        if (cfg->kind == STUDY_DIFFUSION) {
            char error[1100] = "";
            const float *ref = reference_image(shared, scene, cfg, error, sizeof error);
            if (ref) {
                study_linear_diff(image, ref, pixels, &max_abs, &rms);
                add_number_or_null(r, "ref_psnr", study_psnr(image, ref, pixels, NULL));
                add_number_or_null(r, "ref_max_abs", max_abs);
                add_number_or_null(r, "ref_rms", rms);
            } else {
                cJSON_AddStringToObject(r, "ref_error", error);
            }
        }
    }

    char band_text[64];
    if (isnan(band))
        snprintf(band_text, sizeof band_text, "no band");
    else
        snprintf(band_text, sizeof band_text, "band %.2f dB", band);
    if (!isnan(smooth)) {
        const size_t used = strlen(band_text);
        snprintf(band_text + used, sizeof band_text - used, ", smooth %.2f dB", smooth);
    }
    if (!available)
        snprintf(summary, summary_size, "%s", note);
    else if (note[0])
        snprintf(summary, summary_size, "%.1f ms, %.2f dB, %s (%s)", ms, psnr, band_text, note);
    else if (isfinite(ms_large))
        snprintf(summary, summary_size, "%.1f ms (1080p %.1f ms), %.2f dB, %s", ms, ms_large,
                 psnr, band_text);
    else
        snprintf(summary, summary_size, "%.1f ms, %.2f dB, %s", ms, psnr, band_text);
    return r;
}

static cJSON *scene_json(const study_scene *s)
{
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "type", "scene");
    cJSON_AddStringToObject(j, "scene", s->name);
    cJSON_AddStringToObject(j, "dir", s->dir);
    cJSON_AddNumberToObject(j, "width", s->small.width);
    cJSON_AddNumberToObject(j, "height", s->small.height);
    cJSON_AddNumberToObject(j, "large_width", s->large.width);
    cJSON_AddNumberToObject(j, "large_height", s->large.height);
    cJSON_AddNumberToObject(j, "max_abs_coc_px", (double)s->max_abs_coc);
    cJSON_AddBoolToObject(j, "blurred", s->max_abs_coc >= 1.0f);
    cJSON_AddNumberToObject(j, "band_pixels", (double)s->band_pixels);
    cJSON_AddNumberToObject(j, "band_fraction",
                            (double)s->band_pixels / ((double)s->small.width * s->small.height));
    cJSON_AddNumberToObject(j, "smooth_pixels", (double)s->smooth_pixels);
    cJSON_AddNumberToObject(j, "smooth_fraction",
                            (double)s->smooth_pixels / ((double)s->small.width * s->small.height));
    cJSON_AddNumberToObject(j, "silhouette_pixels", (double)s->silhouette_pixels);
    cJSON_AddBoolToObject(j, "fg_element", s->small.fg_rgba != NULL);
    cJSON_AddBoolToObject(j, "rest_image", s->small.rest_rgba != NULL);
    cJSON_AddBoolToObject(j, "fg_resampled_large", s->large.fg_resampled);
    cJSON_AddNumberToObject(j, "coc_ms", s->seconds_coc_small * 1e3);
    cJSON_AddNumberToObject(j, "coc_ms_large", s->seconds_coc_large * 1e3);
    cJSON_AddStringToObject(j, "blender", s->blender);
    cJSON *cam = cJSON_AddObjectToObject(j, "camera");
    cJSON_AddNumberToObject(cam, "focal_length_mm", s->camera.focal_length_mm);
    cJSON_AddNumberToObject(cam, "fstop", s->camera.fstop);
    cJSON_AddNumberToObject(cam, "focus_distance_m", s->camera.focus_distance_m);
    cJSON_AddNumberToObject(cam, "sensor_width_mm", s->camera.sensor_width_mm);
    return j;
}

static int write_line(FILE *f, cJSON *j)
{
    char *text = cJSON_PrintUnformatted(j);
    cJSON_Delete(j);
    if (!text)
        return -1;
    int ok = fprintf(f, "%s\n", text) > 0 && fflush(f) == 0;
    cJSON_free(text);
    return ok ? 0 : -1;
}

static float *abs_of(const float *coc, size_t n)
{
    float *a = malloc(n * sizeof *a);
    if (a)
        for (size_t i = 0; i < n; i++)
            a[i] = fabsf(coc[i]);
    return a;
}

/* ---- commands ---------------------------------------------------------------------------- */

static int cmd_run(const options *o, const study_config_list *list)
{
    char path[4200];
    if (study_mkdirs(o->out) != 0) {
        fprintf(stderr, "ddof-study: cannot create %s\n", o->out);
        return 1;
    }
    snprintf(path, sizeof path, "%s/results.jsonl", o->out);
    FILE *f = fopen(path, o->append ? "a" : "w");
    if (!f) {
        fprintf(stderr, "ddof-study: cannot write %s\n", path);
        return 1;
    }
    const double t_start = study_now();
    if (write_line(f, machine_json(o)) != 0)
        goto io_error;
    ddof_context_options co;
    ddof_context_options_init(&co);
    co.thread_count = o->threads;
    ddof_context *shared;
    if (ddof_context_create(&co, &shared) != DDOF_OK) {
        fclose(f);
        return 1;
    }
    const size_t total = list->count * (size_t)o->scene_count;
    size_t done = 0;
    int failures = 0;
    for (int si = 0; si < o->scene_count; si++) {
        study_scene scene;
        char error[2048] = "";
        const double t_load = study_now();
        if (study_scene_load(shared, o->scenes[si], o->large, &scene, error, sizeof error) != 0) {
            fprintf(stderr, "ddof-study: %s: %s\n", o->scenes[si], error);
            failures++;
            done += list->count;
            continue;
        }
        if (!o->quiet)
            printf("ddof-study: %s: %ux%u%s, CoC up to %.1f px, band %.1f%% of the image, "
                   "smooth far field %.1f%%%s%s (loaded in %.1f s)\n",
                   scene.name, scene.small.width, scene.small.height,
                   scene.large.width ? " + 1920x1080" : "", (double)scene.max_abs_coc,
                   100.0 * (double)scene.band_pixels /
                       ((double)scene.small.width * scene.small.height),
                   100.0 * (double)scene.smooth_pixels /
                       ((double)scene.small.width * scene.small.height),
                   scene.small.fg_rgba ? ", foreground element" : "",
                   scene.nodes[0].image || scene.nodes[1].image || scene.nodes[2].image
                       ? ", Defocus node(s)"
                       : "",
                   study_now() - t_load);
        if (write_line(f, scene_json(&scene)) != 0)
            goto io_error;
        const size_t ps = (size_t)scene.small.width * scene.small.height;
        const size_t pl = (size_t)scene.large.width * scene.large.height;
        float *out_small = malloc(ps * 4 * sizeof(float));
        float *out_large = pl ? malloc(pl * 4 * sizeof(float)) : NULL;
        float *abs_small = abs_of(scene.small.coc, ps);
        float *abs_large = pl ? abs_of(scene.large.coc, pl) : NULL;
        if (!out_small || !abs_small || (pl && (!out_large || !abs_large))) {
            fprintf(stderr, "ddof-study: out of memory\n");
            free(out_small);
            free(out_large);
            free(abs_small);
            free(abs_large);
            study_scene_free(&scene);
            fclose(f);
            ddof_context_free(shared);
            return 1;
        }
        for (size_t i = 0; i < list->count; i++) {
            char summary[1300], label[128];
            const double t0 = study_now();
            cJSON *r = measure(o, shared, &scene, &list->items[i], out_small, out_large,
                               abs_small, abs_large, summary, sizeof summary);
            cJSON_AddNumberToObject(r, "seconds_measuring", study_now() - t0);
            if (write_line(f, r) != 0)
                goto io_error;
            done++;
            study_config_label(&list->items[i], label, sizeof label);
            if (!o->quiet) {
                printf("[%zu/%zu] %s %s: %s\n", done, total, scene.name, label, summary);
                fflush(stdout);
            }
        }
        ref_cache_clear();
        free(out_small);
        free(out_large);
        free(abs_small);
        free(abs_large);
        study_scene_free(&scene);
    }
    {
        struct rusage ru;
        getrusage(RUSAGE_SELF, &ru);
        cJSON *d = cJSON_CreateObject();
        cJSON_AddStringToObject(d, "type", "done");
        cJSON_AddNumberToObject(d, "seconds", study_now() - t_start);
        cJSON_AddNumberToObject(d, "peak_rss_bytes", (double)ru.ru_maxrss * 1024.0);
        cJSON_AddNumberToObject(d, "scene_failures", failures);
        cJSON_AddNumberToObject(d, "seconds_references", ref_seconds);
        if (write_line(f, d) != 0)
            goto io_error;
    }
    ddof_context_free(shared);
    if (fclose(f) != 0) {
        fprintf(stderr, "ddof-study: cannot write %s\n", path);
        return 1;
    }
    if (!o->quiet)
        printf("ddof-study: %zu measurements in %.1f s -> %s\n", done, study_now() - t_start,
               path);
    return failures ? 1 : 0;

io_error:
    fprintf(stderr, "ddof-study: cannot write %s\n", path);
    fclose(f);
    return 1;
}

static void safe_name(const char *id, char *out, size_t size)
{
    snprintf(out, size, "%s", id);
    for (char *p = out; *p; p++)
        if (*p == '/')
            *p = '_';
}

static int cmd_images(const options *o, const study_config_list *list)
{
    ddof_context_options co;
    ddof_context_options_init(&co);
    co.thread_count = o->threads;
    ddof_context *shared;
    if (ddof_context_create(&co, &shared) != DDOF_OK)
        return 1;
    int rc = 0;
    for (int si = 0; si < o->scene_count && !rc; si++) {
        study_scene scene;
        char error[2048] = "", dir[4200], path[4400];
        if (study_scene_load(shared, o->scenes[si], 0, &scene, error, sizeof error) != 0) {
            fprintf(stderr, "ddof-study: %s: %s\n", o->scenes[si], error);
            rc = 1;
            break;
        }
        snprintf(dir, sizeof dir, "%s/%s", o->out, scene.name);
        const uint32_t w = scene.small.width, h = scene.small.height;
        const size_t pixels = (size_t)w * h;
        float *out = malloc(pixels * 4 * sizeof(float));
        float *band = malloc(pixels * sizeof(float));
        float *smooth = malloc(pixels * sizeof(float));
        float *abs_coc = abs_of(scene.small.coc, pixels);
        if (!out || !band || !smooth || !abs_coc || study_mkdirs(dir) != 0) {
            fprintf(stderr, "ddof-study: cannot prepare %s\n", dir);
            rc = 1;
        }
        for (size_t i = 0; !rc && i < pixels; i++) {
            band[i] = scene.band[i];
            smooth[i] = scene.smooth[i];
        }
#define WRITE(name, data, ch)                                                                \
    do {                                                                                     \
        snprintf(path, sizeof path, "%s/%s.npy", dir, name);                                 \
        if (!rc && study_write_npy(path, data, w, h, ch) != 0) {                             \
            fprintf(stderr, "ddof-study: cannot write %s\n", path);                          \
            rc = 1;                                                                          \
        }                                                                                    \
    } while (0)
        WRITE("input_pinhole", scene.small.rgba, 4);
        WRITE("input_truth", scene.truth, 4);
        WRITE("input_coc", scene.small.coc, 1);
        WRITE("input_depth", scene.small.depth, 1);
        WRITE("input_band", band, 1);
        WRITE("input_smooth", smooth, 1);
        for (size_t i = 0; !rc && i < list->count; i++) {
            const study_config *cfg = &list->items[i];
            char name[128];
            safe_name(cfg->id, name, sizeof name);
            if (cfg->kind == STUDY_DEFOCUS) {
                if (scene.nodes[cfg->node].image)
                    WRITE(name, scene.nodes[cfg->node].image, 4);
                continue;
            }
            int owned;
            const char *why, *renderer;
            ddof_context *ctx = context_for(o, cfg, &owned, &why, &renderer);
            if (!ctx)
                continue;
            call c = {.cfg = cfg, .scene = &scene, .frame = &scene.small, .ctx = ctx,
                      .abs_coc = abs_coc, .out = out};
            ddof_status st = run_call(&c);
            if (st == DDOF_OK)
                WRITE(name, out, 4);
            else if (!o->quiet || (st != DDOF_ERROR_UNSUPPORTED &&
                                   st != DDOF_ERROR_BACKEND_UNAVAILABLE))
                fprintf(stderr, "ddof-study: %s %s: %s\n", scene.name, cfg->id, c.error);
            if (owned)
                ddof_context_free(ctx);
        }
#undef WRITE
        if (!o->quiet && !rc)
            printf("ddof-study: images of %s -> %s\n", scene.name, dir);
        free(out);
        free(band);
        free(smooth);
        free(abs_coc);
        study_scene_free(&scene);
    }
    ddof_context_free(shared);
    return rc;
}

static int parse_int(const char *s, int lo, int hi, int *out)
{
    char *end;
    long v = strtol(s, &end, 10);
    if (!*s || *end || v < lo || v > hi)
        return -1;
    *out = (int)v;
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 2 || !strcmp(argv[1], "--help") || !strcmp(argv[1], "-h")) {
        usage(argc < 2 ? stderr : stdout);
        return argc < 2 ? 2 : 0;
    }
    const char *command = argv[1];
    options o = {.configs = NULL, .reps_small = 5, .reps_large = 3, .budget_small = 1.0,
                 .budget_large = 2.0, .large = 1, .large_limit = 5.0};
    o.scenes = calloc((size_t)argc, sizeof *o.scenes);
    if (!o.scenes)
        return 1;
    for (int i = 2; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        int n;
        if (!strcmp(a, "--out") && v) {
            o.out = v;
            i++;
        } else if (!strcmp(a, "--configs") && v) {
            o.configs = v;
            i++;
        } else if (!strcmp(a, "--gl-plugin") && v) {
            o.gl_plugin = v;
            i++;
        } else if (!strcmp(a, "--reps") && v && parse_int(v, 1, 15, &o.reps_small) == 0) {
            i++;
        } else if (!strcmp(a, "--large-reps") && v && parse_int(v, 1, 15, &o.reps_large) == 0) {
            i++;
        } else if (!strcmp(a, "--threads") && v && parse_int(v, 0, 1024, &n) == 0) {
            o.threads = (uint32_t)n;
            i++;
        } else if (!strcmp(a, "--large-limit") && v && atof(v) > 0) {
            o.large_limit = atof(v);
            i++;
        } else if (!strcmp(a, "--no-gl")) {
            o.no_gl = 1;
        } else if (!strcmp(a, "--egl-software")) {
            o.egl_software = 1;
        } else if (!strcmp(a, "--no-large")) {
            o.large = 0;
        } else if (!strcmp(a, "--append")) {
            o.append = 1;
        } else if (!strcmp(a, "-q")) {
            o.quiet = 1;
        } else if (a[0] == '-') {
            fprintf(stderr, "ddof-study: unknown or incomplete option %s\n", a);
            usage(stderr);
            return 2;
        } else {
            o.scenes[o.scene_count++] = a;
        }
    }
    study_config_list list = {0};
    char error[1024];
    if (study_config_from_spec(&list, o.configs ? o.configs : "full", error, sizeof error) != 0) {
        fprintf(stderr, "ddof-study: %s\n", error);
        return 2;
    }
    int rc;
    if (!strcmp(command, "list")) {
        for (size_t i = 0; i < list.count; i++)
            printf("%s\t%s\n", list.items[i].id, list.items[i].sweeps);
        rc = 0;
    } else if (!strcmp(command, "run") || !strcmp(command, "images")) {
        if (!o.out || o.scene_count == 0) {
            fprintf(stderr, "ddof-study %s: --out DIR and at least one scene folder are "
                    "needed\n", command);
            rc = 2;
        } else {
            rc = !strcmp(command, "run") ? cmd_run(&o, &list) : cmd_images(&o, &list);
        }
    } else {
        fprintf(stderr, "ddof-study: unknown command %s\n", command);
        usage(stderr);
        rc = 2;
    }
    for (int i = 0; i < 2; i++)
        ddof_context_free(gl_backends[i].ctx);
    study_config_list_free(&list);
    free(o.scenes);
    return rc;
}
