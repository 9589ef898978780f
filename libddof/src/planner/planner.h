/* SPDX-License-Identifier: MIT */
/* planner.h - decide from the CoC field which effects a frame needs, before any solve. */
#ifndef DDOF_PLANNER_H
#define DDOF_PLANNER_H

#include "runtime/internal.h"

/* What the CoC field contains, from one pass over it. */
typedef struct coc_analysis {
    float max_coc;            /* largest |CoC|                                             */
    float max_near_coc;       /* largest |CoC| of a negative (near-field) CoC              */
    uint64_t background_edges;/* far pixels, CoC >= threshold, next to |CoC| < ramp start  */
    uint64_t near_edges;      /* near pixels with |CoC| >= near threshold next to a pixel  */
                              /* with less than half their |CoC|                           */
    uint64_t near_layer_edges;/* the same with the near layer's threshold                  */
    pixel_box background_box; /* where the background edges are                            */
    pixel_box near_box;       /* where the near-field pixels are (CoC < 0)                  */
} coc_analysis;

#define DDOF_PLAN_TEXT_SIZE DDOF_PLAN_MAX_BYTES /* ddof_context_last_plan holds one whole */

typedef struct frame_plan {
    int copy_only;     /* nothing out of focus and no foreground: output = input       */
    int background;    /* run the background layer(s)                                  */
    int near_spread;   /* spread the near-field CoC before the midground diffusion     */
    int near_layer;    /* split the near field off as the foreground element           */
    int foreground;    /* blur the foreground element and composite it over            */
    int highlights;    /* look for highlights (the pass says what it found)            */
    int far_field;     /* gather the smooth blur (the pass says where)                  */
    int blurred_edges; /* and, where two blurred surfaces meet, in depth slices (likewise) */
    int silhouettes;   /* split mixed silhouette pixels (the pass says how many)      */
    /* The decisions and their reasons, one line each, the passes' lines (what they found)
     * appended as they run: written only through ddof_plan_say, read through
     * ddof_plan_copy_text. Larger than ddof_stats.plan, so that a plan that overflows the
     * caller's copy is cut there at a line, with a mark. */
    char text[DDOF_PLAN_TEXT_SIZE];
    size_t used;       /* bytes of text before its terminating 0                      */
    int truncated;     /* a line did not fit: it and every later one are left out      */
} frame_plan;

/* Appends one line (the format's text and a '\n') to the plan. */
void ddof_plan_say(frame_plan *plan, const char *format, ...) DDOF_PRINTF(2, 3);

/* The plan's text into out (size bytes, 0-terminated): all of it when it fits, else its whole
 * lines that fit, then the line "(the plan goes on)". */
void ddof_plan_copy_text(const frame_plan *plan, char *out, size_t size);

/* One parallel pass over the (validated) CoC field. */
void ddof_analyse_coc(ddof_context *context, const float *coc, size_t coc_stride,
                      uint32_t coc_channels, uint32_t width, uint32_t height,
                      const ddof_params *params, coc_analysis *analysis);

/* Decisions from the analysis, the parameters' AUTO/ON/OFF, the colour's channels and the
 * foreground element: whether one was given, and whether any of its alpha is above 0. */
void ddof_plan_frame(const coc_analysis *analysis, const ddof_params *params,
                     uint32_t color_channels, int foreground_given, int foreground_visible,
                     frame_plan *plan);

/* What decides where a planned frame's layers run. */
typedef struct layers_device_facts {
    const char *backend; /* the context's backend ("cpu", "egl")                           */
    int takes;           /* it runs whole layered frames of this request
                          * (ddof_backend_runs_layers); else the CPU's table runs them       */
} layers_device_facts;

/* Where a planned frame's layers run, every stage of them (the highlights, the far field, the
 * silhouettes, the element last, over every pass): on the context's backend wherever it takes
 * the request, else on the CPU's table. Says which and why in the plan where the context has
 * a device to choose (a CPU context's plan has no line). Returns whether on the backend. */
int ddof_plan_layers_device(frame_plan *plan, const layers_device_facts *facts);

#endif
