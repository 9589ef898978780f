/* SPDX-License-Identifier: MIT */
/* call_checks.c - what the public diffusion calls check before anything runs: the params, the
 * images and their values, the foreground element. Every check happens before the first output
 * pixel is written, so a failed call leaves the output as it was. */
#include "call_checks.h"

#include "backends/backend.h"
#include "disc/disc_kernel.h"
#include "ddof_param_rules.h"
#include "runtime/parallel_rows.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

/* The numeric fields' ranges: ddof_param_rules.h. A range's ends in a message. */
#define LOW(id) ddof_param_range(id)->lowest
#define HIGH(id) ddof_param_range(id)->highest

ddof_status ddof_check_camera_aspect(ddof_context *context, const ddof_camera *camera)
{
    /* The ratio stretches the blur as the pixel aspect does: the diffusion gets the product. */
    const double aspect = camera->pixel_aspect * camera->aperture_ratio;
    if (aspect >= DDOF_MIN_PIXEL_ASPECT && aspect <= DDOF_MAX_PIXEL_ASPECT)
        return DDOF_OK;
    /* DDOF_ERROR_BAD_CAMERA, as for a pixel aspect <= 0 (ddof_camera_terms.h): one status
     * for one field. */
    if (camera->aperture_ratio != 1.0)
        return ddof_fail(context, DDOF_ERROR_BAD_CAMERA,
                         "camera pixel_aspect %.9g times aperture_ratio %.9g must be within "
                         "%g..%g for the diffusion",
                         camera->pixel_aspect, camera->aperture_ratio, DDOF_MIN_PIXEL_ASPECT,
                         DDOF_MAX_PIXEL_ASPECT);
    return ddof_fail(context, DDOF_ERROR_BAD_CAMERA,
                     "camera pixel_aspect %.9g must be within %g..%g for the diffusion",
                     camera->pixel_aspect, DDOF_MIN_PIXEL_ASPECT, DDOF_MAX_PIXEL_ASPECT);
}

/* The caller's params over the defaults (an older caller's struct lacks the layer fields),
 * then every value checked. */
ddof_status ddof_read_params(ddof_context *context, const ddof_params *caller, ddof_params *p)
{
    ddof_params_init(p);
    ddof_status status = ddof_read_struct(context, caller, offsetof(ddof_params, coc_signed), p,
                                          sizeof *p, "params");
    if (status != DDOF_OK)
        return status;
    if ((unsigned)p->solver >= DDOF_SOLVER_COUNT_)
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER, "params.solver %u is not a solver",
                         (unsigned)p->solver);
    if (!ddof_param_ok(PARAM_SUBSTEPS, p->substeps))
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.substeps %u must be within %g..%g", p->substeps,
                         LOW(PARAM_SUBSTEPS), HIGH(PARAM_SUBSTEPS));
    if (!ddof_param_ok(PARAM_BETA_SCALE, p->beta_scale))
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.beta_scale %.9g must be > 0 and at most %g",
                         (double)p->beta_scale, HIGH(PARAM_BETA_SCALE));
    if (!ddof_param_ok(PARAM_PIXEL_ASPECT, p->pixel_aspect))
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.pixel_aspect %.9g must be within %g..%g", (double)p->pixel_aspect,
                         DDOF_MIN_PIXEL_ASPECT, DDOF_MAX_PIXEL_ASPECT);
    if (p->solver == DDOF_SOLVER_JACOBI &&
        !ddof_param_ok(PARAM_JACOBI_ITERATIONS, p->jacobi_iterations))
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.jacobi_iterations %u must be within %g..%g",
                         p->jacobi_iterations, LOW(PARAM_JACOBI_ITERATIONS),
                         HIGH(PARAM_JACOBI_ITERATIONS));
    if (p->coc_signed > 1 || (unsigned)p->background > DDOF_LAYER_ON ||
        (unsigned)p->near_spread > DDOF_LAYER_ON)
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.coc_signed, background or near_spread is not a known value");
    if (!(ddof_param_ok(PARAM_BACKGROUND_RAMP_START, p->background_ramp_start_px) &&
          ddof_param_ok(PARAM_BACKGROUND_THRESHOLD, p->background_threshold_px) &&
          p->background_threshold_px > p->background_ramp_start_px))
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.background_threshold_px (%.9g) must exceed "
                         "background_ramp_start_px (%.9g) >= 0, both at most %g px",
                         (double)p->background_threshold_px,
                         (double)p->background_ramp_start_px, (double)DDOF_MAX_COC_PX);
    if (!ddof_param_ok(PARAM_BACKGROUND_LEVELS, p->background_levels))
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.background_levels %u must be within %g..%g",
                         p->background_levels, LOW(PARAM_BACKGROUND_LEVELS),
                         HIGH(PARAM_BACKGROUND_LEVELS));
    if (!ddof_param_ok(PARAM_NEAR_SPREAD_THRESHOLD, p->near_spread_threshold_px))
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.near_spread_threshold_px %.9g must be > 0 and at most %g px",
                         (double)p->near_spread_threshold_px, (double)DDOF_MAX_COC_PX);
    if ((unsigned)p->method > DDOF_METHOD_COD4_PREVIEW ||
        (unsigned)p->precision > DDOF_PRECISION_PACKED_HALF)
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.method %u or params.precision %u is not a known value",
                         (unsigned)p->method, (unsigned)p->precision);
    if (!ddof_param_ok(PARAM_IN_FOCUS_THRESHOLD, p->in_focus_threshold_px))
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.in_focus_threshold_px %.9g must be >= 0 and at most %g px",
                         (double)p->in_focus_threshold_px, (double)DDOF_MAX_COC_PX);
    if ((unsigned)p->highlights > DDOF_LAYER_ON ||
        !ddof_param_ok(PARAM_HIGHLIGHT_THRESHOLD, p->highlight_threshold))
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.highlights %u is not a known value, or highlight_threshold %.9g "
                         "is not > 0 and finite",
                         (unsigned)p->highlights, (double)p->highlight_threshold);
    if ((unsigned)p->near_layer > DDOF_LAYER_ON ||
        !ddof_param_ok(PARAM_NEAR_LAYER_THRESHOLD, p->near_layer_threshold_px))
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.near_layer %u is not a known value, or near_layer_threshold_px "
                         "%.9g is not > 0 and at most %g px",
                         (unsigned)p->near_layer, (double)p->near_layer_threshold_px,
                         (double)DDOF_MAX_COC_PX);
    if ((unsigned)p->far_field > DDOF_LAYER_ON || (unsigned)p->silhouettes > DDOF_LAYER_ON ||
        (unsigned)p->blurred_edges > DDOF_LAYER_ON)
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.far_field %u, silhouettes %u or blurred_edges %u is not a "
                         "known value",
                         (unsigned)p->far_field, (unsigned)p->silhouettes,
                         (unsigned)p->blurred_edges);
    if (p->near_layer == DDOF_LAYER_ON && p->near_spread == DDOF_LAYER_ON)
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.near_layer and near_spread are both forced on: where the near "
                         "layer runs it takes the near field, and the spread has none left");
    if ((unsigned)p->kernel >= DDOF_KERNEL_COUNT_)
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER, "params.kernel %u is not a kernel",
                         (unsigned)p->kernel);
    if (p->method == DDOF_METHOD_DIFFUSION) {
        ddof_status supported = ddof_check_backend_supports(context, p->solver, p->precision);
        if (supported != DDOF_OK)
            return supported;
    }
    return DDOF_OK;
}

ddof_status ddof_check_near_spread(ddof_context *context, const ddof_params *p)
{
    if (p->near_spread == DDOF_LAYER_ON && !p->coc_signed)
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.near_spread is forced on, but the CoC is unsigned: without "
                         "coc_signed = 1 the near field is unknown");
    if (p->near_layer == DDOF_LAYER_ON && !p->coc_signed)
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.near_layer is forced on, but the CoC is unsigned: without "
                         "coc_signed = 1 the near field is unknown");
    return DDOF_OK;
}

static ddof_status check_same_size(ddof_context *context, const char *what, uint32_t width,
                                   uint32_t height, uint32_t w, uint32_t h)
{
    if (width != w || height != h)
        return ddof_fail(context, DDOF_ERROR_SIZE_MISMATCH, "%s is %ux%u but colour is %ux%u",
                         what, width, height, w, h);
    return DDOF_OK;
}

/* Checks one more image of the call: valid, the colour's size; *stride in floats. */
ddof_status ddof_check_map(ddof_context *context, const char *what, const ddof_image_in *map,
                           const adi_request *r, size_t *stride)
{
    if (!map)
        return ddof_fail(context, DDOF_ERROR_NULL_POINTER, "%s image is NULL", what);
    ddof_status status = ddof_check_image(context, what, map->pixels, map->width, map->height,
                                          map->channels, map->row_stride, stride);
    if (status == DDOF_OK)
        status = check_same_size(context, what, map->width, map->height, r->width, r->height);
    return status;
}

/* Checks colour, the per-pixel input (CoC or depth) and out, and fills the request's images. */
ddof_status ddof_check_call_images(ddof_context *context, const ddof_image_in *color,
                                   const ddof_image_in *map, const char *map_name,
                                   const ddof_image *out, adi_request *r, size_t *map_stride)
{
    if (!color || !out)
        return ddof_fail(context, DDOF_ERROR_NULL_POINTER, "%s image is NULL",
                         !color ? "colour" : "output");
    ddof_status status = ddof_check_image(context, "colour", color->pixels, color->width,
                                          color->height, color->channels, color->row_stride,
                                          &r->color_stride);
    if (status != DDOF_OK)
        return status;
    r->width = color->width;
    r->height = color->height;
    r->channels = color->channels;
    status = ddof_check_map(context, map_name, map, r, map_stride);
    if (status == DDOF_OK)
        status = ddof_check_image(context, "output", out->pixels, out->width, out->height,
                                  out->channels, out->row_stride, &r->out_stride);
    if (status == DDOF_OK)
        status = check_same_size(context, "output", out->width, out->height, color->width,
                                 color->height);
    if (status != DDOF_OK)
        return status;
    if (out->channels != color->channels)
        return ddof_fail(context, DDOF_ERROR_SIZE_MISMATCH,
                         "output has %u channels but colour has %u", out->channels,
                         color->channels);
    if (out->pixels == color->pixels && r->out_stride != r->color_stride)
        return ddof_fail(context, DDOF_ERROR_BAD_STRIDE,
                         "in-place diffusion needs the same stride for colour and output");
    r->color = color->pixels;
    r->out = out->pixels;

    bad_value bad;
    if (ddof_find_bad_value(context, color->pixels, color->width, color->height,
                            color->channels, color->channels, r->color_stride, VALUE_COLOR,
                            &bad, NULL))
        return ddof_fail(context, DDOF_ERROR_BAD_COLOR,
                         "colour at pixel (%u, %u) channel %u is %g (colour must be finite and "
                         "within +-%g)", bad.x, bad.y, bad.channel, (double)bad.value,
                         (double)DDOF_MAX_COLOR);
    return DDOF_OK;
}

ddof_status ddof_check_coc_values(ddof_context *context, const ddof_image_in *coc,
                                  size_t stride, int coc_signed, float *max_abs)
{
    bad_value bad;
    if (ddof_find_bad_value(context, coc->pixels, coc->width, coc->height, coc->channels, 1,
                            stride, coc_signed ? VALUE_COC_SIGNED : VALUE_COC, &bad, max_abs))
        return ddof_fail(context, DDOF_ERROR_BAD_COC,
                         "CoC at pixel (%u, %u) is %.9g; it must be finite, within %s0..%g px",
                         bad.x, bad.y, (double)bad.value, coc_signed ? "+-" : "",
                         (double)DDOF_MAX_COC_PX);
    return DDOF_OK;
}

void ddof_fill_request_params(const ddof_context *context, adi_request *r, const ddof_params *p)
{
    r->solver = p->solver;
    r->precision = p->precision;
    r->substeps = p->substeps;
    r->jacobi_iterations = p->jacobi_iterations;
    r->beta_scale = p->beta_scale;
    r->pixel_aspect = p->pixel_aspect;
    r->disc = p->method == DDOF_METHOD_DIFFUSION
                  ? ddof_backend_disc_kernel(context, p->solver, p->kernel)
                  : NULL;
    r->progress = p->progress;
    r->progress_user = p->progress_user;
    r->in_focus_px = p->in_focus_threshold_px;
}
/* ---- the foreground element ------------------------------------------------------------- */

typedef struct foreground_scan {
    const float *color, *coc;
    size_t color_stride, coc_stride;
    uint32_t coc_channels, width;
    bad_value *first_bad; /* per chunk; channel 4 marks a bad CoC */
    unsigned char *found, *has_alpha;
    pixel_box *box;       /* per chunk: where alpha > 0 */
    float *max_coc;       /* per chunk: largest |CoC| where alpha > 0 */
} foreground_scan;

/* Alpha must be finite everywhere; colour and CoC only matter (and are only read) where
 * alpha > 0, so NaN under alpha 0 is accepted. */
static void scan_foreground_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    const foreground_scan *s = user;
    s->found[chunk] = 0;
    s->has_alpha[chunk] = 0;
    s->box[chunk] = box_empty();
    s->max_coc[chunk] = 0.0f;
    for (uint32_t y = y0; y < y1; y++) {
        const float *px = s->color + (size_t)y * s->color_stride;
        const float *coc = s->coc + (size_t)y * s->coc_stride;
        for (uint32_t x = 0; x < s->width; x++) {
            const float alpha = px[x * 4 + 3];
            const float d = fabsf(coc[(size_t)x * s->coc_channels]);
            int bad_channel = -1;
            if (!isfinite(alpha))
                bad_channel = 3;
            else if (alpha > 0.0f) {
                for (int c = 0; c < 3 && bad_channel < 0; c++)
                    if (!(fabsf(px[x * 4 + c]) <= DDOF_MAX_COLOR))
                        bad_channel = c;
                if (bad_channel < 0 && !(d <= DDOF_MAX_COC_PX))
                    bad_channel = 4;
                s->has_alpha[chunk] = 1;
                box_add(&s->box[chunk], x, y);
                if (d > s->max_coc[chunk])
                    s->max_coc[chunk] = d;
            }
            if (bad_channel >= 0 && !s->found[chunk]) {
                s->first_bad[chunk] =
                    (bad_value){x, y, (uint32_t)bad_channel,
                                bad_channel == 4 ? coc[(size_t)x * s->coc_channels]
                                                 : px[x * 4 + bad_channel]};
                s->found[chunk] = 1;
            }
        }
    }
}

/* Validates the element and fills the request's foreground fields; *visible says whether any
 * alpha > 0 (an element with none changes nothing and is skipped). */
ddof_status ddof_read_foreground(ddof_context *context, const ddof_foreground *caller,
                                 layers_request *q, int *visible)
{
    ddof_foreground fg;
    ddof_foreground_init(&fg);
    ddof_status status = ddof_read_struct(context, caller, DDOF_FOREGROUND_SIZE_0_5, &fg,
                                          sizeof fg, "foreground");
    if (status != DDOF_OK)
        return status;
    const adi_request *r = &q->base;
    if (r->channels < 3)
        return ddof_fail(context, DDOF_ERROR_BAD_CHANNELS,
                         "a foreground element needs colour with 3 or 4 channels, not %u",
                         r->channels);
    size_t color_stride, coc_stride;
    status = ddof_check_map(context, "foreground colour", &fg.color, r, &color_stride);
    if (status == DDOF_OK)
        status = ddof_check_map(context, "foreground coc", &fg.coc, r, &coc_stride);
    if (status != DDOF_OK)
        return status;
    if (fg.color.channels != 4)
        return ddof_fail(context, DDOF_ERROR_BAD_CHANNELS,
                         "foreground colour has %u channels; it must be RGBA (4)",
                         fg.color.channels);

    enum { max_chunks = (DDOF_MAX_DIMENSION + DDOF_ROWS_PER_CHUNK - 1) / DDOF_ROWS_PER_CHUNK };
    bad_value first_bad[max_chunks];
    unsigned char found[max_chunks], has_alpha[max_chunks];
    pixel_box box[max_chunks];
    float max_coc[max_chunks];
    foreground_scan scan = {fg.color.pixels, fg.coc.pixels, color_stride, coc_stride,
                            fg.coc.channels, r->width, first_bad, found, has_alpha, box, max_coc};
    ddof_parallel_rows(context, r->height, scan_foreground_rows, &scan);
    *visible = 0;
    q->fg.box = box_empty();
    q->fg.max_coc = 0.0f;
    for (uint32_t c = 0; c < ddof_row_chunks(r->height); c++) {
        q->fg.box = box_union(q->fg.box, box[c]);
        q->fg.max_coc = ddof_maxf(q->fg.max_coc, max_coc[c]);
        if (found[c]) {
            const bad_value b = first_bad[c];
            return b.channel == 4
                       ? ddof_fail(context, DDOF_ERROR_BAD_COC,
                                   "foreground CoC at pixel (%u, %u) is %g", b.x, b.y,
                                   (double)b.value)
                       : ddof_fail(context, DDOF_ERROR_BAD_COLOR,
                                   "foreground colour at pixel (%u, %u) channel %u is %g "
                                   "(colour must be finite and within +-%g)", b.x, b.y,
                                   b.channel, (double)b.value, (double)DDOF_MAX_COLOR);
        }
        *visible |= has_alpha[c];
    }
    q->fg.color = fg.color.pixels;
    q->fg.color_stride = color_stride;
    q->fg.coc = fg.coc.pixels;
    q->fg.coc_stride = coc_stride;
    q->fg.coc_channels = fg.coc.channels;
    q->fg.premultiplied = fg.premultiplied != 0;
    return DDOF_OK;
}
