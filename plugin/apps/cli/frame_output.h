/* SPDX-License-Identifier: MIT */
/* frame_output.h - what a frame writes: the EXR (the result, and with --keep-channels and
 * --write-coc the input's other channels and the CoC), the previews and the focal-plane view,
 * each atomically (output_file.h); then the comparison with the truth (frame_compare.h). */
#ifndef DDOF_CLI_FRAME_OUTPUT_H
#define DDOF_CLI_FRAME_OUTPUT_H

#include "frame_input.h"
#include "progress.h"

/* The EXR, the previews and the comparison with the truth; the focal-plane view through the
 * frame's context. Returns 0 or -1 (result->error). */
int frame_output_write(ddof_context *context, const frame_setup *setup,
                       const frame_paths *paths, const frame_data *d, frame_result *result,
                       progress *bar, int slot);

#endif

