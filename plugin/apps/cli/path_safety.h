/* SPDX-License-Identifier: MIT */
/* path_safety.h - what the command may write, judged before the work: no output (EXR,
 * preview, focal-plane view, --stats) is an input of any frame or the camera sidecar, under
 * any spelling or link; no two outputs are one file; an output path holds nothing but a
 * regular file, in a directory that takes one; what a killed run left there is removed; and a
 * frame whose outputs are complete and fresh is skipped (--skip-existing). output_file.h
 * writes them. */
#ifndef DDOF_CLI_PATH_SAFETY_H
#define DDOF_CLI_PATH_SAFETY_H

#include "frame.h"
#include "options.h"

#include <stddef.h>

/* Checks the paths of one frame before any work: no output is one of its inputs, and the
 * outputs are not each other. Returns 0 or -1 (error). */
int frame_check_paths(const frame_paths *paths, char *error, size_t error_size);

/* Every frame's outputs and the --stats file, before the first frame: frame_check_paths, no
 * device, FIFO, socket, directory or link at an output path, no output an input of any
 * frame, --stats not an output, and directories that take a file. Says why on stderr;
 * returns 0 or -1. */
int path_safety_check_outputs(const cli_options *o, const frame_paths *paths, int count);

/* Removes the temporary files a killed run left in the output directories, with a note. */
void path_safety_remove_stale_temps(const cli_options *o, const frame_paths *first);

/* --skip-existing: 1 when every output of the frame (EXR and previews) is a regular file no
 * older than any of its inputs (colour, depth file, foreground, camera sidecar) and the EXR
 * opens; 0 when the frame must run. */
int frame_outputs_complete(const cli_options *options, const frame_paths *paths);

#endif

