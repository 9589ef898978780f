/* SPDX-License-Identifier: MIT */
/* frame_passes.h - the passes' plan lines (frame_passes.c): each says what the layers' run
 * found, and adds its effect to the report. */
#ifndef DDOF_FRAME_PASSES_H
#define DDOF_FRAME_PASSES_H

#include "layers/layers.h"

/* Whether the planned highlight pass can run on q's colour (3 or 4 channels); else says why
 * not in the plan. */
int ddof_pass_highlights_can_run(const layers_request *q, frame_plan *plan);

/* The highlights' plan line, from what the layers' run found (`set`'s figures). */
void ddof_say_highlights(const layers_request *q, frame_plan *plan, const highlight_set *set);

/* The far field's plan line and effect, from what the layers' run found (the far field is a
 * stage of that run, on the backend that runs it). */
void ddof_say_far_field(const layers_request *q, frame_plan *plan, layers_report *report);

/* The silhouettes' plan line and effect from the pixels the split changed. */
void ddof_say_silhouettes(const layers_request *q, frame_plan *plan, uint64_t pixels,
                          layers_report *report);

#endif
