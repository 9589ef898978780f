/* SPDX-License-Identifier: MIT */
/* stats_json.c - the --stats report. */
#include "stats_json.h"

#include "camera_json.h"
#include "option_table.h"
#include "output_file.h"

#include <cJSON.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <errno.h>
#include <string.h>

/* The planner's effects, in the order both the summary line and the report list them. */
static const struct {
    uint32_t bit;
    const char *text; /* the summary line's word */
    const char *key;  /* the report's "effects" key */
} effects[] = {{DDOF_EFFECT_MIDGROUND, "midground", "midground"},
               {DDOF_EFFECT_BACKGROUND, "background", "background"},
               {DDOF_EFFECT_NEAR_SPREAD, "near spread", "near_spread"},
               {DDOF_EFFECT_NEAR_LAYER, "near layer", "near_layer"},
               {DDOF_EFFECT_FOREGROUND, "foreground", "foreground"},
               {DDOF_EFFECT_HIGHLIGHTS, "highlights", "highlights"},
               {DDOF_EFFECT_FAR_FIELD, "far field", "far_field"},
               {DDOF_EFFECT_SILHOUETTES, "silhouettes", "silhouettes"}};

void stats_effects(const ddof_stats *s, char *out, size_t out_size)
{
    size_t used = 0, i;
    out[0] = '\0';
    for (i = 0; i < sizeof effects / sizeof effects[0]; i++) {
        int n;
        if (!(s->effects & effects[i].bit))
            continue;
        n = snprintf(out + used, out_size - used, "%s%s", used ? " + " : "", effects[i].text);
        if (n < 0 || (size_t)n >= out_size - used)
            return;
        used += (size_t)n;
    }
    if (!used)
        snprintf(out, out_size, "copy");
}

void stats_explain(const ddof_stats *s, char *out, size_t out_size)
{
    if (s->method == DDOF_METHOD_COD4_PREVIEW)
        snprintf(out, out_size, "largest CoC %.3g px: the CoD4 post-process preview (GPU Gems 3 "
                 "ch. 28), no system solved", (double)s->max_coc_px);
    else if (s->copied_only)
        snprintf(out, out_size, "nothing out of focus (largest CoC %.3g px): the output is a "
                 "copy of the input, no system solved", (double)s->max_coc_px);
    else if (s->lines_skipped > 0)
        snprintf(out, out_size, "largest CoC %.3g px: %llu lines solved in %u sub-step%s; %llu "
                 "lines had no conductive link (all in focus) and were copied",
                 (double)s->max_coc_px, (unsigned long long)s->lines_solved, s->substeps,
                 s->substeps == 1 ? "" : "s", (unsigned long long)s->lines_skipped);
    else
        snprintf(out, out_size, "largest CoC %.3g px: %llu lines solved in %u sub-step%s; no "
                 "line could be skipped", (double)s->max_coc_px,
                 (unsigned long long)s->lines_solved, s->substeps, s->substeps == 1 ? "" : "s");
}

const char *stats_method_name(uint32_t method)
{
    return cli_choice_name(&cli_choices_method, (int)method);
}

/* The backend that ran the frame's call and its renderer. A call can run elsewhere than the
 * context's backend (the CoD4 preview runs on the CPU): then the renderer is the CPU's. */
static const char *frame_renderer(const frame_result *r, char *buffer, size_t size)
{
    if (r->stats.backend == r->backend.kind)
        return r->backend.renderer;
    snprintf(buffer, size, "CPU, %u thread%s", r->stats.threads, r->stats.threads == 1 ? "" : "s");
    return buffer;
}

static const char *backend_name_or(uint32_t kind)
{
    const char *n = ddof_backend_name((ddof_backend_kind)kind);
    return n ? n : "?";
}

static void bytes_text(uint64_t bytes, char *out, size_t size)
{
    if (bytes >= 1024u * 1024u)
        snprintf(out, size, "%.1f MiB", (double)bytes / (1024.0 * 1024.0));
    else if (bytes >= 1024u)
        snprintf(out, size, "%.1f KiB", (double)bytes / 1024.0);
    else
        snprintf(out, size, "%llu B", (unsigned long long)bytes);
}

void stats_backend_line(const frame_result *r, char *out, size_t out_size)
{
    char renderer[64], host[32], device[32];
    bytes_text(r->stats.host_bytes, host, sizeof host);
    bytes_text(r->stats.device_bytes, device, sizeof device);
    snprintf(out, out_size, "backend %s (%s), method %s, memory %s host, %s device%s%s",
             backend_name_or(r->stats.backend), frame_renderer(r, renderer, sizeof renderer),
             stats_method_name(r->stats.method), host, device, r->backend.note[0] ? "; " : "",
             r->backend.note);
}

/* In the sidecar's own spelling (camera_json.h), so that it reads back as one. */
static cJSON *camera_json(const ddof_camera *c)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "lens_model",
                            cli_choice_name(&cli_choices_lens, (int)c->lens_model));
    cJSON_AddNumberToObject(o, "focal_length_mm", c->focal_length_mm);
    cJSON_AddNumberToObject(o, "sensor_width_mm", c->sensor_width_mm);
    cJSON_AddStringToObject(o, "sensor_fit", camera_sidecar_fit_name(c->sensor_fit));
    cJSON_AddNumberToObject(o, "fstop", c->fstop);
    cJSON_AddNumberToObject(o, "focus_distance_m", c->focus_distance_m);
    cJSON_AddNumberToObject(o, "pixel_aspect", c->pixel_aspect);
    cJSON_AddStringToObject(o, "depth", camera_sidecar_depth_name(c->depth_kind));
    cJSON_AddNumberToObject(o, "unit_scale_m", c->depth_unit_m);
    cJSON_AddNumberToObject(o, "aperture_blades", c->aperture_blades);
    cJSON_AddNumberToObject(o, "aperture_rotation_deg", c->aperture_rotation_deg);
    cJSON_AddNumberToObject(o, "aperture_ratio", c->aperture_ratio);
    cJSON_AddNumberToObject(o, "aperture_catseye", c->aperture_catseye);
    return o;
}

/* Every option the table gives a settings key: the resolved value for those that override
 * the preset (what ran), else the option's own. */
static void add_option_settings(cJSON *o, const frame_setup *setup)
{
    size_t i;
    for (i = 0; i < cli_option_count; i++) {
        const cli_option *option = &cli_option_table[i];
        const cli_setting s = cli_option_setting(option, setup->options, &setup->params);
        if (s.type == CLI_SETTING_TEXT)
            cJSON_AddStringToObject(o, option->setting, s.text);
        else if (s.type == CLI_SETTING_NUMBER)
            cJSON_AddNumberToObject(o, option->setting, s.number);
        else if (s.type == CLI_SETTING_BOOL)
            cJSON_AddBoolToObject(o, option->setting, s.number != 0.0);
    }
}

static cJSON *curve_json(const ddof_curve *curve)
{
    cJSON *c = cJSON_CreateObject();
    size_t i;
    for (i = 0; i < 6; i++) {
        double number;
        memcpy(&number, (const char *)curve + cli_curve_numbers[i].field, sizeof number);
        cJSON_AddNumberToObject(c, cli_curve_numbers[i].name, number);
    }
    return c;
}

static void add_coc_source(cJSON *o, const frame_setup *setup)
{
    const cli_options *opt = setup->options;
    switch (opt->source) {
    case COC_FROM_CAMERA:
        cJSON_AddStringToObject(o, "coc_source", "camera");
        cJSON_AddItemToObject(o, "camera", camera_json(&setup->camera));
        break;
    case COC_FROM_CURVE:
        cJSON_AddStringToObject(o, "coc_source", "curve");
        cJSON_AddItemToObject(o, "curve", curve_json(&setup->curve));
        break;
    case COC_FROM_CHANNEL:
        cJSON_AddStringToObject(o, "coc_source", "channel");
        cJSON_AddStringToObject(o, "coc_channel", opt->coc_channel);
        break;
    }
}

static cJSON *settings_json(const frame_setup *setup, uint32_t jobs, uint32_t threads)
{
    const cli_options *opt = setup->options;
    cJSON *o = cJSON_CreateObject();
    add_option_settings(o, setup);
    if (opt->foreground || opt->foreground_layer) {
        cJSON *fg = cJSON_CreateObject();
        if (opt->foreground)
            cJSON_AddStringToObject(fg, "file", opt->foreground);
        if (opt->foreground_layer)
            cJSON_AddStringToObject(fg, "layer", opt->foreground_layer);
        cJSON_AddBoolToObject(fg, "premultiplied", !opt->foreground_straight);
        cJSON_AddItemToObject(o, "foreground", fg);
    }
    /* What the plan chose (the options may have left them to it). */
    cJSON_AddNumberToObject(o, "frames_in_parallel", jobs);
    cJSON_AddNumberToObject(o, "threads_per_frame", threads);
    add_coc_source(o, setup);
    return o;
}

/* JSON has no infinity: an exact match (PSNR = inf) is written as null. */
static void add_number_or_null(cJSON *o, const char *key, double v)
{
    if (isfinite(v))
        cJSON_AddNumberToObject(o, key, v);
    else
        cJSON_AddNullToObject(o, key);
}

static cJSON *error_json(const image_error *e)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "rmse_srgb", e->rmse_srgb);
    add_number_or_null(o, "psnr_srgb_db", e->psnr_srgb);
    cJSON_AddNumberToObject(o, "rmse_linear", e->rmse_linear);
    return o;
}

static cJSON *frame_json(const frame_paths *p, const frame_result *r)
{
    cJSON *o = cJSON_CreateObject();
    char why[512];
    if (p->frame >= 0)
        cJSON_AddNumberToObject(o, "frame", p->frame);
    cJSON_AddStringToObject(o, "input", p->input);
    cJSON_AddStringToObject(o, "output", p->output);
    cJSON_AddStringToObject(o, "status", r->skipped ? "skipped" : r->ok ? "ok" : "failed");
    if (r->skipped)
        return o;
    if (!r->ok) {
        cJSON_AddStringToObject(o, "error", r->error);
        return o;
    }
    if (r->warning[0])
        cJSON_AddStringToObject(o, "warning", r->warning);
    cJSON_AddNumberToObject(o, "width", r->width);
    cJSON_AddNumberToObject(o, "height", r->height);
    cJSON_AddStringToObject(o, "color", r->color_name);
    cJSON_AddStringToObject(o, "depth_or_coc", r->depth_name);
    if (r->matte_ranks)
        cJSON_AddStringToObject(o, "matte", r->matte_name);
    {
        cJSON *s = cJSON_CreateObject();
        stats_explain(&r->stats, why, sizeof why);
        char renderer[64];
        cJSON_AddStringToObject(s, "backend", backend_name_or(r->stats.backend));
        cJSON_AddStringToObject(s, "renderer", frame_renderer(r, renderer, sizeof renderer));
        cJSON_AddBoolToObject(s, "hardware", r->stats.backend == r->backend.kind &&
                                                 r->backend.hardware != 0);
        cJSON_AddStringToObject(s, "backend_note", r->backend.note);
        cJSON_AddStringToObject(s, "method", stats_method_name(r->stats.method));
        cJSON_AddNumberToObject(s, "device_bytes", (double)r->stats.device_bytes);
        cJSON_AddNumberToObject(s, "device_uploads", r->stats.device_uploads);
        cJSON_AddNumberToObject(s, "device_readbacks", r->stats.device_readbacks);
        cJSON_AddNumberToObject(s, "host_bytes", (double)r->stats.host_bytes);
        cJSON_AddStringToObject(s, "kernel", ddof_kernel_name((ddof_kernel)r->stats.kernel));
        cJSON_AddStringToObject(s, "solver", ddof_solver_name((ddof_solver)r->stats.solver));
        cJSON_AddNumberToObject(s, "threads", r->stats.threads);
        cJSON_AddNumberToObject(s, "substeps", r->stats.substeps);
        cJSON_AddNumberToObject(s, "lines_solved", (double)r->stats.lines_solved);
        cJSON_AddNumberToObject(s, "lines_skipped", (double)r->stats.lines_skipped);
        cJSON_AddNumberToObject(s, "max_coc_px", r->stats.max_coc_px);
        cJSON_AddBoolToObject(s, "copied_only", r->stats.copied_only != 0);
        cJSON_AddStringToObject(s, "why", why);
        {
            /* The planner's decisions, one per effect: "background: on: ...". */
            cJSON *effect_flags = cJSON_CreateObject();
            cJSON *plan = cJSON_CreateArray();
            char copy[sizeof r->plan];
            char *line, *save = NULL;
            size_t k;
            for (k = 0; k < sizeof effects / sizeof effects[0]; k++)
                cJSON_AddBoolToObject(effect_flags, effects[k].key,
                                      (r->stats.effects & effects[k].bit) != 0);
            cJSON_AddItemToObject(s, "effects", effect_flags);
            memcpy(copy, r->plan, sizeof r->plan);
            for (line = strtok_r(copy, "\n", &save); line; line = strtok_r(NULL, "\n", &save))
                cJSON_AddItemToArray(plan, cJSON_CreateString(line));
            cJSON_AddItemToObject(s, "plan", plan);
        }
        cJSON_AddItemToObject(o, "simulated", s);
    }
    {
        cJSON *t = cJSON_CreateObject();
        cJSON_AddNumberToObject(t, "read", r->seconds_read);
        cJSON_AddNumberToObject(t, "coc", r->stats.seconds_coc + r->seconds_coc);
        cJSON_AddNumberToObject(t, "rows", r->stats.seconds_rows);
        cJSON_AddNumberToObject(t, "columns", r->stats.seconds_columns);
        cJSON_AddNumberToObject(t, "plan", r->stats.seconds_plan);
        cJSON_AddNumberToObject(t, "background", r->stats.seconds_background);
        cJSON_AddNumberToObject(t, "foreground", r->stats.seconds_foreground);
        cJSON_AddNumberToObject(t, "highlights", r->stats.seconds_highlights);
        cJSON_AddNumberToObject(t, "near_layer", r->stats.seconds_near_layer);
        cJSON_AddNumberToObject(t, "far_field", r->stats.seconds_far_field);
        cJSON_AddNumberToObject(t, "silhouettes", r->stats.seconds_silhouettes);
        cJSON_AddNumberToObject(t, "library_total", r->stats.seconds_total);
        cJSON_AddNumberToObject(t, "write", r->seconds_write);
        cJSON_AddNumberToObject(t, "preview", r->seconds_preview);
        cJSON_AddNumberToObject(t, "compare", r->seconds_compare);
        cJSON_AddNumberToObject(t, "frame", r->seconds_total);
        cJSON_AddItemToObject(o, "seconds", t);
    }
    if (r->compared) {
        cJSON *c = cJSON_CreateObject();
        cJSON_AddStringToObject(c, "truth", p->compare);
        cJSON_AddItemToObject(c, "result", error_json(&r->error_result));
        cJSON_AddItemToObject(c, "input", error_json(&r->error_input));
        cJSON_AddItemToObject(o, "error_vs_truth", c);
    }
    return o;
}

int stats_json_write(const char *path, const frame_setup *setup, const frame_paths *paths,
                     const frame_result *results, int count, uint32_t jobs,
                     uint32_t threads_per_frame, double seconds_wall, char *error,
                     size_t error_size)
{
    cJSON *root = cJSON_CreateObject();
    cJSON *frames;
    output_file file;
    char *text;
    int i, failed = 0, rc = -1;
    size_t length;

    if (!root) {
        snprintf(error, error_size, "out of memory");
        return -1;
    }
    cJSON_AddStringToObject(root, "ddof_version", ddof_version_string());
    cJSON_AddItemToObject(root, "settings", settings_json(setup, jobs, threads_per_frame));
    frames = cJSON_AddArrayToObject(root, "frames");
    for (i = 0; i < count; i++) {
        cJSON_AddItemToArray(frames, frame_json(&paths[i], &results[i]));
        failed += !results[i].ok;
    }
    {
        cJSON *s = cJSON_CreateObject();
        cJSON_AddNumberToObject(s, "frames", count);
        cJSON_AddNumberToObject(s, "failed", failed);
        cJSON_AddNumberToObject(s, "seconds_wall", seconds_wall);
        cJSON_AddItemToObject(root, "summary", s);
    }
    text = cJSON_Print(root);
    cJSON_Delete(root);
    if (!text) {
        snprintf(error, error_size, "out of memory");
        return -1;
    }
    length = strlen(text);
    if (output_file_begin(&file, path, error, error_size) == 0) {
        FILE *stream = output_file_stream(&file);
        errno = 0;
        if (stream && fwrite(text, 1, length, stream) == length && fputc('\n', stream) != EOF) {
            rc = output_file_commit(&file, error, error_size);
        } else {
            const int e = errno; /* ENOSPC on a full disk */
            snprintf(error, error_size, "cannot write %s%s%s", path, e ? ": " : "",
                     e ? strerror(e) : "");
            output_file_abort(&file);
        }
    }
    cJSON_free(text);
    return rc;
}
