/* SPDX-License-Identifier: MIT */
/* layers.h - the layered diffusion: midground, background layer(s), near spread, foreground. */
#ifndef DDOF_LAYERS_H
#define DDOF_LAYERS_H

#include "adi/adi.h"
#include "passes/far_field.h"
#include "passes/highlights.h"
#include "planner/planner.h"
#include "passes/silhouettes.h"

/* A foreground element composited over the frame: the caller's (ddof_foreground) or the
 * near layer's split of the frame itself. */
typedef struct layers_element {
    const float *color;        /* NULL: no element; else 4 channels                           */
    size_t color_stride;
    const float *coc;
    size_t coc_stride;
    uint32_t coc_channels;
    int premultiplied;
    const float *carried_alpha; /* NULL: the output's alpha channel is composited by the
                                   element's coverage (alpha); else the element's part of the
                                   frame's alpha channel (w x h, stride carried_stride), blurred
                                   like its colour and composited as colour is: the near layer
                                   of a frame whose alpha is not 1 where it splits            */
    size_t carried_stride;
    pixel_box box;             /* where the element's alpha > 0                               */
    float max_coc;             /* its largest |CoC| there                                     */
} layers_element;

/* A validated layered request. */
typedef struct layers_request {
    adi_request base;          /* colour, CoC (possibly signed), out and the solver settings */
    const ddof_params *params; /* the layer settings                                         */
    layers_element fg;         /* the foreground element; fg.color NULL: none                 */
    pixel_box background_box;  /* where far CoC >= threshold borders an in-focus pixel        */
    pixel_box near_box;        /* where the near-field pixels are (CoC < 0)                  */
    int near_resident;         /* base's colour and CoC and fg are a device's near split      */
                               /* (ADI_ON_DEVICE), read by that device's layers' run only     */
    highlight_aperture aperture; /* the highlights' shape (zero: a disc); the aperture ratio  */
                               /* is base.pixel_aspect's part                                  */
    object_matte matte;        /* ranks 0: none (ddof_render_frame_with_matte)               */
} layers_request;

/* Everything a layered call reports (folded into ddof_stats by the caller). */
typedef struct layers_report {
    adi_report adi;            /* summed over every diffusion that ran */
    uint32_t effects;          /* DDOF_EFFECT_* bits                   */
    double seconds_background;
    double seconds_foreground;
    double seconds_highlights;
    double seconds_far_field;
    double seconds_silhouettes;
    far_field_report far;      /* what the far field found (in the layers' run)        */
    uint64_t silhouette_pixels; /* the mixed pixels the silhouettes' split changed      */
    highlight_set highlights;  /* what the run's find found (its figures; no items)     */
} layers_report;

/* The frame's diffusions counted, so that the caller's progress sees one rising fraction. */
typedef struct layer_stages {
    ddof_progress_fn progress; /* the caller's */
    void *user;
    uint32_t current, count;
} layer_stages;

layer_stages ddof_layer_stages(const layers_request *q, const frame_plan *plan);

/* The seam's run_layers on the CPU (the CPU table's entry, cpu/backend_cpu.c): the request's
 * layers as the device runs them (the near spread, the midground, the background levels, the
 * element's blur and composite where it carries one), each diffusion through the dispatch, on
 * the CPU or on the context's device one request at a time. out is written only after every
 * check has passed (the caller's job), and on error its contents are finite but unspecified. */
ddof_status ddof_run_layers_on_cpu(ddof_context *context, const adi_layers_request *request,
                                   adi_layers_report *report);

/* Where the foreground element's blur can reach: its box grown by its largest CoC's reach. */
pixel_box ddof_element_area(const layers_request *q);

/* The element's own highlights over its area `area` (in the area's coordinates), found in
 * its colour as its steps premultiply it (DDOF_SCRATCH_ELEMENT_HIGHLIGHTS, without a base),
 * brighter than `threshold`; aperture_sums: ddof_aperture_sums' table or NULL. */
ddof_status ddof_find_element_highlights(ddof_context *context, const layers_request *q,
                                         pixel_box area, float threshold,
                                         const double *aperture_sums, highlight_set *set);

/* The highlight pass as a run_layers request carries it: found in the run when `find`, with
 * q's aperture (its image's table: aperture_sums, or NULL). */
adi_highlights ddof_request_highlights(const layers_request *q, int find, int coc_signed,
                                       const double *aperture_sums);

/* Every layer and pass of the plan as the seam's request (layers_dispatch.c), on the backend
 * the planner chose (on_backend: the context's backend, else the CPU's table): the highlights
 * found in the run (`find_highlights`), taken out of q->base.color and drawn, the plan's
 * foreground element blurred and composited last (its own highlights found in it unless the
 * highlights are off, the part of the frame's alpha it may carry blurred with it);
 * aperture_sums: the aperture image's table, or NULL. */
ddof_status ddof_run_layers(ddof_context *context, const layers_request *q,
                            const frame_plan *plan, int on_backend, int find_highlights,
                            const double *aperture_sums, float max_near_coc,
                            layers_report *report);

#endif
