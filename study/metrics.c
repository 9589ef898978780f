/* SPDX-License-Identifier: MIT */
/* metrics.c - the errors of the study: PSNR as `ddof --compare` computes it (plugin/apps/cli/
 * compare.c: RGB, sRGB-encoded values clamped to [0, 1], peak 1), over the image, over the
 * band around depth edges or over the smooth far field, and linear differences against the
 * double-precision reference. */
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

/* Sets every pixel of mask within radius r (Euclidean) of (x, y) to value. */
static void stamp_disc(unsigned char *mask, uint32_t width, uint32_t height, uint32_t x,
                       uint32_t y, float r, unsigned char value)
{
    const int ri = (int)floorf(r);
    const float r2 = r * r;
    for (int dy = -ri; dy <= ri; dy++) {
        const long yy = (long)y + dy;
        if (yy < 0 || yy >= (long)height)
            continue;
        for (int dx = -ri; dx <= ri; dx++) {
            const long xx = (long)x + dx;
            if (xx < 0 || xx >= (long)width || (float)(dx * dx + dy * dy) > r2)
                continue;
            mask[(size_t)yy * width + (size_t)xx] = value;
        }
    }
}

static float max_rgb(const float *rgba, size_t i)
{
    return fmaxf(rgba[i * 4], fmaxf(rgba[i * 4 + 1], rgba[i * 4 + 2]));
}

size_t study_smooth(const float *coc, const float *rgba, const float *truth, uint32_t width,
                    uint32_t height, unsigned char *smooth)
{
    const size_t pixels = (size_t)width * height;
    for (size_t i = 0; i < pixels; i++)
        smooth[i] = fabsf(coc[i]) > STUDY_SMOOTH_MIN_COC_PX;
    for (uint32_t y = 0; y < height; y++) {
        for (uint32_t x = 0; x < width; x++) {
            const size_t i = (size_t)y * width + x;
            const float c = coc[i];
            /* Depth edges: both pixels of a 4-neighbour pair, the right and the lower. */
            for (int dir = 0; dir < 2; dir++) {
                const uint32_t nx = x + (dir == 0), ny = y + (dir == 1);
                if (nx >= width || ny >= height)
                    continue;
                const float d = coc[(size_t)ny * width + nx];
                if (!(fabsf(c - d) >= STUDY_EDGE_COC_PX))
                    continue;
                /* 12 px, or the reach of the blur across the edge where that is larger (a
                 * near object's, as the band takes it). */
                const float r = fmaxf(STUDY_SMOOTH_EDGE_PX, 0.5f * fmaxf(fabsf(c), fabsf(d)));
                stamp_disc(smooth, width, height, x, y, r, 0);
                stamp_disc(smooth, width, height, nx, ny, r, 0);
            }
            /* Highlights of the input or the truth, and where their discs land. */
            if (max_rgb(rgba, i) > STUDY_SMOOTH_HIGHLIGHT ||
                (truth && max_rgb(truth, i) > STUDY_SMOOTH_HIGHLIGHT))
                stamp_disc(smooth, width, height, x, y,
                           0.5f * fabsf(c) + STUDY_SMOOTH_HIGHLIGHT_MARGIN_PX, 0);
        }
    }
    size_t count = 0;
    for (size_t i = 0; i < pixels; i++)
        count += smooth[i];
    return count;
}

size_t study_silhouettes(const float *coc, uint32_t width, uint32_t height,
                         unsigned char *silhouette)
{
    const size_t pixels = (size_t)width * height;
    memset(silhouette, 0, pixels);
    for (uint32_t y = 0; y < height; y++)
        for (uint32_t x = 0; x < width; x++) {
            const float c = fabsf(coc[(size_t)y * width + x]);
            for (int dir = 0; dir < 2; dir++) {
                const uint32_t nx = x + (dir == 0), ny = y + (dir == 1);
                if (nx >= width || ny >= height)
                    continue;
                const float d = fabsf(coc[(size_t)ny * width + nx]);
                if (!((c < STUDY_IN_FOCUS_PX && d >= STUDY_EDGE_COC_PX) ||
                      (d < STUDY_IN_FOCUS_PX && c >= STUDY_EDGE_COC_PX)))
                    continue;
                stamp_disc(silhouette, width, height, x, y, STUDY_SILHOUETTE_PX, 1);
                stamp_disc(silhouette, width, height, nx, ny, STUDY_SILHOUETTE_PX, 1);
            }
        }
    size_t count = 0;
    for (size_t i = 0; i < pixels; i++)
        count += silhouette[i];
    return count;
}

size_t study_blurred_edges(const float *coc, uint32_t width, uint32_t height,
                           unsigned char *band)
{
    const size_t pixels = (size_t)width * height;
    /* 1 within reach of an edge between blurred surfaces, then 0 within reach of any other
     * edge: two passes, as the stamps of the second overwrite the first's. */
    memset(band, 0, pixels);
    for (int pass = 0; pass < 2; pass++)
        for (uint32_t y = 0; y < height; y++)
            for (uint32_t x = 0; x < width; x++) {
                const float c = coc[(size_t)y * width + x];
                for (int dir = 0; dir < 2; dir++) {
                    const uint32_t nx = x + (dir == 0), ny = y + (dir == 1);
                    if (nx >= width || ny >= height)
                        continue;
                    const float d = coc[(size_t)ny * width + nx];
                    if (!(fabsf(c - d) >= STUDY_EDGE_COC_PX))
                        continue;
                    const int blurred = fminf(fabsf(c), fabsf(d)) >= STUDY_EDGE_COC_PX;
                    if (blurred != (pass == 0))
                        continue;
                    stamp_disc(band, width, height, x, y, STUDY_SMOOTH_EDGE_PX, pass == 0);
                    stamp_disc(band, width, height, nx, ny, STUDY_SMOOTH_EDGE_PX, pass == 0);
                }
            }
    size_t count = 0;
    for (size_t i = 0; i < pixels; i++)
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

void study_brightness(const float *a, const float *b, uint32_t width, uint32_t height,
                      double *inside, double *border)
{
    double sum[2][2] = {{0, 0}, {0, 0}}; /* [border?][a or b] */
    for (uint32_t y = 0; y < height; y++)
        for (uint32_t x = 0; x < width; x++) {
            const int edge = x < STUDY_BORDER_PX || y < STUDY_BORDER_PX ||
                             x + STUDY_BORDER_PX >= width || y + STUDY_BORDER_PX >= height;
            const size_t i = ((size_t)y * width + x) * 4;
            for (int c = 0; c < 3; c++) {
                sum[edge][0] += a[i + (size_t)c];
                sum[edge][1] += b[i + (size_t)c];
            }
        }
    *inside = sum[0][1] > 0.0 ? sum[0][0] / sum[0][1] : NAN;
    *border = sum[1][1] > 0.0 ? sum[1][0] / sum[1][1] : NAN;
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
