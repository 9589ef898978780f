/* SPDX-License-Identifier: MIT */
/* ddof_layer_rules.h - the layers' arithmetic that the core (libddof/src/layers/layers.c and
 * layers_dispatch.c) and a device running whole layered frames (the GL module's
 * libddof/src/layers/gl/gl_layers.c) must share to the bit: how a box grows, how far a kernel
 * carries a CoC, and the background layer's levels. Header-only, so that each side compiles
 * the same expressions. */
#ifndef DDOF_LAYER_RULES_H
#define DDOF_LAYER_RULES_H

#include "ddof_backend_seam.h"

#include <math.h>
#include <stdint.h>

static inline int ddof_box_is_empty(adi_box b)
{
    return b.x0 >= b.x1 || b.y0 >= b.y1;
}

/* b grown by margin pixels on every side, within a width x height image. */
static inline adi_box ddof_box_grow(adi_box b, uint32_t margin, uint32_t width, uint32_t height)
{
    if (ddof_box_is_empty(b))
        return b;
    adi_box g = {b.x0 > margin ? b.x0 - margin : 0, b.y0 > margin ? b.y0 - margin : 0,
                 width - b.x1 > margin ? b.x1 + margin : width,
                 height - b.y1 > margin ? b.y1 + margin : height};
    return g;
}

/* How far a diffusion of CoC d can carry anything (px), for the kernel that runs: beyond it an
 * effect changes values by less than e^-12. heat: 12 decay lengths of exp(-x / sqrt(k d^2));
 * a disc kernel: its fitted reach. */
static inline uint32_t ddof_kernel_reach_px(const disc_kernel *disc, float beta_scale, float coc)
{
    const float per_px = disc ? disc->reach : 12.0f * sqrtf(beta_scale);
    return (uint32_t)ceilf(per_px * coc) + 2;
}

/* ---- the near spread ---------------------------------------------------------------------- */

/* D falls by this much per pixel away from a near-field pixel (layers.c's near spread; the
 * device gets it in adi_layers_request.near_slope). */
#define DDOF_NEAR_SPREAD_SLOPE 4.0f

/* How far the near spread's dilation reaches from the near pixels: the farthest any of them
 * claims (its largest CoC / slope), plus 1 px. */
static inline uint32_t ddof_near_spread_reach_px(float max_near_coc)
{
    return (uint32_t)ceilf(max_near_coc / DDOF_NEAR_SPREAD_SLOPE) + 1;
}

/* ---- the background layer's levels (docs/design.md section 1) ---------------------------- */

/* Level k's threshold: t 2^k. */
static inline float ddof_background_threshold(float threshold_px, uint32_t level)
{
    return threshold_px * (float)(1u << level);
}

/* Level k >= 1 ramps up from the previous level's threshold, so a pixel counts as a hole only
 * at levels well above its own CoC; level 0 from the params' ramp start. */
static inline float ddof_background_ramp_start(float level_threshold, uint32_t level,
                                               float ramp_start_px)
{
    return level ? 0.5f * level_threshold : ramp_start_px;
}

/* The CoC from which level k is blended in: every pixel at level 0. */
static inline float ddof_background_blend_from(float level_threshold, uint32_t level)
{
    return level ? level_threshold : -INFINITY;
}

/* How far the background layer reaches from its edges: the kernel's reach of the larger of the
 * midground's largest CoC and the top level's threshold. It is computed on its edges grown by
 * twice this and blended within it, so the crop's insulated border never shows. */
static inline uint32_t ddof_background_reach_px(const disc_kernel *disc, float beta_scale,
                                                float max_coc, float threshold_px,
                                                uint32_t levels)
{
    const float top = ddof_background_threshold(threshold_px, levels - 1);
    return ddof_kernel_reach_px(disc, beta_scale, max_coc > top ? max_coc : top);
}

#endif
