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

/* The far field over the layers' result, from the colour the layers diffused. */
ddof_status ddof_pass_far_field(ddof_context *context, const layers_request *q,
                                const float *color, size_t color_stride, frame_plan *plan,
                                layers_report *report);

/* The mixed pixels of in-focus silhouettes split in the result; `pairs` from
 * ddof_clean_silhouettes, `color` the colour before their objects were taken out. */
ddof_status ddof_pass_silhouettes(ddof_context *context, const layers_request *q, int pairs,
                                  const float *color, size_t color_stride, frame_plan *plan,
                                  layers_report *report);

#endif
