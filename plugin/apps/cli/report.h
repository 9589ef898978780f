/* SPDX-License-Identifier: MIT */
/* report.h - what the command says about a run of frames: its plan, each frame's warning and
 * comparison with the truth, and the closing lines. */
#ifndef DDOF_CLI_REPORT_H
#define DDOF_CLI_REPORT_H

#include "frame.h"
#include "options.h"
#include "sequence.h"

/* The sequence's plan (frames at a time, threads per frame), for more than one frame. */
void report_plan(const cli_options *o, int count, const sequence_plan *plan);
/* Each frame's warning (once while it repeats) and comparison with the truth. */
void report_frame_notes(const frame_paths *paths, const frame_result *results, int count);
/* The closing lines: the failed frames, or how many were written in how long. */
void report_summary(const cli_options *o, const frame_paths *paths,
                    const frame_result *results, int count, int failed, double seconds);

#endif

