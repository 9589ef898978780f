/* SPDX-License-Identifier: MIT */
/* far_layers.h - the far field's gather where two blurred surfaces meet (docs/design.md,
 * section 1, "The far field"): the frame cut into depth slices at its edges between blurred
 * surfaces, each slice gathered with the lens's shape as premultiplied colour and coverage, and
 * the slices composited nearest first, each covering the farther ones by its coverage. */
#ifndef DDOF_FAR_LAYERS_H
#define DDOF_FAR_LAYERS_H

#include "ddof_backend_seam.h"
#include "ddof_far_rules.h"
#include "runtime/internal.h"

typedef struct far_layers_report {
    uint64_t pixels; /* pixels that took the slices' composite */
    uint32_t slices; /* the slices (0: no edge between two blurred surfaces) */
} far_layers_report;

/* r: the frame as the layers ran it (out holds their result, blended in place); color: what
 * they diffused; radius: |CoC| / 2 where a pixel blurs, else 0; share: each pixel's share of
 * the slices' composite (0..1); largest: the largest radius of a pixel with a share. Scratch:
 * DDOF_SCRATCH_FAR_LAYERS and the gather's levels (DDOF_SCRATCH_FAR_FIELD_LEVELS). */
ddof_status ddof_far_layers(ddof_context *context, const adi_request *r, const float *color,
                            size_t color_stride, const float *radius, const float *share,
                            float largest, far_layers_report *report);

#endif
