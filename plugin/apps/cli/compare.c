/* SPDX-License-Identifier: MIT */
/* compare.c - RMSE and PSNR against a ground truth. */
#include "compare.h"

#include <math.h>

double compare_srgb_encode(double v)
{
    if (!(v > 0.0))
        return 0.0;
    if (v >= 1.0)
        return 1.0;
    return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055;
}

void compare_rgb(const float *a, int a_channels, const float *b, int b_channels, size_t pixels,
                 image_error *out)
{
    double sum_srgb = 0.0, sum_linear = 0.0;
    size_t i;
    int c;
    for (i = 0; i < pixels; i++) {
        for (c = 0; c < 3; c++) {
            const double x = a[i * (size_t)a_channels + (size_t)c];
            const double y = b[i * (size_t)b_channels + (size_t)c];
            const double ds = compare_srgb_encode(x) - compare_srgb_encode(y);
            sum_srgb += ds * ds;
            sum_linear += (x - y) * (x - y);
        }
    }
    if (pixels == 0) {
        out->rmse_srgb = out->rmse_linear = 0.0;
        out->psnr_srgb = INFINITY;
        return;
    }
    out->rmse_srgb = sqrt(sum_srgb / (3.0 * (double)pixels));
    out->rmse_linear = sqrt(sum_linear / (3.0 * (double)pixels));
    out->psnr_srgb = out->rmse_srgb > 0.0 ? -20.0 * log10(out->rmse_srgb) : INFINITY;
}
