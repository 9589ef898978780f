/* SPDX-License-Identifier: MIT */
/* coc.h - circle of confusion: parameter checks and the computation on validated images. */
#ifndef DDOF_COC_H
#define DDOF_COC_H

#include "runtime/internal.h"

/* Read the caller's (possibly older, smaller) struct over the defaults and validate it. */
ddof_status ddof_read_camera(ddof_context *context, const ddof_camera *caller,
                             ddof_camera *camera);
ddof_status ddof_read_curve(ddof_context *context, const ddof_curve *caller, ddof_curve *curve);

/* An image (`what`: "depth", "colour") and the CoC that goes with it: neither NULL, both
 * valid, the CoC of the image's size with one channel; their strides in floats. */
ddof_status ddof_check_image_and_coc(ddof_context *context, const char *what,
                                     const ddof_image_in *image, const ddof_image_in *coc,
                                     size_t *image_stride, size_t *coc_stride);

/* Validate the depth values (first channel), then write CoC diameters in horizontal pixels to
 * `coc` (width x height floats, rows coc_stride floats apart). The image descriptions must
 * already be valid; strides are in floats. On a bad depth nothing is written. */
ddof_status ddof_compute_coc_camera(ddof_context *context, const ddof_camera *camera,
                                    const ddof_image_in *depth, size_t depth_stride,
                                    float *coc, size_t coc_stride);
ddof_status ddof_compute_coc_curve(ddof_context *context, const ddof_curve *curve,
                                   const ddof_image_in *depth, size_t depth_stride, float *coc,
                                   size_t coc_stride);

#endif
