/* SPDX-License-Identifier: MIT */
/* png_write.h - 8-bit PNG output through libpng, shared by ddof-demo and the `ddof` command.
 *
 * Two entry points because the two programs own their temporary files differently: ddof-demo
 * lets png_write_file() make its own temporary file and rename it; `ddof` creates (and registers
 * for removal on Ctrl-C) its temporary file itself and hands the open stream to
 * png_write_stream(). */
#ifndef DDOF_PLUGIN_PNG_WRITE_H
#define DDOF_PLUGIN_PNG_WRITE_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* Encodes `pixels` (8-bit sRGB, `channels` 1 = grey or 3 = RGB, tightly packed rows, top first)
 * as PNG into the open stream `file` (which the caller flushes and closes). `name` is only used
 * in messages. Returns 0, or -1 with a one-line reason in `error` (error_size bytes). */
int png_write_stream(FILE *file, const char *name, const uint8_t *pixels, uint32_t width,
                     uint32_t height, uint32_t channels, char *error, size_t error_size);

/* Writes the same to `path` without ever leaving a half-written file: the data goes to a
 * temporary file beside `path` that is flushed to disk and renamed over `path` only when
 * complete; on failure it is removed and `path` is left as it was. Returns 0 or -1 (error). */
int png_write_file(const char *path, const uint8_t *pixels, uint32_t width, uint32_t height,
                   uint32_t channels, char *error, size_t error_size);

#endif
