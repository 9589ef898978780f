/* SPDX-License-Identifier: MIT */
/* compare.h - the error of an image against a ground truth (docs/design.md section 6), over RGB:
 *  - display-referred: each value clamped to [0, 1] and sRGB-encoded, as a person sees it in
 *    the PNG preview; RMSE and PSNR (peak 1) on that scale are the headline figures;
 *  - scene-referred: RMSE of the linear values, unclamped (bright highlights weigh in fully). */
#ifndef DDOF_CLI_COMPARE_H
#define DDOF_CLI_COMPARE_H

#include <stddef.h>

typedef struct image_error {
    double rmse_srgb;
    double psnr_srgb;   /* dB; +inf for identical images */
    double rmse_linear;
} image_error;

/* a and b: `pixels` pixels of interleaved floats with a_channels / b_channels channels (>= 3);
 * the first three are R, G, B. */
void compare_rgb(const float *a, int a_channels, const float *b, int b_channels, size_t pixels,
                 image_error *out);

/* Linear light to sRGB-encoded value in [0, 1] (IEC 61966-2-1), clamped. */
double compare_srgb_encode(double linear);

#endif
