/* SPDX-License-Identifier: MIT */
/* frame_job.h - one frame, start to finish: read the EXR and find its channels (frame_input.c),
 * one library call for the CoC and the depth of field (frame_job.c), write the EXR and the
 * previews atomically (frame_output.c), and optionally measure against a truth
 * (frame_compare.c). What a frame is: frame.h. What a frame may write is judged in
 * path_safety.c. */
#ifndef DDOF_CLI_FRAME_JOB_H
#define DDOF_CLI_FRAME_JOB_H

#include "frame.h"
#include "progress.h"

#include <ddof.h>

/* A context for one worker thread: thread_count threads (0: all cores) and the backend the
 * options ask for. Returns NULL with a sentence in error when either cannot be had. */
ddof_context *frame_context_create(const cli_options *options, uint32_t thread_count,
                                   char *error, size_t error_size);

/* Processes one frame with `context` (one per worker thread). `slot` is the worker's index for
 * the progress bar (which may be NULL). Fills *result; returns 0 on success, -1 on failure
 * (result->error says why). No partial output survives a failure. */
int frame_run(ddof_context *context, const frame_setup *setup, const frame_paths *paths,
              frame_result *result, progress *bar, int slot);

#endif
