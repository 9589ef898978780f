/* SPDX-License-Identifier: MIT */
/* diffuse.c - the public diffusion calls (ddof_diffuse, ddof_diffuse_layers) and the running
 * they share with the frame call: plan the frame, run the plan, report it. */
#include "call_checks.h"
#include "ddof_output_struct.h"

#include "backend.h"
#include "layers.h"
#include "near_layer.h"
#include "parallel_rows.h"
#include "planner.h"
#include "preview_cod4.h"

#include <stddef.h>
#include <stdio.h>
#include <string.h>

/* Whether a frame whose largest |CoC| is max_coc has nothing out of focus. */
static int all_in_focus(float max_coc, const ddof_params *p)
{
    return max_coc <= 0.0f || max_coc < p->in_focus_threshold_px;
}

/* The fields the caller's struct has room for (ddof.h: output structs); its size was checked
 * before the call ran (ddof_check_stats). */
static void write_stats(ddof_stats *stats, const ddof_stats *full)
{
    if (stats)
        ddof_write_output_struct(stats, full, sizeof *full);
}

/* Working memory the context holds for its calls (grown, reused). */
static uint64_t host_bytes(const ddof_context *context)
{
    uint64_t sum = 0;
    for (int i = 0; i < DDOF_SCRATCH_COUNT; i++)
        sum += context->scratch[i].size;
    return sum;
}

static ddof_stats stats_from(const ddof_context *context, const adi_report *report,
                             const adi_request *r, double t_start, double seconds_coc)
{
    const ddof_solver solver = r->solver;
    const ddof_kernel kernel = r->disc ? r->disc->id : DDOF_KERNEL_HEAT;
    return (ddof_stats){
        .struct_size = sizeof(ddof_stats),
        .solver = (uint32_t)solver,
        .threads = report->threads,
        .substeps = report->substeps_run,
        .lines_solved = report->lines_solved,
        .lines_skipped = report->lines_skipped,
        .max_coc_px = report->max_coc,
        .copied_only = report->substeps_run == 0,
        .seconds_total = ddof_seconds() - t_start,
        .seconds_coc = seconds_coc,
        .seconds_rows = report->seconds_rows,
        .seconds_columns = report->seconds_columns,
        .effects = report->substeps_run ? DDOF_EFFECT_MIDGROUND : 0u,
        .backend = (uint32_t)context->backend.kind,
        .method = (uint32_t)DDOF_METHOD_DIFFUSION,
        .kernel = (uint32_t)kernel,
        .device_bytes = report->device_bytes,
        .host_bytes = host_bytes(context),
        .device_uploads = report->uploads,
        .device_readbacks = report->readbacks,
    };
}

/* ---- running ------------------------------------------------------------------------------ */

/* The CoD4 preview instead of the diffusion. */
static ddof_status run_preview(ddof_context *context, const adi_request *r, int coc_signed,
                               ddof_stats *stats, double t_start, double seconds_coc)
{
    adi_report report = {.threads = context->thread_count};
    ddof_status status = ddof_cod4_preview(context, r, coc_signed, &report);
    if (status != DDOF_OK)
        return status;
    ddof_stats full = stats_from(context, &report, r, t_start, seconds_coc);
    full.backend = (uint32_t)DDOF_BACKEND_CPU;
    full.method = (uint32_t)DDOF_METHOD_COD4_PREVIEW;
    full.substeps = 0;
    full.copied_only = 0;
    full.effects = 0;
    snprintf(full.plan, sizeof full.plan, "preview: the CoD4 post-process (GPU Gems 3 ch. 28)");
    write_stats(stats, &full);
    return DDOF_OK;
}

/* Nothing out of focus: the output is the input, on every backend (no device is involved). */
static void copy_frame(ddof_context *context, const adi_request *r, adi_report *report,
                       float max_coc)
{
    ddof_parallel_copy(context, r->color, r->color_stride, r->out, r->out_stride,
                       (size_t)r->width * r->channels, r->height);
    /* Every line skipped, counted as the run would have: a disc kernel per component. */
    const uint64_t passes = r->disc ? r->disc->components : 1u;
    *report = (adi_report){.threads = context->thread_count,
                           .lines_skipped = ((uint64_t)r->width + r->height) * passes,
                           .max_coc = max_coc};
    if (r->progress)
        r->progress(r->progress_user, 1.0f);
}

static ddof_status run_single(ddof_context *context, const adi_request *r, const ddof_params *p,
                              float max_coc, ddof_stats *stats, double t_start,
                              double seconds_coc)
{
    adi_report report;
    /* On a device the call stays there (it is the backend's frame to run, and it reports
     * what it ran); its CoC is cut to the threshold by ddof_run_adi. */
    if (all_in_focus(max_coc, p) && !context->backend.device) {
        copy_frame(context, r, &report, max_coc);
    } else {
        ddof_status status = ddof_run_adi(context, r, &report);
        if (status != DDOF_OK)
            return status;
    }
    ddof_stats full = stats_from(context, &report, r, t_start, seconds_coc);
    write_stats(stats, &full);
    return DDOF_OK;
}

/* The near layer: the frame's near field becomes the foreground element and the rest, with
 * what it hid filled in, the image the other layers blur (near_layer.h); the background
 * layer's area grows by the edges the fill made. */
static ddof_status split_near_layer(ddof_context *context, layers_request *q,
                                    coc_analysis *analysis, frame_plan *plan)
{
    adi_request *r = &q->base;
    near_split split;
    ddof_status status =
        ddof_split_near(context, r, q->params->near_layer_threshold_px, &split);
    if (status != DDOF_OK)
        return status;
    q->fg_color = split.element;
    q->fg_color_stride = (size_t)r->width * 4;
    q->fg_coc = split.element_coc;
    q->fg_coc_stride = r->width;
    q->fg_coc_channels = 1;
    q->fg_premultiplied = 1;
    q->fg_carried_alpha = split.carried_alpha;
    q->fg_carried_stride = r->width;
    q->fg_box = split.box;
    q->fg_max_coc = split.max_coc;
    plan->foreground = split.element_pixels > 0;
    r->color = split.rest;
    r->color_stride = (size_t)r->width * r->channels;
    r->coc = split.rest_coc;
    r->coc_stride = r->width;
    r->coc_channels = 1;
    coc_analysis rest;
    ddof_analyse_coc(context, r->coc, r->coc_stride, 1, r->width, r->height, q->params, &rest);
    analysis->background_box = box_union(analysis->background_box, rest.background_box);
    analysis->near_box = rest.near_box;
    return DDOF_OK;
}

/* Plans the frame, runs what the plan says, reports it. */
ddof_status ddof_run_layered(ddof_context *context, layers_request *q, int fg_given,
                             int fg_visible, float known_max_coc, ddof_stats *stats,
                             double t_start, double seconds_coc)
{
    const adi_request *r = &q->base;
    if (q->params->method == DDOF_METHOD_COD4_PREVIEW)
        return run_preview(context, r, (int)q->params->coc_signed, stats, t_start, seconds_coc);
    const double t_plan = ddof_seconds();
    coc_analysis analysis = {.max_coc = known_max_coc};
    if (known_max_coc < 0.0f || !all_in_focus(known_max_coc, q->params) ||
        (fg_given && fg_visible))
        ddof_analyse_coc(context, r->coc, r->coc_stride, r->coc_channels, r->width, r->height,
                         q->params, &analysis);
    frame_plan plan;
    ddof_plan_frame(&analysis, q->params, r->channels, fg_given, fg_visible, &plan);
    const double seconds_plan = ddof_seconds() - t_plan;
    double seconds_near_layer = 0.0;
    if (plan.near_layer && !plan.copy_only) {
        const double t0 = ddof_seconds();
        ddof_status status = split_near_layer(context, q, &analysis, &plan);
        if (status != DDOF_OK)
            return status;
        fg_visible = plan.foreground;
        seconds_near_layer = ddof_seconds() - t0;
    }

    layers_report report = {.adi = {.threads = context->thread_count,
                                    .lines_skipped = (uint64_t)r->width + r->height}};
    if (plan.copy_only) {
        copy_frame(context, r, &report.adi, analysis.max_coc);
    } else {
        q->fg_color = fg_visible ? q->fg_color : NULL;
        q->background_box = analysis.background_box;
        q->near_box = analysis.near_box;
        ddof_status status = ddof_run_layers(context, q, &plan, analysis.max_near_coc, &report);
        if (status != DDOF_OK)
            return status;
    }
    ddof_stats full = stats_from(context, &report.adi, r, t_start, seconds_coc);
    full.max_coc_px = analysis.max_coc;
    full.copied_only = plan.copy_only;
    full.effects = report.effects;
    full.seconds_plan = seconds_plan;
    full.seconds_background = report.seconds_background;
    full.seconds_foreground = report.seconds_foreground;
    full.seconds_highlights = report.seconds_highlights;
    full.seconds_near_layer = seconds_near_layer;
    full.seconds_far_field = report.seconds_far_field;
    full.seconds_silhouettes = report.seconds_silhouettes;
    if (plan.near_layer)
        full.effects |= DDOF_EFFECT_NEAR_LAYER;
    memcpy(full.plan, plan.text, sizeof full.plan);
    const char *lines[3] = {report.highlights_line, report.far_field_line,
                            report.silhouettes_line};
    for (int i = 0; i < 3; i++)
        if (lines[i][0]) {
            const size_t used = strlen(full.plan);
            snprintf(full.plan + used, sizeof full.plan - used, "%s\n", lines[i]);
        }
    write_stats(stats, &full);
    return DDOF_OK;
}

/* The checks every diffusion call shares: params, colour, CoC, output. */
static ddof_status prepare(ddof_context *context, const ddof_params *caller_params,
                           const ddof_image_in *color, const ddof_image_in *coc,
                           const ddof_image *out, const ddof_stats *stats, ddof_params *params,
                           adi_request *r, float *max_coc)
{
    size_t coc_stride = 0;
    ddof_status status = ddof_read_params(context, caller_params, params);
    if (status == DDOF_OK)
        status = ddof_check_stats(context, stats);
    if (status == DDOF_OK)
        status = ddof_check_near_spread(context, params);
    if (status == DDOF_OK)
        status = ddof_check_call_images(context, color, coc, "coc", out, r, &coc_stride);
    if (status == DDOF_OK)
        status = ddof_check_coc_values(context, coc, coc_stride, (int)params->coc_signed,
                                       max_coc);
    if (status != DDOF_OK)
        return status;
    r->coc = coc->pixels;
    r->coc_stride = coc_stride;
    r->coc_channels = coc->channels;
    ddof_fill_request_params(r, params);
    return DDOF_OK;
}

static ddof_status diffuse(ddof_context *context, const ddof_params *params,
                           const ddof_image_in *color, const ddof_image_in *coc,
                           const ddof_image *out, ddof_stats *stats)
{
    const double t_start = ddof_seconds();
    ddof_clear_error(context);
    ddof_params p;
    adi_request r = {0};
    float max_coc = 0.0f;
    ddof_status status = prepare(context, params, color, coc, out, stats, &p, &r, &max_coc);
    if (status != DDOF_OK)
        return status;
    if (p.method == DDOF_METHOD_COD4_PREVIEW)
        return run_preview(context, &r, (int)p.coc_signed, stats, t_start,
                           ddof_seconds() - t_start);
    return run_single(context, &r, &p, max_coc, stats, t_start, ddof_seconds() - t_start);
}

ddof_status ddof_diffuse(ddof_context *context, const ddof_params *params,
                         const ddof_image_in *color, const ddof_image_in *coc,
                         const ddof_image *out, ddof_stats *stats)
{
    DDOF_EXCLUSIVE_CALL(context, diffuse(context, params, color, coc, out, stats));
}

static ddof_status diffuse_layers(ddof_context *context, const ddof_params *params,
                                  const ddof_image_in *color, const ddof_image_in *coc,
                                  const ddof_foreground *foreground, const ddof_image *out,
                                  ddof_stats *stats)
{
    const double t_start = ddof_seconds();
    ddof_clear_error(context);
    ddof_params p;
    layers_request q = {.params = &p};
    int fg_visible = 0;
    float max_coc = 0.0f;
    ddof_status status = prepare(context, params, color, coc, out, stats, &p, &q.base, &max_coc);
    if (status == DDOF_OK && foreground && p.method == DDOF_METHOD_COD4_PREVIEW)
        status = ddof_fail(context, DDOF_ERROR_UNSUPPORTED,
                           "the CoD4 preview takes no foreground element");
    if (status == DDOF_OK && foreground)
        status = ddof_check_element_near(context, &p);
    if (status == DDOF_OK && foreground)
        status = ddof_read_foreground(context, foreground, &q, &fg_visible);
    if (status != DDOF_OK)
        return status;
    return ddof_run_layered(context, &q, foreground != NULL, fg_visible, max_coc, stats,
                            t_start, ddof_seconds() - t_start);
}

ddof_status ddof_diffuse_layers(ddof_context *context, const ddof_params *params,
                                const ddof_image_in *color, const ddof_image_in *coc,
                                const ddof_foreground *foreground, const ddof_image *out,
                                ddof_stats *stats)
{
    DDOF_EXCLUSIVE_CALL(context,
                        diffuse_layers(context, params, color, coc, foreground, out, stats));
}
