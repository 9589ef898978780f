/* SPDX-License-Identifier: MIT */
/* aperture_image.h - the image of --aperture-image: a custom aperture for highlights. */
#ifndef DDOF_CLI_APERTURE_IMAGE_H
#define DDOF_CLI_APERTURE_IMAGE_H

#include <stddef.h>
#include <stdint.h>

/* Reads an EXR's aperture: its channel Y, else R, else its first channel (of the first part),
 * rows top first, packed. Returns width * height floats (free them), or NULL with `error`. The
 * library judges the values and the size (ddof_camera_check). */
float *aperture_image_read(const char *path, uint32_t *width, uint32_t *height, char *error,
                           size_t error_size);

#endif
