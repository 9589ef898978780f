/* SPDX-License-Identifier: MIT */
/* preview.c - 8-bit sRGB PNG preview of a linear result. */
#include "preview.h"

#include "compare.h"
#include "output_file.h"
#include "png_write.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

int preview_write(const char *path, const float *rgb, uint32_t channels, uint32_t width,
                  uint32_t height, float exposure_stops, char *error, size_t error_size)
{
    const size_t pixels = (size_t)width * height;
    const double gain = pow(2.0, (double)exposure_stops);
    output_file out;
    uint8_t *bytes;
    FILE *stream;
    size_t i;
    int c;

    bytes = malloc(pixels * 3);
    if (!bytes) {
        snprintf(error, error_size, "%s: out of memory", path);
        return -1;
    }
    for (i = 0; i < pixels; i++)
        for (c = 0; c < 3; c++)
            bytes[i * 3 + (size_t)c] = (uint8_t)(
                compare_srgb_encode(gain * rgb[i * channels + (size_t)c]) * 255.0 + 0.5);

    if (output_file_begin(&out, path, error, error_size) != 0) {
        free(bytes);
        return -1;
    }
    stream = output_file_stream(&out);
    if (!stream) {
        snprintf(error, error_size, "%s: cannot open a stream on the temporary file", path);
        output_file_abort(&out);
        free(bytes);
        return -1;
    }
    if (png_write_stream(stream, path, bytes, width, height, 3, error, error_size) != 0) {
        output_file_abort(&out);
        free(bytes);
        return -1;
    }
    free(bytes);
    return output_file_commit(&out, error, error_size);
}
