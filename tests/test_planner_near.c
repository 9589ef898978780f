/* SPDX-License-Identifier: MIT */
/* test_planner_near.c - the near field's decisions: the near spread, the near layer and a
 * foreground element (planner_test.h). */
#include "planner_test.h"

/* A near blurred object over an in-focus background: the near spread, nothing else. With the
 * object as a separate foreground element instead: the foreground, not the near spread. */
static void test_near(void)
{
    texture(color, CH, 6);
    disc_coc(coc, -20.0f, 0.0f);
    ddof_params p;
    heat_params_init(&p);
    p.highlights = DDOF_LAYER_OFF; /* the texture is above the highlight threshold */
    p.coc_signed = 1;
    p.near_layer = DDOF_LAYER_OFF; /* the near spread's plan (the near layer's: below) */
    ddof_stats st, st_off;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, &st), DDOF_OK);
    dump_plan("near auto", &st);
    CHECK_MSG(st.effects == (DDOF_EFFECT_MIDGROUND | DDOF_EFFECT_NEAR_SPREAD),
              "near object: effects 0x%x, want midground + near spread", st.effects);
    CHECK_MSG(plan_says(&st, "near spread", "on"), "near: plan \"%.*s\"", 511, st.plan);
    CHECK_MSG(plan_says(&st, "near layer", "off"), "near: plan \"%.*s\"", 511, st.plan);
    CHECK_MSG(plan_line(&st, "background", &(size_t){0}) != NULL, "near: plan \"%.*s\"", 511,
              st.plan);
    CHECK_NEAR(st.max_coc_px, 20.0, 0);
    check_timings("near auto", &st, 0, 1);

    /* Near spread forced off: skipped, says so; the result is ddof_diffuse of |CoC| (with the
     * background off too, so that this does not depend on how |CoC| counts for it). */
    p.near_spread = DDOF_LAYER_OFF;
    p.background = DDOF_LAYER_OFF;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, &st_off), DDOF_OK);
    dump_plan("near off", &st_off);
    CHECK_MSG(st_off.effects == DDOF_EFFECT_MIDGROUND, "near spread off: effects 0x%x",
              st_off.effects);
    CHECK_MSG(plan_says(&st_off, "near spread", "off"), "near off: plan \"%.*s\"", 511,
              st_off.plan);
    check_timings("near off", &st_off, 0, 0);
    float *abs_coc = alloc_f(npx);
    for (size_t i = 0; i < npx; i++)
        abs_coc[i] = fabsf(coc[i]);
    ddof_params p1;
    heat_params_init(&p1);
    CHECK_EQ_INT(single(&p1, color, abs_coc, out2, CH, NULL), DDOF_OK);
    double d = max_abs_diff_ff(out, out2, n);
    CHECK_MSG(d <= 1e-6, "near spread off vs ddof_diffuse(|CoC|): %g", d);
    CHECK_MSG(st.lines_solved >= st_off.lines_solved, "near: %llu lines with spread, %llu without",
              (unsigned long long)st.lines_solved, (unsigned long long)st_off.lines_solved);

    /* The spread changes the result (it is what gives the silhouette its soft edge). */
    p.near_spread = DDOF_LAYER_AUTO;
    p.background = DDOF_LAYER_AUTO;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, NULL), DDOF_OK);
    d = max_abs_diff_ff(out, out2, n);
    CHECK_MSG(d > 0.05, "near spread on changes the result by only %g", d);

    /* The same object, unsigned (a far object over an in-focus background): the background
     * layer's case, not the near spread. */
    heat_params_init(&p);
    p.highlights = DDOF_LAYER_OFF; /* the texture is above the highlight threshold */
    CHECK_EQ_INT(layers(&p, color, abs_coc, NULL, out, CH, &st), DDOF_OK);
    dump_plan("far disc", &st);
    CHECK_MSG(st.effects == (DDOF_EFFECT_MIDGROUND | DDOF_EFFECT_BACKGROUND),
              "far disc over in-focus: effects 0x%x", st.effects);

    /* A small near CoC (3 < threshold 4): no spread. */
    disc_coc(coc, -3.0f, 0.0f);
    heat_params_init(&p);
    p.coc_signed = 1;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, &st), DDOF_OK);
    dump_plan("near small", &st);
    CHECK_MSG(st.effects == DDOF_EFFECT_MIDGROUND, "near CoC 3: effects 0x%x", st.effects);

    /* Near spread forced on in a scene with nothing near: it runs. */
    fill_const(coc, npx, 10.0f);
    p.near_spread = DDOF_LAYER_ON;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, &st), DDOF_OK);
    dump_plan("near forced on", &st);
    CHECK_MSG(st.effects == (DDOF_EFFECT_MIDGROUND | DDOF_EFFECT_NEAR_SPREAD),
              "near spread forced on: effects 0x%x", st.effects);
    CHECK_MSG(plan_says(&st, "near spread", "on"), "near forced: plan \"%.*s\"", 511, st.plan);
    free(abs_coc);
}

/* The near layer: AUTO runs it for a blurred near silhouette (and then the element path, not
 * the spread), with its own plan line and time; forced on it runs on a frame with nothing near
 * (an empty element: no foreground), forced off it says so. */
static void test_near_layer(void)
{
    texture(color, CH, 6);
    disc_coc(coc, -20.0f, 0.0f);
    ddof_params p;
    heat_params_init(&p);
    p.highlights = DDOF_LAYER_OFF;
    p.coc_signed = 1;
    ddof_stats st;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, &st), DDOF_OK);
    dump_plan("near layer auto", &st);
    CHECK_MSG(st.effects ==
                  (DDOF_EFFECT_MIDGROUND | DDOF_EFFECT_NEAR_LAYER | DDOF_EFFECT_FOREGROUND),
              "near layer: effects 0x%x", st.effects);
    CHECK_MSG(plan_says(&st, "near layer", "on") && plan_says(&st, "foreground", "on") &&
                  plan_says(&st, "near spread", "off"),
              "near layer: plan \"%.*s\"", 511, st.plan);
    CHECK_MSG(st.seconds_near_layer > 0 && st.seconds_near_layer <= st.seconds_total,
              "near layer: %g s of %g", st.seconds_near_layer, st.seconds_total);
    check_timings("near layer auto", &st, 0, 1);
    CHECK(plan_well_formed(&st));

    /* A threshold above every near CoC: AUTO finds no silhouette to split. */
    p.near_layer_threshold_px = 25.0f;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, &st), DDOF_OK);
    CHECK_MSG(!(st.effects & DDOF_EFFECT_NEAR_LAYER) && plan_says(&st, "near layer", "off") &&
                  plan_says(&st, "near spread", "on"),
              "near layer threshold 25: effects 0x%x, plan \"%.*s\"", st.effects, 511, st.plan);
    CHECK(st.seconds_near_layer == 0.0);
    p.near_layer_threshold_px = 8.0f;

    /* Forced on with nothing near: it looks, finds no element, the midground alone runs. */
    fill_const(coc, npx, 10.0f);
    p.near_layer = DDOF_LAYER_ON;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, &st), DDOF_OK);
    dump_plan("near layer forced on, nothing near", &st);
    CHECK_MSG(st.effects == (DDOF_EFFECT_MIDGROUND | DDOF_EFFECT_NEAR_LAYER),
              "near layer forced on, nothing near: effects 0x%x", st.effects);
    float *plain = alloc_f(n);
    ddof_params p1;
    heat_params_init(&p1);
    CHECK_EQ_INT(single(&p1, color, coc, plain, CH, NULL), DDOF_OK);
    CHECK_MSG(max_abs_diff_ff(out, plain, n) == 0.0, "empty near layer changes the result by %g",
              max_abs_diff_ff(out, plain, n));
    free(plain);

    /* Forced off: said. */
    disc_coc(coc, -20.0f, 0.0f);
    p.near_layer = DDOF_LAYER_OFF;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, &st), DDOF_OK);
    CHECK_MSG(plan_says(&st, "near layer", "forced") && !(st.effects & DDOF_EFFECT_NEAR_LAYER),
              "near layer off: plan \"%.*s\"", 511, st.plan);
}

static void test_foreground(void)
{
    texture(color, CH, 7);
    disc_foreground(fg_color, fg_coc);
    ddof_foreground fg = make_fg(fg_color, fg_coc, 1);
    ddof_params p;
    heat_params_init(&p);
    p.coc_signed = 1;
    ddof_stats st, st_none;

    /* Sharp main image + the object as a foreground element. */
    fill_const(coc, npx, 0.0f);
    CHECK_EQ_INT(layers(&p, color, coc, &fg, out, CH, &st), DDOF_OK);
    dump_plan("foreground, sharp main", &st);
    CHECK_MSG((st.effects & ~DDOF_EFFECT_MIDGROUND) == DDOF_EFFECT_FOREGROUND,
              "foreground over a sharp image: effects 0x%x", st.effects);
    CHECK_EQ_INT(st.copied_only, 0);
    CHECK(st.lines_solved >= (uint64_t)W + H);
    CHECK_MSG(plan_says(&st, "foreground", "on"), "foreground: plan \"%.*s\"", 511, st.plan);
    {
        size_t len;
        const char *line = plan_line(&st, "near", &len);
        if (line)
            CHECK_MSG(has_token(line, len, "off"), "foreground given, near line \"%.*s\"",
                      (int)len, line);
    }
    check_timings("foreground, sharp main", &st, 0, 1);
    /* The element shows. */
    CHECK(max_abs_diff_ff(out, color, n) > 0.1);

    /* The same scene without the element: nothing to do. */
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out2, CH, &st_none), DDOF_OK);
    CHECK(st_none.effects == 0 && st_none.lines_solved == 0);
    CHECK_MSG(st.lines_solved > st_none.lines_solved, "foreground adds no lines");

    /* Uniformly (mildly) blurred main image + foreground: midground + foreground exactly. */
    fill_const(coc, npx, 6.0f);
    CHECK_EQ_INT(layers(&p, color, coc, &fg, out, CH, &st), DDOF_OK);
    dump_plan("foreground, blurred main", &st);
    CHECK_MSG(st.effects == (DDOF_EFFECT_MIDGROUND | DDOF_EFFECT_FOREGROUND),
              "foreground over a blurred image: effects 0x%x", st.effects);
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out2, CH, &st_none), DDOF_OK);
    CHECK_MSG(st.lines_solved >= st_none.lines_solved + W + H,
              "foreground: %llu lines, without %llu", (unsigned long long)st.lines_solved,
              (unsigned long long)st_none.lines_solved);

    /* The near object also in the main image's signed CoC, and the element given: the element
     * is used, the near spread is not (it needs no foreground element). */
    disc_coc(coc, -20.0f, 0.0f);
    CHECK_EQ_INT(layers(&p, color, coc, &fg, out, CH, &st), DDOF_OK);
    dump_plan("foreground + near CoC", &st);
    CHECK(st.effects & DDOF_EFFECT_FOREGROUND);
    CHECK_MSG(!(st.effects & DDOF_EFFECT_NEAR_SPREAD),
              "foreground given but near spread ran: effects 0x%x", st.effects);
}

int main(void)
{
    planner_test_begin();

    test_near();
    test_near_layer();
    test_foreground();

    return planner_test_end("test_planner_near");
}
