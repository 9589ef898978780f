/* SPDX-License-Identifier: MIT */
/* preview_cod4.h - the practical post-process depth of field of Call of Duty 4 (GPU Gems 3
 * ch. 28, Earl Hammon Jr.) as libddof's fast preview mode: near CoC at quarter resolution,
 * blurred and dilated (D = max(D0, 2 D_blurred - D0)), three blur levels interpolated by CoC. */
#ifndef DDOF_PREVIEW_COD4_H
#define DDOF_PREVIEW_COD4_H

#include "adi/adi.h"

/* Runs the preview on a validated request: r->color (r->channels), r->coc (first of
 * r->coc_channels floats per pixel; negative = near field when coc_signed, otherwise all
 * CoC is treated as far) into r->out (may equal r->color). Solver fields of r are ignored;
 * r->progress is honoured. Fills report->seconds_rows (all the time), max_coc, threads.
 * Output stays within the input's range per channel (every level is a convex blend). */
ddof_status ddof_cod4_preview(ddof_context *context, const adi_request *r, int coc_signed,
                              adi_report *report);

#endif
