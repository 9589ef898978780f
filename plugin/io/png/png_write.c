/* SPDX-License-Identifier: MIT */
/* png_write.c - PNG output through libpng's simplified API; atomic file variant (temp + rename). */
#include "png_write.h"

#include <png.h>

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#if !defined(PNG_SIMPLIFIED_WRITE_SUPPORTED) || !defined(PNG_STDIO_SUPPORTED)
#error "ddof's PNG output needs libpng 1.6 or newer with the simplified write API"
#endif

int png_write_stream(FILE *file, const char *name, const uint8_t *pixels, uint32_t width,
                     uint32_t height, uint32_t channels, char *error, size_t error_size)
{
    png_image image;

    if (channels != 1 && channels != 3) {
        snprintf(error, error_size, "%s: %u channels (only 1 or 3 are written)", name, channels);
        return -1;
    }
    if ((uint64_t)width * channels > 0x7fffffffu) {
        snprintf(error, error_size, "%s: image too wide for PNG", name);
        return -1;
    }
    memset(&image, 0, sizeof image);
    image.version = PNG_IMAGE_VERSION;
    image.width = width;
    image.height = height;
    image.format = channels == 1 ? PNG_FORMAT_GRAY : PNG_FORMAT_RGB; /* 8-bit: tagged sRGB */
    if (!png_image_write_to_stdio(&image, file, 0, pixels, (png_int_32)(width * channels),
                                  NULL)) {
        snprintf(error, error_size, "cannot write %s: libpng: %s", name, image.message);
        png_image_free(&image);
        return -1;
    }
    return 0;
}

int png_write_file(const char *path, const uint8_t *pixels, uint32_t width, uint32_t height,
                   uint32_t channels, char *error, size_t error_size)
{
    char temp[4096];
    FILE *file;
    int written;
    int length;

    length = snprintf(temp, sizeof temp, "%s.tmp-%ld", path, (long)getpid());
    if (length < 0 || (size_t)length >= sizeof temp) {
        snprintf(error, error_size, "%s: path too long", path);
        return -1;
    }

    /* A leftover from a killed run that had the same process id is ours to replace. */
    (void)remove(temp);
    file = fopen(temp, "wbx");
    if (!file) {
        snprintf(error, error_size, "cannot create %s: %s", temp, strerror(errno));
        return -1;
    }

    written = png_write_stream(file, temp, pixels, width, height, channels, error,
                               error_size) == 0;
    if (written && (fflush(file) != 0 || fsync(fileno(file)) != 0)) {
        snprintf(error, error_size, "cannot write %s: %s", temp, strerror(errno));
        written = 0;
    }
    if (fclose(file) != 0 && written) {
        snprintf(error, error_size, "cannot write %s: %s", temp, strerror(errno));
        written = 0;
    }
    if (!written) {
        (void)remove(temp);
        return -1;
    }
    if (rename(temp, path) != 0) {
        snprintf(error, error_size, "cannot rename %s to %s: %s", temp, path, strerror(errno));
        (void)remove(temp);
        return -1;
    }
    return 0;
}
