/* SPDX-License-Identifier: MIT */
/* aperture_image.c - the image of --aperture-image, read through exrio. */
#include "aperture_image.h"

#include "exrio.h"
#include "input_file.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The channel the aperture is read from: Y, else R, else the first one. */
static int aperture_channel(const exrio_image *image)
{
    const char *const names[] = {"Y", "R"};
    for (int k = 0; k < 2; k++) {
        const int c = exrio_find_channel(image, names[k], 0);
        if (c >= 0)
            return c;
    }
    for (int c = 0; c < image->channel_count; c++)
        if (image->channels[c].part == 0)
            return c;
    return -1;
}

float *aperture_image_read(const char *path, uint32_t *width, uint32_t *height, char *error,
                           size_t error_size)
{
    exrio_image image;
    float *pixels = NULL;
    if (input_file_open_exr(path, "aperture image", &image, error, error_size) != EXRIO_OK)
        return NULL;
    const int c = aperture_channel(&image);
    unsigned char *wanted = calloc((size_t)image.channel_count + 1, 1);
    if (c < 0 || image.channels[c].type == EXRIO_UINT) {
        snprintf(error, error_size, "%s: no half or float channel (Y, R or any) for the "
                 "aperture image", path);
    } else if (!wanted) {
        snprintf(error, error_size, "out of memory");
    } else {
        wanted[c] = 1;
        if (exrio_load(&image, wanted, error, error_size) == EXRIO_OK) {
            const exrio_part *part = &image.parts[image.channels[c].part];
            const size_t count = (size_t)part->width * part->height;
            pixels = malloc(count * sizeof *pixels);
            if (pixels) {
                memcpy(pixels, image.channels[c].pixels, count * sizeof *pixels);
                *width = part->width;
                *height = part->height;
            } else {
                snprintf(error, error_size, "out of memory");
            }
        }
    }
    free(wanted);
    exrio_close(&image);
    return pixels;
}
