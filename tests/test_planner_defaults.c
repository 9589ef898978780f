/* SPDX-License-Identifier: MIT */
/* test_planner_defaults.c - the planner on the defaults and on a frame with nothing out of focus,
 * and older callers' structs (planner_test.h). */
#include "planner_test.h"

static void test_defaults(void)
{
    ddof_params p;
    memset(&p, 0x5A, sizeof p);
    heat_params_init(&p);
    CHECK_EQ_INT(p.struct_size, sizeof p);
    CHECK_EQ_INT(p.coc_signed, 0);
    CHECK_EQ_INT(p.background, DDOF_LAYER_AUTO);
    CHECK_EQ_INT(p.near_spread, DDOF_LAYER_AUTO);
    CHECK_NEAR(p.background_threshold_px, 8.0, 0);
    CHECK_NEAR(p.background_ramp_start_px, 2.0, 0);
    CHECK_EQ_INT(p.background_levels, 1);
    CHECK_NEAR(p.near_spread_threshold_px, 4.0, 0);

    ddof_foreground fg;
    memset(&fg, 0x5A, sizeof fg);
    ddof_foreground_init(&fg);
    CHECK_EQ_INT(fg.struct_size, sizeof fg);
    CHECK_EQ_INT(fg.premultiplied, 1);
    CHECK(fg.color.pixels == NULL && fg.coc.pixels == NULL);

    ddof_camera cam;
    memset(&cam, 0x5A, sizeof cam);
    ddof_camera_init(&cam);
    CHECK_EQ_INT(cam.signed_coc, 0);
    ddof_curve curve;
    memset(&curve, 0x5A, sizeof curve);
    ddof_curve_init(&curve);
    CHECK_EQ_INT(curve.signed_coc, 0);
}

/* Nothing out of focus: zero solves, a bitwise copy, no effect. */
static void test_all_sharp(void)
{
    texture(color, CH, 1);
    fill_const(coc, npx, 0.0f);
    for (int variant = 0; variant < 2; variant++) {
        ddof_params p;
        heat_params_init(&p);
        p.coc_signed = (uint32_t)variant;
        ddof_stats st;
        fill_const(out, n, -7.0f);
        ddof_status s = layers(&p, color, coc, NULL, out, CH, &st);
        CHECK_EQ_INT(s, DDOF_OK);
        dump_plan("all sharp", &st);
        CHECK_EQ_INT(st.lines_solved, 0);
        CHECK_EQ_INT(st.copied_only, 1);
        CHECK_EQ_INT(st.substeps, 0);
        CHECK_MSG(st.effects == 0, "all sharp: effects 0x%x, nothing was simulated", st.effects);
        CHECK(!memcmp(out, color, n * sizeof(float)));
        CHECK_MSG(plan_well_formed(&st), "all sharp: plan \"%.*s\"", 511, st.plan);
        CHECK_NEAR(st.max_coc_px, 0.0, 0.0);
        check_timings("all sharp", &st, 0, 0);
    }
}

/* Older callers: a v0.1 ddof_params gets the layer defaults, a v0.1 ddof_stats is not written
 * past its size. */
static void test_old_structs(void)
{
    texture(color, CH, 8);
    bars_coc(coc);
    ddof_params p;
    ddof_params_init(&p); /* the whole default, disc kernel included */
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out2, CH, NULL), DDOF_OK);

    unsigned char pbuf[sizeof(ddof_params)];
    memset(pbuf, 0xA7, sizeof pbuf); /* garbage in the fields an old caller does not have */
    memcpy(pbuf, &p, offsetof(ddof_params, coc_signed));
    ((ddof_params *)(void *)pbuf)->struct_size = (uint32_t)offsetof(ddof_params, coc_signed);
    ddof_params old;
    memcpy(&old, pbuf, sizeof old);
    CHECK_EQ_INT(layers(&old, color, coc, NULL, out, CH, NULL), DDOF_OK);
    double d = max_abs_diff_ff(out, out2, n);
    CHECK_MSG(d <= 1e-6, "v0.1 params: result differs from the defaults by %g", d);

    /* ddof_diffuse with v0.1 params works as before. */
    CHECK_EQ_INT(single(&old, color, coc, out, CH, NULL), DDOF_OK);

    unsigned char sbuf[sizeof(ddof_stats)];
    memset(sbuf, 0xC3, sizeof sbuf);
    const size_t old_size = offsetof(ddof_stats, effects);
    ddof_stats *st = (ddof_stats *)(void *)sbuf;
    st->struct_size = (uint32_t)old_size;
    ddof_image_in ci = {color, W, H, CH, 0};
    ddof_image_in zi = {coc, W, H, 1, 0};
    ddof_image oi = {out, W, H, CH, 0};
    CHECK_EQ_INT(ddof_diffuse_layers(ctx, &p, &ci, &zi, NULL, &oi, st), DDOF_OK);
    size_t changed = 0;
    for (size_t i = old_size; i < sizeof sbuf; i++)
        if (sbuf[i] != 0xC3)
            changed++;
    CHECK_MSG(changed == 0, "v0.1 stats: %zu bytes past struct_size written", changed);
    CHECK_EQ_INT(st->struct_size, old_size);
    CHECK(st->lines_solved > 0);
}

int main(void)
{
    planner_test_begin();

    test_defaults();
    test_all_sharp();
    test_old_structs();

    return planner_test_end("test_planner_defaults");
}
