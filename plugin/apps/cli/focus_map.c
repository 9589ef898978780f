/* SPDX-License-Identifier: MIT */
/* focus_map.c - the focal-plane view as a PNG (focus_map.h). */
#include "focus_map.h"

#include "output_file.h"
#include "png_write.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define PI 3.14159265358979323846

static uint8_t byte_of(double v)
{
    return (uint8_t)(fmin(fmax(v, 0.0), 1.0) * 255.0 + 0.5);
}

void focus_map_pixels(const float *coc, const float *rgb, uint32_t channels, uint32_t width,
                      uint32_t height, uint8_t *bytes)
{
    static const double sharp[3] = {0.15, 1.0, 0.2}, near[3] = {1.0, 0.45, 0.1},
                        far[3] = {0.2, 0.45, 1.0};
    const size_t pixels = (size_t)width * height;
    double largest = 0.0;
    size_t i;
    for (i = 0; i < pixels; i++)
        if (isfinite(coc[i]))
            largest = fmax(largest, fabs((double)coc[i]));
    for (i = 0; i < pixels; i++) {
        const float *p = rgb + i * channels;
        const double y = fmin(fmax(0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2], 0.0), 1.0);
        const double shade = 0.35 + 0.65 * sqrt(y);
        const double a = fabs((double)coc[i]);
        const double *hue = sharp;
        double v = 1.0;
        int c;
        if (!(a < DDOF_FOCUS_MAP_SHARP_PX)) {
            const double span = largest - DDOF_FOCUS_MAP_SHARP_PX;
            const double t = span > 0.0 ? fmin((a - DDOF_FOCUS_MAP_SHARP_PX) / span, 1.0) : 1.0;
            hue = coc[i] < 0.0f ? near : far;
            v = 0.35 + 0.65 * t;
        }
        for (c = 0; c < 3; c++)
            bytes[i * 3 + (size_t)c] = byte_of(hue[c] * v * shade);
    }
}

/* Whether the legend's point (x, y) (image axes, y down, the shape's unit radius at height 1)
 * lies in the aperture, as a light behind the focus draws it. */
static int in_aperture(const ddof_camera *camera, float peak, double x, double y)
{
    const double ratio = camera->aperture_ratio;
    if (camera->aperture_image) { /* its texel at least half the brightest */
        const uint32_t w = camera->aperture_image_width, h = camera->aperture_image_height;
        const double u = (x * ratio + 1.0) * 0.5 * w, v = (y + 1.0) * 0.5 * h;
        if (!(u >= 0.0 && u < w && v >= 0.0 && v < h))
            return 0;
        return camera->aperture_image[(size_t)v * w + (size_t)u] >= 0.5f * peak;
    }
    const double ax = x * ratio, ay = -y;
    if (camera->aperture_blades < 3)
        return ax * ax + ay * ay <= 1.0;
    double far = -INFINITY;
    for (uint32_t k = 0; k < camera->aperture_blades; k++) {
        const double a = camera->aperture_rotation_deg * (PI / 180.0) +
                         2.0 * PI * k / camera->aperture_blades;
        far = fmax(far, ax * cos(a) + ay * sin(a));
    }
    return far <= cos(PI / camera->aperture_blades);
}

void focus_map_aperture(const ddof_camera *camera, uint32_t width, uint32_t height,
                        uint8_t *bytes)
{
    if (!camera || (camera->aperture_blades < 3 && camera->aperture_ratio == 1.0 &&
                    !camera->aperture_image))
        return;
    const uint32_t side = (width < height ? width : height) / 4;
    const uint32_t s = side > 64 ? 64 : side;
    if (s < 12)
        return;
    const uint32_t x0 = width - s - 2, y0 = 2;
    const double half = 0.5 * s, scale = half - 1.0;
    /* The shape is 1 / ratio wide and 1 tall: the larger of the two fills the square. */
    const double extent = camera->aperture_ratio < 1.0 ? 1.0 / camera->aperture_ratio : 1.0;
    float peak = 0.0f;
    for (uint32_t i = 0; camera->aperture_image &&
                         i < camera->aperture_image_width * camera->aperture_image_height;
         i++)
        peak = camera->aperture_image[i] > peak ? camera->aperture_image[i] : peak;
    for (uint32_t y = y0; y < y0 + s; y++)
        for (uint32_t x = x0; x < x0 + s; x++) {
            const double u = (x + 0.5 - (x0 + half)) / scale * extent;
            const double v = (y + 0.5 - (y0 + half)) / scale * extent;
            const uint8_t value = in_aperture(camera, peak, u, v) ? 255 : 0;
            for (int c = 0; c < 3; c++)
                bytes[((size_t)y * width + x) * 3 + (size_t)c] = value;
        }
}

int focus_map_write(const char *path, const float *coc, const float *rgb, uint32_t channels,
                    uint32_t width, uint32_t height, const ddof_camera *camera, char *error,
                    size_t error_size)
{
    output_file out;
    FILE *stream;
    uint8_t *bytes = malloc((size_t)width * height * 3);
    if (!bytes) {
        snprintf(error, error_size, "%s: out of memory", path);
        return -1;
    }
    focus_map_pixels(coc, rgb, channels, width, height, bytes);
    focus_map_aperture(camera, width, height, bytes);
    if (output_file_begin(&out, path, error, error_size) != 0) {
        free(bytes);
        return -1;
    }
    stream = output_file_stream(&out);
    if (!stream || png_write_stream(stream, path, bytes, width, height, 3, error,
                                    error_size) != 0) {
        if (!stream)
            snprintf(error, error_size, "%s: cannot open a stream on the temporary file", path);
        output_file_abort(&out);
        free(bytes);
        return -1;
    }
    free(bytes);
    return output_file_commit(&out, error, error_size);
}
