/* SPDX-License-Identifier: MIT */
/* call_checks.h - the checks the public diffusion calls share (call_checks.c). Each returns
 * DDOF_OK or a failure recorded in the context, and none writes an output pixel. */
#ifndef DDOF_CALL_CHECKS_H
#define DDOF_CALL_CHECKS_H

#include "adi/adi.h"
#include "layers/layers.h"

/* The caller's params over the defaults (an older caller's struct lacks the later fields),
 * every value checked, the solver and precision against the context's backend. */
ddof_status ddof_read_params(ddof_context *context, const ddof_params *caller, ddof_params *p);

/* A forced near spread or near layer needs signed CoC: judged once the call knows the CoC's
 * sign. */
ddof_status ddof_check_near_spread(ddof_context *context, const ddof_params *p);

/* Whether these params take a foreground element (frame.c, where the element's rules live):
 * the CoD4 preview blurs one image, and the element is the near field, so neither one-image
 * near effect may be forced on beside it. */
ddof_status ddof_check_element_allowed(ddof_context *context, const ddof_params *p);

/* A camera's pixel aspect within what the diffusion accepts (as params.pixel_aspect). */
ddof_status ddof_check_camera_aspect(ddof_context *context, const ddof_camera *camera);

/* One more image of the call (`what` names it): valid, and the colour's size (r->width,
 * r->height). *stride in floats. */
ddof_status ddof_check_map(ddof_context *context, const char *what, const ddof_image_in *map,
                           const adi_request *r, size_t *stride);

/* Colour, the per-pixel input (CoC or depth, named map_name) and out: fills the request's
 * images and sizes, and checks the colour's values (finite). */
ddof_status ddof_check_call_images(ddof_context *context, const ddof_image_in *color,
                                   const ddof_image_in *map, const char *map_name,
                                   const ddof_image *out, adi_request *r, size_t *map_stride);

/* CoC values: finite, |CoC| <= DDOF_MAX_COC_PX, negative only when signed; *max_abs (may be
 * NULL) gets the largest |CoC|, found by the same read. */
ddof_status ddof_check_coc_values(ddof_context *context, const ddof_image_in *coc,
                                  size_t stride, int coc_signed, float *max_abs);

/* The request's solver settings from validated params; its kernel is the one the context's
 * backend runs (ddof_backend_disc_kernel). */
void ddof_fill_request_params(const ddof_context *context, adi_request *r, const ddof_params *p);

/* Validates the element and fills the request's foreground fields; *visible says whether any
 * alpha > 0 (an element with none changes nothing and is skipped). */
ddof_status ddof_read_foreground(ddof_context *context, const ddof_foreground *caller,
                                 layers_request *q, int *visible);

#endif
