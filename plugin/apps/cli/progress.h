/* SPDX-License-Identifier: MIT */
/* progress.h - a one-line progress bar on stderr for frame sequences, shared by the worker
 * threads. It is drawn only when enabled (by default: when stderr is a terminal), so logs of
 * batch jobs get clean per-frame lines and no carriage-return noise. Every other line the
 * command prints goes through progress_print() so that it appears above the bar. */
#ifndef DDOF_CLI_PROGRESS_H
#define DDOF_CLI_PROGRESS_H

#include <stdio.h>

typedef struct progress progress;

/* `slots`: how many frames may be in flight at once (worker threads). NULL on no memory. */
progress *progress_create(int enabled, int total_frames, int slots);
void progress_free(progress *p);

/* The frame in worker `slot` is `fraction` done (0..1). Cheap; redraws at most 10 times/s. */
void progress_update(progress *p, int slot, float fraction);
/* The frame in worker `slot` is finished (written or failed). */
void progress_frame_done(progress *p, int slot);
/* Prints `text` (ending in a newline) to `to`, above the bar. */
void progress_print(progress *p, FILE *to, const char *text);
/* Removes the bar (at the end). */
void progress_finish(progress *p);

#endif
