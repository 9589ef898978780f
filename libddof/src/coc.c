/* SPDX-License-Identifier: MIT */
/* coc.c - circle of confusion from a camera and depth, or from the artist curve.
 *
 * Both lens models reduce to d = K * |1 - S1/Z| pixels, which is 0 at the focus plane and K for
 * the sky (Z = +inf) without special cases:
 *   Cycles:    c = f^2 / (N S1)       * |Z - S1| / Z   (fixed pinhole projection, planar focus)
 *   thin lens: c = f^2 / (N (S1 - f)) * |Z - S1| / Z   (larger by S1 / (S1 - f))
 * Everything is computed in millimetres and double precision, then stored as float pixels. */
#include "coc.h"

#include "parallel_rows.h"

#include <math.h>
#include <stddef.h>

static int positive_finite(double v)
{
    return isfinite(v) && v > 0.0;
}

ddof_status ddof_read_camera(ddof_context *context, const ddof_camera *caller,
                             ddof_camera *camera)
{
    ddof_camera_init(camera);
    ddof_status status = ddof_read_struct(context, caller, offsetof(ddof_camera, signed_coc),
                                          camera, sizeof *camera, "camera");
    if (status != DDOF_OK)
        return status;
    if ((unsigned)camera->lens_model > DDOF_LENS_THIN_LENS ||
        (unsigned)camera->depth_kind > DDOF_DEPTH_RADIAL ||
        (unsigned)camera->sensor_fit > DDOF_SENSOR_FIT_VERTICAL)
        return ddof_fail(context, DDOF_ERROR_BAD_CAMERA,
                         "camera lens_model, depth_kind or sensor_fit is not a known value");
    if (!positive_finite(camera->fstop))
        return ddof_fail(context, DDOF_ERROR_BAD_CAMERA, "camera f-number %g must be > 0",
                         camera->fstop);
    if (!positive_finite(camera->focal_length_mm))
        return ddof_fail(context, DDOF_ERROR_BAD_CAMERA, "camera focal length %g mm must be > 0",
                         camera->focal_length_mm);
    if (!positive_finite(camera->sensor_width_mm))
        return ddof_fail(context, DDOF_ERROR_BAD_CAMERA, "camera sensor width %g mm must be > 0",
                         camera->sensor_width_mm);
    if (!positive_finite(camera->pixel_aspect))
        return ddof_fail(context, DDOF_ERROR_BAD_CAMERA, "camera pixel aspect %g must be > 0",
                         camera->pixel_aspect);
    if (!positive_finite(camera->depth_unit_m))
        return ddof_fail(context, DDOF_ERROR_BAD_CAMERA, "camera depth unit %g m must be > 0",
                         camera->depth_unit_m);
    if (!isfinite(camera->focus_distance_m) ||
        camera->focus_distance_m * 1000.0 <= camera->focal_length_mm)
        return ddof_fail(context, DDOF_ERROR_BAD_CAMERA,
                         "camera focus distance %g m must be beyond the focal length (%g mm)",
                         camera->focus_distance_m, camera->focal_length_mm);
    if ((camera->frame_width == 0) != (camera->frame_height == 0) ||
        camera->frame_width > DDOF_MAX_DIMENSION || camera->frame_height > DDOF_MAX_DIMENSION)
        return ddof_fail(context, DDOF_ERROR_BAD_CAMERA,
                         "camera frame %ux%u: both sides must be 0 (the image is the frame) or "
                         "1..%u", camera->frame_width, camera->frame_height, DDOF_MAX_DIMENSION);
    if (camera->frame_width == 0 && (camera->window_x != 0 || camera->window_y != 0))
        return ddof_fail(context, DDOF_ERROR_BAD_CAMERA,
                         "camera window (%d, %d) needs the full frame's size (frame_width, "
                         "frame_height)", (int)camera->window_x, (int)camera->window_y);
    if (camera->window_x < -(int32_t)DDOF_MAX_DIMENSION ||
        camera->window_x > (int32_t)DDOF_MAX_DIMENSION ||
        camera->window_y < -(int32_t)DDOF_MAX_DIMENSION ||
        camera->window_y > (int32_t)DDOF_MAX_DIMENSION)
        return ddof_fail(context, DDOF_ERROR_BAD_CAMERA,
                         "camera window (%d, %d) must be within -%u..%u",
                         (int)camera->window_x, (int)camera->window_y, DDOF_MAX_DIMENSION,
                         DDOF_MAX_DIMENSION);
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

void ddof_camera_pixel_size(const ddof_camera *camera, uint32_t width, uint32_t height,
                            double *pixel_width_mm, double *pixel_height_mm)
{
    int horizontal = camera->sensor_fit == DDOF_SENSOR_FIT_HORIZONTAL ||
                     (camera->sensor_fit == DDOF_SENSOR_FIT_AUTO &&
                      (double)width * camera->pixel_aspect >= (double)height);
    if (horizontal) {
        *pixel_width_mm = camera->sensor_width_mm / width;
        *pixel_height_mm = *pixel_width_mm / camera->pixel_aspect;
    } else {
        *pixel_height_mm = camera->sensor_width_mm / height;
        *pixel_width_mm = *pixel_height_mm * camera->pixel_aspect;
    }
}

typedef struct camera_job {
    const float *depth;
    size_t depth_stride;
    uint32_t depth_channels, width, height;
    float *coc;
    size_t coc_stride;
    double frame_width, frame_height; /* the full frame (the image unless cropped)  */
    double window_x, window_y;        /* the image's top-left pixel in the frame     */
    double k_px;          /* CoC in pixels of an object at infinity        */
    double focus_units;   /* S1 in depth units                             */
    int radial;
    int signed_coc;       /* near points (Z < S1) negative                */
    double pixel_w_over_f, pixel_h_over_f; /* for the radial -> planar factor */
} camera_job;

static void camera_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const camera_job *job = user;
    for (uint32_t y = y0; y < y1; y++) {
        const float *depth = job->depth + (size_t)y * job->depth_stride;
        float *coc = job->coc + (size_t)y * job->coc_stride;
        /* (double)y + window_y is the frame's row exactly: a crop's values are the frame's. */
        const double ys =
            ((double)y + job->window_y + 0.5 - 0.5 * job->frame_height) * job->pixel_h_over_f;
        for (uint32_t x = 0; x < job->width; x++) {
            double z = depth[(size_t)x * job->depth_channels];
            if (job->radial) {
                /* Planar Z of a point at distance r seen through this pixel's centre. */
                const double xs = ((double)x + job->window_x + 0.5 - 0.5 * job->frame_width) *
                                  job->pixel_w_over_f;
                z /= sqrt(1.0 + xs * xs + ys * ys);
            }
            const double d = job->k_px * fabs(1.0 - job->focus_units / z);
            const float clamped = d < DDOF_MAX_COC_PX ? (float)d : DDOF_MAX_COC_PX;
            coc[x] = job->signed_coc && z < job->focus_units ? -clamped : clamped;
        }
    }
}

ddof_status ddof_compute_coc_camera(ddof_context *context, const ddof_camera *camera,
                                    const ddof_image_in *depth, size_t depth_stride,
                                    float *coc, size_t coc_stride)
{
    bad_value bad;
    if (ddof_find_bad_value(context, depth->pixels, depth->width, depth->height,
                            depth->channels, 1, depth_stride, VALUE_DEPTH, &bad, NULL))
        return ddof_fail(context, DDOF_ERROR_BAD_DEPTH,
                         "depth at pixel (%u, %u) is %g; it must be > 0 (+inf for the sky)",
                         bad.x, bad.y, (double)bad.value);

    /* The sensor spans the full frame, a crop is a part of it. */
    const uint32_t frame_w = camera->frame_width ? camera->frame_width : depth->width;
    const uint32_t frame_h = camera->frame_height ? camera->frame_height : depth->height;
    double pixel_w, pixel_h;
    ddof_camera_pixel_size(camera, frame_w, frame_h, &pixel_w, &pixel_h);
    const double f = camera->focal_length_mm;
    const double s1_mm = camera->focus_distance_m * 1000.0;
    const double lens_distance = camera->lens_model == DDOF_LENS_CYCLES ? s1_mm : s1_mm - f;
    const double k_mm = f * f / (camera->fstop * lens_distance);
    camera_job job = {
        .depth = depth->pixels, .depth_stride = depth_stride, .depth_channels = depth->channels,
        .width = depth->width, .height = depth->height, .coc = coc, .coc_stride = coc_stride,
        .frame_width = frame_w, .frame_height = frame_h,
        .window_x = camera->window_x, .window_y = camera->window_y,
        .k_px = k_mm / pixel_w,
        .focus_units = camera->focus_distance_m / camera->depth_unit_m,
        .radial = camera->depth_kind == DDOF_DEPTH_RADIAL,
        .signed_coc = camera->signed_coc != 0,
        .pixel_w_over_f = pixel_w / f, .pixel_h_over_f = pixel_h / f,
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
    bad_value bad;
    if (ddof_find_bad_value(context, depth->pixels, depth->width, depth->height,
                            depth->channels, 1, depth_stride, VALUE_DEPTH_ZERO, &bad, NULL))
        return ddof_fail(context, DDOF_ERROR_BAD_DEPTH,
                         "depth at pixel (%u, %u) is %g; it must be >= 0 (+inf for the sky)",
                         bad.x, bad.y, (double)bad.value);
    curve_job job = {depth->pixels, depth_stride, depth->channels, depth->width, coc,
                     coc_stride, *curve};
    ddof_parallel_rows(context, depth->height, curve_rows, &job);
    return DDOF_OK;
}

/* The public entry points: validate everything, then compute. */
static ddof_status check_coc_images(ddof_context *context, const ddof_image_in *depth,
                                    const ddof_image *coc, size_t *depth_stride,
                                    size_t *coc_stride)
{
    if (!depth || !coc)
        return ddof_fail(context, DDOF_ERROR_NULL_POINTER, "%s is NULL",
                         depth ? "coc image" : "depth image");
    ddof_status status = ddof_check_image(context, "depth", depth->pixels, depth->width,
                                          depth->height, depth->channels, depth->row_stride,
                                          depth_stride);
    if (status == DDOF_OK)
        status = ddof_check_image(context, "coc", coc->pixels, coc->width, coc->height,
                                  coc->channels, coc->row_stride, coc_stride);
    if (status != DDOF_OK)
        return status;
    if (coc->width != depth->width || coc->height != depth->height || coc->channels != 1)
        return ddof_fail(context, DDOF_ERROR_SIZE_MISMATCH,
                         "coc is %ux%u with %u channels; it must be %ux%u with 1 channel",
                         coc->width, coc->height, coc->channels, depth->width, depth->height);
    return DDOF_OK;
}

ddof_status ddof_coc_from_camera(ddof_context *context, const ddof_camera *camera,
                                 const ddof_image_in *depth, const ddof_image *coc)
{
    if (!context)
        return DDOF_ERROR_NULL_POINTER;
    ddof_clear_error(context);
    size_t depth_stride, coc_stride;
    ddof_camera full;
    ddof_status status = ddof_read_camera(context, camera, &full);
    if (status == DDOF_OK)
        status = check_coc_images(context, depth, coc, &depth_stride, &coc_stride);
    if (status != DDOF_OK)
        return status;
    return ddof_compute_coc_camera(context, &full, depth, depth_stride, coc->pixels, coc_stride);
}

ddof_status ddof_coc_from_curve(ddof_context *context, const ddof_curve *curve,
                                const ddof_image_in *depth, const ddof_image *coc)
{
    if (!context)
        return DDOF_ERROR_NULL_POINTER;
    ddof_clear_error(context);
    size_t depth_stride, coc_stride;
    ddof_curve full;
    ddof_status status = ddof_read_curve(context, curve, &full);
    if (status == DDOF_OK)
        status = check_coc_images(context, depth, coc, &depth_stride, &coc_stride);
    if (status != DDOF_OK)
        return status;
    return ddof_compute_coc_curve(context, &full, depth, depth_stride, coc->pixels, coc_stride);
}
