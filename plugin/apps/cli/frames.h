/* SPDX-License-Identifier: MIT */
/* frames.h - frame lists ("1-240", "1-240x2", "1,4,10-12") and path patterns in which a run
 * of '#' stands for the zero-padded frame number (render_####.exr -> render_0007.exr), as in
 * Blender's output paths. */
#ifndef DDOF_CLI_FRAMES_H
#define DDOF_CLI_FRAMES_H

#include <stddef.h>

/* A generous bound; a longer list is surely a typo (1-1000000000). */
#define FRAMES_MAX 1000000
/* The largest frame number: eight digits, as Blender's frame range allows. */
#define FRAMES_LARGEST 99999999

/* Parses `text` into a new array of frame numbers (ascending as written, duplicates removed).
 * Returns the count (>= 1), or -1 with a message in `error`. Free *frames with free(). */
int frames_parse(const char *text, int **frames, char *error, size_t error_size);

/* 1 when `pattern` has a run of '#'. */
int frames_has_pattern(const char *pattern);

/* Writes `pattern` with its last run of '#' replaced by `frame`, zero-padded to the run's
 * length. Returns 0, or -1 when it does not fit in out_size. */
int frames_expand(const char *pattern, int frame, char *out, size_t out_size);

#endif
