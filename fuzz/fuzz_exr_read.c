/* SPDX-License-Identifier: MIT */
/* fuzz_exr_read.c - the command's EXR read path on fuzzed files: open (header), find the
 * channel layout as `ddof` does, load the channels, write them back with exrio_write_fd and
 * read the copy again, which must hold the same values.
 *
 * exrio reads through a path, so each input is written to a per-process temporary file first.
 * Files of more than FUZZ_MAX_PIXELS pixels in a part are opened but not loaded: the reader
 * accepts up to EXRIO_MAX_PIXELS (2^28), which is a memory limit, not a defect. */
#include "exrio.h"
#include "exrio_layout.h"

#include <fcntl.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define FUZZ_MAX_PIXELS (1u << 16)

static char input_path[256], copy_path[256];

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    const char *tmp = getenv("TMPDIR");
    (void)argc;
    (void)argv;
    snprintf(input_path, sizeof input_path, "%s/fuzz_exr_read-%ld.exr", tmp ? tmp : "/tmp",
             (long)getpid());
    snprintf(copy_path, sizeof copy_path, "%s/fuzz_exr_read-%ld-copy.exr", tmp ? tmp : "/tmp",
             (long)getpid());
    return 0;
}

static int write_input(const uint8_t *data, size_t size)
{
    FILE *f = fopen(input_path, "wb");
    int ok;
    if (!f)
        return -1;
    ok = fwrite(data, 1, size, f) == size;
    return fclose(f) == 0 && ok ? 0 : -1;
}

/* Same value, NaN matching NaN (a half NaN's payload may change on the way). */
static int same_value(exrio_pixel_type type, const void *a, const void *b, size_t i)
{
    if (type == EXRIO_UINT)
        return ((const uint32_t *)a)[i] == ((const uint32_t *)b)[i];
    {
        const float x = ((const float *)a)[i], y = ((const float *)b)[i];
        return x == y || (isnan(x) && isnan(y));
    }
}

/* Writes the loaded channels of `part` to copy_path and checks that they read back equal. */
static void write_back(const exrio_image *image, int part)
{
    const exrio_part *p = &image->parts[part];
    exrio_write_channel channels[64];
    exrio_write_spec spec;
    exrio_image copy;
    char error[1024];
    int c, n = 0, fd;
    for (c = 0; c < image->channel_count && n < 64; c++) {
        const exrio_channel *ch = &image->channels[c];
        if (ch->part != part || !ch->pixels)
            continue;
        channels[n].name = ch->name;
        channels[n].type = ch->type;
        channels[n].pixels = ch->pixels;
        channels[n].pixel_stride = 4;
        channels[n].line_stride = (size_t)p->width * 4;
        n++;
    }
    if (n == 0)
        return;
    memset(&spec, 0, sizeof spec);
    spec.data_window = p->data_window;
    spec.display_window = p->display_window;
    spec.pixel_aspect = p->pixel_aspect;
    spec.compression = EXRIO_COMPRESSION_ZIP;
    spec.channel_count = n;
    spec.channels = channels;
    spec.metadata_from = image;
    spec.metadata_part = part;
    fd = open(copy_path, O_RDWR | O_CREAT | O_TRUNC, 0600);
    if (fd < 0)
        return;
    if (exrio_write_fd(fd, copy_path, &spec, error, sizeof error) != EXRIO_OK) {
        /* Some inputs cannot be written (a window or name the writer refuses): fine. */
        close(fd);
        return;
    }
    close(fd);
    if (exrio_open(copy_path, &copy, error, sizeof error) != EXRIO_OK) {
        fprintf(stderr, "fuzz_exr_read: the written copy does not open: %s\n", error);
        abort();
    }
    if (exrio_load(&copy, NULL, error, sizeof error) != EXRIO_OK) {
        fprintf(stderr, "fuzz_exr_read: the written copy does not load: %s\n", error);
        abort();
    }
    for (c = 0; c < n; c++) {
        const int k = exrio_find_channel(&copy, channels[c].name, 0);
        size_t i;
        if (k < 0 || copy.channels[k].type != channels[c].type) {
            fprintf(stderr, "fuzz_exr_read: channel %s lost in the copy\n", channels[c].name);
            abort();
        }
        for (i = 0; i < (size_t)p->width * p->height; i++)
            if (!same_value(channels[c].type, channels[c].pixels, copy.channels[k].pixels, i)) {
                fprintf(stderr, "fuzz_exr_read: channel %s differs at %zu\n", channels[c].name, i);
                abort();
            }
    }
    exrio_close(&copy);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    exrio_image image;
    exrio_layout layout;
    exrio_layout_request request;
    char error[2048], list[1024];
    int p, small = 1;

    if (write_input(data, size) != 0)
        return 0;
    if (exrio_open(input_path, &image, error, sizeof error) != EXRIO_OK)
        return 0;
    for (p = 0; p < image.part_count; p++)
        small &= (uint64_t)image.parts[p].width * image.parts[p].height <= FUZZ_MAX_PIXELS;
    exrio_list_channels(&image, 40, list, sizeof list);
    memset(&request, 0, sizeof request);
    request.need_depth = 1;
    (void)exrio_find_layout(&image, &request, &layout, error, sizeof error);
    request.need_depth = 0;
    request.coc = "C";
    (void)exrio_find_layout(&image, &request, &layout, error, sizeof error);
    (void)exrio_find_depth(&image, "", NULL);
    if (small && exrio_load(&image, NULL, error, sizeof error) == EXRIO_OK)
        for (p = 0; p < image.part_count && p < 4; p++)
            write_back(&image, p);
    exrio_close(&image);
    return 0;
}
