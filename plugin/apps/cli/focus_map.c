/* SPDX-License-Identifier: MIT */
/* focus_map.c - the focal-plane view as a PNG (focus_map.h). */
#include "focus_map.h"

#include "output_file.h"
#include "png_write.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

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

int focus_map_write(const char *path, const float *coc, const float *rgb, uint32_t channels,
                    uint32_t width, uint32_t height, char *error, size_t error_size)
{
    output_file out;
    FILE *stream;
    uint8_t *bytes = malloc((size_t)width * height * 3);
    if (!bytes) {
        snprintf(error, error_size, "%s: out of memory", path);
        return -1;
    }
    focus_map_pixels(coc, rgb, channels, width, height, bytes);
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
