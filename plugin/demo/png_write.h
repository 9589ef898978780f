/* png_write.h - write an 8-bit image as PNG without ever leaving a half-written file. */
#ifndef DDOF_DEMO_PNG_WRITE_H
#define DDOF_DEMO_PNG_WRITE_H

#include <stddef.h>
#include <stdint.h>

/* Writes `pixels` (8-bit sRGB, `channels` 1 = grey or 3 = RGB, tightly packed rows, top first) to
 * `path`. The data goes to a temporary file beside `path` that is flushed to disk and renamed
 * over `path` only when complete; on failure it is removed and `path` is left as it was.
 * Returns 0 on success, or -1 with a one-line reason in `error` (error_size bytes). */
int demo_png_write(const char *path, const uint8_t *pixels, uint32_t width, uint32_t height,
                   uint32_t channels, char *error, size_t error_size);

#endif
