/* SPDX-License-Identifier: MIT */
/* frame_run.h - one frame's run (frame_run.c): what every rendering call hands over once its
 * checks have passed. */
#ifndef DDOF_FRAME_RUN_H
#define DDOF_FRAME_RUN_H

#include "layers/layers.h"

/* A validated frame, as every rendering call hands it to the runner. */
typedef struct frame_request {
    layers_request layers; /* its images and settings; the runner may split the near layer  */
    struct {
        int given;         /* the caller gave a foreground element (layers.fg)               */
        int visible;       /* ... and its alpha is above 0 somewhere                         */
    } element;
    float known_max_coc;   /* the largest |CoC| when the validation found it (a frame below
                            * the in-focus threshold then needs no analysis), or negative    */
    double t_start;        /* when the call began (ddof_seconds)                             */
    double seconds_coc;    /* what the CoC stage took before                                 */
} frame_request;

/* Plans the frame, runs what the plan says (or the CoD4 preview) and reports it in stats. */
ddof_status ddof_run_frame(ddof_context *context, frame_request *frame, ddof_stats *stats);

/* One diffusion of a validated request, unplanned (ddof_diffuse), on the context's backend
 * (told when the request is in focus: max_coc, its largest |CoC|), or the CoD4 preview. */
ddof_status ddof_run_one_diffusion(ddof_context *context, const adi_request *r,
                                   const ddof_params *p, float max_coc, ddof_stats *stats,
                                   double t_start, double seconds_coc);

#endif
