/* SPDX-License-Identifier: MIT */
/* test_highlights.c - the highlight pass (libddof/src/passes/highlights.h): an HDR highlight
 * comes out as a flat disc of its CoC with its energy kept and no dark rim (the disc kernel alone leaves
 * one, its ring clamped to the input's range), nothing lands on in-focus or nearer pixels, a near highlight spreads over what is
 * behind it, a light's anti-aliased rim goes with the light's CoC, alpha is the diffusion's, the
 * budget holds, a highlight split by a thin in-focus bar keeps its light, and the parameters
 * are checked. */
#include "test_util.h"

#include <ddof.h>

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { W = 96, H = 80, N = W * H };

static ddof_context *ctx;

typedef struct frame {
    float color[N * 4], coc[N], out[N * 4];
} frame;

/* A dim flat background (0.1) of CoC `coc`, RGBA with alpha 1. */
static void flat(frame *f, float coc)
{
    for (int i = 0; i < N; i++) {
        for (int c = 0; c < 3; c++)
            f->color[i * 4 + c] = 0.1f;
        f->color[i * 4 + 3] = 1.0f;
        f->coc[i] = coc;
    }
}

static ddof_status run(frame *f, ddof_layer_mode highlights, ddof_stats *stats)
{
    ddof_params p;
    ddof_params_init(&p);
    p.kernel = DDOF_KERNEL_DISC_2X2; /* a disc kernel's ring is what the pass is for */
    p.far_field = DDOF_LAYER_OFF;    /* on a flat frame the gather would hide the ring */
    p.coc_signed = 1;
    p.highlights = highlights;
    p.background = DDOF_LAYER_OFF;
    p.near_spread = DDOF_LAYER_OFF;
    p.silhouettes = DDOF_LAYER_OFF; /* it blurs a thin bar's background share */
    return ddof_diffuse_layers(ctx, &p, &(ddof_image_in){f->color, W, H, 4, 0},
                               &(ddof_image_in){f->coc, W, H, 1, 0}, NULL,
                               &(ddof_image){f->out, W, H, 4, 0}, stats);
}

static double channel_sum(const float *img, int c)
{
    double s = 0.0;
    for (int i = 0; i < N; i++)
        s += img[i * 4 + c];
    return s;
}

/* One pixel of 200 at CoC 24 on the flat background. */
static void test_one_highlight(void)
{
    static frame f, g;
    flat(&f, 24.0f);
    /* One black pixel far away: the input's range starts at 0, as in any textured frame,
     * so the disc kernel's ring (clamped to that range) shows. */
    for (int c = 0; c < 3; c++)
        f.color[(2 * W + 2) * 4 + c] = 0.0f;
    const int cx = 48, cy = 40;
    for (int c = 0; c < 3; c++)
        f.color[(cy * W + cx) * 4 + c] = 200.0f;
    g = f;
    ddof_stats st = {.struct_size = sizeof st};
    CHECK(run(&f, DDOF_LAYER_AUTO, &st) == DDOF_OK);
    CHECK(st.effects & DDOF_EFFECT_HIGHLIGHTS);
    CHECK_MSG(strstr(st.plan, "highlights: on: 1 pixels") != NULL, "%s", st.plan);
    CHECK(run(&g, DDOF_LAYER_OFF, NULL) == DDOF_OK);

    /* The energy is kept: the diffusion keeps the base, the disc the excess. */
    CHECK_NEAR(channel_sum(f.out, 0) / channel_sum(f.color, 0), 1.0, 2e-3);
    /* Inside the disc (radius 12, one pixel in from the rim) it is flat: the excess spread
     * evenly; without the pass the diffused spike is anything but. */
    double lo = 1e30, hi = -1e30, lo_off = 1e30, hi_off = -1e30;
    for (int y = cy - 10; y <= cy + 10; y++)
        for (int x = cx - 10; x <= cx + 10; x++) {
            if ((x - cx) * (x - cx) + (y - cy) * (y - cy) > 10 * 10)
                continue;
            const float v = f.out[(y * W + x) * 4], u = g.out[(y * W + x) * 4];
            lo = fmin(lo, v);
            hi = fmax(hi, v);
            lo_off = fmin(lo_off, u);
            hi_off = fmax(hi_off, u);
        }
    const double level = 200.0 / (3.14159 * 12.5 * 12.5); /* the excess per disc pixel */
    CHECK_MSG(hi - lo < 0.05 * level, "disc not flat: %g..%g (level %g)", lo, hi, level);
    CHECK_MSG(hi_off - lo_off > 0.3 * level, "the disc kernel alone was flat already: %g..%g",
              lo_off, hi_off);
    /* No dark rim: the background around the disc stays at 0.1 (the kernel alone rings to 0:
     * -7% of a 200-unit spike is far below the background, clamped to black). */
    float min_on = 1e30f, min_off = 1e30f;
    for (int i = 0; i < N; i++) {
        if (abs(i % W - 2) < 14 && abs(i / W - 2) < 14)
            continue; /* the black pixel's own blur */
        min_on = fminf(min_on, f.out[i * 4]);
        min_off = fminf(min_off, g.out[i * 4]);
    }
    CHECK_MSG(min_on > 0.09f, "dark rim with the pass: min %g", (double)min_on);
    CHECK_MSG(min_off < 0.08f, "no dark rim without the pass (min %g): the test shows nothing",
              (double)min_off);
    /* Alpha is the diffusion's alone. */
    int alpha_differs = 0;
    for (int i = 0; i < N; i++)
        alpha_differs += f.out[i * 4 + 3] != g.out[i * 4 + 3];
    CHECK_EQ_INT(alpha_differs, 0);
}

/* A far highlight beside an in-focus column and a nearer region: neither gets its light. */
/* A highlight near the frame's left edge: the part of its disc past the edge is light that
 * leaves the frame, as through a lens, not light folded back into it. One pixel of 200 at
 * x = 3 with CoC 24: the edge (x = -0.5) cuts the disc of radius 12 at 3.5 px from its centre,
 * leaving 68.3% of its area inside. */
static void test_light_leaves_at_the_border(void)
{
    static frame f;
    flat(&f, 24.0f);
    const int cx = 3, cy = 40;
    for (int c = 0; c < 3; c++)
        f.color[(cy * W + cx) * 4 + c] = 200.0f;
    ddof_stats st = {.struct_size = sizeof st};
    CHECK(run(&f, DDOF_LAYER_AUTO, &st) == DDOF_OK);
    CHECK(st.effects & DDOF_EFFECT_HIGHLIGHTS);
    const double r = 12.0, d = 3.5;
    const double inside = 1.0 - (r * r * acos(d / r) - d * sqrt(r * r - d * d)) / (3.14159265358979 * r * r);
    const double excess = 200.0 - 0.25; /* above the default threshold */
    for (int c = 0; c < 3; c++) {
        /* The base is diffused with its sum kept: the rest is the disc's light in the frame. */
        const double kept = channel_sum(f.out, c) - (channel_sum(f.color, c) - excess);
        CHECK_MSG(fabs(kept / excess - inside) < 0.02,
                  "channel %d: %.4f of the light in the frame, the lens keeps %.4f", c,
                  kept / excess, inside);
    }
}

static void test_occlusion(void)
{
    static frame f, g;
    flat(&f, 20.0f);
    for (int y = 0; y < H; y++) {
        f.coc[y * W + 52] = 0.0f; /* an in-focus column 4 px right of the highlight */
        for (int x = 0; x < 40; x++)
            f.coc[y * W + x] = -20.0f; /* a near region to its left, 8 px away */
    }
    for (int c = 0; c < 3; c++)
        f.color[(40 * W + 48) * 4 + c] = 500.0f;
    g = f;
    CHECK(run(&f, DDOF_LAYER_ON, NULL) == DDOF_OK);
    CHECK(run(&g, DDOF_LAYER_OFF, NULL) == DDOF_OK);
    int column_changed = 0, near_lit = 0;
    for (int y = 0; y < H; y++) {
        for (int c = 0; c < 4; c++)
            column_changed += f.out[(y * W + 52) * 4 + c] != f.color[(y * W + 52) * 4 + c];
        for (int x = 0; x < 40; x++)
            near_lit += f.out[(y * W + x) * 4] > g.out[(y * W + x) * 4] + 1e-6f;
    }
    CHECK_EQ_INT(column_changed, 0);
    CHECK_EQ_INT(near_lit, 0);
    /* The light the column and the near region did not take stays on this side. */
    CHECK_NEAR(channel_sum(f.out, 0) / channel_sum(f.color, 0), 1.0, 1e-2);
}

/* A far highlight (5 x 5 pixels of 100 at CoC 20) split by an in-focus bar 3 px wide: the lens
 * sees the whole disc around the bar, so the light the bar hides in the pinhole is filled in
 * from the highlight's two visible sides and lands around the bar (libddof before this drew
 * only the visible 10 pixels' worth: 0.63 of the light around the bar without it). The bar's
 * pixels stay exactly as they were. */
static void test_split_by_bar(void)
{
    static frame f, g;
    flat(&f, 20.0f);
    for (int y = 38; y <= 42; y++)
        for (int x = 46; x <= 50; x++)
            for (int c = 0; c < 3; c++)
                f.color[(y * W + x) * 4 + c] = 100.0f;
    g = f; /* the same highlight without the bar */
    for (int y = 0; y < H; y++)
        for (int x = 47; x <= 49; x++) {
            for (int c = 0; c < 3; c++)
                f.color[(y * W + x) * 4 + c] = 0.3f;
            f.coc[y * W + x] = 0.0f;
        }
    ddof_stats st = {.struct_size = sizeof st};
    CHECK(run(&f, DDOF_LAYER_ON, &st) == DDOF_OK);
    CHECK_MSG(strstr(st.plan, "highlights: on: 10 pixels") != NULL &&
                  strstr(st.plan, "(+15 hidden by sharp occluders)") != NULL,
              "%s", st.plan);
    CHECK(run(&g, DDOF_LAYER_ON, NULL) == DDOF_OK);
    int bar_changed = 0, bad = 0;
    double around_f = 0.0, around_g = 0.0;
    for (int i = 0; i < N; i++) {
        const int x = i % W;
        for (int c = 0; c < 4; c++)
            bad += !isfinite(f.out[i * 4 + c]);
        if (x >= 47 && x <= 49) {
            for (int c = 0; c < 4; c++)
                bar_changed += f.out[i * 4 + c] != f.color[i * 4 + c];
        } else {
            around_f += f.out[i * 4];
            around_g += g.out[i * 4];
        }
    }
    CHECK_EQ_INT(bad, 0);
    CHECK_EQ_INT(bar_changed, 0);
    /* The hidden 15 pixels' excess (100 - 0.25 each) comes on top of the frame's own, less
     * the share of their discs that the bar covers (a lens' disc loses that strip too). */
    const double added = channel_sum(f.out, 0) - channel_sum(f.color, 0);
    CHECK_MSG(added > 0.7 * 15.0 * 99.75 && added < 15.0 * 99.75, "hidden light %g of %g",
              added, 15.0 * 99.75);
    /* Around the bar, what the same highlight without the bar puts there: a little more (the
     * visible pixels' discs are renormalised around the bar, as before), never less. */
    CHECK_MSG(around_f >= 0.99 * around_g && around_f <= 1.1 * around_g,
              "around the bar %g, without the bar %g", around_f, around_g);
    printf("split by a bar: hidden light %.1f of %.1f, around the bar %.1f (without it %.1f)\n",
           added, 15.0 * 99.75, around_f, around_g);
}

/* A bar wider than the highlight's radius hides what the lens cannot see around either: no
 * hidden part is made up. */
static void test_wide_occluder(void)
{
    static frame f;
    flat(&f, 20.0f);
    for (int y = 38; y <= 42; y++)
        for (int x = 30; x <= 50; x++)
            for (int c = 0; c < 3; c++)
                f.color[(y * W + x) * 4 + c] = 100.0f;
    for (int y = 0; y < H; y++)
        for (int x = 33; x <= 47; x++) { /* 15 px: wider than the radius of 10 */
            for (int c = 0; c < 3; c++)
                f.color[(y * W + x) * 4 + c] = 0.3f;
            f.coc[y * W + x] = 0.0f;
        }
    ddof_stats st = {.struct_size = sizeof st};
    CHECK(run(&f, DDOF_LAYER_ON, &st) == DDOF_OK);
    CHECK_MSG(strstr(st.plan, "hidden by sharp occluders") == NULL, "%s", st.plan);
    CHECK_NEAR(channel_sum(f.out, 0) / channel_sum(f.color, 0), 1.0, 1e-3);
}

/* A near highlight in front of an in-focus background spreads over it. */
static void test_near_spreads(void)
{
    static frame f;
    flat(&f, 0.0f);
    const int cx = 30, cy = 30;
    f.coc[cy * W + cx] = -16.0f;
    for (int c = 0; c < 3; c++)
        f.color[(cy * W + cx) * 4 + c] = 300.0f;
    CHECK(run(&f, DDOF_LAYER_AUTO, NULL) == DDOF_OK);
    const float beside = f.out[(cy * W + cx + 5) * 4];
    CHECK_MSG(beside > 0.1f + 0.5f * 300.0f / (3.14159f * 8.5f * 8.5f),
              "the near highlight did not spread over the sharp background: %g",
              (double)beside);
    CHECK(f.out[(cy * W + cx + 12) * 4] == 0.1f); /* beyond its radius 8: untouched */
}

/* A small near light (a 4 x 4 block of 6 at CoC -8) over a far background (CoC 20) whose
 * anti-aliased rim (a ring of 2, as a pinhole render's coverage gives) carries the
 * background's depth, as a render's depth pass does. The rim's light is the light's: it comes
 * out inside the light's own disc (radius 4 around the block), not as a halo of the
 * background's size (radius 10). */
static void test_rim_takes_the_lights_coc(void)
{
    static frame f, bg;
    flat(&f, 20.0f);
    flat(&bg, 20.0f);
    const int cx = 48, cy = 40; /* the block: [cx - 2, cx + 2) x [cy - 2, cy + 2) */
    double light = 0.0;
    for (int y = cy - 3; y < cy + 3; y++)
        for (int x = cx - 3; x < cx + 3; x++) {
            const int inner = x >= cx - 2 && x < cx + 2 && y >= cy - 2 && y < cy + 2;
            for (int c = 0; c < 3; c++)
                f.color[(y * W + x) * 4 + c] = inner ? 6.0f : 2.0f;
            f.coc[y * W + x] = inner ? -8.0f : 20.0f;
            light += (inner ? 6.0 : 2.0) - 0.1;
        }
    CHECK(run(&f, DDOF_LAYER_AUTO, NULL) == DDOF_OK);
    CHECK(run(&bg, DDOF_LAYER_AUTO, NULL) == DDOF_OK);
    double outside = 0.0; /* the light beyond 7 px of the block's centre */
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const double dx = x + 0.5 - cx, dy = y + 0.5 - cy;
            if (dx * dx + dy * dy > 49.0)
                outside += f.out[(y * W + x) * 4] - bg.out[(y * W + x) * 4];
        }
    CHECK_MSG(outside < 0.05 * light, "%.1f%% of the light drawn as a halo beyond the disc",
              100.0 * outside / light);
}

/* A bright in-focus pixel beside a brighter blurred one is not taken from, whichever CoC the
 * brighter one's light is drawn with. */
static void test_in_focus_beside_a_highlight(void)
{
    static frame f;
    flat(&f, 10.0f);
    const int x = 40, y = 40;
    f.coc[y * W + x] = 0.0f;
    for (int c = 0; c < 3; c++) {
        f.color[(y * W + x) * 4 + c] = 3.0f;
        f.color[(y * W + x + 1) * 4 + c] = 50.0f;
    }
    CHECK(run(&f, DDOF_LAYER_AUTO, NULL) == DDOF_OK);
    for (int c = 0; c < 4; c++)
        CHECK_MSG(f.out[(y * W + x) * 4 + c] == f.color[(y * W + x) * 4 + c],
                  "in-focus pixel changed: channel %d %g", c, (double)f.out[(y * W + x) * 4 + c]);
}

/* A bright pixel in a foreground element (alpha 1, CoC 24) over a sharp background: the
 * element's own highlights are drawn as the flat disc too, not the disc kernel's uneven one. */
static void test_element_highlight(void)
{
    static frame f;
    static float fg_color[N * 4], fg_coc[N];
    flat(&f, 0.0f);
    const int cx = 48, cy = 40;
    memset(fg_color, 0, sizeof fg_color);
    for (int i = 0; i < N; i++)
        fg_coc[i] = 24.0f;
    for (int c = 0; c < 3; c++)
        fg_color[(cy * W + cx) * 4 + c] = 200.0f;
    fg_color[(cy * W + cx) * 4 + 3] = 1.0f;
    ddof_foreground fg;
    ddof_foreground_init(&fg);
    fg.color = (ddof_image_in){fg_color, W, H, 4, 0};
    fg.coc = (ddof_image_in){fg_coc, W, H, 1, 0};
    double spread[2];
    for (int pass = 0; pass < 2; pass++) {
        ddof_params p;
        ddof_params_init(&p);
        p.highlights = pass ? DDOF_LAYER_AUTO : DDOF_LAYER_OFF;
        p.far_field = DDOF_LAYER_OFF; /* the element's gather would draw the flat disc too */
        ddof_stats st = {.struct_size = sizeof st};
        CHECK(ddof_diffuse_layers(ctx, &p, &(ddof_image_in){f.color, W, H, 4, 0},
                                  &(ddof_image_in){f.coc, W, H, 1, 0}, &fg,
                                  &(ddof_image){f.out, W, H, 4, 0}, &st) == DDOF_OK);
        CHECK(!pass || (st.effects & DDOF_EFFECT_HIGHLIGHTS));
        float lo = INFINITY, hi = 0.0f;
        for (int y = cy - 8; y <= cy + 8; y++)
            for (int x = cx - 8; x <= cx + 8; x++)
                if ((x - cx) * (x - cx) + (y - cy) * (y - cy) <= 64) {
                    lo = fminf(lo, f.out[(y * W + x) * 4]);
                    hi = fmaxf(hi, f.out[(y * W + x) * 4]);
                }
        const double level = 200.0 / (3.14159265 * 12.0 * 12.0);
        spread[pass] = (hi - lo) / level;
        if (pass)
            CHECK_NEAR(channel_sum(f.out, 0) - 0.1 * N, 200.0, 200.0 * 0.01);
    }
    CHECK_MSG(spread[1] < 0.05, "the element's highlight is not flat: %.3f of its level",
              spread[1]);
    CHECK_MSG(spread[0] > 0.2, "the disc kernel alone was flat already (%.3f): the test shows "
              "nothing", spread[0]);
}

/* 300 bright pixels of CoC 60 (2 to 4096, as many in each octave) would cost 17 operations
 * per frame pixel: the brightest are drawn within the budget of 8, the threshold raised; all
 * pixels about equally bright (a sky): none. */
static void test_budget(void)
{
    static frame f;
    flat(&f, 60.0f);
    test_rng rng = {99u};
    for (int k = 0; k < 300; k++) {
        const int i = (int)(test_uniform(&rng) * N);
        const float v = 2.0f * exp2f(11.0f * (float)test_uniform(&rng)); /* 2 .. 4096 */
        for (int c = 0; c < 3; c++)
            f.color[i * 4 + c] = v;
    }
    ddof_stats st = {.struct_size = sizeof st};
    CHECK(run(&f, DDOF_LAYER_AUTO, &st) == DDOF_OK);
    const char *line = strstr(st.plan, "highlights: on:");
    CHECK_MSG(line != NULL, "%s", st.plan);
    double per_pixel = 99.0, threshold = 0.0;
    unsigned count = 0;
    if (line)
        CHECK(sscanf(line, "highlights: on: %u pixels brighter than %lf with CoC >= 4 px drawn "
                           "as discs (%lf",
                     &count, &threshold, &per_pixel) == 3);
    CHECK_MSG(per_pixel <= 8.0 && per_pixel > 4.0, "%g operations per frame pixel", per_pixel);
    CHECK_MSG(threshold >= 32.0, "the threshold was not raised: %g", threshold);
    CHECK_MSG(count > 0 && count < 300, "%u highlights", count);
    for (int i = 0; i < N * 4; i++)
        if (!isfinite(f.out[i])) {
            CHECK_MSG(0, "non-finite output at %d", i);
            break;
        }
    for (int i = 0; i < N; i++)
        for (int c = 0; c < 3; c++)
            f.color[i * 4 + c] = 5.0f + (float)(i % 7);
    CHECK(run(&f, DDOF_LAYER_AUTO, &st) == DDOF_OK);
    CHECK_MSG(strstr(st.plan, "highlights: off: the brightest pixels") != NULL, "%s", st.plan);
}

/* Highlights split by many bars: their hidden parts come within the pass's budget. */
static void test_hidden_budget(void)
{
    static frame f;
    flat(&f, 40.0f);
    test_rng rng = {7u};
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            if (x % 4 == 0) {
                f.coc[y * W + x] = 0.0f; /* a bar every 4 columns */
                continue;
            }
            const float v = 2.0f * exp2f(11.0f * (float)test_uniform(&rng)); /* 2 .. 4096 */
            for (int c = 0; c < 3; c++)
                f.color[(y * W + x) * 4 + c] = v;
        }
    ddof_stats st = {.struct_size = sizeof st};
    CHECK(run(&f, DDOF_LAYER_AUTO, &st) == DDOF_OK);
    const char *hidden = strstr(st.plan, "hidden by sharp occluders"),
               *cost = strstr(st.plan, "drawn as discs (");
    double per_pixel = 99.0;
    CHECK_MSG(hidden != NULL && cost != NULL, "%s", st.plan);
    if (cost)
        CHECK(sscanf(cost, "drawn as discs (%lf", &per_pixel) == 1);
    CHECK_MSG(per_pixel <= 8.0, "%g operations per frame pixel", per_pixel);
    int bad = 0, bar_changed = 0;
    for (int i = 0; i < N; i++) {
        for (int c = 0; c < 4; c++)
            bad += !isfinite(f.out[i * 4 + c]);
        if (i % W % 4 == 0)
            for (int c = 0; c < 4; c++)
                bar_changed += f.out[i * 4 + c] != f.color[i * 4 + c];
    }
    CHECK_EQ_INT(bad, 0);
    CHECK_EQ_INT(bar_changed, 0);
}

static void test_params(void)
{
    static frame f;
    flat(&f, 10.0f);
    ddof_params p;
    ddof_params_init(&p);
    CHECK_EQ_INT(p.highlights, DDOF_LAYER_AUTO);
    CHECK_NEAR(p.highlight_threshold, 0.25, 0.0);
    p.highlight_threshold = 0.0f;
    CHECK_EQ_INT(ddof_params_check(ctx, &p), DDOF_ERROR_BAD_PARAMETER);
    p.highlight_threshold = NAN;
    CHECK_EQ_INT(ddof_params_check(ctx, &p), DDOF_ERROR_BAD_PARAMETER);
    p.highlight_threshold = 1.0f;
    p.highlights = (ddof_layer_mode)3;
    CHECK_EQ_INT(ddof_params_check(ctx, &p), DDOF_ERROR_BAD_PARAMETER);
    /* An older struct (0.4: up to the kernel) gets the pass's defaults. */
    ddof_params_init(&p);
    p.struct_size = (uint32_t)offsetof(ddof_params, in_focus_threshold_px);
    p.highlight_threshold = -5.0f; /* beyond the caller's struct: never read */
    CHECK_EQ_INT(ddof_params_check(ctx, &p), DDOF_OK);
    /* One channel: no colour to judge; the plan says so. */
    static float gray[N], out[N];
    for (int i = 0; i < N; i++)
        gray[i] = i == 500 ? 100.0f : 0.1f;
    ddof_params_init(&p);
    ddof_stats st = {.struct_size = sizeof st};
    CHECK(ddof_diffuse_layers(ctx, &p, &(ddof_image_in){gray, W, H, 1, 0},
                              &(ddof_image_in){f.coc, W, H, 1, 0}, NULL,
                              &(ddof_image){out, W, H, 1, 0}, &st) == DDOF_OK);
    CHECK_MSG(strstr(st.plan, "highlights: off: 1 colour channel") != NULL, "%s", st.plan);
    CHECK(!(st.effects & DDOF_EFFECT_HIGHLIGHTS));
    /* A pixel so bright that brightness / threshold overflows to +inf (DDOF_MAX_COLOR over a
     * threshold of 1e-30), among pixels of 1e-21 too many to draw (their discs are over the
     * budget; 1e9 times the threshold, a class below the top one, which starts at 2^32). Its
     * class was the int of +inf: undefined (clang's UBSan stops on it; x86 gave INT_MIN, i.e.
     * the dimmest class), so the budget dropped it with the rest and the pass went off. It is
     * the brightest class: it alone is drawn, its light kept. */
    flat(&f, 10.0f);
    for (int i = 0; i < N; i++)
        for (int c = 0; c < 3; c++)
            f.color[i * 4 + c] = 1e-21f;
    f.color[(40 * W + 48) * 4 + 0] = DDOF_MAX_COLOR;
    ddof_params_init(&p);
    p.highlight_threshold = 1e-30f;
    p.background = DDOF_LAYER_OFF;
    p.near_spread = DDOF_LAYER_OFF;
    st = (ddof_stats){.struct_size = sizeof st};
    CHECK_EQ_INT(ddof_diffuse_layers(ctx, &p, &(ddof_image_in){f.color, W, H, 4, 0},
                                     &(ddof_image_in){f.coc, W, H, 1, 0}, NULL,
                                     &(ddof_image){f.out, W, H, 4, 0}, &st),
                 DDOF_OK);
    CHECK_MSG(st.effects & DDOF_EFFECT_HIGHLIGHTS, "%s", st.plan);
    const double red = channel_sum(f.out, 0), red_in = channel_sum(f.color, 0);
    CHECK_MSG(isfinite(red) && fabs(red / red_in - 1.0) < 1e-3, "red %.6g of %.6g", red, red_in);
}

/* Colour at the ends of the accepted range (+-DDOF_MAX_COLOR) beside a highlight: the lower
 * end in one channel of a bright pixel, the upper in another's, and both in one row. With the
 * pass on, the disc added to the diffused colour can overflow to -inf (DDOF_OK, at -FLT_MAX);
 * cyclic reduction can give NaN where +-3e38 meet in a row (the fuzzer found it), and Thomas a
 * clamped, wrong row. The output must be finite with every solver and kernel, and a value
 * beyond the range is DDOF_ERROR_BAD_COLOR naming the pixel, the output untouched. */
static void test_extreme_colour(void)
{
    static frame f;
    static const ddof_kernel kernels[2] = {DDOF_KERNEL_HEAT, DDOF_KERNEL_DISC_2X2};
    static const ddof_solver solvers[5] = {DDOF_SOLVER_THOMAS, DDOF_SOLVER_CYCLIC_REDUCTION,
                                           DDOF_SOLVER_PCR, DDOF_SOLVER_JACOBI,
                                           DDOF_SOLVER_REFERENCE_F64};
    for (int k = 0; k < 2; k++)
        for (int v = 0; v < 5; v++) {
            flat(&f, 12.0f);
            /* Green at the lower end over a band of rows, and lights in it: the diffused green
             * stays near it and the lights' discs bring more of it. Blue at the upper end in
             * four pixels, and both ends side by side in one row of red. */
            for (int i = 20 * W; i < 40 * W; i++)
                f.color[i * 4 + 1] = -DDOF_MAX_COLOR;
            for (int i = 50 * W + 20; i < 50 * W + 24; i++)
                f.color[i * 4 + 2] = DDOF_MAX_COLOR;
            f.color[(60 * W + 10) * 4] = -DDOF_MAX_COLOR;
            f.color[(60 * W + 11) * 4] = DDOF_MAX_COLOR;
            for (int x = 30; x < 60; x += 7) {
                f.color[(size_t)(30 * W + x) * 4] = 10.0f;
                f.color[(size_t)(55 * W + x) * 4] = 10.0f;
            }
            ddof_params p;
            ddof_params_init(&p);
            p.coc_signed = 1;
            p.kernel = kernels[k];
            p.solver = solvers[v];
            p.background = DDOF_LAYER_OFF;
            p.near_spread = DDOF_LAYER_OFF;
            p.highlights = DDOF_LAYER_ON;
            ddof_stats st = {.struct_size = sizeof st};
            const ddof_status got = ddof_diffuse_layers(
                ctx, &p, &(ddof_image_in){f.color, W, H, 4, 0},
                &(ddof_image_in){f.coc, W, H, 1, 0}, NULL, &(ddof_image){f.out, W, H, 4, 0}, &st);
            CHECK_MSG(got == DDOF_OK, "kernel %d solver %d: %s", k, v,
                      ddof_context_last_error(ctx));
            CHECK_MSG(st.effects & DDOF_EFFECT_HIGHLIGHTS, "kernel %d solver %d: %s", k, v,
                      st.plan);
            int bad = 0;
            for (int i = 0; i < N * 4; i++)
                bad += !isfinite(f.out[i]);
            CHECK_MSG(bad == 0, "kernel %d solver %d: %d output values not finite", k, v, bad);

            /* One step beyond the range: refused, the output as it was. */
            f.color[(60 * W + 11) * 4] = nextafterf(DDOF_MAX_COLOR, INFINITY);
            for (int i = 0; i < N * 4; i++)
                f.out[i] = -5.0f;
            CHECK_EQ_INT(ddof_diffuse_layers(ctx, &p, &(ddof_image_in){f.color, W, H, 4, 0},
                                             &(ddof_image_in){f.coc, W, H, 1, 0}, NULL,
                                             &(ddof_image){f.out, W, H, 4, 0}, NULL),
                         DDOF_ERROR_BAD_COLOR);
            CHECK_MSG(strstr(ddof_context_last_error(ctx), "pixel (11, 60) channel 0") != NULL,
                      "%s", ddof_context_last_error(ctx));
            bad = 0;
            for (int i = 0; i < N * 4; i++)
                bad += f.out[i] != -5.0f;
            CHECK(bad == 0);
        }
}

int main(void)
{
    ddof_context_options co;
    ddof_context_options_init(&co);
    co.thread_count = 2;
    CHECK(ddof_context_create(&co, &ctx) == DDOF_OK);
    test_one_highlight();
    test_light_leaves_at_the_border();
    test_occlusion();
    test_split_by_bar();
    test_wide_occluder();
    test_near_spreads();
    test_rim_takes_the_lights_coc();
    test_in_focus_beside_a_highlight();
    test_element_highlight();
    test_budget();
    test_hidden_budget();
    test_params();
    test_extreme_colour();
    ddof_context_free(ctx);
    return test_report("test_highlights");
}
