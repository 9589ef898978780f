/* SPDX-License-Identifier: MIT */
/* list.c - --list (list.h). */
#include "list.h"

#include "exrio.h"
#include "exrio_layout.h"
#include "frame_paths.h"
#include "frames.h"
#include "input_file.h"
#include "matte_input.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* --list: parts, channels, and what ddof would use. */
static int list_file(const cli_options *o, const char *path)
{
    exrio_image image;
    exrio_layout layout;
    exrio_layout_request request;
    char error[2048];
    int p, c;
    if (input_file_open_exr(path, "file to list", &image, error, sizeof error) != EXRIO_OK) {
        fprintf(stderr, "ddof: %s\n", error);
        return 1;
    }
    printf("%s: %d part%s\n", path, image.part_count, image.part_count == 1 ? "" : "s");
    for (p = 0; p < image.part_count; p++) {
        const exrio_part *part = &image.parts[p];
        printf("  part %d%s%s%s: %s, %s compression, data window (%d,%d)-(%d,%d) = %ux%u, "
               "display window (%d,%d)-(%d,%d), pixel aspect %g\n",
               p, part->name ? " '" : "", part->name ? part->name : "", part->name ? "'" : "",
               part->deep ? "deep" : part->tiled ? "tiled" : "scanline",
               exrio_compression_name(part->compression), (int)part->data_window.min_x,
               (int)part->data_window.min_y, (int)part->data_window.max_x,
               (int)part->data_window.max_y, part->width, part->height,
               (int)part->display_window.min_x, (int)part->display_window.min_y,
               (int)part->display_window.max_x, (int)part->display_window.max_y,
               (double)part->pixel_aspect);
        for (c = 0; c < image.channel_count; c++)
            if (image.channels[c].part == p)
                printf("    %-40s %s\n", image.channels[c].name,
                       exrio_pixel_type_name(image.channels[c].type));
    }
    memset(&request, 0, sizeof request);
    request.layer = o->layer;
    request.color = o->color;
    request.depth = o->depth;
    request.coc = o->source == COC_FROM_CHANNEL ? o->coc_channel : NULL;
    request.need_depth = o->source != COC_FROM_CHANNEL && !o->depth_file;
    if (exrio_find_layout(&image, &request, &layout, error, sizeof error) != EXRIO_LAYOUT_OK) {
        printf("ddof would not run on it: %s\n", error);
        exrio_close(&image);
        return 1;
    }
    printf("ddof uses: colour %s", image.channels[layout.color[0]].name);
    for (c = 1; c < layout.color_count; c++)
        printf(", %s", image.channels[layout.color[c]].name);
    if (layout.depth >= 0)
        printf("; depth %s", image.channels[layout.depth].name);
    if (layout.coc >= 0)
        printf("; CoC %s", image.channels[layout.coc].name);
    int matte[2 * DDOF_MATTE_MAX_RANKS];
    char matte_name[256];
    const int ranks = matte_find(&image, &layout, o->matte, matte, matte_name,
                                 sizeof matte_name, error, sizeof error);
    if (ranks > 0)
        printf("; matte %s (%d ranks)", matte_name, ranks);
    printf("\n");
    if (ranks < 0) {
        printf("ddof would not run on it: %s\n", error);
        exrio_close(&image);
        return 1;
    }
    exrio_close(&image);
    return 0;
}

int list_run(const cli_options *o)
{
    char first[PATH_MAX], error[2048];
    int *frames = NULL;
    const int n = o->frames ? frames_parse(o->frames, &frames, error, sizeof error) : 0;
    int rc;
    if (n < 0) {
        fprintf(stderr, "ddof: %s\n", error);
        return CLI_EXIT_USAGE;
    }
    rc = frame_paths_expand(o->input, frames ? frames[0] : -1, first, "input");
    free(frames);
    return rc != 0 ? CLI_EXIT_USAGE : list_file(o, first);
}
