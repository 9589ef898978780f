/* SPDX-License-Identifier: MIT */
/* test_coc.c - circle of confusion from a camera (Cycles and thin-lens models, sensor fits,
 * pixel aspect, radial depth, depth units, sky), against formulas evaluated in double
 * (coc_test.h). */
#include "coc_test.h"

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

int main(void)
{
    if (coc_test_begin() != 0)
        return 2;
    test_defaults();
    test_lens_models();
    test_units_and_sky();
    test_sensor_fit();
    test_radial();
    return coc_test_end("test_coc");
}
