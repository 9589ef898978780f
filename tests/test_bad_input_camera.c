/* SPDX-License-Identifier: MIT */
/* test_bad_input_camera.c - the CoC's sources: bad cameras, curves and depths for
 * ddof_coc_from_camera, ddof_coc_from_curve and ddof_depth_of_field leave the CoC and the
 * output untouched (bad_input_test.h). */
#include "bad_input_test.h"

static int coc_untouched(void) { return !memcmp(coc_buf, sentinel_buf, W * H * sizeof(float)); }

static void reset_depth(float v)
{
    for (size_t i = 0; i < W * H; i++)
        color_buf[i] = v + 0.01f * (float)(i % 7);
}

/* The depth image (color_buf, 5 m) with `v` at pixel (27, 13), and the CoC image (coc_buf)
 * reset to the sentinel so that any write shows. */
static void plant_depth(float v)
{
    reset_depth(5.0f);
    color_buf[13 * W + 27] = v;
    memcpy(coc_buf, sentinel_buf, sizeof coc_buf);
}

static void test_camera(void)
{
    ddof_camera cam;
    ddof_camera_init(&cam);
    ddof_image_in depth = {color_buf, W, H, 1, 0};
    ddof_image coc = {coc_buf, W, H, 1, 0};

    const float bad_depth[] = {NAN, 0.0f, -0.0f, -1.0f, -INFINITY};
    const char *names[] = {"NaN", "0", "-0", "-1", "-inf"};
    for (int i = 0; i < 5; i++) {
        plant_depth(bad_depth[i]);
        ddof_status s = ddof_coc_from_camera(ctx, &cam, &depth, &coc);
        CHECK_MSG(s == DDOF_ERROR_BAD_DEPTH, "camera, depth %s: status %d", names[i], (int)s);
        CHECK_MSG(coc_untouched(), "camera, depth %s: coc written", names[i]);
        CHECK(ddof_context_last_error(ctx)[0] != '\0');
    }
    reset_depth(5.0f);
    color_buf[13 * W + 27] = INFINITY;
    CHECK_EQ_INT(ddof_coc_from_camera(ctx, &cam, &depth, &coc), DDOF_OK);
    CHECK(ddof_context_last_error(ctx)[0] == '\0');
    CHECK(isfinite(coc_buf[13 * W + 27]) && coc_buf[13 * W + 27] > 0.0f);

#define BAD_CAM(what, stmt, alt)                                                               \
    do {                                                                                       \
        ddof_camera_init(&cam);                                                                \
        stmt;                                                                                  \
        memcpy(coc_buf, sentinel_buf, sizeof coc_buf);                                         \
        ddof_status s_ = ddof_coc_from_camera(ctx, &cam, &depth, &coc);                        \
        CHECK_MSG(s_ == DDOF_ERROR_BAD_CAMERA || s_ == (alt), "%s: status %d", what, (int)s_); \
        CHECK_MSG(coc_untouched(), "%s: coc written", what);                                   \
        CHECK(ddof_context_last_error(ctx)[0] != '\0');                                        \
    } while (0)
    reset_depth(5.0f);
    BAD_CAM("fstop 0", cam.fstop = 0, DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("fstop -2", cam.fstop = -2, DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("fstop NaN", cam.fstop = NAN, DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("focal length 0", cam.focal_length_mm = 0, DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("focal length -50", cam.focal_length_mm = -50, DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("focal length NaN", cam.focal_length_mm = NAN, DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("focus = focal length", (cam.focal_length_mm = 50, cam.focus_distance_m = 0.05),
            DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("focus < focal length", (cam.focal_length_mm = 50, cam.focus_distance_m = 0.03),
            DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("focus 0", cam.focus_distance_m = 0, DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("focus -1", cam.focus_distance_m = -1, DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("focus NaN", cam.focus_distance_m = NAN, DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("sensor 0", cam.sensor_width_mm = 0, DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("sensor -36", cam.sensor_width_mm = -36, DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("pixel_aspect 0", cam.pixel_aspect = 0, DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("pixel_aspect -1", cam.pixel_aspect = -1, DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("pixel_aspect NaN", cam.pixel_aspect = NAN, DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("depth_unit_m 0", cam.depth_unit_m = 0, DDOF_ERROR_BAD_PARAMETER);
    BAD_CAM("depth_unit_m -1", cam.depth_unit_m = -1, DDOF_ERROR_BAD_PARAMETER);
    BAD_CAM("lens model 7", cam.lens_model = (ddof_lens_model)7, DDOF_ERROR_BAD_PARAMETER);
    BAD_CAM("depth kind 7", cam.depth_kind = (ddof_depth_kind)7, DDOF_ERROR_BAD_PARAMETER);
    BAD_CAM("sensor fit 7", cam.sensor_fit = (ddof_sensor_fit)7, DDOF_ERROR_BAD_PARAMETER);
#undef BAD_CAM

    /* Malformed structs and images. */
    ddof_camera_init(&cam);
    memcpy(coc_buf, sentinel_buf, sizeof coc_buf);
    CHECK_EQ_INT(ddof_coc_from_camera(ctx, NULL, &depth, &coc), DDOF_ERROR_NULL_POINTER);
    CHECK_EQ_INT(ddof_coc_from_camera(NULL, &cam, &depth, &coc), DDOF_ERROR_NULL_POINTER);
    CHECK_EQ_INT(ddof_coc_from_camera(ctx, &cam, NULL, &coc), DDOF_ERROR_NULL_POINTER);
    CHECK_EQ_INT(ddof_coc_from_camera(ctx, &cam, &depth, NULL), DDOF_ERROR_NULL_POINTER);
    cam.struct_size = 0;
    CHECK_EQ_INT(ddof_coc_from_camera(ctx, &cam, &depth, &coc), DDOF_ERROR_BAD_PARAMETER);
    ddof_camera_init(&cam);
    ddof_image coc2 = coc;
    coc2.width = W - 1;
    CHECK_EQ_INT(ddof_coc_from_camera(ctx, &cam, &depth, &coc2), DDOF_ERROR_SIZE_MISMATCH);
    coc2 = coc;
    coc2.channels = 2;
    ddof_status s = ddof_coc_from_camera(ctx, &cam, &depth, &coc2);
    CHECK_MSG(s == DDOF_ERROR_BAD_CHANNELS || s == DDOF_ERROR_SIZE_MISMATCH,
              "2-channel coc output: %d", (int)s);
    coc2 = coc;
    coc2.row_stride = W * 4 - 4;
    CHECK_EQ_INT(ddof_coc_from_camera(ctx, &cam, &depth, &coc2), DDOF_ERROR_BAD_STRIDE);
    ddof_image_in d2 = depth;
    d2.width = DDOF_MAX_DIMENSION + 1;
    coc2 = coc;
    coc2.width = DDOF_MAX_DIMENSION + 1;
    CHECK_EQ_INT(ddof_coc_from_camera(ctx, &cam, &d2, &coc2), DDOF_ERROR_BAD_SIZE);
    CHECK_MSG(coc_untouched(), "coc written by a failing ddof_coc_from_camera");
}

static void test_curve(void)
{
    ddof_curve cv;
    ddof_image_in depth = {color_buf, W, H, 1, 0};
    ddof_image coc = {coc_buf, W, H, 1, 0};
    reset_depth(5.0f);
#define BAD_CURVE(what, stmt)                                                                  \
    do {                                                                                       \
        cv = curve_of(4, 1, 2, 10, 20, 8);                                                     \
        CHECK_EQ_INT(ddof_coc_from_curve(ctx, &cv, &depth, &coc), DDOF_OK);                    \
        stmt;                                                                                  \
        memcpy(coc_buf, sentinel_buf, sizeof coc_buf);                                         \
        ddof_status s_ = ddof_coc_from_curve(ctx, &cv, &depth, &coc);                          \
        CHECK_MSG(s_ == DDOF_ERROR_BAD_PARAMETER, "curve %s: status %d", what, (int)s_);       \
        CHECK_MSG(coc_untouched(), "curve %s: coc written", what);                             \
        CHECK(ddof_context_last_error(ctx)[0] != '\0');                                       \
    } while (0)
    BAD_CURVE("near_start > near_end", cv.near_start = 3);
    BAD_CURVE("near_end > far_start", cv.near_end = 11);
    BAD_CURVE("far_start > far_end", cv.far_start = 21);
    BAD_CURVE("near_start < 0", cv.near_start = -1);
    BAD_CURVE("near_blur < 0", cv.near_blur_px = -1);
    BAD_CURVE("far_blur < 0", cv.far_blur_px = -0.5);
    BAD_CURVE("far_blur > max", cv.far_blur_px = 2.0 * DDOF_MAX_COC_PX);
    BAD_CURVE("near_blur NaN", cv.near_blur_px = NAN);
    BAD_CURVE("far_end NaN", cv.far_end = NAN);
    BAD_CURVE("struct_size 0", cv.struct_size = 0);
#undef BAD_CURVE

    ddof_curve_init(&cv);
    const float bad_depth[] = {NAN, -1.0f, -INFINITY};
    const char *names[] = {"NaN", "-1", "-inf"};
    for (int i = 0; i < 3; i++) {
        plant_depth(bad_depth[i]);
        ddof_status s = ddof_coc_from_curve(ctx, &cv, &depth, &coc);
        CHECK_MSG(s == DDOF_ERROR_BAD_DEPTH, "curve, depth %s: status %d", names[i], (int)s);
        CHECK_MSG(coc_untouched(), "curve, depth %s: coc written", names[i]);
    }
    /* 0 and +inf depth are valid for the curve. */
    reset_depth(5.0f);
    color_buf[0] = 0.0f;
    color_buf[1] = INFINITY;
    CHECK_EQ_INT(ddof_coc_from_curve(ctx, &cv, &depth, &coc), DDOF_OK);
    CHECK_EQ_INT(ddof_coc_from_curve(ctx, NULL, &depth, &coc), DDOF_ERROR_NULL_POINTER);
}

static void test_depth_of_field(void)
{
    ddof_camera cam;
    ddof_camera_init(&cam);
    ddof_params p;
    ddof_params_init(&p);
    float depth_buf[W * H];
    for (size_t i = 0; i < W * H; i++)
        depth_buf[i] = 2.0f + (float)(i % 13);
    reset_inputs();
    ddof_image_in ci = {color_buf, W, H, CH, 0}, di = {depth_buf, W, H, 1, 0};
    ddof_image oi = {out_buf, W, H, CH, 0};
    CHECK_EQ_INT(ddof_depth_of_field(ctx, &p, &cam, &ci, &di, &oi, NULL), DDOF_OK);

#define BAD_DOF(what, want, stmt, undo)                                                        \
    do {                                                                                       \
        stmt;                                                                                  \
        fill_sentinel();                                                                       \
        ddof_status s_ = ddof_depth_of_field(ctx, &p, &cam, &ci, &di, &oi, NULL);              \
        check_failure(what, s_, want, want);                                                   \
        undo;                                                                                  \
        CHECK_EQ_INT(ddof_depth_of_field(ctx, &p, &cam, &ci, &di, &oi, NULL), DDOF_OK);        \
    } while (0)
    BAD_DOF("dof: depth NaN", DDOF_ERROR_BAD_DEPTH, depth_buf[77] = NAN, depth_buf[77] = 3);
    BAD_DOF("dof: depth 0", DDOF_ERROR_BAD_DEPTH, depth_buf[77] = 0, depth_buf[77] = 3);
    BAD_DOF("dof: colour NaN", DDOF_ERROR_BAD_COLOR, color_buf[77] = NAN, color_buf[77] = 0.5f);
    BAD_DOF("dof: fstop 0", DDOF_ERROR_BAD_CAMERA, cam.fstop = 0, cam.fstop = 2.8);
    BAD_DOF("dof: depth size", DDOF_ERROR_SIZE_MISMATCH, di.width = W - 1, di.width = W);
    BAD_DOF("dof: substeps 0", DDOF_ERROR_BAD_PARAMETER, p.substeps = 0, p.substeps = 1);
    /* The camera's pixel aspect becomes params.pixel_aspect: the same range, checked on the
     * double before it is converted (1e-300 would become 0, 1e300 infinity). A bad camera, as
     * a negative one is (issue 22: it was BAD_PARAMETER for 1e20 and BAD_CAMERA for -1). */
    BAD_DOF("dof: camera pixel_aspect 1e20", DDOF_ERROR_BAD_CAMERA, cam.pixel_aspect = 1e20,
            cam.pixel_aspect = 1.0);
    BAD_DOF("dof: camera pixel_aspect 1e-300", DDOF_ERROR_BAD_CAMERA,
            cam.pixel_aspect = 1e-300, cam.pixel_aspect = 1.0);
    BAD_DOF("dof: camera pixel_aspect -1", DDOF_ERROR_BAD_CAMERA, cam.pixel_aspect = -1.0,
            cam.pixel_aspect = 1.0);
    cam.pixel_aspect = 1e-300;
    CHECK(ddof_depth_of_field(ctx, &p, &cam, &ci, &di, &oi, NULL) == DDOF_ERROR_BAD_CAMERA);
    CHECK_MSG(strstr(ddof_context_last_error(ctx), "pixel_aspect 1e-300 must be within 0.01..100"),
              "%s", ddof_context_last_error(ctx));
    cam.pixel_aspect = 100.0;
    CHECK_EQ_INT(ddof_depth_of_field(ctx, &p, &cam, &ci, &di, &oi, NULL), DDOF_OK);
    cam.pixel_aspect = 1.0;
    BAD_DOF("dof: depth NULL pixels", DDOF_ERROR_NULL_POINTER, di.pixels = NULL,
            di.pixels = depth_buf);
#undef BAD_DOF
    fill_sentinel();
    CHECK_EQ_INT(ddof_depth_of_field(ctx, &p, NULL, &ci, &di, &oi, NULL),
                 DDOF_ERROR_NULL_POINTER);
    CHECK_EQ_INT(ddof_depth_of_field(ctx, NULL, &cam, &ci, &di, &oi, NULL),
                 DDOF_ERROR_NULL_POINTER);
    CHECK_EQ_INT(ddof_depth_of_field(ctx, &p, &cam, &ci, NULL, &oi, NULL),
                 DDOF_ERROR_NULL_POINTER);
    CHECK(out_untouched());
}

int main(void)
{
    bad_input_test_begin();

    test_camera();
    test_curve();
    test_depth_of_field();

    return bad_input_test_end("test_bad_input_camera");
}
