/* SPDX-License-Identifier: MIT */
/* test_coc_frames.c - the CoC over a frame's forms: a crop of the full frame, clamping, the
 * images' layout (strides, channels); the artist curve; ddof_depth_of_field's CoC (coc_test.h). */
#include "coc_test.h"

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
    if (coc_test_begin() != 0)
        return 2;
    test_crop();
    test_clamp();
    test_layout();
    test_curve();
    test_depth_of_field();
    return coc_test_end("test_coc_frames");
}
