/* SPDX-License-Identifier: MIT */
/* near_layer.h - the near field of one image as a foreground element (docs/design.md section 1,
 * "Blurring on top"): the strongly blurred near pixels are split off into an element, and what
 * they hid is filled in from their surroundings, so the layers can blur the element over the
 * rest as they blur a separately rendered one. */
#ifndef DDOF_NEAR_LAYER_H
#define DDOF_NEAR_LAYER_H

#include "adi/adi.h"

/* The matte (ddof_near_matte) and the split's other rules, shared with the device. The split
 * adds the element's 1-px fringe to the matte (near_layer.c, matte_rows). */
#include "ddof_near_rules.h"

/* A frame split into the near element and the rest. Images are w x h, tightly packed, in the
 * context's scratch memory (valid until the next call on the context). */
typedef struct near_split {
    const float *rest;     /* colour (the request's channels): the input, with the pixels wholly
                              in the element replaced by the fill of what they hid           */
    const float *rest_coc; /* signed CoC: the input's, filled the same way in those pixels   */
    const float *element;  /* premultiplied RGBA: the input's colour times the matte, alpha
                              the matte: the element's share of the pixel, so that the
                              composite F + (1 - m) C gives the pixel back where nothing
                              blurs                                                          */
    const float *element_coc; /* its |CoC| (w x h): the frame's, and for its fringe (pixels
                              beside one of matte 1, whose depth is the background's) the
                              largest near |CoC| beside it                                   */
    const float *carried_alpha; /* with 4 channels, where an element pixel's alpha is not 1:
                              the matte times the input's alpha (w x h), the element's part of
                              the alpha channel (layers_request.fg.carried_alpha); else NULL */
    pixel_box box;         /* where the element's alpha is above 0                           */
    float max_coc;         /* the element's largest |CoC|                                    */
    uint64_t element_pixels; /* pixels with matte > 0                                        */
    uint64_t holes;        /* pixels with matte 1 (filled in the rest)                       */
    int filled;            /* 0 when no pixel outside the element could serve as a source:
                              the rest keeps the input's colour and CoC there                */
} near_split;

/* Splits the request's frame (signed CoC, colour with 3 or 4 channels) by the near matte of
 * `threshold`. The holes' colour and CoC are filled from the pixels outside the element, the
 * far side preferred (a near one counts less, the more blurred it is: what a near object hides
 * is background, not more of the near field); near_layer.c says how. */
ddof_status ddof_split_near(ddof_context *context, const adi_request *r, float threshold,
                            near_split *split);

#endif
