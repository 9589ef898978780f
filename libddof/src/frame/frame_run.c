/* SPDX-License-Identifier: MIT */
/* frame_run.c - one frame's run, for every call that renders one (ddof_render_frame,
 * ddof_depth_of_field, ddof_diffuse_layers, ddof_diffuse): from a validated request with its
 * CoC, the plan (planner.c), the near layer's split, the highlights found, the layers and
 * their passes as one run_layers request on the backend the planner chose (the CPU's table
 * or the context's device), the passes' plan lines (frame_passes.c), the element's composite
 * where the request could not take it, and the stats. */
#include "frame_run.h"
#include "ddof_output_struct.h"

#include "backends/backend.h"
#include "frame_passes.h"
#include "passes/near_layer.h"
#include "passes/preview_cod4.h"
#include "passes/silhouettes.h"

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

/* The plan into the stats, cut to their room, and whole into the context
 * (ddof_context_last_plan). */
static void keep_plan(ddof_context *context, const frame_plan *plan, ddof_stats *full)
{
    ddof_plan_copy_text(plan, full->plan, sizeof full->plan);
    ddof_plan_copy_text(plan, context->last_plan, sizeof context->last_plan);
}

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
    frame_plan plan = {0};
    ddof_plan_say(&plan, "preview: the CoD4 post-process (GPU Gems 3 ch. 28)");
    keep_plan(context, &plan, &full);
    /* The preview's plan is its one line, unterminated. */
    full.plan[strcspn(full.plan, "\n")] = '\0';
    context->last_plan[strcspn(context->last_plan, "\n")] = '\0';
    write_stats(stats, &full);
    return DDOF_OK;
}

ddof_status ddof_run_one_diffusion(ddof_context *context, const adi_request *r,
                                   const ddof_params *p, float max_coc, ddof_stats *stats,
                                   double t_start, double seconds_coc)
{
    if (p->method == DDOF_METHOD_COD4_PREVIEW)
        return run_preview(context, r, (int)p->coc_signed, stats, t_start, seconds_coc);
    /* The backend's frame to run: the CPU copies one in focus, a device runs it as any. */
    adi_request one = *r;
    one.all_in_focus = (uint32_t)all_in_focus(max_coc, p);
    one.known_max_coc = max_coc;
    adi_report report;
    ddof_status status = ddof_run_adi(context, &one, &report);
    if (status != DDOF_OK)
        return status;
    ddof_stats full = stats_from(context, &report, r, t_start, seconds_coc);
    write_stats(stats, &full);
    return DDOF_OK;
}

/* ---- where the layers run ---------------------------------------------------------------- */

/* Where the layers run: what the planner needs to know, found here, and its decision. */
static int place_layers(ddof_context *context, const layers_request *q, frame_plan *plan)
{
    const layers_device_facts facts = {
        .backend = ddof_backend_name(context->backend.kind),
        .takes = ddof_backend_runs_layers(context, &q->base),
    };
    return ddof_plan_layers_device(plan, &facts);
}

/* The planned frame's layers and every pass, in one run (the element last in it), on the
 * table the planner places them on; the passes' plan lines from what the run found. */
static ddof_status run_planned(ddof_context *context, const layers_request *q,
                               frame_plan *plan, float max_near_coc, layers_report *report)
{
    memset(report, 0, sizeof *report);
    /* The layers' run finds the highlights, the frame's and the element's own, takes them out
     * of the colours and draws them into the results; an aperture image's table is built once
     * here for it. */
    const int find = plan->highlights && ddof_pass_highlights_can_run(q, plan);
    const int element_lights = plan->foreground && q->params->highlights != DDOF_LAYER_OFF;
    const double *sums = NULL;
    if ((find || element_lights) && q->aperture.image &&
        !(sums = ddof_aperture_sums(context, &q->aperture)))
        return DDOF_ERROR_OUT_OF_MEMORY;
    const int on_backend = place_layers(context, q, plan);
    const ddof_status status =
        ddof_run_layers(context, q, plan, on_backend, find, sums, max_near_coc, report);
    if (status != DDOF_OK)
        return status;
    if (find)
        ddof_say_highlights(q, plan, &report->highlights);
    if (plan->far_field)
        ddof_say_far_field(q, plan, report);
    if (plan->silhouettes)
        ddof_say_silhouettes(q, plan, report->silhouette_pixels, report);
    return DDOF_OK;
}

/* ---- the frame ---------------------------------------------------------------------------- */

/* The near layer: the frame's near field becomes the foreground element and the rest, with
 * what it hid filled in, the image the other layers blur (near_layer.h), split by the backend
 * that runs the layers (on a device the images stay there); the background layer's area grows
 * by the edges the fill made. `transfers`: the split's device memory and transfers. */
static ddof_status split_near_layer(ddof_context *context, layers_request *q,
                                    coc_analysis *analysis, frame_plan *plan,
                                    adi_report *transfers)
{
    adi_request *r = &q->base;
    const ddof_params *p = q->params;
    const adi_near_request request = {.base = *r,
                                      .threshold = p->near_layer_threshold_px,
                                      .background_threshold_px = p->background_threshold_px,
                                      .background_ramp_start_px = p->background_ramp_start_px};
    adi_near_split split;
    ddof_status status = ddof_backend_split_near(context, &request, &split, transfers);
    if (status != DDOF_OK)
        return status;
    q->fg.color = split.element;
    q->fg.color_stride = (size_t)r->width * 4;
    q->fg.coc = split.element_coc;
    q->fg.coc_stride = r->width;
    q->fg.coc_channels = 1;
    q->fg.premultiplied = 1;
    q->fg.carried_alpha = split.carried_alpha;
    q->fg.carried_stride = r->width;
    q->fg.box = split.box;
    q->fg.max_coc = split.max_coc;
    q->near_resident = split.rest == ADI_ON_DEVICE;
    plan->foreground = split.element_pixels > 0;
    r->color = split.rest;
    r->color_stride = (size_t)r->width * r->channels;
    r->coc = split.rest_coc;
    r->coc_stride = r->width;
    r->coc_channels = 1;
    analysis->background_box = box_union(analysis->background_box, split.rest_background_box);
    analysis->near_box = split.rest_near_box;
    return DDOF_OK;
}

ddof_status ddof_run_frame(ddof_context *context, frame_request *frame, ddof_stats *stats)
{
    layers_request *q = &frame->layers;
    const adi_request *r = &q->base;
    const int fg_given = frame->element.given;
    int fg_visible = frame->element.visible;
    const float known_max_coc = frame->known_max_coc;
    const double t_start = frame->t_start, seconds_coc = frame->seconds_coc;
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
    adi_report split_transfers = {0};
    if (plan.near_layer && !plan.copy_only) {
        const double t0 = ddof_seconds();
        ddof_status status = split_near_layer(context, q, &analysis, &plan, &split_transfers);
        if (status != DDOF_OK)
            return status;
        fg_visible = plan.foreground;
        seconds_near_layer = ddof_seconds() - t0;
    }

    layers_report report = {.adi = {.threads = context->thread_count,
                                    .lines_skipped = (uint64_t)r->width + r->height}};
    if (plan.copy_only) {
        /* Nothing out of focus: the output is the input, on every backend. */
        ddof_adi_copy_in_focus(context, r, &report.adi, analysis.max_coc);
    } else {
        q->fg.color = fg_visible ? q->fg.color : NULL;
        q->background_box = analysis.background_box;
        q->near_box = analysis.near_box;
        ddof_status status = run_planned(context, q, &plan, analysis.max_near_coc, &report);
        if (status != DDOF_OK)
            return status;
    }
    /* The split's transfers are the frame's too; its device memory is freed of nothing before
     * the layers run, so the frame's peak is the larger call's. */
    report.adi.uploads += split_transfers.uploads;
    report.adi.readbacks += split_transfers.readbacks;
    if (split_transfers.device_bytes > report.adi.device_bytes)
        report.adi.device_bytes = split_transfers.device_bytes;
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
    keep_plan(context, &plan, &full);
    write_stats(stats, &full);
    return DDOF_OK;
}
