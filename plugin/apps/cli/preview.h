/* SPDX-License-Identifier: MIT */
/* preview.h - the PNG preview of a result: linear RGB times 2^exposure, clamped, sRGB-encoded
 * to 8 bits, written through libpng (plugin/io/png/png_write.h) as an atomic output. */
#ifndef DDOF_CLI_PREVIEW_H
#define DDOF_CLI_PREVIEW_H

#include <stddef.h>
#include <stdint.h>

/* rgb: width * height pixels of `channels` (>= 3) interleaved floats, rows top first. */
int preview_write(const char *path, const float *rgb, uint32_t channels, uint32_t width,
                  uint32_t height, float exposure_stops, char *error, size_t error_size);

#endif
