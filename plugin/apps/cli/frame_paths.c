/* SPDX-License-Identifier: MIT */
/* frame_paths.c - each frame's paths from the options' patterns (frame_paths.h). */
#include "frame_paths.h"

#include "frames.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int frame_paths_expand(const char *pattern, int frame, char *out, const char *what)
{
    if (!pattern) {
        out[0] = '\0';
        return 0;
    }
    if (frame < 0) {
        if (strlen(pattern) >= PATH_MAX) {
            fprintf(stderr, "ddof: %s path too long\n", what);
            return -1;
        }
        strcpy(out, pattern);
        return 0;
    }
    if (frames_expand(pattern, frame, out, PATH_MAX) != 0) {
        fprintf(stderr, "ddof: %s path too long\n", what);
        return -1;
    }
    return 0;
}

frame_paths *frame_paths_build(const cli_options *o, int *count)
{
    int *frames = NULL;
    int n = 1, i;
    frame_paths *paths;

    if (o->frames) {
        char error[256];
        n = frames_parse(o->frames, &frames, error, sizeof error);
        if (n < 0) {
            fprintf(stderr, "ddof: %s\n", error);
            return NULL;
        }
        if (!frames_has_pattern(o->input) || !frames_has_pattern(o->output) ||
            (o->preview && !frames_has_pattern(o->preview)) ||
            (o->preview_input && !frames_has_pattern(o->preview_input)) ||
            (o->focus_map && !frames_has_pattern(o->focus_map))) {
            fprintf(stderr, "ddof: with --frames, the input, -o and preview paths need a run "
                    "of '#' for the frame number (render_####.exr)\n");
            free(frames);
            return NULL;
        }
    }
    paths = calloc((size_t)n, sizeof *paths);
    if (!paths) {
        fprintf(stderr, "ddof: out of memory\n");
        free(frames);
        return NULL;
    }
    for (i = 0; i < n; i++) {
        const int f = frames ? frames[i] : -1;
        paths[i].frame = f;
        if (frame_paths_expand(o->input, f, paths[i].input, "input") ||
            frame_paths_expand(o->output, f, paths[i].output, "output") ||
            frame_paths_expand(o->preview, f, paths[i].preview, "preview") ||
            frame_paths_expand(o->preview_input, f, paths[i].preview_input, "input preview") ||
            frame_paths_expand(o->focus_map, f, paths[i].focus_map, "focus map") ||
            frame_paths_expand(o->depth_file, f, paths[i].depth_file, "depth file") ||
            frame_paths_expand(o->foreground, f, paths[i].foreground, "foreground") ||
            frame_paths_expand(o->compare, f, paths[i].compare, "compare")) {
            free(paths);
            free(frames);
            return NULL;
        }
    }
    free(frames);
    *count = n;
    return paths;
}
