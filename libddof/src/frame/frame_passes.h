/* SPDX-License-Identifier: MIT */
/* frame_passes.h - the CPU passes around a frame's layers (frame_passes.c): each says in the
 * plan what it found, and adds its effect and time to the report. */
#ifndef DDOF_FRAME_PASSES_H
#define DDOF_FRAME_PASSES_H

#include "layers/layers.h"

/* Finds the frame's highlights (colour with 3 or 4 channels) into `set`, the colour with them
 * taken out into ddof_highlight_base_image. */
ddof_status ddof_pass_find_highlights(ddof_context *context, const layers_request *q,
                                      highlight_set *set, frame_plan *plan);

/* Draws what the highlight pass took out into the result, through `scratch` (width x height x
 * 3 floats), or NULL: through the colour's buffer, ddof_highlight_base_image (then the last
 * reader of that colour). */
void ddof_pass_draw_highlights(ddof_context *context, const layers_request *q,
                               const highlight_set *set, float *scratch, layers_report *report);

/* The far field's plan line and effect, from what the layers' run found (the far field is a
 * stage of that run, on the backend that runs it). */
void ddof_say_far_field(const layers_request *q, frame_plan *plan, layers_report *report);

/* The silhouettes' plan line and effect from the pixels the split changed. */
void ddof_say_silhouettes(const layers_request *q, frame_plan *plan, uint64_t pixels,
                          layers_report *report);

/* The mixed pixels of in-focus silhouettes split in the result (after the highlights' discs,
 * with an object matte); `pairs` from ddof_clean_silhouettes, `color` the colour before their
 * objects were taken out. */
ddof_status ddof_pass_silhouettes(ddof_context *context, const layers_request *q, int pairs,
                                  const float *color, size_t color_stride, frame_plan *plan,
                                  layers_report *report);

#endif
