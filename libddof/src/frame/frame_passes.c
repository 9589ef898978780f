/* SPDX-License-Identifier: MIT */
/* frame_passes.c - the passes' plan lines: the highlights, the far field and the silhouettes'
 * split, from what the layers' run found (each is a stage of that run). */
#include "frame_passes.h"

#include "passes/silhouettes.h"

#include <stdio.h>

int ddof_pass_highlights_can_run(const layers_request *q, frame_plan *plan)
{
    const uint32_t channels = q->base.channels;
    if (channels >= 3)
        return 1;
    ddof_plan_say(plan, "highlights: off: %u colour channel%s (the pass needs RGB)", channels,
                  channels == 1 ? "" : "s");
    return 0;
}

void ddof_say_highlights(const layers_request *q, frame_plan *plan, const highlight_set *set)
{
    const adi_request *r = &q->base;
    char shape[48] = "discs";
    if (q->aperture.image)
        snprintf(shape, sizeof shape, "the %ux%u aperture image", q->aperture.image_width,
                 q->aperture.image_height);
    else if (q->aperture.blades >= 3)
        snprintf(shape, sizeof shape, "%u-bladed polygons", q->aperture.blades);
    char hidden[48] = "";
    if (set->hidden)
        snprintf(hidden, sizeof hidden, " (+%u hidden by sharp occluders)", set->hidden);
    if (set->count)
        ddof_plan_say(plan,
                      "highlights: on: %u pixels brighter than %.3g with CoC >= %.3g px%s "
                      "drawn as %s (%.2f operations per pixel)",
                      set->count - set->hidden, (double)set->threshold,
                      (double)DDOF_HIGHLIGHT_MIN_COC_PX, hidden, shape,
                      (double)set->cost / ((double)r->width * r->height));
    else if (set->over_budget)
        ddof_plan_say(plan,
                      "highlights: off: the brightest pixels (above %.3g, CoC >= %.3g px) "
                      "alone would cost over %.3g operations per frame pixel",
                      (double)set->threshold, (double)DDOF_HIGHLIGHT_MIN_COC_PX,
                      (double)DDOF_HIGHLIGHT_BUDGET);
    else
        ddof_plan_say(plan, "highlights: off: no pixel brighter than %.3g with CoC >= %.3g px",
                      (double)q->params->highlight_threshold, (double)DDOF_HIGHLIGHT_MIN_COC_PX);
}

/* The far field's plan line, from what the layers' run found (it runs there, over their
 * result, from the colour they diffused: without the highlights). */
void ddof_say_far_field(const layers_request *q, frame_plan *plan, layers_report *report)
{
    const far_field_report *far = &report->far;
    const double pixels = (double)q->base.width * q->base.height;
    /* Where two blurred surfaces meet (ddof_params.blurred_edges), in the same line: the plan
     * a caller gets is short. */
    char edges[80];
    if (far->slices)
        snprintf(edges, sizeof edges, "; blurred edges: %.1f%%, %u depth slices",
                 100.0 * (double)far->layered_pixels / pixels, far->slices);
    else
        snprintf(edges, sizeof edges, "; blurred edges: %s",
                 plan->blurred_edges                            ? "none"
                 : q->params->blurred_edges == DDOF_LAYER_OFF ? "forced off"
                                                                : "off (unsigned CoC)");
    if (far->pixels) {
        report->effects |= DDOF_EFFECT_FAR_FIELD;
        ddof_plan_say(plan, "far field: on: %.1f%% of pixels, %u level%s%s",
                      100.0 * (double)far->pixels / pixels, far->levels,
                      far->levels == 1 ? "" : "s", edges);
    } else {
        ddof_plan_say(plan, "far field: off: every blurred pixel is near a depth edge");
    }
}

/* The silhouettes' plan line and effect from the pixels the split changed. */
void ddof_say_silhouettes(const layers_request *q, frame_plan *plan, uint64_t pixels,
                          layers_report *report)
{
    report->silhouette_pixels = pixels;
    if (pixels) {
        report->effects |= DDOF_EFFECT_SILHOUETTES;
        ddof_plan_say(plan, "silhouettes: on: %llu mixed pixels split%s",
                      (unsigned long long)pixels, q->matte.ranks ? " by the object matte" : "");
    } else {
        ddof_plan_say(plan,
                      "silhouettes: off: no in-focus pixel meets a CoC >= %.3g px behind it",
                      (double)DDOF_SILHOUETTE_MIN_COC_PX);
    }
}
