/* SPDX-License-Identifier: MIT */
/* measure.c - one configuration on one scene: its settings, its times at both sizes, its errors
 * against the truth and the reference, as one JSON record of results.jsonl. */
#include "study.h"

#include <cJSON.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

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

/* What a measurement found: whether the configuration ran (else why not, in note; note also
 * says what to know about a run), its image at the scene's size and its times. */
typedef struct outcome {
    int available;
    char note[1100];
    const float *image;
    double ms, ms_large;
} outcome;

/* The record's head: the configuration and, for the diffusion, its settings as the library
 * gets them. */
static cJSON *settings_json(const study_scene *scene, const study_config *cfg)
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
        cJSON_AddStringToObject(r, "blurred_edges", layer_mode_name(p.blurred_edges));
    } else {
        cJSON_AddStringToObject(r, "backend",
                                cfg->kind == STUDY_DEFOCUS ? "blender" : "cpu");
    }
    cJSON_AddBoolToObject(r, "fg_element", fg);
    cJSON_AddBoolToObject(r, "matte", cfg->matte);
    cJSON_AddBoolToObject(r, "rest_image", fg && cfg->layers == LAYERS_FG &&
                                               scene->small.rest_rgba != NULL);
    return r;
}

/* Blender's Defocus node: its image and times come with the scene folder. */
static void node_outcome(cJSON *r, const study_scene *scene, const study_config *cfg,
                         outcome *m)
{
    const study_node *node = &scene->nodes[cfg->node];
    if (!node->image) {
        m->available = 0;
        snprintf(m->note, sizeof m->note, "no %s.exr in the scene folder",
                 study_node_names[cfg->node]);
    } else {
        m->image = node->image;
        m->ms = node->seconds >= 0 ? node->seconds * 1e3 : NAN;
        m->ms_large = node->seconds_large >= 0 ? node->seconds_large * 1e3 : NAN;
        cJSON_AddStringToObject(r, "blender_version", node->blender);
    }
    cJSON_AddNumberToObject(r, "width", scene->small.width);
    cJSON_AddNumberToObject(r, "height", scene->small.height);
    add_number_or_null(r, "ms", m->ms);
    if (scene->large.width) {
        cJSON_AddNumberToObject(r, "large_width", scene->large.width);
        cJSON_AddNumberToObject(r, "large_height", scene->large.height);
    }
    add_number_or_null(r, "ms_large", m->ms_large);
}

/* The timed calls in ms under key; returns their median in ms. */
static double add_runs(cJSON *r, const char *key, double *runs, int count)
{
    cJSON *arr = cJSON_AddArrayToObject(r, key);
    for (int i = 0; i < count; i++)
        cJSON_AddItemToArray(arr, cJSON_CreateNumber(runs[i] * 1e3));
    return study_median(runs, (size_t)count) * 1e3;
}

/* The 1920x1080 frame, timed in a fresh CPU context too (its host_bytes is then the large
 * frame's); *ctx and *owned follow the context. */
static void large_outcome(cJSON *r, const study_options *o, const study_scene *scene,
                          const study_config *cfg, ddof_context **ctx, int *owned,
                          float *out_large, const float *abs_large, outcome *m)
{
    if (*owned) {
        const char *why, *renderer;
        ddof_context_free(*ctx);
        *ctx = study_context_for(o, cfg, owned, &why, &renderer);
    }
    double runs[16];
    int count = 0;
    study_call L = {.cfg = cfg, .scene = scene, .frame = &scene->large, .ctx = *ctx,
                    .abs_coc = abs_large, .out = out_large};
    ddof_status st = *ctx ? study_time_calls(&L, o->reps_large, o->budget_large, runs, &count)
                          : DDOF_ERROR_OUT_OF_MEMORY;
    cJSON_AddNumberToObject(r, "large_width", scene->large.width);
    cJSON_AddNumberToObject(r, "large_height", scene->large.height);
    if (st == DDOF_OK) {
        m->ms_large = add_runs(r, "ms_large_runs", runs, count);
        cJSON_AddNumberToObject(r, "host_bytes_large", (double)L.stats.host_bytes);
        cJSON_AddNumberToObject(r, "device_bytes_large", (double)L.stats.device_bytes);
    } else {
        snprintf(m->note, sizeof m->note, "1920x1080 failed: %s", L.error);
    }
    add_number_or_null(r, "ms_large", m->ms_large);
}

/* The diffusion, the CoD4 preview or a computed baseline: timed at the scene's size, then at
 * 1920x1080 unless the scene's size predicts a call over --large-limit (a prediction, recorded
 * as such: the cost is linear in the pixel count). */
static void call_outcome(cJSON *r, const study_options *o, const study_scene *scene,
                         const study_config *cfg, float *out_small, float *out_large,
                         const float *abs_small, const float *abs_large, outcome *m)
{
    int owned;
    const char *why, *renderer;
    ddof_context *ctx = study_context_for(o, cfg, &owned, &why, &renderer);
    if (renderer[0])
        cJSON_AddStringToObject(r, "renderer", renderer);
    if (!ctx) {
        m->available = 0;
        snprintf(m->note, sizeof m->note, "not available: %s", why);
        return;
    }
    double runs[16];
    int count = 0;
    study_call c = {.cfg = cfg, .scene = scene, .frame = &scene->small, .ctx = ctx,
                    .abs_coc = abs_small, .out = out_small};
    ddof_status st = study_time_calls(&c, o->reps_small, o->budget_small, runs, &count);
    if (st != DDOF_OK) {
        m->available = 0;
        snprintf(m->note, sizeof m->note, "%s%s",
                 st == DDOF_ERROR_UNSUPPORTED || st == DDOF_ERROR_BACKEND_UNAVAILABLE
                     ? "not available: "
                     : "failed: ",
                 c.error);
    } else {
        m->image = out_small;
        m->ms = add_runs(r, "ms_runs", runs, count);
        cJSON_AddNumberToObject(r, "host_bytes", (double)c.stats.host_bytes);
        cJSON_AddNumberToObject(r, "device_bytes", (double)c.stats.device_bytes);
        add_effects(r, &c.stats);
        cJSON_AddStringToObject(r, "plan", c.stats.plan);
        cJSON_AddNumberToObject(r, "threads", c.stats.threads);
    }
    cJSON_AddNumberToObject(r, "width", scene->small.width);
    cJSON_AddNumberToObject(r, "height", scene->small.height);
    add_number_or_null(r, "ms", m->ms);
    const double ratio = scene->large.width
                             ? (double)scene->large.width * scene->large.height /
                                   ((double)scene->small.width * scene->small.height)
                             : 0.0;
    const double ms = m->ms;
    if (m->available && o->large && scene->large.width && ms * ratio > o->large_limit * 1e3) {
        cJSON_AddNumberToObject(r, "large_width", scene->large.width);
        cJSON_AddNumberToObject(r, "large_height", scene->large.height);
        cJSON_AddNullToObject(r, "ms_large");
        cJSON_AddNumberToObject(r, "ms_large_estimate", ms * ratio);
        snprintf(m->note, sizeof m->note,
                 "1920x1080 not timed: %.0f ms at %ux%u predicts %.0f s per call "
                 "(over --large-limit %g s)",
                 ms, scene->small.width, scene->small.height, ms * ratio * 1e-3, o->large_limit);
    } else if (m->available && o->large && scene->large.width) {
        large_outcome(r, o, scene, cfg, &ctx, &owned, out_large, abs_large, m);
    }
    if (owned)
        ddof_context_free(ctx);
}

/* The errors of the image against the truth (the whole image, the band, the smooth far field,
 * the silhouettes, where blurred surfaces meet, the mean brightness inside the frame and at
 * its border) and, for the diffusion, against the double-precision solve of its settings. */
static void add_errors(cJSON *r, ddof_context *shared, const study_scene *scene,
                       const study_config *cfg, const float *image, double *psnr, double *band,
                       double *smooth)
{
    const size_t pixels = (size_t)scene->small.width * scene->small.height;
    *psnr = study_psnr(image, scene->truth, pixels, NULL);
    *band = study_psnr(image, scene->truth, pixels, scene->band);
    double max_abs, rms;
    study_linear_diff(image, scene->truth, pixels, &max_abs, &rms);
    add_number_or_null(r, "psnr", *psnr);
    add_number_or_null(r, "psnr_band", *band);
    *smooth = study_psnr(image, scene->truth, pixels, scene->smooth);
    add_number_or_null(r, "psnr_smooth", *smooth);
    add_number_or_null(r, "psnr_silhouette",
                       study_psnr(image, scene->truth, pixels, scene->silhouette));
    add_number_or_null(r, "psnr_blurred_edges",
                       study_psnr(image, scene->truth, pixels, scene->blurred_edges));
    add_number_or_null(r, "rmse_linear", rms);
    double inside, border;
    study_brightness(image, scene->truth, scene->small.width, scene->small.height, &inside,
                     &border);
    add_number_or_null(r, "brightness_inside", inside);
    add_number_or_null(r, "brightness_border", border);
    if (cfg->kind != STUDY_DIFFUSION)
        return;
    char error[1100] = "";
    const float *ref = study_reference_image(shared, scene, cfg, error, sizeof error);
    if (ref) {
        study_linear_diff(image, ref, pixels, &max_abs, &rms);
        add_number_or_null(r, "ref_psnr", study_psnr(image, ref, pixels, NULL));
        add_number_or_null(r, "ref_max_abs", max_abs);
        add_number_or_null(r, "ref_rms", rms);
    } else {
        cJSON_AddStringToObject(r, "ref_error", error);
    }
}

/* The measurement's progress line. */
static void summarise(const outcome *m, double psnr, double band, double smooth, char *summary,
                      size_t summary_size)
{
    char band_text[64];
    if (isnan(band))
        snprintf(band_text, sizeof band_text, "no band");
    else
        snprintf(band_text, sizeof band_text, "band %.2f dB", band);
    if (!isnan(smooth)) {
        const size_t used = strlen(band_text);
        snprintf(band_text + used, sizeof band_text - used, ", smooth %.2f dB", smooth);
    }
    if (!m->available)
        snprintf(summary, summary_size, "%s", m->note);
    else if (m->note[0])
        snprintf(summary, summary_size, "%.1f ms, %.2f dB, %s (%s)", m->ms, psnr, band_text,
                 m->note);
    else if (isfinite(m->ms_large))
        snprintf(summary, summary_size, "%.1f ms (1080p %.1f ms), %.2f dB, %s", m->ms,
                 m->ms_large, psnr, band_text);
    else
        snprintf(summary, summary_size, "%.1f ms, %.2f dB, %s", m->ms, psnr, band_text);
}

cJSON *study_measure(const study_options *o, ddof_context *shared, const study_scene *scene,
                     const study_config *cfg, float *out_small, float *out_large,
                     const float *abs_small, const float *abs_large, char *summary,
                     size_t summary_size)
{
    cJSON *r = settings_json(scene, cfg);
    outcome m = {.available = 1, .ms = NAN, .ms_large = NAN};
    if (cfg->kind == STUDY_DEFOCUS)
        node_outcome(r, scene, cfg, &m);
    else
        call_outcome(r, o, scene, cfg, out_small, out_large, abs_small, abs_large, &m);
    cJSON_AddBoolToObject(r, "available", m.available);
    cJSON_AddStringToObject(r, "note", m.note);
    double psnr = NAN, band = NAN, smooth = NAN;
    if (m.image)
        add_errors(r, shared, scene, cfg, m.image, &psnr, &band, &smooth);
    summarise(&m, psnr, band, smooth, summary, summary_size);
    return r;
}
