/* SPDX-License-Identifier: MIT */
/* metrics.c - the errors of the study: PSNR as `ddof --compare` computes it (plugin/apps/cli/
 * compare.c: RGB, sRGB-encoded values clamped to [0, 1], peak 1), over the image or over the
 * band around depth edges, and linear differences against the double-precision reference. */
#include "study.h"

#include "compare.h"

#include <math.h>
#include <string.h>

size_t study_band(const float *coc, uint32_t width, uint32_t height, unsigned char *band)
{
    memset(band, 0, (size_t)width * height);
    for (uint32_t y = 0; y < height; y++) {
        for (uint32_t x = 0; x < width; x++) {
            const float c = coc[(size_t)y * width + x];
            /* The right and the lower neighbour: every 4-neighbour pair once. */
            for (int dir = 0; dir < 2; dir++) {
                const uint32_t nx = x + (dir == 0), ny = y + (dir == 1);
                if (nx >= width || ny >= height)
                    continue;
                const float d = coc[(size_t)ny * width + nx];
                if (!(fabsf(c - d) >= STUDY_EDGE_COC_PX))
                    continue;
                const float r = fmaxf(STUDY_BAND_MIN_PX, 0.5f * fmaxf(fabsf(c), fabsf(d)));
                const int ri = (int)ceilf(r);
                const float r2 = r * r;
                /* A disc of radius r around the pair's midpoint-ish: around both pixels. */
                for (int dy = -ri; dy <= ri + (dir == 1); dy++) {
                    const long yy = (long)y + dy;
                    if (yy < 0 || yy >= (long)height)
                        continue;
                    for (int dx = -ri; dx <= ri + (dir == 0); dx++) {
                        const long xx = (long)x + dx;
                        if (xx < 0 || xx >= (long)width)
                            continue;
                        /* distance to the nearer pixel of the pair */
                        const float ax = (float)dx, ay = (float)dy;
                        const float bx = ax - (float)(dir == 0), by = ay - (float)(dir == 1);
                        if (ax * ax + ay * ay <= r2 || bx * bx + by * by <= r2)
                            band[(size_t)yy * width + (size_t)xx] = 1;
                    }
                }
            }
        }
    }
    size_t count = 0;
    for (size_t i = 0; i < (size_t)width * height; i++)
        count += band[i];
    return count;
}

double study_psnr(const float *a, const float *b, size_t pixels, const unsigned char *mask)
{
    double sum = 0.0;
    size_t n = 0;
    for (size_t i = 0; i < pixels; i++) {
        if (mask && !mask[i])
            continue;
        for (int c = 0; c < 3; c++) {
            const double d = compare_srgb_encode(a[i * 4 + (size_t)c]) -
                             compare_srgb_encode(b[i * 4 + (size_t)c]);
            sum += d * d;
        }
        n++;
    }
    if (n == 0)
        return NAN;
    const double rmse = sqrt(sum / (3.0 * (double)n));
    return rmse > 0.0 ? -20.0 * log10(rmse) : INFINITY;
}

void study_linear_diff(const float *a, const float *b, size_t pixels, double *max_abs,
                       double *rms)
{
    double m = 0.0, sum = 0.0;
    for (size_t i = 0; i < pixels * 4; i++) {
        const double d = fabs((double)a[i] - (double)b[i]);
        if (d > m || d != d)
            m = d != d ? INFINITY : d;
        sum += d * d;
    }
    *max_abs = m;
    *rms = pixels ? sqrt(sum / (4.0 * (double)pixels)) : 0.0;
}
