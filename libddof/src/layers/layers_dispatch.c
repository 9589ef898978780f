/* SPDX-License-Identifier: MIT */
/* layers_dispatch.c - a planned frame's layers handed whole to a backend as the seam's
 * run_layers request: the plan's switches, the areas the layers' steps use and the passes'
 * inputs (the highlights' threshold and aperture, the object matte). */
#include "layers.h"

#include "backends/backend.h"
#include "disc/disc_kernel.h"

#include <math.h>

static adi_box seam_box(pixel_box b)
{
    return (adi_box){b.x0, b.y0, b.x1, b.y1};
}

/* The plan and the areas layers.c uses, handed to a backend's run_layers, which runs the same
 * steps: the CPU's (layers.c) or the device's (gl/gl_layers.c: one upload, one read-back).
 * The background's area depends on the midground's largest CoC, so the backend grows its
 * edges itself. */
ddof_status ddof_run_layers(ddof_context *context, const layers_request *q,
                            const frame_plan *plan, int on_backend, int find_highlights,
                            const double *aperture_sums, float max_near_coc,
                            layers_report *report)
{
    const adi_request *r = &q->base;
    const ddof_params *p = q->params;
    adi_layers_request d = {.base = *r, .near_spread = (uint32_t)plan->near_spread,
                            .near_slope = DDOF_NEAR_SPREAD_SLOPE,
                            .near_resident = (uint32_t)q->near_resident};
    if (plan->near_spread) {
        const uint32_t reach = ddof_near_spread_reach_px(max_near_coc);
        d.near_dilate = seam_box(box_grow(q->near_box, reach, r->width, r->height));
    }
    if (plan->background) {
        d.background_levels = p->background_levels;
        d.background_threshold_px = p->background_threshold_px;
        d.background_ramp_start_px = p->background_ramp_start_px;
        const pixel_box edges = q->background_box;
        d.background_edges = seam_box(box_is_empty(edges) ? (pixel_box){0, 0, r->width, r->height}
                                                          : edges);
    }
    const int element = plan->foreground && q->fg.color;
    if (element) {
        d.fg_color = q->fg.color;
        d.fg_color_stride = q->fg.color_stride;
        d.fg_coc = q->fg.coc;
        d.fg_coc_stride = q->fg.coc_stride;
        d.fg_coc_channels = q->fg.coc_channels;
        d.fg_premultiplied = (uint32_t)q->fg.premultiplied;
        d.fg_max_coc = q->fg.max_coc;
        d.fg_carried_alpha = q->fg.carried_alpha;
        d.fg_carried_stride = q->fg.carried_stride;
        d.fg_area = seam_box(ddof_element_area(q));
        d.fg_gather = p->far_field != DDOF_LAYER_OFF;
        d.fg_highlights = ddof_request_highlights(q, p->highlights != DDOF_LAYER_OFF, 0,
                                                  aperture_sums);
    }
    d.far_field = (uint32_t)plan->far_field;
    d.far_slices = (uint32_t)plan->blurred_edges;
    d.highlights = ddof_request_highlights(q, find_highlights, (int)p->coc_signed,
                                           aperture_sums);
    if (plan->silhouettes && r->channels >= 3) {
        d.silhouettes = 1;
        d.matte = q->matte.ranks ? q->matte.pairs : NULL;
        d.matte_stride = q->matte.stride;
        d.matte_ranks = q->matte.ranks;
    }
    adi_layers_report a = {0};
    const ddof_status status = ddof_backend_run_layers(context, on_backend, &d, &a);
    if (status != DDOF_OK)
        return status;
    report->adi = a.adi;
    report->seconds_background = a.seconds_background;
    report->seconds_foreground = a.seconds_foreground;
    report->seconds_far_field = a.seconds_far_field;
    report->far = (far_field_report){.pixels = a.far_pixels,
                                     .layered_pixels = a.far_layered_pixels,
                                     .slices = a.far_slices,
                                     .levels = a.far_levels};
    report->seconds_silhouettes = a.seconds_silhouettes;
    report->seconds_highlights += a.seconds_highlights;
    report->silhouette_pixels = a.silhouette_pixels;
    report->highlights = (highlight_set){.count = a.highlights_count,
                                         .threshold = a.highlights_threshold,
                                         .cost = a.highlights_cost,
                                         .over_budget = (int)a.highlights_over_budget,
                                         .hidden = a.highlights_hidden};
    report->effects |= DDOF_EFFECT_MIDGROUND |
                      (plan->near_spread ? (uint32_t)DDOF_EFFECT_NEAR_SPREAD : 0u) |
                      (plan->background ? (uint32_t)DDOF_EFFECT_BACKGROUND : 0u) |
                      (element ? (uint32_t)DDOF_EFFECT_FOREGROUND : 0u) |
                      a.element_effects |
                      (a.highlights_count ? (uint32_t)DDOF_EFFECT_HIGHLIGHTS : 0u);
    return DDOF_OK;
}
