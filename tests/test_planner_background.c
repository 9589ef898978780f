/* SPDX-License-Identifier: MIT */
/* test_planner_background.c - the background layer's decisions: a uniform blur, a frame half sharp,
 * bars over a blurred background, the layer forced on (planner_test.h). */
#include "planner_test.h"

/* Uniform blur, no in-focus pixel: the midground only; equal to ddof_diffuse. */
static void test_uniform_blur(void)
{
    texture(color, CH, 2);
    fill_const(coc, npx, 10.0f);
    ddof_params p;
    heat_params_init(&p);
    ddof_stats st, st1;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, &st), DDOF_OK);
    dump_plan("uniform", &st);
    CHECK_MSG(st.effects == DDOF_EFFECT_MIDGROUND, "uniform blur: effects 0x%x, want 0x%x",
              st.effects, DDOF_EFFECT_MIDGROUND);
    CHECK_EQ_INT(st.copied_only, 0);
    CHECK(st.lines_solved >= (uint64_t)W + H);
    CHECK_MSG(plan_well_formed(&st), "uniform: plan \"%.*s\"", 511, st.plan);
    CHECK_MSG(plan_says(&st, "background", "off"), "uniform: plan \"%.*s\"", 511, st.plan);
    CHECK_MSG(plan_has_near_or_foreground(&st), "uniform: no near/foreground line in \"%.*s\"",
              511, st.plan);
    check_timings("uniform", &st, 0, 0);

    CHECK_EQ_INT(single(&p, color, coc, out2, CH, &st1), DDOF_OK);
    double d = max_abs_diff_ff(out, out2, n);
    CHECK_MSG(d <= 1e-6, "uniform: layered vs ddof_diffuse differ by %g", d);
    CHECK_EQ_INT(st.lines_solved, st1.lines_solved);
    CHECK_MSG(st1.effects == DDOF_EFFECT_MIDGROUND, "ddof_diffuse effects 0x%x", st1.effects);

    /* Signed CoC with nothing near: the same. */
    p.coc_signed = 1;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out2, CH, &st), DDOF_OK);
    CHECK_MSG(st.effects == DDOF_EFFECT_MIDGROUND, "uniform signed: effects 0x%x", st.effects);
    CHECK(max_abs_diff_ff(out, out2, n) <= 1e-6);
}

/* Half the image sharp (top), the other half mildly blurred (CoC 6 < threshold 8): the sharp
 * rows are skipped, the background layer is not called for. */
static void test_half_sharp(void)
{
    texture(color, CH, 3);
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++)
            coc[(size_t)y * W + x] = y < H / 2 ? 0.0f : 6.0f;
    ddof_params p;
    heat_params_init(&p);
    p.highlights = DDOF_LAYER_OFF; /* the texture is above the highlight threshold */
    ddof_stats st;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, &st), DDOF_OK);
    dump_plan("half sharp", &st);
    CHECK_MSG(st.effects == DDOF_EFFECT_MIDGROUND, "half sharp: effects 0x%x", st.effects);
    CHECK_MSG(st.lines_skipped >= H / 2, "half sharp: %llu lines skipped, want >= %u",
              (unsigned long long)st.lines_skipped, H / 2);
    CHECK(!memcmp(out, color, (size_t)(H / 2) * W * CH * sizeof(float)));
    check_timings("half sharp", &st, 0, 0);
}

/* Thin sharp bars over a blurred background: the background layer, nothing else. */
static void test_bars(void)
{
    texture(color, CH, 4);
    bars_coc(coc);
    ddof_params p;
    heat_params_init(&p);
    ddof_stats st_auto, st_off, st_on, st2;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, &st_auto), DDOF_OK);
    dump_plan("bars auto", &st_auto);
    CHECK_MSG(st_auto.effects == (DDOF_EFFECT_MIDGROUND | DDOF_EFFECT_BACKGROUND),
              "bars: effects 0x%x, want midground + background", st_auto.effects);
    CHECK_MSG(plan_well_formed(&st_auto), "bars: plan \"%.*s\"", 511, st_auto.plan);
    CHECK_MSG(plan_says(&st_auto, "background", "on"), "bars: plan \"%.*s\"", 511, st_auto.plan);
    CHECK_MSG(plan_has_near_or_foreground(&st_auto), "bars: no near line in \"%.*s\"", 511,
              st_auto.plan);
    check_timings("bars auto", &st_auto, 1, 0);

    /* Signed CoC, nothing near: still only the background. */
    p.coc_signed = 1;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out2, CH, &st2), DDOF_OK);
    CHECK_MSG(st2.effects == (DDOF_EFFECT_MIDGROUND | DDOF_EFFECT_BACKGROUND),
              "bars signed: effects 0x%x", st2.effects);
    CHECK(max_abs_diff_ff(out, out2, n) <= 1e-6);
    p.coc_signed = 0;

    /* Forced on: the same as AUTO here. */
    p.background = DDOF_LAYER_ON;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out2, CH, &st_on), DDOF_OK);
    CHECK(st_on.effects & DDOF_EFFECT_BACKGROUND);
    CHECK(max_abs_diff_ff(out, out2, n) <= 1e-6);

    /* Forced off: skipped, says so, and the result is the single-layer diffusion. */
    p.background = DDOF_LAYER_OFF;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, &st_off), DDOF_OK);
    dump_plan("bars off", &st_off);
    CHECK_MSG(st_off.effects == DDOF_EFFECT_MIDGROUND, "bars, background off: effects 0x%x",
              st_off.effects);
    CHECK_MSG(plan_says(&st_off, "background", "off"), "bars off: plan \"%.*s\"", 511,
              st_off.plan);
    check_timings("bars off", &st_off, 0, 0);
    CHECK_EQ_INT(single(&p, color, coc, out2, CH, NULL), DDOF_OK);
    double d = max_abs_diff_ff(out, out2, n);
    CHECK_MSG(d <= 1e-6, "bars, background off vs ddof_diffuse: %g", d);

    /* The background layer solves at least one more row and column pass (CoC fill + colour). */
    CHECK_MSG(st_auto.lines_solved >= st_off.lines_solved + W + H,
              "bars: %llu lines with background, %llu without",
              (unsigned long long)st_auto.lines_solved, (unsigned long long)st_off.lines_solved);

    /* A second level (threshold 16 <= CoC 20) solves more lines still. */
    p.background = DDOF_LAYER_AUTO;
    p.background_levels = 2;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out2, CH, &st2), DDOF_OK);
    CHECK(st2.effects == (DDOF_EFFECT_MIDGROUND | DDOF_EFFECT_BACKGROUND));
    CHECK_MSG(st2.lines_solved > st_auto.lines_solved, "bars: 2 levels %llu lines, 1 level %llu",
              (unsigned long long)st2.lines_solved, (unsigned long long)st_auto.lines_solved);

    /* A higher threshold (25 > every CoC) leaves nothing to put underneath. */
    p.background_levels = 1;
    p.background_threshold_px = 25.0f;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out2, CH, &st2), DDOF_OK);
    dump_plan("bars threshold 25", &st2);
    CHECK_MSG(st2.effects == DDOF_EFFECT_MIDGROUND, "bars, threshold 25: effects 0x%x",
              st2.effects);
}

/* Forcing the background on where AUTO would not run it. */
static void test_force_background_on(void)
{
    texture(color, CH, 5);
    fill_const(coc, npx, 10.0f);
    ddof_params p;
    heat_params_init(&p);
    p.background = DDOF_LAYER_ON;
    ddof_stats st;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, &st), DDOF_OK);
    dump_plan("uniform, background on", &st);
    CHECK_MSG(st.effects == (DDOF_EFFECT_MIDGROUND | DDOF_EFFECT_BACKGROUND),
              "uniform, background forced on: effects 0x%x", st.effects);
    size_t len = 0;
    const char *line = plan_line(&st, "background", &len);
    CHECK_MSG(line && has_token(line, len, "on"), "plan \"%.*s\"", 511, st.plan);
    CHECK_MSG(line && (ci_find(line, len, "forc") || ci_find(line, len, "param") ||
                       ci_find(line, len, "request") || ci_find(line, len, "caller")),
              "forced background: the line does not say it was forced: \"%.*s\"", (int)len,
              line ? line : "");
    check_timings("uniform, background on", &st, 1, 0);
    /* Every pixel is wholly background (matte 1 at CoC 10 >= 8): finite, within the input. */
    int ok = 1;
    for (size_t i = 0; i < n; i++)
        if (!(out[i] >= 0.1f - 1e-5f && out[i] <= 1.0f + 1e-5f))
            ok = 0;
    CHECK(ok);
}

int main(void)
{
    planner_test_begin();

    test_uniform_blur();
    test_half_sharp();
    test_bars();
    test_force_background_on();

    return planner_test_end("test_planner_background");
}
