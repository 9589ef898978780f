/* SPDX-License-Identifier: MIT */
/* far_field.h - the smooth blur drawn with the aperture's exact shape (docs/design.md, section 1,
 * "The far field"): where no depth edge lies within a pixel's reach, its output becomes the
 * average of the colour over the region whose light lands on it, blended with the diffusion's
 * result over a ramp toward the edges, where the diffusion stays the method. */
#ifndef DDOF_FAR_FIELD_H
#define DDOF_FAR_FIELD_H

#include "runtime/internal.h"
#include "ddof_backend_seam.h"

/* The smallest |CoC| (px) of a frame for which the pass looks at all. */
#define DDOF_FAR_FIELD_MIN_COC_PX 1.0f

typedef struct far_field_report {
    uint64_t pixels;         /* pixels that took some of the gather (weight > 0)          */
    uint64_t layered_pixels; /* of which took the depth slices' gather (far_layers.h)     */
    uint32_t slices;         /* the depth slices (0: no edge between two blurred surfaces) */
    uint32_t levels;         /* image levels the gather read (1: the frame only)          */
} far_field_report;

/* r: the frame as the layers ran it (its CoC, size, channels, pixel aspect, in-focus
 * threshold, and out holding their result, which is blended in place); color: what they
 * diffused (the highlights taken out), color_stride floats a row. Scratch: the context's
 * DDOF_SCRATCH_FAR_FIELD_* slots. DDOF_ERROR_OUT_OF_MEMORY leaves out as the layers wrote it. */
/* slices: 1 to gather where two blurred surfaces meet in depth slices (far_layers.h), 0 to
 * leave the diffusion's result there. */
ddof_status ddof_far_field(ddof_context *context, const adi_request *r, const float *color,
                           size_t color_stride, int slices, far_field_report *report);

#endif
