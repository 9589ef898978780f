/* SPDX-License-Identifier: MIT */
/* scene_matte.c - a study scene's object matte: the Cryptomatte of matte.exr (the pinhole render
 * with Blender's CryptoObject pass) as interleaved ranks of (id, coverage), found and read as
 * `ddof --matte auto` finds and reads it (matte_input.c, frame_input.c). */
#include "study.h"

#include "exrio.h"
#include "exrio_layout.h"
#include "frame_input.h"
#include "matte_input.h"

#include <stdio.h>
#include <stdlib.h>

/* Finds the matte beside the colour of an opened file and loads its channels. */
static int load_matte(exrio_image *image, uint32_t width, uint32_t height, float **pairs,
                      uint32_t *ranks, char *message, size_t message_size)
{
    exrio_layout_request request = {0};
    exrio_layout layout;
    if (exrio_find_layout(image, &request, &layout, message, message_size) != EXRIO_LAYOUT_OK)
        return -1;
    const exrio_part *part = &image->parts[layout.part];
    if (part->width != width || part->height != height) {
        snprintf(message, message_size, "it is %ux%u, pinhole.exr %ux%u", part->width,
                 part->height, width, height);
        return -1;
    }
    int index[2 * DDOF_MATTE_MAX_RANKS];
    char found[256];
    const int count =
        matte_find(image, &layout, NULL, index, found, sizeof found, message, message_size);
    if (count <= 0) {
        if (count == 0)
            snprintf(message, message_size, "it holds no CryptoObject layer");
        return -1;
    }
    unsigned char *wanted = calloc((size_t)image->channel_count, 1);
    if (!wanted) {
        snprintf(message, message_size, "out of memory");
        return -1;
    }
    for (int i = 0; i < 2 * count; i++)
        wanted[index[i]] = 1;
    const exrio_status st = exrio_load(image, wanted, message, message_size);
    free(wanted);
    if (st != EXRIO_OK)
        return -1;
    *pairs = frame_interleave(image, index, 2 * count, (size_t)width * height);
    if (!*pairs) {
        snprintf(message, message_size, "out of memory");
        return -1;
    }
    *ranks = (uint32_t)count;
    return 0;
}

int study_read_matte(const char *path, uint32_t width, uint32_t height, float **pairs,
                     uint32_t *ranks, char *error, size_t size)
{
    exrio_image image;
    char message[2048];
    *pairs = NULL;
    *ranks = 0;
    if (exrio_open(path, &image, message, sizeof message) != EXRIO_OK) {
        snprintf(error, size, "%s", message);
        return -1;
    }
    const int rc = load_matte(&image, width, height, pairs, ranks, message, sizeof message);
    exrio_close(&image);
    if (rc)
        snprintf(error, size, "%s: %s", path, message);
    return rc;
}
