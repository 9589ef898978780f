/* preview_cod4.c - placeholder until the CoD4 preview lands: copies colour to out. */
#include "preview_cod4.h"

#include <string.h>

ddof_status ddof_cod4_preview(ddof_context *context, const adi_request *r, int coc_signed,
                              adi_report *report)
{
    (void)context;
    (void)coc_signed;
    (void)report;
    if (r->out != r->color)
        for (uint32_t y = 0; y < r->height; y++)
            memcpy(r->out + (size_t)y * r->out_stride, r->color + (size_t)y * r->color_stride,
                   (size_t)r->width * r->channels * sizeof(float));
    return DDOF_OK;
}
