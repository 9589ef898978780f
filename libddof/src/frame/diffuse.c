/* SPDX-License-Identifier: MIT */
/* diffuse.c - the public diffusion calls (ddof_diffuse, ddof_diffuse_layers): their checks;
 * the run is the frame's (frame_run.c). */
#include "call_checks.h"
#include "frame_run.h"

#include <stddef.h>

/* The checks every diffusion call shares: params, colour, CoC, output. */
static ddof_status prepare(ddof_context *context, const ddof_params *caller_params,
                           const ddof_image_in *color, const ddof_image_in *coc,
                           const ddof_image *out, const ddof_stats *stats, ddof_params *params,
                           adi_request *r, float *max_coc)
{
    size_t coc_stride = 0;
    ddof_status status = ddof_read_params(context, caller_params, params);
    if (status == DDOF_OK)
        status = ddof_check_stats(context, stats);
    if (status == DDOF_OK)
        status = ddof_check_near_spread(context, params);
    if (status == DDOF_OK)
        status = ddof_check_call_images(context, color, coc, "coc", out, r, &coc_stride);
    if (status == DDOF_OK)
        status = ddof_check_coc_values(context, coc, coc_stride, (int)params->coc_signed,
                                       max_coc);
    if (status != DDOF_OK)
        return status;
    r->coc = coc->pixels;
    r->coc_stride = coc_stride;
    r->coc_channels = coc->channels;
    ddof_fill_request_params(context, r, params);
    return DDOF_OK;
}

static ddof_status diffuse(ddof_context *context, const ddof_params *params,
                           const ddof_image_in *color, const ddof_image_in *coc,
                           const ddof_image *out, ddof_stats *stats)
{
    const double t_start = ddof_seconds();
    ddof_params p;
    adi_request r = {0};
    float max_coc = 0.0f;
    ddof_status status = prepare(context, params, color, coc, out, stats, &p, &r, &max_coc);
    if (status != DDOF_OK)
        return status;
    return ddof_run_one_diffusion(context, &r, &p, max_coc, stats, t_start,
                                  ddof_seconds() - t_start);
}

ddof_status ddof_diffuse(ddof_context *context, const ddof_params *params,
                         const ddof_image_in *color, const ddof_image_in *coc,
                         const ddof_image *out, ddof_stats *stats)
{
    DDOF_EXCLUSIVE_CALL(context, diffuse(context, params, color, coc, out, stats));
}

static ddof_status diffuse_layers(ddof_context *context, const ddof_params *params,
                                  const ddof_image_in *color, const ddof_image_in *coc,
                                  const ddof_foreground *foreground, const ddof_image *out,
                                  ddof_stats *stats)
{
    const double t_start = ddof_seconds();
    ddof_params p;
    frame_request f = {.layers = {.params = &p}};
    layers_request *q = &f.layers;
    float max_coc = 0.0f;
    ddof_status status = prepare(context, params, color, coc, out, stats, &p, &q->base, &max_coc);
    if (status == DDOF_OK && foreground)
        status = ddof_check_element_allowed(context, &p);
    if (status == DDOF_OK && foreground)
        status = ddof_read_foreground(context, foreground, q, &f.element.visible);
    if (status != DDOF_OK)
        return status;
    f.element.given = foreground != NULL;
    f.known_max_coc = max_coc;
    f.t_start = t_start;
    f.seconds_coc = ddof_seconds() - t_start;
    return ddof_run_frame(context, &f, stats);
}

ddof_status ddof_diffuse_layers(ddof_context *context, const ddof_params *params,
                                const ddof_image_in *color, const ddof_image_in *coc,
                                const ddof_foreground *foreground, const ddof_image *out,
                                ddof_stats *stats)
{
    DDOF_EXCLUSIVE_CALL(context,
                        diffuse_layers(context, params, color, coc, foreground, out, stats));
}
