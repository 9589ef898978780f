/* SPDX-License-Identifier: MIT */
/* focus_map.c - the focal-plane view as a PNG (focus_map.h). */
#ifndef DDOF_EXPERIMENTAL /* ddof_focus_map (the build may define it already) */
#define DDOF_EXPERIMENTAL
#endif
#include "focus_map.h"

#include "output_file.h"
#include "png_write.h"

#include <stdio.h>
#include <stdlib.h>

int focus_map_write(ddof_context *context, const char *path, const float *coc, const float *rgb,
                    uint32_t channels, uint32_t width, uint32_t height,
                    const ddof_camera *camera, char *error, size_t error_size)
{
    output_file out;
    FILE *stream;
    const size_t size = (size_t)width * height * 3;
    uint8_t *bytes = malloc(size);
    if (!bytes) {
        snprintf(error, error_size, "%s: out of memory", path);
        return -1;
    }
    const ddof_image_in color_in = {rgb, width, height, channels, 0};
    const ddof_image_in coc_in = {coc, width, height, 1, 0};
    const ddof_status status =
        ddof_focus_map(context, &color_in, &coc_in, camera, bytes, size, NULL);
    if (status != DDOF_OK) {
        snprintf(error, error_size, "%s: %s (%s)", path, ddof_status_string(status),
                 ddof_context_last_error(context));
        free(bytes);
        return -1;
    }
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
