/* SPDX-License-Identifier: MIT */
/* ddof_camera_terms.h - a camera's CoC reduced to a few numbers per frame, shared by the core's
 * CPU pass (libddof/src/camera/coc.c) and the GL plugin's device pass
 * (plugin/gl/host_pack.comp through ddof_gl_host_diffuse_depth), so both sides compute one CoC
 * from one formula.
 *
 * Both lens models reduce to d = k_px * |1 - S1 / Z| pixels, which is 0 at the focus plane and
 * k_px for the sky (Z = +inf) without special cases:
 *   Cycles:    c = f^2 / (N S1)       * |Z - S1| / Z   (fixed pinhole projection, planar focus)
 *   thin lens: c = f^2 / (N (S1 - f)) * |Z - S1| / Z   (larger by S1 / (S1 - f))
 * Radial depth r becomes planar Z = r / sqrt(1 + xs^2 + ys^2), with xs, ys the pixel centre's
 * offset from the full frame's centre in units of the focal length. The terms are computed in
 * millimetres and double precision from a validated camera. */
#ifndef DDOF_CAMERA_TERMS_H
#define DDOF_CAMERA_TERMS_H

#include "ddof.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>

typedef struct ddof_camera_terms {
    double k_px;                      /* CoC in pixels of a point at infinity           */
    double focus_units;               /* S1 in depth units                              */
    double frame_width, frame_height; /* the full frame (the image unless cropped)     */
    double window_x, window_y;        /* the image's top-left pixel in the frame        */
    double pixel_w_over_f, pixel_h_over_f; /* a pixel's size over f: radial -> planar    */
    int radial;                       /* depth is the distance to the camera             */
    int signed_coc;                   /* near points (Z < S1) negative                   */
} ddof_camera_terms;

/* Whether a camera's aperture image cannot be used, and if so why, in `message`. */
static inline int ddof_aperture_image_problem(const ddof_camera *camera, char *message,
                                              size_t size)
{
    const uint32_t w = camera->aperture_image_width, h = camera->aperture_image_height;
    if (w < 1 || h < 1 || w > DDOF_MAX_APERTURE_IMAGE || h > DDOF_MAX_APERTURE_IMAGE) {
        snprintf(message, size, "camera aperture image %ux%u: each side must be 1..%u", w, h,
                 DDOF_MAX_APERTURE_IMAGE);
        return 1;
    }
    double sum = 0.0;
    for (uint32_t i = 0; i < w * h; i++) {
        const float v = camera->aperture_image[i];
        if (!(v >= 0.0f && v <= 3.0e38f)) {
            snprintf(message, size, "camera aperture image value %g at (%u, %u) must be finite "
                     "and >= 0", (double)v, i % w, i / w);
            return 1;
        }
        sum += v;
    }
    if (!(sum > 0.0)) {
        snprintf(message, size, "camera aperture image %ux%u is all 0: it would draw nothing", w,
                 h);
        return 1;
    }
    return 0;
}

/* Whether a camera (read over the defaults) cannot be used, and if so why, in `message`: the
 * rules of ddof_camera_check, for the core and a backend alike. */
static inline int ddof_camera_problem(const ddof_camera *camera, char *message, size_t size)
{
#define DDOF_POSITIVE_FINITE(v) (isfinite(v) && (v) > 0.0)
    if ((unsigned)camera->lens_model > DDOF_LENS_THIN_LENS ||
        (unsigned)camera->depth_kind > DDOF_DEPTH_RADIAL ||
        (unsigned)camera->sensor_fit > DDOF_SENSOR_FIT_VERTICAL)
        snprintf(message, size, "camera lens_model, depth_kind or sensor_fit is not a known value");
    else if (!DDOF_POSITIVE_FINITE(camera->fstop))
        snprintf(message, size, "camera f-number %g must be > 0", camera->fstop);
    else if (!DDOF_POSITIVE_FINITE(camera->focal_length_mm))
        snprintf(message, size, "camera focal length %g mm must be > 0", camera->focal_length_mm);
    else if (!DDOF_POSITIVE_FINITE(camera->sensor_width_mm))
        snprintf(message, size, "camera sensor width %g mm must be > 0", camera->sensor_width_mm);
    else if (!DDOF_POSITIVE_FINITE(camera->pixel_aspect))
        snprintf(message, size, "camera pixel aspect %g must be > 0", camera->pixel_aspect);
    else if (!DDOF_POSITIVE_FINITE(camera->depth_unit_m))
        snprintf(message, size, "camera depth unit %g m must be > 0", camera->depth_unit_m);
    else if (!isfinite(camera->focus_distance_m) ||
             camera->focus_distance_m * 1000.0 <= camera->focal_length_mm)
        snprintf(message, size,
                 "camera focus distance %g m must be beyond the focal length (%g mm)",
                 camera->focus_distance_m, camera->focal_length_mm);
    else if ((camera->frame_width == 0) != (camera->frame_height == 0) ||
             camera->frame_width > DDOF_MAX_DIMENSION || camera->frame_height > DDOF_MAX_DIMENSION)
        snprintf(message, size,
                 "camera frame %ux%u: both sides must be 0 (the image is the frame) or 1..%u",
                 camera->frame_width, camera->frame_height, DDOF_MAX_DIMENSION);
    else if (camera->frame_width == 0 && (camera->window_x != 0 || camera->window_y != 0))
        snprintf(message, size,
                 "camera window (%d, %d) needs the full frame's size (frame_width, "
                 "frame_height)", (int)camera->window_x, (int)camera->window_y);
    else if (camera->window_x < -(int32_t)DDOF_MAX_DIMENSION ||
             camera->window_x > (int32_t)DDOF_MAX_DIMENSION ||
             camera->window_y < -(int32_t)DDOF_MAX_DIMENSION ||
             camera->window_y > (int32_t)DDOF_MAX_DIMENSION)
        snprintf(message, size, "camera window (%d, %d) must be within -%u..%u",
                 (int)camera->window_x, (int)camera->window_y, DDOF_MAX_DIMENSION,
                 DDOF_MAX_DIMENSION);
    else if (camera->aperture_blades > DDOF_MAX_APERTURE_BLADES)
        snprintf(message, size, "camera aperture_blades %u must be 0 (round) or 3..%u",
                 camera->aperture_blades, DDOF_MAX_APERTURE_BLADES);
    else if (!(fabs(camera->aperture_rotation_deg) <= 360.0))
        snprintf(message, size, "camera aperture_rotation_deg %g must be within -360..360",
                 camera->aperture_rotation_deg);
    else if (!(camera->aperture_ratio >= DDOF_MIN_APERTURE_RATIO &&
               camera->aperture_ratio <= DDOF_MAX_APERTURE_RATIO))
        snprintf(message, size, "camera aperture_ratio %g must be within %g..%g",
                 camera->aperture_ratio, DDOF_MIN_APERTURE_RATIO, DDOF_MAX_APERTURE_RATIO);
    else if (!(camera->aperture_catseye >= 0.0 && camera->aperture_catseye <= 1.0))
        snprintf(message, size, "camera aperture_catseye %g must be within 0..1",
                 camera->aperture_catseye);
    else if (camera->aperture_image && ddof_aperture_image_problem(camera, message, size))
        return 1;
    else
        return 0;
#undef DDOF_POSITIVE_FINITE
    return 1;
}

/* Size of one pixel on the sensor, in mm, for the camera's sensor fit and pixel aspect. */
static inline void ddof_camera_pixel_size(const ddof_camera *camera, uint32_t width,
                                          uint32_t height, double *pixel_width_mm,
                                          double *pixel_height_mm)
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

/* The terms of a validated camera for an image of width x height pixels (the full frame's
 * size is the camera's frame_width/height when set). */
static inline ddof_camera_terms ddof_camera_terms_of(const ddof_camera *camera, uint32_t width,
                                                     uint32_t height)
{
    /* The sensor spans the full frame, a crop is a part of it. */
    const uint32_t frame_w = camera->frame_width ? camera->frame_width : width;
    const uint32_t frame_h = camera->frame_height ? camera->frame_height : height;
    double pixel_w, pixel_h;
    ddof_camera_pixel_size(camera, frame_w, frame_h, &pixel_w, &pixel_h);
    const double f = camera->focal_length_mm;
    const double s1_mm = camera->focus_distance_m * 1000.0;
    const double lens_distance = camera->lens_model == DDOF_LENS_CYCLES ? s1_mm : s1_mm - f;
    const double k_mm = f * f / (camera->fstop * lens_distance);
    /* The ratio narrows the blur: its width is the CoC over the ratio (Cycles scales the
     * aperture's x by 1 / ratio), its height the CoC. */
    return (ddof_camera_terms){
        .k_px = k_mm / pixel_w / camera->aperture_ratio,
        .focus_units = camera->focus_distance_m / camera->depth_unit_m,
        .frame_width = frame_w, .frame_height = frame_h,
        .window_x = camera->window_x, .window_y = camera->window_y,
        .pixel_w_over_f = pixel_w / f, .pixel_h_over_f = pixel_h / f,
        .radial = camera->depth_kind == DDOF_DEPTH_RADIAL,
        .signed_coc = camera->signed_coc != 0,
    };
}

#endif
