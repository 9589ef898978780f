/* SPDX-License-Identifier: MIT */
/* frame_run.h - one frame's run (frame_run.c): what every rendering call hands over once its
 * checks have passed. */
#ifndef DDOF_FRAME_RUN_H
#define DDOF_FRAME_RUN_H

#include "layers/layers.h"

/* Plans the frame of a validated request, runs what the plan says (or the CoD4 preview) and
 * reports it in stats. known_max_coc: the largest |CoC| when the validation found it (a frame
 * below the in-focus threshold then needs no analysis), or negative. seconds_coc: what the CoC
 * stage took before. */
ddof_status ddof_run_frame(ddof_context *context, layers_request *q, int fg_given,
                           int fg_visible, float known_max_coc, ddof_stats *stats,
                           double t_start, double seconds_coc);

/* One diffusion of a validated request, unplanned (ddof_diffuse), or the CoD4 preview;
 * max_coc: the request's largest |CoC|. */
ddof_status ddof_run_one_diffusion(ddof_context *context, const adi_request *r,
                                   const ddof_params *p, float max_coc, ddof_stats *stats,
                                   double t_start, double seconds_coc);

#endif
