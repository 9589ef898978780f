/* SPDX-License-Identifier: MIT */
/* planner.c - simulate only what the scene calls for.
 *
 * One pass over the CoC field counts the discontinuities that make each effect necessary:
 *  - the background layer exists to blur a far background *behind* in-focus midground pixels,
 *    which insulate; it matters only where a far CoC of at least the threshold borders a pixel
 *    below the matte's ramp (an insulator). Without such an edge the single layer is already
 *    right. A near-field CoC (negative, when signed) is never background: a blurred near
 *    object is in front of what it borders, which is the near spread's or foreground's case.
 *  - the near-field spread exists to let a blurred near object spread over what lies behind it;
 *    it matters only where a near CoC of at least its threshold borders a pixel with less than
 *    half that CoC (a silhouette the single layer would keep sharp).
 * The decisions and their reasons go to ddof_stats.plan: every line of it is written through
 * ddof_plan_say, the passes' own (what they found) included. */
#include "planner.h"

#include "passes/far_field.h"
#include "passes/highlights.h"
#include "passes/silhouettes.h"

#include "runtime/parallel_rows.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

typedef struct analysis_job {
    const float *coc;
    size_t stride;
    uint32_t channels, width, height;
    float bg_threshold, bg_insulator, near_threshold, near_layer_threshold;
    coc_analysis *chunks; /* one per row chunk */
} analysis_job;

static float coc_abs(const analysis_job *job, uint32_t x, uint32_t y)
{
    return fabsf(job->coc[(size_t)y * job->stride + (size_t)x * job->channels]);
}

/* The smallest |CoC| among the 4-neighbours of (x, y). */
static float min_neighbour(const analysis_job *job, uint32_t x, uint32_t y)
{
    float m = INFINITY;
    if (x > 0)
        m = ddof_minf(m, coc_abs(job, x - 1, y));
    if (x + 1 < job->width)
        m = ddof_minf(m, coc_abs(job, x + 1, y));
    if (y > 0)
        m = ddof_minf(m, coc_abs(job, x, y - 1));
    if (y + 1 < job->height)
        m = ddof_minf(m, coc_abs(job, x, y + 1));
    return m;
}

static void analyse_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    const analysis_job *job = user;
    coc_analysis a = {.background_box = box_empty(), .near_box = box_empty()};
    for (uint32_t y = y0; y < y1; y++) {
        const float *row = job->coc + (size_t)y * job->stride;
        for (uint32_t x = 0; x < job->width; x++) {
            const float c = row[(size_t)x * job->channels];
            const float d = fabsf(c);
            a.max_coc = ddof_maxf(a.max_coc, d);
            if (c < 0.0f) {
                a.max_near_coc = ddof_maxf(a.max_near_coc, d);
                box_add(&a.near_box, x, y);
            }
            /* The neighbour look-up only where an edge is possible: most pixels skip it. */
            if (c >= job->bg_threshold && min_neighbour(job, x, y) < job->bg_insulator) {
                a.background_edges++;
                box_add(&a.background_box, x, y);
            }
            if (c < 0.0f && d >= ddof_minf(job->near_threshold, job->near_layer_threshold)) {
                const float m = min_neighbour(job, x, y);
                a.near_edges += d >= job->near_threshold && m < 0.5f * d;
                a.near_layer_edges += d >= job->near_layer_threshold && m < 0.5f * d;
            }
        }
    }
    job->chunks[chunk] = a;
}

void ddof_analyse_coc(ddof_context *context, const float *coc, size_t coc_stride,
                      uint32_t coc_channels, uint32_t width, uint32_t height,
                      const ddof_params *params, coc_analysis *analysis)
{
    enum { max_chunks = (DDOF_MAX_DIMENSION + DDOF_ROWS_PER_CHUNK - 1) / DDOF_ROWS_PER_CHUNK };
    static const coc_analysis none = {0};
    coc_analysis chunks[max_chunks];
    analysis_job job = {coc, coc_stride, coc_channels, width, height,
                        params->background_threshold_px, params->background_ramp_start_px,
                        params->near_spread_threshold_px, params->near_layer_threshold_px,
                        chunks};
    ddof_parallel_rows(context, height, analyse_rows, &job);
    *analysis = none;
    analysis->background_box = box_empty();
    analysis->near_box = box_empty();
    for (uint32_t c = 0; c < ddof_row_chunks(height); c++) {
        analysis->background_box = box_union(analysis->background_box, chunks[c].background_box);
        analysis->near_box = box_union(analysis->near_box, chunks[c].near_box);
        analysis->max_coc = ddof_maxf(analysis->max_coc, chunks[c].max_coc);
        analysis->max_near_coc = ddof_maxf(analysis->max_near_coc, chunks[c].max_near_coc);
        analysis->background_edges += chunks[c].background_edges;
        analysis->near_edges += chunks[c].near_edges;
        analysis->near_layer_edges += chunks[c].near_layer_edges;
    }
}

void ddof_plan_say(frame_plan *plan, const char *format, ...)
{
    if (plan->truncated)
        return;
    char line[DDOF_PLAN_TEXT_SIZE];
    va_list args;
    va_start(args, format);
    const int n = vsnprintf(line, sizeof line, format, args);
    va_end(args);
    /* A line that does not fit whole is left out, and the text says so when it is read. */
    if (n < 0 || plan->used + (size_t)n + 2 > sizeof plan->text) {
        plan->truncated = 1;
        return;
    }
    memcpy(plan->text + plan->used, line, (size_t)n);
    plan->used += (size_t)n;
    plan->text[plan->used++] = '\n';
    plan->text[plan->used] = '\0';
}

/* The planner's own lines, under a name that keeps them on one line of source each. */
#define say ddof_plan_say

/* What marks a plan whose lines did not all fit. */
static const char cut_mark[] = "(the plan goes on)\n";

void ddof_plan_copy_text(const frame_plan *plan, char *out, size_t size)
{
    if (!size)
        return;
    if (plan->used < size && !plan->truncated) {
        memcpy(out, plan->text, plan->used + 1);
        return;
    }
    /* Whole lines up to the room the mark leaves. */
    size_t keep = 0;
    for (size_t i = 0; i < plan->used && i + sizeof cut_mark <= size; i++)
        if (plan->text[i] == '\n')
            keep = i + 1;
    memcpy(out, plan->text, keep);
    if (keep + sizeof cut_mark <= size)
        memcpy(out + keep, cut_mark, sizeof cut_mark);
    else
        out[keep] = '\0';
}

static const char *forced(ddof_layer_mode mode)
{
    return mode == DDOF_LAYER_ON ? "forced on" : "forced off";
}

/* The near layer's decision (one image, signed CoC, no element). */
static void plan_near_layer(const coc_analysis *a, const ddof_params *p, uint32_t channels,
                            frame_plan *plan)
{
    if (p->near_layer == DDOF_LAYER_OFF) {
        say(plan, "near layer: %s", forced(p->near_layer));
    } else if (channels < 3) {
        say(plan, "near layer: off: %u colour channel%s (the layer needs RGB)", channels,
            channels == 1 ? "" : "s");
    } else if (p->near_layer == DDOF_LAYER_ON) {
        plan->near_layer = 1;
        say(plan, "near layer: %s", forced(p->near_layer));
    } else if (p->near_spread == DDOF_LAYER_ON) {
        say(plan, "near layer: off: the near spread is forced on");
    } else if (a->near_layer_edges > 0) {
        plan->near_layer = 1;
        say(plan, "near layer: on: %llu near pixels with CoC >= %.3g px at a silhouette",
            (unsigned long long)a->near_layer_edges, (double)p->near_layer_threshold_px);
    } else {
        say(plan, "near layer: off: no blurred near silhouette with CoC >= %.3g px (largest "
                  "near CoC %.3g px)",
            (double)p->near_layer_threshold_px, (double)a->max_near_coc);
    }
}

void ddof_plan_frame(const coc_analysis *a, const ddof_params *p, uint32_t color_channels,
                     int foreground_given, int foreground_visible, frame_plan *plan)
{
    const int has_foreground = foreground_given && foreground_visible;
    const char *no_foreground = foreground_given
                                    ? "foreground: off: the foreground element is fully transparent"
                                    : "foreground: off: no foreground element";
    memset(plan, 0, sizeof *plan);
    /* Below the in-focus threshold no pixel conducts (adi_request.in_focus_px), so the
     * diffusion would copy every line: the frame is a copy without solving any. */
    if ((a->max_coc <= 0.0f || a->max_coc < p->in_focus_threshold_px) && !has_foreground) {
        plan->copy_only = 1;
        say(plan, "midground: off: nothing is out of focus (largest CoC %.3g px, in-focus "
                  "threshold %.3g px), output = input",
            (double)a->max_coc, (double)p->in_focus_threshold_px);
        say(plan, "background: off: nothing is out of focus");
        say(plan, "near spread: off: nothing is out of focus");
        say(plan, "near layer: off: nothing is out of focus");
        say(plan, "%s", no_foreground);
        say(plan, "highlights: off: nothing is out of focus");
        say(plan, "far field: off: nothing is out of focus");
        say(plan, "silhouettes: off: nothing is out of focus");
        return;
    }
    say(plan, "midground: on: largest CoC %.3g px", (double)a->max_coc);

    if (p->background != DDOF_LAYER_AUTO) {
        plan->background = p->background == DDOF_LAYER_ON;
        say(plan, "background: %s", forced(p->background));
    } else if (a->background_edges > 0) {
        plan->background = 1;
        say(plan, "background: on: %llu pixels with far CoC >= %.3g px border in-focus pixels",
            (unsigned long long)a->background_edges, (double)p->background_threshold_px);
    } else {
        say(plan, "background: off: no far CoC >= %.3g px borders an in-focus pixel",
            (double)p->background_threshold_px);
    }

    if (has_foreground) {
        plan->foreground = 1;
        say(plan, "foreground: on: a foreground element was given");
        say(plan, "near spread: off: the foreground element covers the near field");
        say(plan, "near layer: off: the foreground element covers the near field");
    } else {
        if (!p->coc_signed) {
            say(plan, "near layer: off: the CoC is unsigned (near and far unknown)");
            say(plan, "%s", no_foreground);
        } else {
            plan_near_layer(a, p, color_channels, plan);
            if (plan->near_layer)
                say(plan, "foreground: on: the near layer");
            else
                say(plan, "%s", no_foreground);
        }
        if (!p->coc_signed) {
            say(plan, "near spread: off: the CoC is unsigned (near and far unknown)");
        } else if (plan->near_layer) {
            say(plan, "near spread: off: the near layer takes the near field");
        } else if (p->near_spread != DDOF_LAYER_AUTO) {
            plan->near_spread = p->near_spread == DDOF_LAYER_ON;
            say(plan, "near spread: %s", forced(p->near_spread));
        } else if (a->near_edges > 0) {
            plan->near_spread = 1;
            say(plan, "near spread: on: %llu near pixels with CoC >= %.3g px border pixels "
                      "with less than half their CoC",
                (unsigned long long)a->near_edges, (double)p->near_spread_threshold_px);
        } else {
            /* The near layer's line gave the largest near CoC, and the caller's copy of the
             * plan (ddof_stats.plan) has 512 bytes. */
            say(plan, "near spread: off: no blurred near silhouette");
        }
    }

    /* Whether any pixel is bright enough needs the colour: the pass itself finds out and
     * says so in the plan (frame_passes.c). */
    if (p->highlights == DDOF_LAYER_OFF)
        say(plan, "highlights: %s", forced(p->highlights));
    else if (a->max_coc < DDOF_HIGHLIGHT_MIN_COC_PX)
        say(plan, "highlights: off: the largest CoC is below %.3g px, where a disc and a blob "
                  "look the same", (double)DDOF_HIGHLIGHT_MIN_COC_PX);
    else
        plan->highlights = 1;

    /* Where the blur is smooth needs a distance map: the pass finds out and says
     * (frame_passes.c). */
    if (p->far_field == DDOF_LAYER_OFF)
        say(plan, "far field: %s", forced(p->far_field));
    else if (a->max_coc < DDOF_FAR_FIELD_MIN_COC_PX)
        say(plan, "far field: off: the largest CoC is below %.3g px",
            (double)DDOF_FAR_FIELD_MIN_COC_PX);
    else
        plan->far_field = 1;
    /* The far field's line says what became of them (frame_passes.c). */
    plan->blurred_edges =
        plan->far_field && p->blurred_edges != DDOF_LAYER_OFF && p->coc_signed;

    if (p->silhouettes == DDOF_LAYER_OFF)
        say(plan, "silhouettes: %s", forced(p->silhouettes));
    else if (!p->coc_signed)
        say(plan, "silhouettes: off: the CoC is unsigned (what lies behind what unknown)");
    else if (color_channels < 3)
        say(plan, "silhouettes: off: %u colour channel%s (the split needs RGB)", color_channels,
            color_channels == 1 ? "" : "s");
    else if (a->max_coc < DDOF_SILHOUETTE_MIN_COC_PX)
        say(plan, "silhouettes: off: the largest CoC is below %.3g px",
            (double)DDOF_SILHOUETTE_MIN_COC_PX);
    else
        plan->silhouettes = 1;
}

int ddof_plan_layers_device(frame_plan *plan, const layers_device_facts *facts)
{
    /* A CPU context had no choice to make: no line. */
    if (strcmp(facts->backend, "cpu") == 0)
        return facts->takes;
    if (facts->takes)
        ddof_plan_say(plan, "layers: on %s", facts->backend);
    else
        ddof_plan_say(plan, "layers: on cpu (the %s device does not take this request)",
                      facts->backend);
    return facts->takes;
}
