/* SPDX-License-Identifier: MIT */
/* coc.c - circle of confusion from a camera and depth, or from the artist curve.
 *
 * A camera's CoC is d = k_px * |1 - S1/Z| pixels for either lens model (ddof_camera_terms.h,
 * shared with the GL plugin's device pass), computed in double and stored as float pixels. */
#include "coc.h"

#include "ddof_camera_terms.h"

#include "runtime/parallel_rows.h"

#include <math.h>
#include <stddef.h>

ddof_status ddof_read_camera(ddof_context *context, const ddof_camera *caller,
                             ddof_camera *camera)
{
    ddof_camera_init(camera);
    ddof_status status = ddof_read_struct(context, caller, offsetof(ddof_camera, signed_coc),
                                          camera, sizeof *camera, "camera");
    if (status != DDOF_OK)
        return status;
    char problem[256];
    if (ddof_camera_problem(camera, problem, sizeof problem))
        return ddof_fail(context, DDOF_ERROR_BAD_CAMERA, "%s", problem);
    return DDOF_OK;
}

ddof_status ddof_read_curve(ddof_context *context, const ddof_curve *caller, ddof_curve *curve)
{
    ddof_curve_init(curve);
    ddof_status status = ddof_read_struct(context, caller, offsetof(ddof_curve, signed_coc),
                                          curve, sizeof *curve, "curve");
    if (status != DDOF_OK)
        return status;
    const double d[4] = {curve->near_start, curve->near_end, curve->far_start, curve->far_end};
    for (int i = 0; i < 4; i++)
        if (!isfinite(d[i]) || d[i] < 0.0 || (i > 0 && d[i] < d[i - 1]))
            return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                             "curve distances must be finite, >= 0 and non-decreasing "
                             "(near_start %g, near_end %g, far_start %g, far_end %g)",
                             d[0], d[1], d[2], d[3]);
    if (!(curve->near_blur_px >= 0.0 && curve->near_blur_px <= DDOF_MAX_COC_PX) ||
        !(curve->far_blur_px >= 0.0 && curve->far_blur_px <= DDOF_MAX_COC_PX))
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "curve blur sizes must be within 0..%g px (near %g, far %g)",
                         (double)DDOF_MAX_COC_PX, curve->near_blur_px, curve->far_blur_px);
    return DDOF_OK;
}

/* The depth's first channel against `rule`; the error names the first bad pixel and what a
 * depth must be (`must_be`). */
static ddof_status check_depth(ddof_context *context, const ddof_image_in *depth,
                               size_t depth_stride, value_rule rule, const char *must_be)
{
    bad_value bad;
    if (ddof_find_bad_value(context, depth->pixels, depth->width, depth->height,
                            depth->channels, 1, depth_stride, rule, &bad, NULL))
        return ddof_fail(context, DDOF_ERROR_BAD_DEPTH,
                         "depth at pixel (%u, %u) is %g; it must be %s (+inf for the sky)",
                         bad.x, bad.y, (double)bad.value, must_be);
    return DDOF_OK;
}

typedef struct camera_job {
    const float *depth;
    size_t depth_stride;
    uint32_t depth_channels, width, height;
    float *coc;
    size_t coc_stride;
    ddof_camera_terms t;
} camera_job;

static void camera_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const camera_job *job = user;
    const ddof_camera_terms *t = &job->t;
    for (uint32_t y = y0; y < y1; y++) {
        const float *depth = job->depth + (size_t)y * job->depth_stride;
        float *coc = job->coc + (size_t)y * job->coc_stride;
        /* (double)y + window_y is the frame's row exactly: a crop's values are the frame's. */
        const double ys =
            ((double)y + t->window_y + 0.5 - 0.5 * t->frame_height) * t->pixel_h_over_f;
        for (uint32_t x = 0; x < job->width; x++) {
            double z = depth[(size_t)x * job->depth_channels];
            if (t->radial) {
                /* Planar Z of a point at distance r seen through this pixel's centre. */
                const double xs = ((double)x + t->window_x + 0.5 - 0.5 * t->frame_width) *
                                  t->pixel_w_over_f;
                z /= sqrt(1.0 + xs * xs + ys * ys);
            }
            const double d = t->k_px * fabs(1.0 - t->focus_units / z);
            const float clamped = d < DDOF_MAX_COC_PX ? (float)d : DDOF_MAX_COC_PX;
            coc[x] = t->signed_coc && z < t->focus_units ? -clamped : clamped;
        }
    }
}

ddof_status ddof_compute_coc_camera(ddof_context *context, const ddof_camera *camera,
                                    const ddof_image_in *depth, size_t depth_stride,
                                    float *coc, size_t coc_stride)
{
    const ddof_status status = check_depth(context, depth, depth_stride, VALUE_DEPTH, "> 0");
    if (status != DDOF_OK)
        return status;
    camera_job job = {
        .depth = depth->pixels, .depth_stride = depth_stride, .depth_channels = depth->channels,
        .width = depth->width, .height = depth->height, .coc = coc, .coc_stride = coc_stride,
        .t = ddof_camera_terms_of(camera, depth->width, depth->height),
    };
    ddof_parallel_rows(context, depth->height, camera_rows, &job);
    return DDOF_OK;
}

typedef struct curve_job {
    const float *depth;
    size_t depth_stride;
    uint32_t depth_channels, width;
    float *coc;
    size_t coc_stride;
    ddof_curve curve;
} curve_job;

/* Blur at depth z on the piecewise-linear curve; the ramps are skipped when they are empty. */
static double curve_blur(const ddof_curve *c, double z)
{
    if (z <= c->near_start)
        return c->near_blur_px;
    if (z < c->near_end)
        return c->near_blur_px * (c->near_end - z) / (c->near_end - c->near_start);
    if (z <= c->far_start)
        return 0.0;
    if (z < c->far_end)
        return c->far_blur_px * (z - c->far_start) / (c->far_end - c->far_start);
    return c->far_blur_px;
}

static void curve_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const curve_job *job = user;
    for (uint32_t y = y0; y < y1; y++) {
        const float *depth = job->depth + (size_t)y * job->depth_stride;
        float *coc = job->coc + (size_t)y * job->coc_stride;
        for (uint32_t x = 0; x < job->width; x++) {
            const double z = depth[(size_t)x * job->depth_channels];
            const float blur = (float)curve_blur(&job->curve, z);
            coc[x] = job->curve.signed_coc && z < job->curve.near_end ? -blur : blur;
        }
    }
}

ddof_status ddof_compute_coc_curve(ddof_context *context, const ddof_curve *curve,
                                   const ddof_image_in *depth, size_t depth_stride, float *coc,
                                   size_t coc_stride)
{
    const ddof_status status =
        check_depth(context, depth, depth_stride, VALUE_DEPTH_ZERO, ">= 0");
    if (status != DDOF_OK)
        return status;
    curve_job job = {depth->pixels, depth_stride, depth->channels, depth->width, coc,
                     coc_stride, *curve};
    ddof_parallel_rows(context, depth->height, curve_rows, &job);
    return DDOF_OK;
}

ddof_status ddof_check_image_and_coc(ddof_context *context, const char *what,
                                     const ddof_image_in *image, const ddof_image_in *coc,
                                     size_t *image_stride, size_t *coc_stride)
{
    if (!image || !coc)
        return ddof_fail(context, DDOF_ERROR_NULL_POINTER, "%s image is NULL",
                         image ? "coc" : what);
    const ddof_status status = ddof_check_image(context, what, image->pixels, image->width,
                                                image->height, image->channels,
                                                image->row_stride, image_stride);
    if (status != DDOF_OK)
        return status;
    return ddof_check_coc_image(context, "coc", *coc, image->width, image->height, coc_stride);
}

/* The public entry points: validate everything, then compute. */
/* The CoC from the camera (from_camera) or else from the curve: the model is read first, so
 * that its errors come before the images'. */
static ddof_status coc_from_model(ddof_context *context, int from_camera,
                                  const ddof_camera *camera, const ddof_curve *curve,
                                  const ddof_image_in *depth, const ddof_image *coc)
{
    ddof_camera full_camera;
    ddof_curve full_curve;
    ddof_status status = from_camera ? ddof_read_camera(context, camera, &full_camera)
                                     : ddof_read_curve(context, curve, &full_curve);
    size_t depth_stride, coc_stride;
    const ddof_image_in coc_in = coc ? ddof_as_input(coc) : (ddof_image_in){0};
    if (status == DDOF_OK)
        status = ddof_check_image_and_coc(context, "depth", depth, coc ? &coc_in : NULL,
                                          &depth_stride, &coc_stride);
    if (status != DDOF_OK)
        return status;
    return from_camera ? ddof_compute_coc_camera(context, &full_camera, depth, depth_stride,
                                                 coc->pixels, coc_stride)
                       : ddof_compute_coc_curve(context, &full_curve, depth, depth_stride,
                                                coc->pixels, coc_stride);
}

ddof_status ddof_coc_from_camera(ddof_context *context, const ddof_camera *camera,
                                 const ddof_image_in *depth, const ddof_image *coc)
{
    DDOF_EXCLUSIVE_CALL(context, coc_from_model(context, 1, camera, NULL, depth, coc));
}

ddof_status ddof_coc_from_curve(ddof_context *context, const ddof_curve *curve,
                                const ddof_image_in *depth, const ddof_image *coc)
{
    DDOF_EXCLUSIVE_CALL(context, coc_from_model(context, 0, NULL, curve, depth, coc));
}
