/* SPDX-License-Identifier: MIT */
/* sequence.h - running a list of frames: one after another with one context using every
 * core, or several at once with one single-threaded context per worker thread when frames are
 * small (there the library's per-call thread start-up and the single-threaded EXR decode and
 * encode dominate, and whole frames in parallel use the cores better). */
#ifndef DDOF_CLI_SEQUENCE_H
#define DDOF_CLI_SEQUENCE_H

#include "frame_job.h"
#include "progress.h"

#include <stdint.h>

/* Frames of at most this many pixels run in parallel by default (when there are >= 2 frames
 * and >= 2 cores). Measured on the bundled 320x180 sample; see docs/cli.md. */
#define SEQUENCE_PARALLEL_MAX_PIXELS (2u * 1024u * 1024u)

typedef struct sequence_plan {
    uint32_t jobs;              /* frames in flight at once                      */
    uint32_t threads_per_frame; /* thread_count of each worker's context (0: all) */
    const char *reason;         /* one line on why                                */
} sequence_plan;

/* Chooses how to run `frames` frames of `pixels` pixels each with the options' --jobs and
 * --threads. */
sequence_plan sequence_plan_for(const cli_options *options, int frames, uint64_t pixels);

/* Runs every frame; fills results[i]. Prints a summary line per frame (unless quiet) and each
 * failure, above the progress bar. Returns the number of failed frames, or -1 when no worker
 * could start (error says why). */
int sequence_run(const frame_setup *setup, const frame_paths *paths, frame_result *results,
                 int count, const sequence_plan *plan, progress *bar, char *error,
                 size_t error_size);

#endif
