/* SPDX-License-Identifier: MIT */
/* test_planner_threshold.c - the in-focus threshold: pixels under it are copied, bit for bit, and
 * the planner says so (planner_test.h). */
#include "planner_test.h"

/* The in-focus threshold (params.in_focus_threshold_px, default 0.5 px). A frame whose largest
 * |CoC| is below it is a copy: no line solved, copied_only 1, the output bit for bit the input,
 * through ddof_diffuse and ddof_diffuse_layers, both kernels, signed or not, in place or not.
 * The same frame with the threshold 0 does blur: the threshold is what made it a copy. Inside
 * a blurred frame a pixel below the threshold conducts as CoC 0 and keeps its value. */
static void sub_pixel_coc(float *coc, float max, int with_near, unsigned long long seed)
{
    test_rng rng = {seed};
    for (size_t i = 0; i < npx; i++) {
        const float v = (float)(max * test_uniform(&rng));
        coc[i] = with_near && (i / W + i % W) % 3 == 0 ? -v : v;
    }
    /* The largest |CoC| is exactly `max`, on two neighbours: a link of that size. */
    coc[npx / 2 + W / 2] = coc[npx / 2 + W / 2 + 1] = with_near ? -max : max;
}

/* How many values of pixels with |CoC| below t differ from the input, bit for bit. */
static size_t in_focus_changed(const float *out, const float *in, const float *coc, float t)
{
    size_t changed = 0;
    for (size_t i = 0; i < npx; i++)
        if (fabsf(coc[i]) < t)
            changed += memcmp(out + i * CH, in + i * CH, CH * sizeof(float)) != 0;
    return changed;
}

static void check_copy(const char *name, const ddof_stats *st, const float *result, float max)
{
    CHECK_MSG(st->lines_solved == 0, "%s: %llu lines solved", name,
              (unsigned long long)st->lines_solved);
    CHECK_MSG(st->copied_only == 1, "%s: copied_only %u", name, st->copied_only);
    CHECK_EQ_INT(st->substeps, 0);
    CHECK_MSG(st->effects == 0, "%s: effects 0x%x", name, st->effects);
    CHECK_MSG(st->max_coc_px == max, "%s: max_coc_px %.9g, the frame's is %.9g", name,
              (double)st->max_coc_px, (double)max);
    CHECK_MSG(!memcmp(result, color, n * sizeof(float)), "%s: output is not the input", name);
}

static void test_in_focus_threshold(void)
{
    texture(color, CH, 11);
    ddof_params defaults;
    for (int preset = 0; preset < DDOF_PRESET_COUNT_; preset++) {
        CHECK_EQ_INT(ddof_params_init_preset(&defaults, (ddof_preset)preset), DDOF_OK);
        CHECK_NEAR(defaults.in_focus_threshold_px, 0.5, 0.0);
    }

    static const float below = 0.45f; /* the frame's largest |CoC|, under the default */
    for (int variant = 0; variant < 8; variant++) {
        const int layered = variant & 1, disc = (variant >> 1) & 1, in_place = variant >> 2;
        char name[96];
        snprintf(name, sizeof name, "sub-pixel %s %s%s", layered ? "layers" : "single",
                 disc ? "disc" : "heat", in_place ? " in place" : "");
        ddof_params p;
        ddof_params_init(&p); /* the default preset: disc-2x2 */
        if (!disc)
            p.kernel = DDOF_KERNEL_HEAT;
        p.coc_signed = 1;
        sub_pixel_coc(coc, below, 1, 100 + (unsigned)variant);
        ddof_stats st;
        float *result = in_place ? out2 : out;
        if (in_place)
            memcpy(out2, color, n * sizeof(float));
        else
            fill_const(out, n, -7.0f);
        const float *input = in_place ? out2 : color;
        CHECK_EQ_INT(layered ? layers(&p, input, coc, NULL, result, CH, &st)
                             : single(&p, input, coc, result, CH, &st),
                     DDOF_OK);
        check_copy(name, &st, result, below);
        if (layered) {
            CHECK_MSG(plan_says(&st, "midground", "off"), "%s: plan \"%.*s\"", name, 511,
                      st.plan);
            check_timings(name, &st, 0, 0);
        }

        /* Without the threshold the same frame is blurred: lines solved, output changed. */
        p.in_focus_threshold_px = 0.0f;
        if (in_place)
            memcpy(out2, color, n * sizeof(float));
        CHECK_EQ_INT(layered ? layers(&p, input, coc, NULL, result, CH, &st)
                             : single(&p, input, coc, result, CH, &st),
                     DDOF_OK);
        CHECK_MSG(st.lines_solved > 0 && st.copied_only == 0, "%s, threshold 0: %llu lines",
                  name, (unsigned long long)st.lines_solved);
        CHECK_MSG(max_abs_diff_ff(result, color, n) > 1e-4,
                  "%s, threshold 0: the output is the input", name);
    }

    /* ddof_depth_of_field computes its CoC (no validation pass finds the largest): a scene
     * just behind the focus plane has a CoC far below a pixel, and is a copy too. */
    {
        ddof_camera cam;
        ddof_camera_init(&cam); /* 50 mm f/2.8 focused at 10 m */
        float *depth = alloc_f(npx);
        for (size_t i = 0; i < npx; i++)
            depth[i] = 10.0f + 0.01f * (float)(i % 7);
        ddof_params p;
        ddof_params_init(&p);
        ddof_image_in ci = {color, W, H, CH, 0}, di = {depth, W, H, 1, 0};
        ddof_image oi = {out, W, H, CH, 0};
        ddof_stats st = stats_init();
        fill_const(out, n, -7.0f);
        CHECK_EQ_INT(ddof_depth_of_field(ctx, &p, &cam, &ci, &di, &oi, &st), DDOF_OK);
        CHECK_MSG(st.max_coc_px > 0.0f && st.max_coc_px < 0.5f, "camera: largest CoC %g",
                  (double)st.max_coc_px);
        check_copy("camera, sub-pixel", &st, out, st.max_coc_px);
        /* The heat kernel: a disc kernel drops links below DDOF_LENS_MIN_LINK, which CoCs this
         * small (the quick run's smaller frame has larger pixels) do not reach. */
        p.in_focus_threshold_px = 0.0f;
        p.kernel = DDOF_KERNEL_HEAT;
        CHECK_EQ_INT(ddof_depth_of_field(ctx, &p, &cam, &ci, &di, &oi, &st), DDOF_OK);
        CHECK_MSG(st.lines_solved > 0, "camera, threshold 0: %llu lines",
                  (unsigned long long)st.lines_solved);
        free(depth);
    }

    /* The bound: a largest |CoC| equal to the threshold conducts (|CoC| < t is in focus), one
     * a hair below it does not. */
    ddof_params p;
    heat_params_init(&p);
    ddof_stats st;
    sub_pixel_coc(coc, 0.8f, 0, 7);
    p.in_focus_threshold_px = 0.8f;
    CHECK_EQ_INT(single(&p, color, coc, out, CH, &st), DDOF_OK);
    CHECK_MSG(st.lines_solved > 0 && st.copied_only == 0,
              "largest CoC = threshold: %llu lines, copied_only %u",
              (unsigned long long)st.lines_solved, st.copied_only);
    p.in_focus_threshold_px = nextafterf(0.8f, 1.0f);
    CHECK_EQ_INT(single(&p, color, coc, out, CH, &st), DDOF_OK);
    check_copy("largest CoC just below the threshold", &st, out, 0.8f);

    /* A blurred frame: its sub-pixel pixels conduct as CoC 0 and keep their values exactly,
     * with either kernel; the others blur. */
    for (int disc = 0; disc < 2; disc++) {
        ddof_params_init(&p);
        if (!disc)
            p.kernel = DDOF_KERNEL_HEAT;
        test_rng rng = {31};
        for (size_t i = 0; i < npx; i++)
            coc[i] = test_uniform(&rng) < 0.3 ? (float)(0.49 * test_uniform(&rng)) : 10.0f;
        CHECK_EQ_INT(single(&p, color, coc, out, CH, &st), DDOF_OK);
        CHECK(st.lines_solved > 0 && st.copied_only == 0);
        size_t changed = in_focus_changed(out, color, coc, 0.5f);
        CHECK_MSG(changed == 0, "%s: %zu sub-pixel pixels changed", disc ? "disc" : "heat",
                  changed);
        CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, &st), DDOF_OK);
        CHECK(st.lines_solved > 0);
        /* Without the threshold they blur like any other. */
        p.in_focus_threshold_px = 0.0f;
        CHECK_EQ_INT(single(&p, color, coc, out, CH, &st), DDOF_OK);
        changed = in_focus_changed(out, color, coc, 0.5f);
        CHECK_MSG(changed > npx / 10, "%s, threshold 0: only %zu sub-pixel pixels changed",
                  disc ? "disc" : "heat", changed);
    }

    /* The range: >= 0, at most DDOF_MAX_COC_PX; outside it a status and out untouched. */
    sub_pixel_coc(coc, below, 0, 5);
    const float bad[] = {-0.25f, -FLT_MIN, NAN, INFINITY, 2.0f * DDOF_MAX_COC_PX,
                         nextafterf(DDOF_MAX_COC_PX, INFINITY)};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        heat_params_init(&p);
        p.in_focus_threshold_px = bad[i];
        fill_const(out, n, -7.0f);
        CHECK_MSG(single(&p, color, coc, out, CH, NULL) == DDOF_ERROR_BAD_PARAMETER,
                  "threshold %g accepted by ddof_diffuse", (double)bad[i]);
        CHECK_MSG(layers(&p, color, coc, NULL, out, CH, NULL) == DDOF_ERROR_BAD_PARAMETER,
                  "threshold %g accepted by ddof_diffuse_layers", (double)bad[i]);
        CHECK_MSG(ci_find(ddof_context_last_error(ctx), strlen(ddof_context_last_error(ctx)),
                          "in_focus_threshold_px"),
                  "threshold %g: error \"%s\"", (double)bad[i], ddof_context_last_error(ctx));
        size_t touched = 0;
        for (size_t k = 0; k < n; k++)
            touched += out[k] != -7.0f;
        CHECK_MSG(touched == 0, "threshold %g: %zu output values written", (double)bad[i],
                  touched);
    }
    const float good[] = {0.0f, DDOF_MAX_COC_PX};
    for (size_t i = 0; i < 2; i++) {
        heat_params_init(&p);
        p.in_focus_threshold_px = good[i];
        CHECK_EQ_INT(single(&p, color, coc, out, CH, &st), DDOF_OK);
        CHECK_EQ_INT(st.copied_only, good[i] > 0.0f);
    }

    /* Bad colour in a frame that would be a copy is still found, and out stays untouched. */
    heat_params_init(&p);
    color[n / 3] = NAN;
    fill_const(out, n, -7.0f);
    CHECK_EQ_INT(single(&p, color, coc, out, CH, NULL), DDOF_ERROR_BAD_COLOR);
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, NULL), DDOF_ERROR_BAD_COLOR);
    size_t touched = 0;
    for (size_t k = 0; k < n; k++)
        touched += out[k] != -7.0f;
    CHECK_MSG(touched == 0, "bad colour, sub-pixel frame: %zu output values written", touched);
    texture(color, CH, 11);

    /* An older caller (params up to kernel, garbage after) gets the default threshold. */
    ddof_params_init(&p);
    p.kernel = DDOF_KERNEL_HEAT;
    unsigned char pbuf[sizeof(ddof_params)];
    memset(pbuf, 0xA7, sizeof pbuf);
    const size_t v04 = offsetof(ddof_params, in_focus_threshold_px);
    memcpy(pbuf, &p, v04);
    ((ddof_params *)(void *)pbuf)->struct_size = (uint32_t)v04;
    ddof_params old;
    memcpy(&old, pbuf, sizeof old);
    CHECK_MSG(!(old.in_focus_threshold_px >= 0.0f && old.in_focus_threshold_px <= 1.0f),
              "the garbage must not itself be a plausible threshold");
    for (int layered = 0; layered < 2; layered++) {
        fill_const(out, n, -7.0f);
        CHECK_EQ_INT(layered ? layers(&old, color, coc, NULL, out, CH, &st)
                             : single(&old, color, coc, out, CH, &st),
                     DDOF_OK);
        check_copy(layered ? "v0.4 params, layers" : "v0.4 params, single", &st, out, below);
    }
}

int main(void)
{
    planner_test_begin();

    test_in_focus_threshold();

    return planner_test_end("test_planner_threshold");
}
