/* SPDX-License-Identifier: MIT */
/* test_frame_calls.h - ddof_diffuse_layers and a foreground element on the one frame of a test
 * that keeps its size and context file-wide: the including file declares `W` and `H` (the
 * frame's size) and `ctx` (its context) before including this header. */
#ifndef DDOF_TEST_FRAME_CALLS_H
#define DDOF_TEST_FRAME_CALLS_H

#include "ddof.h"
#include "test_images.h"

/* ddof_diffuse_layers on the frame; st (may be NULL) is reset first. */
static inline ddof_status layers(const ddof_params *p, const float *color, const float *coc,
                                 const ddof_foreground *fg, float *out, uint32_t ch,
                                 ddof_stats *st)
{
    if (st)
        *st = stats_init();
    return diffuse_layers(ctx, p, color, coc, fg, out, W, H, ch, st);
}

/* A foreground element of the frame's size: RGBA colour and its CoC. */
static inline ddof_foreground make_fg(const float *fg_color, const float *fg_coc,
                                      uint32_t premultiplied)
{
    ddof_foreground fg;
    ddof_foreground_init(&fg);
    fg.color = (ddof_image_in){fg_color, W, H, 4, 0};
    fg.coc = (ddof_image_in){fg_coc, W, H, 1, 0};
    fg.premultiplied = premultiplied;
    return fg;
}

#endif
