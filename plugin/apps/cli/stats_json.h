/* SPDX-License-Identifier: MIT */
/* stats_json.h - `--stats FILE.json`: per frame, what the library simulated and skipped and
 * why, and the time of every stage, for the accuracy study and for batch logs. Written with
 * cJSON, atomically (output_file.h). */
#ifndef DDOF_CLI_STATS_JSON_H
#define DDOF_CLI_STATS_JSON_H

#include "frame.h"

#include <stddef.h>

/* "midground + background" etc.: the DDOF_EFFECT_* bits of a call, in words. */
void stats_effects(const ddof_stats *stats, char *out, size_t out_size);

/* A sentence that says what a frame's diffusion did and why, from its ddof_stats. */
void stats_explain(const ddof_stats *stats, char *out, size_t out_size);

/* "backend cpu (CPU, 2 threads), method diffusion, memory 1.2 MB host, 0 B device; auto: the
 * CPU, because ...": which backend ran a frame, its renderer, AUTO's note. */
void stats_backend_line(const frame_result *result, char *out, size_t out_size);

/* The name of a ddof_method: "diffusion", "cod4". */
const char *stats_method_name(uint32_t method);

int stats_json_write(const char *path, const frame_setup *setup, const frame_paths *paths,
                     const frame_result *results, int count, uint32_t jobs,
                     uint32_t threads_per_frame, double seconds_wall, char *error,
                     size_t error_size);

#endif
