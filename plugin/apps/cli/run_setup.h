/* SPDX-License-Identifier: MIT */
/* run_setup.h - everything checked once, before the first frame is read: the parameters
 * (the library's preset < flags), the camera (defaults < sidecar < flags) and the library's
 * judgement of them and of the backend, the frame list, the outputs' paths (path_safety.h),
 * the first frame's header. A 240-frame job with a typo fails in a second, not after frame 1
 * or frame 240. */
#ifndef DDOF_CLI_RUN_SETUP_H
#define DDOF_CLI_RUN_SETUP_H

#include "frame_job.h"
#include "options.h"

#include <stdint.h>

/* Fills *setup and the frames' paths (*paths, *count; free them and setup->aperture_pixels),
 * and *pixels, the first frame's size (0 when unknown). Returns 0, or the exit status with
 * nothing to free. */
int run_setup_prepare(const cli_options *o, frame_setup *setup, frame_paths **paths, int *count,
                      uint64_t *pixels);

#endif

