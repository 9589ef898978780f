/* SPDX-License-Identifier: MIT */
/* frame_passes.h - the highlights found before a frame's layers, and the passes' plan lines
 * (frame_passes.c): each says what it found, and adds its effect to the report. */
#ifndef DDOF_FRAME_PASSES_H
#define DDOF_FRAME_PASSES_H

#include "layers/layers.h"

/* Finds the frame's highlights (colour with 3 or 4 channels) into `set`: the layers' run
 * takes them out of the colour and draws them. */
ddof_status ddof_pass_find_highlights(ddof_context *context, const layers_request *q,
                                      highlight_set *set, frame_plan *plan);

/* The far field's plan line and effect, from what the layers' run found (the far field is a
 * stage of that run, on the backend that runs it). */
void ddof_say_far_field(const layers_request *q, frame_plan *plan, layers_report *report);

/* The silhouettes' plan line and effect from the pixels the split changed. */
void ddof_say_silhouettes(const layers_request *q, frame_plan *plan, uint64_t pixels,
                          layers_report *report);

#endif
