/* SPDX-License-Identifier: MIT */
/* coc_test.h - what the CoC tests share (test_coc*.c): the formulas evaluated here in double
 * (docs/design.md section 1, ddof.h) and the check of a camera's CoC image against them.
 *
 * Conventions used for the expected values (readings of the header):
 *  - pixel size: HORIZONTAL fit  pw = sensor / width,  ph = pw / pixel_aspect;
 *                VERTICAL fit    ph = sensor / height, pw = ph * pixel_aspect;
 *                AUTO            HORIZONTAL if width >= height else VERTICAL (tested with
 *                                pixel_aspect 1 only; with another aspect "larger" is ambiguous).
 *    CoC in horizontal pixels is c_mm / pw.
 *  - radial depth r at pixel (x, y): the pixel centre sits on the sensor at
 *    xs = (x + 0.5 - width/2) * pw, ys = (y + 0.5 - height/2) * ph (mm) and
 *    Z = r / sqrt(1 + (xs/f)^2 + (ys/f)^2). */
#ifndef DDOF_COC_TEST_H
#define DDOF_COC_TEST_H

#include "ddof.h"
#include "test_util.h"
#include "test_images.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

static ddof_context *ctx;
static double worst_rel; /* measured, printed at the end */

/* c in mm on the sensor; Z, S1, f in mm. */
static inline double cycles_mm(double f, double N, double S1, double Z)
{
    if (isinf(Z))
        return f * f / (N * S1);
    return f * f / (N * S1) * fabs(Z - S1) / Z;
}

static inline double thin_mm(double f, double N, double S1, double Z)
{
    if (isinf(Z))
        return (f / N) * f / (S1 - f);
    return (f / N) * fabs(Z - S1) / Z * f / (S1 - f);
}

static inline void pixel_size(const ddof_camera *cam, uint32_t w, uint32_t h, double *pw,
                              double *ph)
{
    ddof_sensor_fit fit = cam->sensor_fit;
    if (fit == DDOF_SENSOR_FIT_AUTO)
        fit = w >= h ? DDOF_SENSOR_FIT_HORIZONTAL : DDOF_SENSOR_FIT_VERTICAL;
    if (fit == DDOF_SENSOR_FIT_HORIZONTAL) {
        *pw = cam->sensor_width_mm / w;
        *ph = *pw / cam->pixel_aspect;
    } else {
        *ph = cam->sensor_width_mm / h;
        *pw = *ph * cam->pixel_aspect;
    }
}

/* The expected CoC (px) of the depth value at (x, y). */
static inline double expected_coc(const ddof_camera *cam, uint32_t w, uint32_t h, uint32_t x,
                                  uint32_t y, double depth)
{
    double pw, ph;
    pixel_size(cam, w, h, &pw, &ph);
    const double f = cam->focal_length_mm, S1 = cam->focus_distance_m * 1000.0;
    double Z = depth * cam->depth_unit_m * 1000.0;
    if (cam->depth_kind == DDOF_DEPTH_RADIAL && !isinf(Z)) {
        double xs = (x + 0.5 - w / 2.0) * pw, ys = (y + 0.5 - h / 2.0) * ph;
        Z = Z / sqrt(1.0 + (xs / f) * (xs / f) + (ys / f) * (ys / f));
    }
    double c = cam->lens_model == DDOF_LENS_THIN_LENS ? thin_mm(f, cam->fstop, S1, Z)
                                                       : cycles_mm(f, cam->fstop, S1, Z);
    double d = c / pw;
    return d > DDOF_MAX_COC_PX ? DDOF_MAX_COC_PX : d;
}

static inline ddof_status coc_from_camera(const ddof_camera *cam, const float *depth, float *coc,
                                          uint32_t w, uint32_t h)
{
    ddof_image_in di = {depth, w, h, 1, 0};
    ddof_image ci = {coc, w, h, 1, 0};
    return ddof_coc_from_camera(ctx, cam, &di, &ci);
}

/* Compares every pixel with the formula; tolerance relative plus a small absolute part scaled by
 * the sky CoC (near the focus plane |Z - S1| cancels, and depth is a float). */
static inline void check_camera_image(const char *what, const ddof_camera *cam, const float *depth,
                                      uint32_t w, uint32_t h)
{
    float *coc = alloc_f((size_t)w * h);
    ddof_status s = coc_from_camera(cam, depth, coc, w, h);
    CHECK_MSG(s == DDOF_OK, "%s: status %d (%s)", what, (int)s, ddof_context_last_error(ctx));
    if (s == DDOF_OK) {
        double pw, ph;
        pixel_size(cam, w, h, &pw, &ph);
        const double sky = cycles_mm(cam->focal_length_mm, cam->fstop,
                                     cam->focus_distance_m * 1000.0, INFINITY) / pw;
        size_t bad = 0;
        double worst = 0, worst_got = 0, worst_want = 0;
        uint32_t wx = 0, wy = 0;
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++) {
                double want = expected_coc(cam, w, h, x, y, depth[(size_t)y * w + x]);
                double got = coc[(size_t)y * w + x];
                double err = fabs(got - want);
                double tol = 1e-5 * want + 1e-6 * sky;
                if (want > 0)
                    worst_rel = fmax(worst_rel, err / want);
                if (!(err <= tol)) {
                    bad++;
                    if (!(err <= worst)) {
                        worst = err;
                        worst_got = got;
                        worst_want = want;
                        wx = x;
                        wy = y;
                    }
                }
            }
        CHECK_MSG(bad == 0, "%s: %zu pixels off; worst at (%u, %u): %.9g, expected %.9g", what,
                  bad, wx, wy, worst_got, worst_want);
    }
    free(coc);
}

/* The lens part of a camera: focal length (mm), f-number, focus distance (m). */
static inline void set_lens(ddof_camera *cam, double focal_mm, double fstop, double focus_m)
{
    cam->focal_length_mm = focal_mm;
    cam->fstop = fstop;
    cam->focus_distance_m = focus_m;
}

static inline void fill_depth(float *depth, size_t n, test_rng *rng, double lo, double hi)
{
    for (size_t i = 0; i < n; i++)
        depth[i] = (float)(lo * pow(hi / lo, test_uniform(rng))); /* log-uniform */
}

/* The context; 2 when it cannot be had. */
static inline int coc_test_begin(void)
{
    if (ddof_context_create(NULL, &ctx) != DDOF_OK || !ctx) {
        fprintf(stderr, "ddof_context_create failed\n");
        return 2;
    }
    return 0;
}

/* The worst error measured, the context freed; the exit status. */
static inline int coc_test_end(const char *name)
{
    printf("worst relative CoC error vs the double formulas: %.3g\n", worst_rel);
    ddof_context_free(ctx);
    return test_report(name);
}

#endif
