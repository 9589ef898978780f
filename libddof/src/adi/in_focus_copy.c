/* SPDX-License-Identifier: MIT */
/* in_focus_copy.c - a request with nothing out of focus: the output is the input (adi.h). */
#include "adi.h"

#include "disc/disc_kernel.h"
#include "runtime/parallel_rows.h"

void ddof_adi_copy_in_focus(ddof_context *context, const adi_request *r, adi_report *report,
                            float max_coc)
{
    ddof_parallel_copy(context, r->color, r->color_stride, r->out, r->out_stride,
                       (size_t)r->width * r->channels, r->height);
    /* Every line skipped, counted as the run would have: a disc kernel per component. */
    const uint64_t passes = r->disc ? r->disc->components : 1u;
    *report = (adi_report){.threads = context->thread_count,
                           .lines_skipped = ((uint64_t)r->width + r->height) * passes,
                           .max_coc = max_coc};
    if (r->progress)
        r->progress(r->progress_user, 1.0f);
}
