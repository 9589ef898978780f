/* SPDX-License-Identifier: MIT */
/* test_layers_near.c - the near field of one image: the signed CoC of ddof_coc_from_camera and
 * ddof_coc_from_curve, ddof_depth_of_field's near field, a small near light. */
#include "layers_test.h"

static void test_signed_coc(void)
{
    static const float depths[] = {1e-7f, 0.3f, 1.0f, 2.5f, 7.0f, 9.99f, 10.0f, 10.01f, 15.0f,
                                   100.0f, 1e6f, INFINITY};
    const uint32_t nd = sizeof depths / sizeof depths[0];
    float u[16], s[16];
    ddof_image_in din = {depths, nd, 1, 1, 0};
    ddof_image uo = {u, nd, 1, 1, 0}, so = {s, nd, 1, 1, 0};
    for (int model = 0; model < 2; model++) {
        ddof_camera cam;
        ddof_camera_init(&cam);
        cam.lens_model = model ? DDOF_LENS_THIN_LENS : DDOF_LENS_CYCLES;
        CHECK_EQ_INT(ddof_coc_from_camera(ctx, &cam, &din, &uo), DDOF_OK);
        cam.signed_coc = 1;
        CHECK_EQ_INT(ddof_coc_from_camera(ctx, &cam, &din, &so), DDOF_OK);
        for (uint32_t i = 0; i < nd; i++) {
            CHECK_MSG(u[i] >= 0, "unsigned CoC at depth %g is %g", (double)depths[i], (double)u[i]);
            if (depths[i] < 10.0f) {
                CHECK_MSG(u[i] > 0 && s[i] == -u[i], "depth %g: signed %g, unsigned %g",
                          (double)depths[i], (double)s[i], (double)u[i]);
            } else if (depths[i] == 10.0f) {
                CHECK_MSG(s[i] == 0.0f && u[i] == 0.0f, "focus: signed %g, unsigned %g",
                          (double)s[i], (double)u[i]);
            } else {
                CHECK_MSG(u[i] > 0 && s[i] == u[i], "depth %g: signed %g, unsigned %g",
                          (double)depths[i], (double)s[i], (double)u[i]);
            }
        }
        CHECK_NEAR(s[0], -DDOF_MAX_COC_PX, 0); /* clamped, keeps its sign */
    }

    ddof_curve curve;
    ddof_curve_init(&curve);
    curve.near_blur_px = 12;
    curve.near_start = 1;
    curve.near_end = 3;
    curve.far_start = 10;
    curve.far_end = 100;
    curve.far_blur_px = 16;
    static const float cd[] = {0.5f, 2.0f, 5.0f, 55.0f, 200.0f, INFINITY};
    static const float want[] = {-12.0f, -6.0f, 0.0f, 8.0f, 16.0f, 16.0f};
    const uint32_t nc = sizeof cd / sizeof cd[0];
    ddof_image_in cin = {cd, nc, 1, 1, 0};
    ddof_image co = {s, nc, 1, 1, 0};
    curve.signed_coc = 1;
    CHECK_EQ_INT(ddof_coc_from_curve(ctx, &curve, &cin, &co), DDOF_OK);
    for (uint32_t i = 0; i < nc; i++)
        CHECK_MSG(fabs(s[i] - want[i]) <= 1e-4, "curve at %g: %g, want %g", (double)cd[i],
                  (double)s[i], (double)want[i]);
    curve.signed_coc = 0;
    CHECK_EQ_INT(ddof_coc_from_curve(ctx, &curve, &cin, &co), DDOF_OK);
    for (uint32_t i = 0; i < nc; i++)
        CHECK_MSG(fabs(s[i] - fabsf(want[i])) <= 1e-4, "unsigned curve at %g: %g", (double)cd[i],
                  (double)s[i]);
}

static void test_depth_of_field_near(void)
{
    const size_t npx = (size_t)W * H, n = npx * CH;
    float *color = alloc_f(n), *depth = alloc_f(npx), *out = alloc_f(n), *out2 = alloc_f(n);
    float *coc = alloc_f(npx);
    texture(color, CH, 71);
    const double R = disc_radius();
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++)
            depth[(size_t)y * W + x] = disc_dist(x, y) <= R ? 0.5f : 10.0f;
    ddof_camera cam;
    ddof_camera_init(&cam);
    cam.fstop = 1.4;
    ddof_params p;
    heat_params_init(&p); /* coc_signed 0: ddof_depth_of_field uses signed CoC anyway */
    /* The camera's CoC scales with the frame's width: the disc's is 6 px at 64x48
     * (DDOF_TEST_QUICK), 15 px at 160x120; the near layer runs for both. */
    p.near_layer_threshold_px = 4.0f;
    ddof_image_in ci = {color, W, H, CH, 0}, di = {depth, W, H, 1, 0};
    ddof_image oi = {out, W, H, CH, 0};
    ddof_stats st;
    st = stats_init();
    CHECK_EQ_INT(ddof_depth_of_field(ctx, &p, &cam, &ci, &di, &oi, &st), DDOF_OK);
    if (verbose)
        printf("depth of field, near disc: effects 0x%x, max CoC %g, plan:\n%s\n", st.effects,
               (double)st.max_coc_px, st.plan);
    /* The near layer (AUTO) takes the near field: the spread does not run. */
    CHECK_MSG(st.effects & DDOF_EFFECT_NEAR_LAYER, "ddof_depth_of_field, near object: effects 0x%x",
              st.effects);
    CHECK(st.effects & DDOF_EFFECT_FOREGROUND);
    CHECK(!(st.effects & DDOF_EFFECT_NEAR_SPREAD));
    CHECK(st.max_coc_px >= 4.0f);
    CHECK(all_finite(out, n));

    /* The same as the signed CoC + ddof_diffuse_layers by hand. */
    ddof_image co = {coc, W, H, 1, 0};
    cam.signed_coc = 1;
    CHECK_EQ_INT(ddof_coc_from_camera(ctx, &cam, &di, &co), DDOF_OK);
    size_t negative = 0;
    for (size_t i = 0; i < npx; i++)
        negative += coc[i] < 0;
    CHECK(negative > 0);
    p.coc_signed = 1;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out2, CH, NULL), DDOF_OK);
    CHECK_MSG(max_abs_diff_ff(out, out2, n) <= 1e-6, "depth_of_field vs coc + layers: %g",
              max_abs_diff_ff(out, out2, n));
    free(color);
    free(depth);
    free(out);
    free(out2);
    free(coc);
}

/* A small near object (a 5x5 light of CoC 20 px, value 30) over an in-focus background: the
 * near spread must let it blur as a large one of the same CoC would. Measured (160x120 and
 * 64x48, the default preset): its peak falls to 0.30 of its value and 0.71 of its energy leaves
 * its own pixels; GPU Gems 3's D = max(D0, 2 D_blurred - D0) in place of the spread barely
 * raises its surroundings' CoC and leaves 0.66 and 0.36 (a sharp dot in a faint halo). */
static void test_small_near_light(void)
{
    const size_t npx = (size_t)W * H;
    float *img = alloc_f(npx * CH), *coc = alloc_f(npx), *out = alloc_f(npx * CH);
    const uint32_t cx = W / 2, cy = H / 2;
    double inside = 0.0, total_in = 0.0;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            const size_t i = (size_t)y * W + x;
            const int light = x + 2 >= cx && x <= cx + 2 && y + 2 >= cy && y <= cy + 2;
            for (uint32_t c = 0; c < CH; c++)
                img[i * CH + c] = light ? 30.0f : 0.1f;
            coc[i] = light ? -20.0f : 0.0f;
            total_in += img[i * CH];
        }
    ddof_params p;
    heat_params_init(&p);
    p.coc_signed = 1;
    p.near_layer = DDOF_LAYER_OFF; /* the near spread's test (the near layer: test_near_layer.c) */
    ddof_stats st;
    CHECK_EQ_INT(layers(&p, img, coc, NULL, out, CH, &st), DDOF_OK);
    CHECK_MSG(st.effects & DDOF_EFFECT_NEAR_SPREAD, "small near light: effects 0x%x", st.effects);
    double total_out = 0.0, peak = 0.0;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            const size_t i = (size_t)y * W + x;
            const double v = out[i * CH] - 0.1; /* the light's part */
            total_out += out[i * CH];
            peak = fmax(peak, v);
            if (x + 2 >= cx && x <= cx + 2 && y + 2 >= cy && y <= cy + 2)
                inside += v;
        }
    const double energy = 25.0 * (30.0 - 0.1);
    if (verbose)
        printf("small near light: peak %.3f of its value, %.3f of its energy outside it\n",
               peak / (30.0 - 0.1), 1.0 - inside / energy);
    CHECK_MSG(peak <= 0.6 * (30.0 - 0.1), "small near light stays sharp: peak %.3g", peak);
    CHECK_MSG(inside <= 0.45 * energy, "small near light: %.3g of its energy stayed on it",
              inside / energy);
    CHECK_NEAR(total_out, total_in, 1e-4 * total_in); /* diffusion conserves it */
    free(img);
    free(coc);
    free(out);
}

int main(void)
{
    layers_test_begin();
    test_small_near_light();
    test_signed_coc();
    test_depth_of_field_near();
    return layers_test_end("test_layers_near");
}
