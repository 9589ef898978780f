/* SPDX-License-Identifier: MIT */
/* silhouettes.h - mixed pixels where an in-focus object meets a blurred background behind it
 * (docs/design.md, section 1, "Mixed pixels at silhouettes").
 *
 * A render's edge pixel holds both surfaces, its depth one of them. On the blurred side of the
 * silhouette the diffusion blurs the object's share of the pixel away with the background; on
 * the sharp side the background's share stays sharp. The pass splits each such pixel by the
 * colours on both sides: the object's share is put back sharp on the blurred side, and the
 * background's share on the sharp side becomes the blurred background beside it. */
#ifndef DDOF_SILHOUETTES_H
#define DDOF_SILHOUETTES_H

#include "ddof_backend_seam.h"
#include "ddof_silhouette_rules.h"
#include "runtime/internal.h"


/* A render's object matte (Cryptomatte): per pixel `ranks` pairs of (id, coverage), `stride`
 * floats a row; ranks 0: none, the shares come from the colours. */
typedef struct object_matte {
    const float *pairs;
    size_t stride;
    uint32_t ranks;
} object_matte;

typedef struct silhouette_report {
    uint64_t pixels; /* mixed pixels split, both sides */
} silhouette_report;

/* Before the layers: *pairs says whether the frame's CoC has a pair at all (when not, nothing
 * else runs: the split need not either); *color becomes a copy (scratch
 * DDOF_SCRATCH_SILHOUETTE_COLOR, tightly packed, *color_stride set) in which each blurred pixel
 * of a pair holds the background alone, when its colours tell; else it is left as it is.
 * r: the frame's CoC and size. */
ddof_status ddof_clean_silhouettes(ddof_context *context, const adi_request *r,
                                   const object_matte *matte, const float **color,
                                   size_t *color_stride, int *pairs);

/* After the layers, before the highlights are drawn (after them with a matte, frame_run.c):
 * r is the frame (its signed CoC, size, channels, in-focus threshold) with out holding the
 * result so far, changed in place; color: the colour before ddof_clean_silhouettes
 * (color_stride floats a row), from which each pixel's shares are estimated, or taken from
 * the matte (NULL or no ranks: none). 3 or 4 channels (alpha is left as it is); scratch:
 * DDOF_SCRATCH_SILHOUETTES. */
ddof_status ddof_split_silhouettes(ddof_context *context, const adi_request *r,
                                   const object_matte *matte, const float *color,
                                   size_t color_stride, silhouette_report *report);

/* The split's delta image (DDOF_SCRATCH_SILHOUETTES: width x height x 3 floats), free for
 * another pass until ddof_split_silhouettes runs (the highlights' discs are drawn through it
 * when the split comes after them); NULL when it cannot be allocated. */
float *ddof_silhouettes_scratch(ddof_context *context, const adi_request *r);

#endif
