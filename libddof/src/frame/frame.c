/* SPDX-License-Identifier: MIT */
/* frame.c - the one call a host needs (ddof_render_frame): the CoC from the frame's source,
 * the foreground element's CoC from its own depth, then the planned layers. Also the checks a
 * host runs before it has pixels (ddof_params_check, ddof_camera_check). */
#include "call_checks.h"
#include "camera/coc.h"
#include "passes/element_edges.h"
#include "frame_run.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

void ddof_frame_init_sized(ddof_frame *frame, size_t size)
{
    if (!frame || size < sizeof(uint32_t))
        return;
    ddof_frame full;
    memset(&full, 0, sizeof full);
    full.foreground_premultiplied = 1;
    const size_t n = size < sizeof full ? size : sizeof full;
    memcpy(frame, &full, n);
    frame->struct_size = (uint32_t)n;
}

/* For binaries built against 0.5, whose struct has the 0.5 layout (ddof.h, Conventions). */
void (ddof_frame_init)(ddof_frame *frame)
{
    ddof_frame_init_sized(frame, DDOF_FRAME_SIZE_0_5);
}

ddof_status ddof_check_element_allowed(ddof_context *context, const ddof_params *p)
{
    if (p->method == DDOF_METHOD_COD4_PREVIEW)
        return ddof_fail(context, DDOF_ERROR_UNSUPPORTED,
                         "the CoD4 preview blurs one image and takes no foreground element");
    if (p->near_spread == DDOF_LAYER_ON || p->near_layer == DDOF_LAYER_ON)
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.%s is forced on, but a foreground element is given: the "
                         "element is the near field, and the %s works on one image only",
                         p->near_spread == DDOF_LAYER_ON ? "near_spread" : "near_layer",
                         p->near_spread == DDOF_LAYER_ON ? "near spread" : "near layer");
    return DDOF_OK;
}

typedef enum coc_source { SOURCE_CAMERA, SOURCE_CURVE, SOURCE_GIVEN } coc_source;

/* Everything the frame call reads, validated. */
typedef struct frame_setup {
    ddof_frame frame;
    coc_source source;
    ddof_camera camera;
    ddof_curve curve;
    int aperture_camera; /* a CoC image with a camera: the camera gives the aperture only */
    int has_foreground;
    size_t map_stride, fg_map_stride, coc_out_stride; /* in floats */
} frame_setup;

static int given(const ddof_image_in *image)
{
    return image->pixels != NULL;
}

static ddof_status read_source(ddof_context *context, frame_setup *s, ddof_params *p)
{
    /* Depth missing beside a camera or curve is the image check's NULL pointer. A CoC image
     * (a renderer's CoC pass) with a camera and no depth takes the camera's aperture: its
     * blades, rotation, ratio, cat's eye or image shape the blur as they do from depth. */
    const ddof_frame *f = &s->frame;
    s->aperture_camera = f->camera && given(&f->coc) && !given(&f->depth) && !f->curve;
    const int sources =
        (f->camera != NULL && !s->aperture_camera) + (f->curve != NULL) + given(&f->coc);
    if (sources != 1 || (given(&f->coc) && given(&f->depth)))
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "a frame needs exactly one CoC source: depth with a camera, depth with "
                         "a curve, or a CoC image (with a camera for its aperture, optionally) "
                         "(given: %s%s%s%s)",
                         f->camera ? "camera " : "", f->curve ? "curve " : "",
                         given(&f->depth) ? "depth " : "", given(&f->coc) ? "coc" : "");
    ddof_status status = DDOF_OK;
    if (s->aperture_camera) {
        s->source = SOURCE_GIVEN;
        status = ddof_read_camera(context, f->camera, &s->camera);
        if (status == DDOF_OK)
            status = ddof_check_camera_aspect(context, &s->camera);
        /* The ratio's ellipse, as from depth (the CoC image is the blur's width). */
        p->pixel_aspect = (float)(s->camera.pixel_aspect * s->camera.aperture_ratio);
    } else if (f->camera) {
        s->source = SOURCE_CAMERA;
        status = ddof_read_camera(context, f->camera, &s->camera);
        if (status == DDOF_OK)
            status = ddof_check_camera_aspect(context, &s->camera);
        /* Signed, so the planner knows the near field from the far. */
        s->camera.signed_coc = 1;
        p->coc_signed = 1;
        p->pixel_aspect = (float)(s->camera.pixel_aspect * s->camera.aperture_ratio);
    } else if (f->curve) {
        s->source = SOURCE_CURVE;
        status = ddof_read_curve(context, f->curve, &s->curve);
        s->curve.signed_coc = 1;
        p->coc_signed = 1;
    } else {
        s->source = SOURCE_GIVEN;
    }
    return status;
}

static ddof_status check_foreground(ddof_context *context, frame_setup *s, const ddof_params *p,
                                    const adi_request *r)
{
    const ddof_frame *f = &s->frame;
    s->has_foreground = given(&f->foreground_color);
    const int depth_given = given(&f->foreground_depth), coc_given = given(&f->foreground_coc);
    if (!s->has_foreground) {
        if (depth_given || coc_given)
            return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                             "the frame has a foreground %s but no foreground colour",
                             depth_given ? "depth" : "coc");
        return DDOF_OK;
    }
    ddof_status allowed = ddof_check_element_allowed(context, p);
    if (allowed != DDOF_OK)
        return allowed;
    const int wants_coc = s->source == SOURCE_GIVEN;
    if (wants_coc ? !coc_given || depth_given : !depth_given || coc_given)
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "the foreground element needs its own %s (as the frame's CoC comes "
                         "from %s), and only that",
                         wants_coc ? "coc" : "depth", wants_coc ? "a CoC image" : "depth");
    return ddof_check_map(context, wants_coc ? "foreground coc" : "foreground depth",
                          wants_coc ? &f->foreground_coc : &f->foreground_depth, r,
                          &s->fg_map_stride);
}

/* coc_out: valid, the frame's size with 1 channel, sharing no byte with an input (the matte
 * included: the split reads it after the CoC is written) or the output. The matte, when
 * given, is already validated. */
static ddof_status check_coc_out(ddof_context *context, frame_setup *s,
                                 const ddof_image_in *matte, const adi_request *r)
{
    const ddof_image *c = &s->frame.coc_out;
    if (!c->pixels)
        return DDOF_OK;
    ddof_status status = ddof_check_coc_image(context, "coc_out", ddof_as_input(c), r->width,
                                              r->height, &s->coc_out_stride);
    if (status != DDOF_OK)
        return status;
    const ddof_frame *f = &s->frame;
    const ddof_image_in *inputs[7] = {&f->color, &f->depth, &f->coc, &f->foreground_color,
                                      &f->foreground_depth, &f->foreground_coc, matte};
    static const char *const names[7] = {"the frame's colour", "the frame's depth",
                                         "the frame's coc", "the frame's foreground colour",
                                         "the frame's foreground depth",
                                         "the frame's foreground coc", "the matte"};
    const ddof_image_bytes bytes =
        ddof_image_bytes_of(c->pixels, c->width, c->height, c->channels, c->row_stride);
    for (int i = 0; i < 7; i++) {
        if (!inputs[i] || !inputs[i]->pixels)
            continue;
        status = ddof_check_apart(context, "coc_out", bytes, names[i],
                                  ddof_image_bytes_of(inputs[i]->pixels, inputs[i]->width,
                                                      inputs[i]->height, inputs[i]->channels,
                                                      inputs[i]->row_stride));
        if (status != DDOF_OK)
            return status;
    }
    return ddof_check_apart(context, "coc_out", bytes, "the output image",
                            ddof_image_bytes_of(r->out, r->width, r->height, r->channels,
                                                r->out_stride * sizeof(float)));
}

/* The CoC of `depth` (validated, stride in floats) from the setup's camera or curve. */
static ddof_status compute_coc(ddof_context *context, const frame_setup *s,
                               const ddof_image_in *depth, size_t depth_stride, float *coc,
                               size_t coc_stride)
{
    return s->source == SOURCE_CAMERA
               ? ddof_compute_coc_camera(context, &s->camera, depth, depth_stride, coc,
                                         coc_stride)
               : ddof_compute_coc_curve(context, &s->curve, depth, depth_stride, coc,
                                        coc_stride);
}

/* The element's CoC (computed into scratch when it comes from its depth), then its checks. */
static ddof_status prepare_foreground(ddof_context *context, const frame_setup *s,
                                      layers_request *q, int *visible)
{
    const ddof_frame *f = &s->frame;
    const adi_request *r = &q->base;
    ddof_foreground element;
    ddof_foreground_init(&element);
    element.color = f->foreground_color;
    element.premultiplied = f->foreground_premultiplied;
    if (s->source == SOURCE_GIVEN) {
        element.coc = f->foreground_coc;
    } else {
        float *coc = ddof_scratch_get(context, DDOF_SCRATCH_FOREGROUND_COC,
                                      (size_t)r->width * r->height * sizeof(float));
        if (!coc)
            return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                             "could not allocate the %ux%u foreground CoC buffer", r->width,
                             r->height);
        ddof_status status = compute_coc(context, s, &f->foreground_depth, s->fg_map_stride,
                                         coc, r->width);
        if (status != DDOF_OK)
            return status;
        /* The edge fix reads the element's alpha; an element that fails its checks is
         * reported by ddof_read_foreground below. */
        const ddof_image_in *fc = &f->foreground_color;
        size_t color_stride = 0;
        if (fc->width == r->width && fc->height == r->height && fc->channels == 4 &&
            ddof_check_image(context, "foreground colour", fc->pixels, fc->width, fc->height,
                             fc->channels, fc->row_stride, &color_stride) == DDOF_OK)
            ddof_fix_element_edges(context, fc->pixels, color_stride,
                                   f->foreground_depth.pixels, s->fg_map_stride,
                                   f->foreground_depth.channels, coc, r->width, r->height);
        element.coc = (ddof_image_in){coc, r->width, r->height, 1, 0};
    }
    return ddof_read_foreground(context, &element, q, visible);
}

/* The frame's CoC: into coc_out when the caller wants it, else into scratch; a given CoC is
 * checked (*max_coc its largest |CoC|; left negative for a computed one, which the planner
 * measures) and, for coc_out, copied. */
static ddof_status prepare_coc(ddof_context *context, const frame_setup *s, const ddof_params *p,
                               adi_request *r, float *max_coc)
{
    const ddof_frame *f = &s->frame;
    if (s->source == SOURCE_GIVEN) {
        ddof_status status = ddof_check_coc_values(context, &f->coc, s->map_stride,
                                                   (int)p->coc_signed, max_coc);
        if (status != DDOF_OK)
            return status;
        r->coc = f->coc.pixels;
        r->coc_stride = s->map_stride;
        r->coc_channels = f->coc.channels;
        if (f->coc_out.pixels)
            for (uint32_t y = 0; y < r->height; y++) {
                const float *from = f->coc.pixels + (size_t)y * s->map_stride;
                float *to = f->coc_out.pixels + (size_t)y * s->coc_out_stride;
                for (uint32_t x = 0; x < r->width; x++)
                    to[x] = from[(size_t)x * f->coc.channels];
            }
        return DDOF_OK;
    }
    float *coc = f->coc_out.pixels;
    size_t stride = s->coc_out_stride;
    if (!coc) {
        coc = ddof_scratch_get(context, DDOF_SCRATCH_COC,
                               (size_t)r->width * r->height * sizeof(float));
        stride = r->width;
        if (!coc)
            return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                             "could not allocate the %ux%u CoC buffer", r->width, r->height);
    }
    ddof_status status = compute_coc(context, s, &f->depth, s->map_stride, coc, stride);
    r->coc = coc;
    r->coc_stride = stride;
    r->coc_channels = 1;
    return status;
}

/* The highlights' aperture from the camera; the frame is the full one when the image is a crop. */
static highlight_aperture aperture_of(const ddof_camera *c, uint32_t width, uint32_t height)
{
    const double frame_w = c->frame_width ? c->frame_width : width;
    const double frame_h = c->frame_height ? c->frame_height : height;
    return (highlight_aperture){
        .blades = c->aperture_blades,
        .rotation_rad = c->aperture_rotation_deg * (3.14159265358979323846 / 180.0),
        .catseye = c->aperture_catseye,
        .centre_x = 0.5 * frame_w - c->window_x,
        .centre_y = 0.5 * frame_h - c->window_y,
        .half_width = 0.5 * frame_w,
        .half_height = 0.5 * frame_h,
        .image = c->aperture_image,
        .image_width = c->aperture_image_width,
        .image_height = c->aperture_image_height,
    };
}

/* An object matte: an image (ddof_check_image's rules) of the frame's size, an even number of
 * channels up to DDOF_MATTE_MAX_RANKS ranks, every coverage finite (ids are bit patterns: any
 * value), no byte shared with the output. */
static ddof_status read_matte(ddof_context *context, const ddof_image_in *matte,
                              const adi_request *r, object_matte *m)
{
    *m = (object_matte){0};
    if (!matte)
        return DDOF_OK;
    size_t stride;
    ddof_status status =
        ddof_check_image_up_to(context, "matte", matte->pixels, matte->width, matte->height,
                               matte->channels, 2 * DDOF_MATTE_MAX_RANKS, matte->row_stride,
                               &stride);
    if (status != DDOF_OK)
        return status;
    if (matte->width != r->width || matte->height != r->height)
        return ddof_fail(context, DDOF_ERROR_SIZE_MISMATCH, "the matte is %ux%u, the frame %ux%u",
                         matte->width, matte->height, r->width, r->height);
    if (matte->channels % 2)
        return ddof_fail(context, DDOF_ERROR_BAD_CHANNELS,
                         "the matte has %u channels: (id, coverage) per rank, an even count",
                         matte->channels);
    /* The split reads it after the layers wrote the output: the two must not share bytes. */
    status = ddof_check_apart(context, "the output image",
                              ddof_image_bytes_of(r->out, r->width, r->height, r->channels,
                                                  r->out_stride * sizeof(float)),
                              "the matte",
                              ddof_image_bytes_of(matte->pixels, matte->width, matte->height,
                                                  matte->channels, matte->row_stride));
    if (status != DDOF_OK)
        return status;
    *m = (object_matte){.pairs = matte->pixels, .stride = stride, .ranks = matte->channels / 2};
    for (uint32_t y = 0; y < r->height; y++)
        for (uint32_t x = 0; x < r->width; x++)
            for (uint32_t k = 0; k < m->ranks; k++) {
                const float coverage = m->pairs[(size_t)y * m->stride + (size_t)x * 2 * m->ranks +
                                                2 * k + 1];
                if (!isfinite(coverage))
                    return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                                     "matte coverage at pixel (%u, %u), rank %u, is %g",
                                     x, y, k, (double)coverage);
            }
    return DDOF_OK;
}

static ddof_status render_frame(ddof_context *context, const ddof_params *params,
                                const ddof_frame *frame, const ddof_image_in *matte,
                                const ddof_image *out, ddof_stats *stats)
{
    const double t_start = ddof_seconds();
    frame_setup s = {0};
    ddof_frame_init(&s.frame);
    ddof_params p;
    frame_request f = {.layers = {.params = &p}};
    layers_request *q = &f.layers;
    adi_request *r = &q->base;
    float max_coc = -1.0f;
    ddof_status status = ddof_read_struct(context, frame, DDOF_FRAME_SIZE_0_5, &s.frame,
                                          sizeof s.frame, "frame");
    if (status == DDOF_OK)
        status = ddof_read_params(context, params, &p);
    if (status == DDOF_OK)
        status = ddof_check_stats(context, stats);
    if (status == DDOF_OK)
        status = read_source(context, &s, &p);
    if (status == DDOF_OK)
        status = ddof_check_near_spread(context, &p);
    if (status == DDOF_OK)
        status = ddof_check_call_images(context, &s.frame.color,
                                        s.source == SOURCE_GIVEN ? &s.frame.coc : &s.frame.depth,
                                        s.source == SOURCE_GIVEN ? "coc" : "depth", out, r,
                                        &s.map_stride);
    if (status == DDOF_OK)
        status = read_matte(context, matte, r, &q->matte);
    if (status == DDOF_OK)
        status = check_foreground(context, &s, &p, r);
    if (status == DDOF_OK)
        status = check_coc_out(context, &s, matte, r);
    if (status == DDOF_OK && s.has_foreground)
        status = prepare_foreground(context, &s, q, &f.element.visible);
    if (status == DDOF_OK)
        status = prepare_coc(context, &s, &p, r, &max_coc);
    if (status != DDOF_OK)
        return status;
    ddof_fill_request_params(context, r, &p);
    if (s.source == SOURCE_CAMERA || s.aperture_camera)
        q->aperture = aperture_of(&s.camera, r->width, r->height);
    f.element.given = s.has_foreground;
    f.known_max_coc = max_coc;
    f.t_start = t_start;
    f.seconds_coc = ddof_seconds() - t_start;
    return ddof_run_frame(context, &f, stats);
}

ddof_status ddof_render_frame(ddof_context *context, const ddof_params *params,
                              const ddof_frame *frame, const ddof_image *out, ddof_stats *stats)
{
    DDOF_EXCLUSIVE_CALL(context, render_frame(context, params, frame, NULL, out, stats));
}

ddof_status ddof_render_frame_with_matte(ddof_context *context, const ddof_params *params,
                                         const ddof_frame *frame, const ddof_image_in *matte,
                                         const ddof_image *out, ddof_stats *stats)
{
    DDOF_EXCLUSIVE_CALL(context, render_frame(context, params, frame, matte, out, stats));
}

static ddof_status depth_of_field(ddof_context *context, const ddof_params *params,
                                  const ddof_camera *camera, const ddof_image_in *color,
                                  const ddof_image_in *depth, const ddof_image *out,
                                  ddof_stats *stats)
{
    if (!camera || !color || !depth)
        return ddof_fail(context, DDOF_ERROR_NULL_POINTER, "%s is NULL",
                         !camera ? "camera" : !color ? "colour image" : "depth image");
    ddof_frame frame;
    ddof_frame_init(&frame);
    frame.color = *color;
    frame.depth = *depth;
    frame.camera = camera;
    return render_frame(context, params, &frame, NULL, out, stats);
}

ddof_status ddof_depth_of_field(ddof_context *context, const ddof_params *params,
                                const ddof_camera *camera, const ddof_image_in *color,
                                const ddof_image_in *depth, const ddof_image *out,
                                ddof_stats *stats)
{
    DDOF_EXCLUSIVE_CALL(context,
                        depth_of_field(context, params, camera, color, depth, out, stats));
}

ddof_status ddof_params_check(ddof_context *context, const ddof_params *params)
{
    ddof_params full;
    DDOF_EXCLUSIVE_CALL(context, ddof_read_params(context, params, &full));
}

static ddof_status camera_check(ddof_context *context, const ddof_camera *camera)
{
    ddof_camera full;
    ddof_status status = ddof_read_camera(context, camera, &full);
    return status == DDOF_OK ? ddof_check_camera_aspect(context, &full) : status;
}

ddof_status ddof_camera_check(ddof_context *context, const ddof_camera *camera)
{
    DDOF_EXCLUSIVE_CALL(context, camera_check(context, camera));
}

ddof_status ddof_curve_check(ddof_context *context, const ddof_curve *curve)
{
    ddof_curve full;
    DDOF_EXCLUSIVE_CALL(context, ddof_read_curve(context, curve, &full));
}
