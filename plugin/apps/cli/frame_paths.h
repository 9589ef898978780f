/* SPDX-License-Identifier: MIT */
/* frame_paths.h - the frames' paths: one file, or the frames of --frames with the runs of '#'
 * in each path replaced by the frame number (frames.h). */
#ifndef DDOF_CLI_FRAME_PATHS_H
#define DDOF_CLI_FRAME_PATHS_H

#include "frame.h"
#include "options.h"

/* `pattern` for `frame` (-1: the path as given) into out (PATH_MAX); NULL gives "". Says on
 * stderr that the `what` path is too long and returns -1 when it does not fit. */
int frame_paths_expand(const char *pattern, int frame, char *out, const char *what);

/* The frame list (*count entries; free it), or NULL with the reason on stderr. */
frame_paths *frame_paths_build(const cli_options *o, int *count);

#endif

