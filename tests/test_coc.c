/* SPDX-License-Identifier: MIT */
/* test_coc.c - circle of confusion from a camera (Cycles and thin-lens models, sensor fits,
 * pixel aspect, radial depth, depth units, sky, clamping) and from the artist curve, against
 * formulas evaluated here in double (docs/design.md section 1, ddof.h).
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
static double cycles_mm(double f, double N, double S1, double Z)
{
    if (isinf(Z))
        return f * f / (N * S1);
    return f * f / (N * S1) * fabs(Z - S1) / Z;
}

static double thin_mm(double f, double N, double S1, double Z)
{
    if (isinf(Z))
        return (f / N) * f / (S1 - f);
    return (f / N) * fabs(Z - S1) / Z * f / (S1 - f);
}

static void pixel_size(const ddof_camera *cam, uint32_t w, uint32_t h, double *pw, double *ph)
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
static double expected_coc(const ddof_camera *cam, uint32_t w, uint32_t h, uint32_t x,
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

static ddof_status coc_from_camera(const ddof_camera *cam, const float *depth, float *coc,
                                   uint32_t w, uint32_t h)
{
    ddof_image_in di = {depth, w, h, 1, 0};
    ddof_image ci = {coc, w, h, 1, 0};
    return ddof_coc_from_camera(ctx, cam, &di, &ci);
}

/* Compares every pixel with the formula; tolerance relative plus a small absolute part scaled by
 * the sky CoC (near the focus plane |Z - S1| cancels, and depth is a float). */
static void check_camera_image(const char *what, const ddof_camera *cam, const float *depth,
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
static void set_lens(ddof_camera *cam, double focal_mm, double fstop, double focus_m)
{
    cam->focal_length_mm = focal_mm;
    cam->fstop = fstop;
    cam->focus_distance_m = focus_m;
}

static void fill_depth(float *depth, size_t n, test_rng *rng, double lo, double hi)
{
    for (size_t i = 0; i < n; i++)
        depth[i] = (float)(lo * pow(hi / lo, test_uniform(rng))); /* log-uniform */
}

static void test_defaults(void)
{
    ddof_camera cam;
    memset(&cam, 0xFF, sizeof cam);
    ddof_camera_init(&cam);
    CHECK_EQ_INT(cam.struct_size, sizeof cam);
    CHECK_EQ_INT(cam.lens_model, DDOF_LENS_CYCLES);
    CHECK_EQ_INT(cam.depth_kind, DDOF_DEPTH_PLANAR);
    CHECK_EQ_INT(cam.sensor_fit, DDOF_SENSOR_FIT_AUTO);
    CHECK(cam.focal_length_mm == 50 && cam.sensor_width_mm == 36 && cam.fstop == 2.8);
    CHECK(cam.focus_distance_m == 10 && cam.pixel_aspect == 1 && cam.depth_unit_m == 1);

    ddof_curve cv;
    memset(&cv, 0xFF, sizeof cv);
    ddof_curve_init(&cv);
    CHECK_EQ_INT(cv.struct_size, sizeof cv);
    CHECK(cv.near_blur_px == 0 && cv.near_start == 0 && cv.near_end == 0);
    CHECK(cv.far_start == 10 && cv.far_end == 100 && cv.far_blur_px == 16);
}

static void test_lens_models(void)
{
    test_rng rng = {4};
    const uint32_t w = 200, h = 100;
    const size_t px = (size_t)w * h;
    float *depth = alloc_f(px), *cy = alloc_f(px), *th = alloc_f(px);
    fill_depth(depth, px, &rng, 0.3, 500.0);
    depth[0] = 2.0f;      /* the focus plane */
    depth[1] = INFINITY;  /* sky */
    depth[2] = 1.0f;      /* twice as close as the focus */

    ddof_camera cam;
    ddof_camera_init(&cam);
    set_lens(&cam, 100, 2, 2);
    cam.sensor_width_mm = 36;
    cam.sensor_fit = DDOF_SENSOR_FIT_HORIZONTAL;
    check_camera_image("cycles, f100 N2 S1=2m", &cam, depth, w, h);
    CHECK_EQ_INT(coc_from_camera(&cam, depth, cy, w, h), DDOF_OK);
    /* Hand-checked numbers: f^2/(N S1) = 10000/4000 = 2.5 mm on the sensor, pixel 0.18 mm. */
    CHECK(cy[0] == 0.0f);
    CHECK_NEAR(cy[1], 2.5 / 0.18, 1e-4);
    CHECK_NEAR(cy[2], 2.5 / 0.18, 1e-4); /* |1 - 2| / 1 = 1: the same as the sky */

    cam.lens_model = DDOF_LENS_THIN_LENS;
    check_camera_image("thin lens, f100 N2 S1=2m", &cam, depth, w, h);
    CHECK_EQ_INT(coc_from_camera(&cam, depth, th, w, h), DDOF_OK);
    CHECK(th[0] == 0.0f);
    CHECK_NEAR(th[1], 50.0 * 100.0 / 1900.0 / 0.18, 1e-4);
    /* The two models differ by S1 / (S1 - f) = 2000 / 1900 everywhere. */
    double worst = 0;
    for (size_t i = 1; i < px; i++)
        if (cy[i] > 1e-3f)
            worst = fmax(worst, fabs(th[i] / cy[i] - 2000.0 / 1900.0));
    CHECK_MSG(worst <= 1e-5, "thin lens / cycles ratio off by %.3g from %.6f", worst,
              2000.0 / 1900.0);

    /* Other cameras: a wide angle focused near, a long lens focused far, f/16. */
    cam.lens_model = DDOF_LENS_CYCLES;
    set_lens(&cam, 24, 1.4, 0.5);
    check_camera_image("cycles, f24 N1.4 S1=0.5m", &cam, depth, w, h);
    cam.lens_model = DDOF_LENS_THIN_LENS;
    check_camera_image("thin lens, f24 N1.4 S1=0.5m", &cam, depth, w, h);
    set_lens(&cam, 300, 16, 50);
    check_camera_image("thin lens, f300 N16 S1=50m", &cam, depth, w, h);
    cam.lens_model = DDOF_LENS_CYCLES;
    check_camera_image("cycles, f300 N16 S1=50m", &cam, depth, w, h);
    free(depth);
    free(cy);
    free(th);
}

static void test_units_and_sky(void)
{
    test_rng rng = {9};
    const uint32_t w = 64, h = 48;
    const size_t px = (size_t)w * h;
    float *dm = alloc_f(px), *dcm = alloc_f(px), *a = alloc_f(px), *b = alloc_f(px);
    fill_depth(dm, px, &rng, 0.5, 200.0);
    dm[5] = INFINITY;
    for (size_t i = 0; i < px; i++)
        dcm[i] = dm[i] * 100.0f;
    ddof_camera cam;
    ddof_camera_init(&cam);
    CHECK_EQ_INT(coc_from_camera(&cam, dm, a, w, h), DDOF_OK);
    cam.depth_unit_m = 0.01;
    CHECK_EQ_INT(coc_from_camera(&cam, dcm, b, w, h), DDOF_OK);
    check_camera_image("depth in cm", &cam, dcm, w, h);
    double worst = 0;
    for (size_t i = 0; i < px; i++)
        worst = fmax(worst, fabs((double)a[i] - b[i]) / fmax(1e-3, a[i]));
    CHECK_MSG(worst <= 1e-5, "depth in cm vs m: relative difference %.3g", worst);

    /* Sky: f^2 / (N S1) / pixel size, defaults f 50, N 2.8, S1 10 m, 36 mm over 64 px. */
    CHECK_NEAR(a[5], 2500.0 / (2.8 * 10000.0) / (36.0 / 64.0), 1e-5);
    /* Far depth approaches the sky value from below; beyond focus the CoC grows with depth. */
    CHECK(a[5] > 0.0f);
    float far[2] = {1e30f, 100.0f}, out[2];
    cam.depth_unit_m = 1;
    CHECK_EQ_INT(coc_from_camera(&cam, far, out, 2, 1), DDOF_OK);
    CHECK_NEAR(out[0], 2500.0 / (2.8 * 10000.0) / (36.0 / 2.0), 1e-5);
    CHECK(out[1] < out[0]);
    free(dm);
    free(dcm);
    free(a);
    free(b);
}

static void test_sensor_fit(void)
{
    test_rng rng = {10};
    const uint32_t dims[2][2] = {{120, 80}, {80, 120}}; /* landscape, portrait */
    for (int t = 0; t < 2; t++) {
        const uint32_t w = dims[t][0], h = dims[t][1];
        const size_t px = (size_t)w * h;
        float *depth = alloc_f(px), *coc = alloc_f(px);
        fill_depth(depth, px, &rng, 1.0, 100.0);
        ddof_camera cam;
        ddof_camera_init(&cam);
        const ddof_sensor_fit fits[] = {DDOF_SENSOR_FIT_AUTO, DDOF_SENSOR_FIT_HORIZONTAL,
                                        DDOF_SENSOR_FIT_VERTICAL};
        for (int f = 0; f < 3; f++) {
            cam.sensor_fit = fits[f];
            char what[64];
            snprintf(what, sizeof what, "%ux%u fit %d", w, h, (int)fits[f]);
            check_camera_image(what, &cam, depth, w, h);
        }
        /* The explicit numbers: a 5 m depth, AUTO spans the larger side (120 px). */
        for (size_t i = 0; i < px; i++)
            depth[i] = 5.0f;
        cam.sensor_fit = DDOF_SENSOR_FIT_AUTO;
        CHECK_EQ_INT(coc_from_camera(&cam, depth, coc, w, h), DDOF_OK);
        const double c5 = 2500.0 / (2.8 * 10000.0) * 5000.0 / 5000.0; /* |5-10|/5 = 1 */
        CHECK_NEAR(coc[0], c5 / (36.0 / 120.0), 1e-5);
        cam.sensor_fit = DDOF_SENSOR_FIT_HORIZONTAL;
        CHECK_EQ_INT(coc_from_camera(&cam, depth, coc, w, h), DDOF_OK);
        CHECK_NEAR(coc[0], c5 / (36.0 / w), 1e-5);
        cam.sensor_fit = DDOF_SENSOR_FIT_VERTICAL;
        CHECK_EQ_INT(coc_from_camera(&cam, depth, coc, w, h), DDOF_OK);
        CHECK_NEAR(coc[0], c5 / (36.0 / h), 1e-5);

        /* Pixel aspect 2 (wide pixels): horizontal fit keeps the horizontal pixel size, vertical
         * fit makes horizontal pixels twice as wide, so half the CoC in horizontal pixels. */
        cam.pixel_aspect = 2.0;
        cam.sensor_fit = DDOF_SENSOR_FIT_HORIZONTAL;
        CHECK_EQ_INT(coc_from_camera(&cam, depth, coc, w, h), DDOF_OK);
        CHECK_NEAR(coc[0], c5 / (36.0 / w), 1e-5);
        cam.sensor_fit = DDOF_SENSOR_FIT_VERTICAL;
        CHECK_EQ_INT(coc_from_camera(&cam, depth, coc, w, h), DDOF_OK);
        CHECK_NEAR(coc[0], c5 / (2.0 * 36.0 / h), 1e-5);
        free(depth);
        free(coc);
    }
}

static void test_radial(void)
{
    test_rng rng = {12};
    const uint32_t w = 101, h = 61; /* odd: pixel (50, 30) sits on the optical axis */
    const size_t px = (size_t)w * h;
    float *depth = alloc_f(px), *planar = alloc_f(px), *radial = alloc_f(px);
    fill_depth(depth, px, &rng, 0.5, 50.0);
    depth[3] = INFINITY;
    depth[0] = 10.0f; /* corner: radial 10 m is planar ~7.2 m, a clearly different CoC */
    ddof_camera cam;
    ddof_camera_init(&cam);
    set_lens(&cam, 20, 2, 3); /* wide: corners at ~45 degrees, radial != planar by ~1.4x */
    const ddof_sensor_fit fits[] = {DDOF_SENSOR_FIT_HORIZONTAL, DDOF_SENSOR_FIT_VERTICAL};
    for (int f = 0; f < 2; f++) {
        cam.sensor_fit = fits[f];
        cam.depth_kind = DDOF_DEPTH_RADIAL;
        check_camera_image(f ? "radial, vertical fit" : "radial, horizontal fit", &cam, depth, w,
                           h);
        CHECK_EQ_INT(coc_from_camera(&cam, depth, radial, w, h), DDOF_OK);
        cam.depth_kind = DDOF_DEPTH_PLANAR;
        CHECK_EQ_INT(coc_from_camera(&cam, depth, planar, w, h), DDOF_OK);
        const size_t centre = (size_t)(h / 2) * w + w / 2;
        CHECK_NEAR(radial[centre], planar[centre], 1e-5 * planar[centre] + 1e-7);
        CHECK(radial[3] == planar[3]); /* sky */
        CHECK_MSG(radial[0] < 0.98f * planar[0], "corner: radial %g, planar %g",
                  (double)radial[0], (double)planar[0]);
    }
    /* The corner by hand: r = S1 * sqrt(1 + (xs/f)^2 + (ys/f)^2) lies on the focus plane. */
    cam.sensor_fit = DDOF_SENSOR_FIT_HORIZONTAL;
    cam.depth_kind = DDOF_DEPTH_RADIAL;
    const double pw = 36.0 / w;
    const double xs = (0.5 - w / 2.0) * pw, ys = (0.5 - h / 2.0) * pw;
    depth[0] = (float)(3.0 * sqrt(1.0 + (xs / 20) * (xs / 20) + (ys / 20) * (ys / 20)));
    CHECK_EQ_INT(coc_from_camera(&cam, depth, radial, w, h), DDOF_OK);
    cam.depth_kind = DDOF_DEPTH_PLANAR;
    CHECK_EQ_INT(coc_from_camera(&cam, depth, planar, w, h), DDOF_OK);
    const double sky = 400.0 / (2.0 * 3000.0) / pw;
    CHECK_MSG(radial[0] <= 1e-5 * sky, "corner radial depth %g on the focus plane: CoC %g",
              (double)depth[0], (double)radial[0]);
    CHECK(planar[0] > 0.1 * sky); /* the same number read as planar is well out of focus */
    free(depth);
    free(planar);
    free(radial);
}

/* A crop (a render border, an EXR data window): with the full frame's size and the window's
 * offset in the camera, the CoC of the crop is the same region of the full frame's CoC, bit for
 * bit, for every sensor fit, planar and radial depth, odd offsets and a window reaching out of
 * the frame. Without them the crop's width is taken as the sensor's (the old behaviour, a
 * different CoC): that is checked too, so the test can tell. Older struct sizes and bad frames. */
static void test_crop(void)
{
    test_rng rng = {15};
    const uint32_t w = 96, h = 54;
    const size_t px = (size_t)w * h;
    float *depth = alloc_f(px), *full = alloc_f(px);
    fill_depth(depth, px, &rng, 0.3, 40.0);
    depth[5] = INFINITY;
    struct { uint32_t x, y, cw, ch; } crops[] = {{0, 0, w, h}, {17, 9, 31, 23}, {0, 30, 96, 24},
                                                  {60, 0, 36, 54}, {95, 53, 1, 1}, {1, 1, 7, 50}};
    const ddof_sensor_fit fits[] = {DDOF_SENSOR_FIT_AUTO, DDOF_SENSOR_FIT_HORIZONTAL,
                                    DDOF_SENSOR_FIT_VERTICAL};
    double largest_diff_old = 0.0;
    for (int kind = 0; kind < 2; kind++)
        for (int f = 0; f < 3; f++)
            for (size_t c = 0; c < sizeof crops / sizeof crops[0]; c++) {
                ddof_camera cam;
                ddof_camera_init(&cam);
                set_lens(&cam, 24, 1.8, 2.5);
                cam.sensor_fit = fits[f];
                cam.depth_kind = kind ? DDOF_DEPTH_RADIAL : DDOF_DEPTH_PLANAR;
                cam.pixel_aspect = f == 2 ? 1.25 : 1.0;
                cam.signed_coc = 1;
                CHECK_EQ_INT(coc_from_camera(&cam, depth, full, w, h), DDOF_OK);
                const uint32_t cw = crops[c].cw, ch = crops[c].ch;
                float *sub = alloc_f((size_t)cw * ch), *got = alloc_f((size_t)cw * ch);
                for (uint32_t y = 0; y < ch; y++)
                    memcpy(sub + (size_t)y * cw, depth + (size_t)(y + crops[c].y) * w + crops[c].x,
                           cw * sizeof(float));
                cam.frame_width = w;
                cam.frame_height = h;
                cam.window_x = (int32_t)crops[c].x;
                cam.window_y = (int32_t)crops[c].y;
                ddof_status s = coc_from_camera(&cam, sub, got, cw, ch);
                CHECK_MSG(s == DDOF_OK, "crop %zu: %s", c, ddof_context_last_error(ctx));
                size_t bad = 0;
                for (uint32_t y = 0; y < ch; y++)
                    for (uint32_t x = 0; x < cw; x++)
                        bad += got[(size_t)y * cw + x] !=
                               full[(size_t)(y + crops[c].y) * w + x + crops[c].x];
                CHECK_MSG(bad == 0, "crop %zu (%u,%u %ux%u), fit %d, %s: %zu pixels differ from "
                          "the full frame's", c, crops[c].x, crops[c].y, cw, ch, f,
                          kind ? "radial" : "planar", bad);
                /* The crop as a frame of its own: another CoC (the old, wrong one). */
                cam.frame_width = cam.frame_height = 0;
                cam.window_x = cam.window_y = 0;
                CHECK_EQ_INT(coc_from_camera(&cam, sub, got, cw, ch), DDOF_OK);
                for (uint32_t y = 0; y < ch; y++)
                    for (uint32_t x = 0; x < cw; x++)
                        largest_diff_old = fmax(largest_diff_old,
                                                fabs(got[(size_t)y * cw + x] -
                                                     full[(size_t)(y + crops[c].y) * w + x +
                                                          crops[c].x]));
                free(sub);
                free(got);
            }
    CHECK_MSG(largest_diff_old > 1.0, "a crop as its own frame should differ (%g px)",
              largest_diff_old);
    printf("crop vs full frame: bit for bit; the crop as its own frame differs by up to %.3g px\n",
           largest_diff_old);

    /* A window reaching out of the frame (overscan): the formula at those pixels. */
    ddof_camera cam;
    ddof_camera_init(&cam);
    set_lens(&cam, 24, 1.8, 2.5);
    cam.depth_kind = DDOF_DEPTH_RADIAL;
    cam.sensor_fit = DDOF_SENSOR_FIT_HORIZONTAL;
    float one = 3.0f, got1 = 0.0f;
    cam.frame_width = w;
    cam.frame_height = h;
    cam.window_x = -4;
    cam.window_y = 60;
    CHECK_EQ_INT(coc_from_camera(&cam, &one, &got1, 1, 1), DDOF_OK);
    {
        const double pw = 36.0 / w, fl = 24.0;
        const double xs = (-4 + 0.5 - w / 2.0) * pw, ys = (60 + 0.5 - h / 2.0) * pw;
        const double z = 3000.0 / sqrt(1.0 + (xs / fl) * (xs / fl) + (ys / fl) * (ys / fl));
        const double want = cycles_mm(fl, 1.8, 2500.0, z) / pw;
        CHECK_NEAR(got1, want, 1e-5 * want);
    }

    /* An older struct (0.4: up to signed_coc) gets the defaults: the image is the frame. */
    cam.struct_size = (uint32_t)offsetof(ddof_camera, frame_width);
    float old = 0.0f, plain = 0.0f;
    CHECK_EQ_INT(coc_from_camera(&cam, &one, &old, 1, 1), DDOF_OK);
    ddof_camera cam2 = cam;
    cam2.struct_size = sizeof cam2;
    cam2.frame_width = cam2.frame_height = 0;
    cam2.window_x = cam2.window_y = 0;
    CHECK_EQ_INT(coc_from_camera(&cam2, &one, &plain, 1, 1), DDOF_OK);
    CHECK(old == plain);
    CHECK(old != got1);

    /* Bad frames are refused with a message. */
    float dummy = 0.0f;
    cam2.frame_width = 10;
    cam2.frame_height = 0;
    CHECK_EQ_INT(coc_from_camera(&cam2, &one, &dummy, 1, 1), DDOF_ERROR_BAD_CAMERA);
    CHECK(strstr(ddof_context_last_error(ctx), "frame") != NULL);
    cam2.frame_width = 0;
    cam2.window_x = 3;
    CHECK_EQ_INT(coc_from_camera(&cam2, &one, &dummy, 1, 1), DDOF_ERROR_BAD_CAMERA);
    cam2.frame_width = cam2.frame_height = DDOF_MAX_DIMENSION + 1;
    cam2.window_x = 0;
    CHECK_EQ_INT(coc_from_camera(&cam2, &one, &dummy, 1, 1), DDOF_ERROR_BAD_CAMERA);
    cam2.frame_width = cam2.frame_height = 100;
    cam2.window_y = INT32_MIN;
    CHECK_EQ_INT(coc_from_camera(&cam2, &one, &dummy, 1, 1), DDOF_ERROR_BAD_CAMERA);
    free(depth);
    free(full);
}

static void test_clamp(void)
{
    ddof_camera cam;
    ddof_camera_init(&cam);
    cam.sensor_fit = DDOF_SENSOR_FIT_HORIZONTAL;
    const uint32_t w = 4;
    /* d = 2500/28000 mm * |Z - 10000|/Z / (36/4 mm): 1e-7 m -> ~9.9e5 px (clamped), 1e-5 m ->
     * ~9.9e3 px (not clamped); FLT_MIN and a denormal overflow any float intermediate. */
    float depth[4] = {1e-7f, 1e-5f, FLT_MIN, 1e-45f}, coc[4];
    CHECK_EQ_INT(coc_from_camera(&cam, depth, coc, w, 1), DDOF_OK);
    CHECK(coc[0] == DDOF_MAX_COC_PX);
    CHECK_NEAR(coc[1], expected_coc(&cam, w, 1, 1, 0, depth[1]), 1e-5 * coc[1]);
    CHECK(coc[1] < DDOF_MAX_COC_PX);
    CHECK(coc[2] == DDOF_MAX_COC_PX);
    CHECK(coc[3] == DDOF_MAX_COC_PX);
    /* A clamped CoC is a valid input to the diffusion. */
    float color[4] = {1, 0, 0, 1}, out[4];
    ddof_params p;
    heat_params_init(&p);
    CHECK_EQ_INT(diffuse(ctx, &p, color, coc, out, w, 1, 1, NULL), DDOF_OK);
}

/* depth with several channels (only the first is read: the others hold NaN), padded strides on
 * both images (the CoC's padding keeps its sentinel). */
static void test_layout(void)
{
    test_rng rng = {13};
    const uint32_t w = 21, h = 9, dch = 3;
    const size_t dstride = w * dch + 5, cstride = w + 3; /* in floats */
    float *depth = alloc_f(dstride * h), *coc = alloc_f(cstride * h);
    float *plain = alloc_f((size_t)w * h), *ref = alloc_f((size_t)w * h);
    fill_const(depth, dstride * h, NAN);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++)
            plain[y * w + x] = depth[y * dstride + x * dch] = (float)(1 + 40 * test_uniform(&rng));
    fill_const(coc, cstride * h, -123.0f);
    ddof_camera cam;
    ddof_camera_init(&cam);
    ddof_image_in di = {depth, w, h, dch, dstride * 4};
    ddof_image ci = {coc, w, h, 1, cstride * 4};
    ddof_status s = ddof_coc_from_camera(ctx, &cam, &di, &ci);
    CHECK_MSG(s == DDOF_OK, "3-channel padded depth: %d (%s)", (int)s,
              ddof_context_last_error(ctx));
    CHECK_EQ_INT(coc_from_camera(&cam, plain, ref, w, h), DDOF_OK);
    size_t diff = padded_rows_differ(coc, cstride, ref, w, h);
    size_t pad = padding_changed(coc, cstride, w, h, -123.0f);
    CHECK_MSG(diff == 0, "%zu rows differ between padded 3-channel and plain depth", diff);
    CHECK_MSG(pad == 0, "%zu padding floats of the CoC overwritten", pad);

    /* The curve too. */
    ddof_curve cv;
    ddof_curve_init(&cv);
    fill_const(coc, cstride * h, -123.0f);
    CHECK_EQ_INT(ddof_coc_from_curve(ctx, &cv, &di, &ci), DDOF_OK);
    pad = padding_changed(coc, cstride, w, h, -123.0f);
    CHECK_EQ_INT(pad, 0);
    free(depth);
    free(coc);
    free(plain);
    free(ref);
}

static void test_curve(void)
{
    ddof_curve cv = curve_of(8, 1, 2, 5, 10, 20);
    const float depth[] = {0.0f, 0.5f, 1.0f, 1.25f, 1.5f, 2.0f, 3.0f, 5.0f,
                           6.0f, 7.5f, 10.0f, 11.0f, 1e6f, 1e30f, INFINITY};
    const double want[] = {8, 8, 8, 6, 4, 0, 0, 0, 4, 10, 20, 20, 20, 20, 20};
    const uint32_t n = sizeof depth / sizeof depth[0];
    float coc[sizeof depth / sizeof depth[0]];
    ddof_image_in di = {depth, n, 1, 1, 0};
    ddof_image ci = {coc, n, 1, 1, 0};
    CHECK_EQ_INT(ddof_coc_from_curve(ctx, &cv, &di, &ci), DDOF_OK);
    for (uint32_t i = 0; i < n; i++)
        CHECK_MSG(fabs(coc[i] - want[i]) <= 1e-5, "curve at depth %g: %.9g, expected %g",
                  (double)depth[i], (double)coc[i], want[i]);
    /* In-focus range is exactly 0. */
    CHECK(coc[5] == 0.0f && coc[6] == 0.0f && coc[7] == 0.0f);

    /* The defaults: no near blur, 0 up to 10, 16 px from 100 on. */
    ddof_curve_init(&cv);
    const double want_default[] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 16.0 / 90.0, 16, 16, 16};
    CHECK_EQ_INT(ddof_coc_from_curve(ctx, &cv, &di, &ci), DDOF_OK);
    for (uint32_t i = 0; i < n; i++)
        CHECK_MSG(fabs(coc[i] - want_default[i]) <= 1e-5,
                  "default curve at depth %g: %.9g, expected %g", (double)depth[i],
                  (double)coc[i], want_default[i]);

    /* Steps: near_start == near_end and far_start == far_end. */
    cv = curve_of(3, 2, 2, 6, 6, 9);
    const float sd[] = {0.0f, 1.999f, 2.001f, 5.999f, 6.001f, INFINITY};
    const double sw[] = {3, 3, 0, 0, 9, 9};
    float so[6];
    ddof_image_in sdi = {sd, 6, 1, 1, 0};
    ddof_image sci = {so, 6, 1, 1, 0};
    CHECK_EQ_INT(ddof_coc_from_curve(ctx, &cv, &sdi, &sci), DDOF_OK);
    for (int i = 0; i < 6; i++)
        CHECK_MSG(fabs(so[i] - sw[i]) <= 1e-5, "step curve at %g: %g, expected %g",
                  (double)sd[i], (double)so[i], sw[i]);
    /* Blur of exactly DDOF_MAX_COC_PX is allowed. */
    cv.far_blur_px = DDOF_MAX_COC_PX;
    CHECK_EQ_INT(ddof_coc_from_curve(ctx, &cv, &sdi, &sci), DDOF_OK);
    CHECK(so[5] == DDOF_MAX_COC_PX);
}

/* ddof_depth_of_field is ddof_coc_from_camera, then ddof_diffuse with the camera's pixel aspect. */
static void test_depth_of_field(void)
{
    test_rng rng = {14};
    const uint32_t w = 48, h = 36, ch = 4;
    const size_t px = (size_t)w * h;
    float *color = alloc_f(px * ch), *depth = alloc_f(px), *coc = alloc_f(px);
    float *a = alloc_f(px * ch), *b = alloc_f(px * ch);
    for (size_t i = 0; i < px * ch; i++)
        color[i] = (float)test_uniform(&rng);
    fill_depth(depth, px, &rng, 0.5, 100.0);
    ddof_camera cam;
    ddof_camera_init(&cam);
    cam.fstop = 1.4;
    cam.focus_distance_m = 3;
    cam.pixel_aspect = 1.5;
    cam.sensor_fit = DDOF_SENSOR_FIT_HORIZONTAL;
    ddof_params p;
    heat_params_init(&p);
    p.substeps = 2;
    ddof_image_in ci = {color, w, h, ch, 0}, di = {depth, w, h, 1, 0};
    ddof_image oa = {a, w, h, ch, 0}, cz = {coc, w, h, 1, 0};
    ddof_stats st = stats_init();
    CHECK_EQ_INT(ddof_depth_of_field(ctx, &p, &cam, &ci, &di, &oa, &st), DDOF_OK);
    CHECK_EQ_INT(ddof_coc_from_camera(ctx, &cam, &di, &cz), DDOF_OK);
    float maxc = 0;
    for (size_t i = 0; i < px; i++)
        maxc = fmaxf(maxc, coc[i]);
    CHECK_MSG(st.max_coc_px == maxc, "stats.max_coc_px %g, CoC image max %g",
              (double)st.max_coc_px, (double)maxc);
    CHECK(st.seconds_coc >= 0 && st.seconds_coc <= st.seconds_total + 1e-6);
    p.pixel_aspect = 1.5f;
    CHECK_EQ_INT(diffuse(ctx, &p, color, coc, b, w, h, ch, NULL), DDOF_OK);
    CHECK_MSG(!memcmp(a, b, px * ch * sizeof(float)),
              "depth_of_field differs from coc_from_camera + diffuse(pixel_aspect 1.5)");
    p.pixel_aspect = 1.0f;
    CHECK_EQ_INT(diffuse(ctx, &p, color, coc, b, w, h, ch, NULL), DDOF_OK);
    CHECK_MSG(memcmp(a, b, px * ch * sizeof(float)) != 0,
              "pixel aspect of the camera had no effect");
    free(color);
    free(depth);
    free(coc);
    free(a);
    free(b);
}

int main(void)
{
    if (ddof_context_create(NULL, &ctx) != DDOF_OK || !ctx) {
        fprintf(stderr, "ddof_context_create failed\n");
        return 2;
    }
    test_defaults();
    test_lens_models();
    test_units_and_sky();
    test_sensor_fit();
    test_radial();
    test_crop();
    test_clamp();
    test_layout();
    test_curve();
    test_depth_of_field();
    printf("worst relative CoC error vs the double formulas: %.3g\n", worst_rel);
    ddof_context_free(ctx);
    return test_report("test_coc");
}
