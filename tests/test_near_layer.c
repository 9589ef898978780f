/* SPDX-License-Identifier: MIT */
/* test_near_layer.c - the near layer (ddof_params.near_layer): a blurred near object of one
 * image split off as a foreground element over the rest, what it hid filled in.
 *
 *  - over a flat background the fill is exact, so the one image gives the separately rendered
 *    element's result, and both the double-precision reference of "blurred object over sharp
 *    background";
 *  - the split's own invariants: the fill from a textured surround stays within its sources'
 *    range, in-focus pixels the element's blur does not reach keep their bits, a frame whose
 *    alpha is not 1 keeps its alpha channel, the 4-channel and 3-channel calls agree;
 *  - a repeating surround (bricks, tiles) continues behind the near object: the fill copies it
 *    from one period away, exactly;
 *  - the hard cases: a frame that is all near field (no source for the fill), an object on the
 *    border, a 1-pixel near island, a near field only mildly blurred (the matte's ramp), holes
 *    whose row or column has no source (the result independent of the scratch's contents);
 *  - the planner and the parameter checks. */
#include "ddof.h"
#include "disc/disc_kernel.h"
#include "passes/near_layer.h"
#include "test_images.h"
#include "test_util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { W = 96, H = 72, CH = 4 };
#define NPX ((size_t)W * H)

static ddof_context *ctx;

#include "test_frame_calls.h"

static double max_diff(const float *a, const float *b, size_t n)
{
    double m = 0.0;
    for (size_t i = 0; i < n; i++)
        m = fmax(m, isfinite(a[i]) && isfinite(b[i]) ? fabs((double)a[i] - b[i]) : INFINITY);
    return m;
}

static int in_disc(uint32_t x, uint32_t y, double cx, double cy, double r)
{
    const double dx = x + 0.5 - cx, dy = y + 0.5 - cy;
    return dx * dx + dy * dy <= r * r;
}

/* The heat kernel (the layers' convexity holds for it), signed CoC, the near layer on AUTO. */
static ddof_params near_params(void)
{
    ddof_params p;
    heat_params_init(&p);
    p.coc_signed = 1;
    return p;
}

/* A near disc of CoC -20 over a flat in-focus background: the fill has one value to give, so
 * the one-image result is the element path's (its CoC the same) and the reference's, F over
 * the background, F the disc diffused alone in double precision. */
static void test_flat_background_is_exact(void)
{
    const float bg_rgb[4] = {0.2f, 0.5f, 0.3f, 1.0f}, obj_rgb[4] = {0.9f, 0.8f, 0.1f, 1.0f};
    float *img = alloc_f(NPX * CH), *coc = alloc_f(NPX), *bg = alloc_f(NPX * CH);
    float *obj = alloc_f(NPX * 4), *objcoc = alloc_f(NPX), *zero = alloc_f(NPX);
    float *one = alloc_f(NPX * CH), *two = alloc_f(NPX * CH), *ref = alloc_f(NPX * CH);
    float *tmp = alloc_f(NPX * 4), *flat = alloc_f(NPX);
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            const size_t i = (size_t)y * W + x;
            const int in = in_disc(x, y, W / 2.0, H / 2.0, H / 5.0);
            for (int c = 0; c < CH; c++) {
                bg[i * CH + c] = bg_rgb[c];
                img[i * CH + c] = in ? obj_rgb[c] : bg_rgb[c];
                obj[i * 4 + c] = in ? obj_rgb[c] : 0.0f;
            }
            coc[i] = in ? -20.0f : 0.0f;
            objcoc[i] = in ? 20.0f : 0.0f;
        }
    fill_const(zero, NPX, 0.0f);
    fill_const(flat, NPX, 20.0f);
    ddof_params p = near_params();
    ddof_stats st;
    CHECK_EQ_INT(layers(&p, img, coc, NULL, one, CH, &st), DDOF_OK);
    CHECK_MSG((st.effects & (DDOF_EFFECT_NEAR_LAYER | DDOF_EFFECT_FOREGROUND)) ==
                  (DDOF_EFFECT_NEAR_LAYER | DDOF_EFFECT_FOREGROUND) &&
                  !(st.effects & DDOF_EFFECT_NEAR_SPREAD),
              "near disc: effects 0x%x, plan:\n%s", st.effects, st.plan);
    CHECK_MSG(strstr(st.plan, "near layer: on:") && strstr(st.plan, "foreground: on: the near "
                                                                    "layer") &&
                  strstr(st.plan, "near spread: off: the near layer takes the near field"),
              "plan:\n%s", st.plan);
    CHECK(st.seconds_near_layer > 0.0);

    /* The element path with the true background. */
    ddof_params pe = p;
    pe.near_layer = DDOF_LAYER_AUTO;
    ddof_foreground fg;
    ddof_foreground_init(&fg);
    fg.color = (ddof_image_in){obj, W, H, 4, 0};
    fg.coc = (ddof_image_in){objcoc, W, H, 1, 0};
    CHECK_EQ_INT(layers(&pe, bg, zero, &fg, two, CH, &st), DDOF_OK);
    CHECK(!(st.effects & DDOF_EFFECT_NEAR_LAYER));
    const double d_element = max_diff(one, two, NPX * CH);

    /* The reference: the disc diffused alone (double precision) over the background. */
    ddof_params pr = p;
    pr.solver = DDOF_SOLVER_REFERENCE_F64;
    CHECK_EQ_INT(diffuse(ctx, &pr, obj, flat, tmp, W, H, 4, NULL), DDOF_OK);
    for (size_t i = 0; i < NPX; i++)
        for (int c = 0; c < CH; c++)
            ref[i * CH + c] = tmp[i * 4 + c] + (1.0f - tmp[i * 4 + 3]) * bg[i * CH + c];
    const double d_ref = max_diff(one, ref, NPX * CH);
    printf("near disc over a flat background: max |one image - element| %.3g, "
           "|one image - reference| %.3g\n", d_element, d_ref);
    CHECK_MSG(d_element <= 1e-5, "one image vs the element path: %g", d_element);
    CHECK_MSG(d_ref <= 1e-3, "one image vs the reference: %g", d_ref);

    /* Off: the near spread's result instead, and it is not the element's. */
    p.near_layer = DDOF_LAYER_OFF;
    CHECK_EQ_INT(layers(&p, img, coc, NULL, tmp, CH, &st), DDOF_OK);
    CHECK(!(st.effects & DDOF_EFFECT_NEAR_LAYER) && (st.effects & DDOF_EFFECT_NEAR_SPREAD));
    CHECK_MSG(max_diff(tmp, ref, NPX * CH) > 10 * d_ref, "the near spread is as good: %g",
              max_diff(tmp, ref, NPX * CH));

    /* 3 channels give the 4-channel result's colour. */
    float *img3 = alloc_f(NPX * 3), *out3 = alloc_f(NPX * 3);
    for (size_t i = 0; i < NPX; i++)
        for (int c = 0; c < 3; c++)
            img3[i * 3 + c] = img[i * CH + c];
    p.near_layer = DDOF_LAYER_AUTO;
    CHECK_EQ_INT(layers(&p, img3, coc, NULL, out3, 3, NULL), DDOF_OK);
    double d3 = 0.0;
    for (size_t i = 0; i < NPX; i++)
        for (int c = 0; c < 3; c++)
            d3 = fmax(d3, fabs((double)out3[i * 3 + c] - one[i * CH + c]));
    CHECK_MSG(d3 <= 1e-6, "3 vs 4 channels: %g", d3);

    free(img3);
    free(out3);
    free(img);
    free(coc);
    free(bg);
    free(obj);
    free(objcoc);
    free(zero);
    free(one);
    free(two);
    free(ref);
    free(tmp);
    free(flat);
}

/* A textured in-focus surround: the split's rest stays within its sources' range (the fill is
 * a weighted mean of them), the element holds exactly matte x colour, and the frame's result
 * is finite and in range; in-focus pixels beyond the element's reach keep their bits. */
static void test_textured_surround(void)
{
    float *img = alloc_f(NPX * CH), *coc = alloc_f(NPX), *out = alloc_f(NPX * CH);
    block_texture(img, W, H, CH, 5, 0.05, 0.55);
    const double cx = W / 5.0, cy = H / 2.0, r = 7.0;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            const size_t i = (size_t)y * W + x;
            const int in = in_disc(x, y, cx, cy, r);
            coc[i] = in ? -12.0f : 0.0f;
            if (in)
                for (int c = 0; c < 3; c++)
                    img[i * CH + c] = 5.0f; /* far brighter than anything around it */
            img[i * CH + 3] = 1.0f;
        }
    float lo[CH], hi[CH];
    for (int c = 0; c < CH; c++) {
        lo[c] = INFINITY;
        hi[c] = -INFINITY;
    }
    for (size_t i = 0; i < NPX; i++)
        if (coc[i] == 0.0f)
            for (int c = 0; c < CH; c++) {
                lo[c] = fminf(lo[c], img[i * CH + c]);
                hi[c] = fmaxf(hi[c], img[i * CH + c]);
            }

    /* The split itself: where nothing blurs, element over rest is the input (F + (1 - F.a) R
     * = C, at every pixel: wholly in the element, outside it, and in its fringe, whose pixels
     * beside the bright disc are shared between the two); the holes' fill stays within its
     * sources' range. */
    adi_request r0 = {.color = img, .color_stride = (size_t)W * CH, .channels = CH, .width = W,
                      .height = H, .coc = coc, .coc_stride = W, .coc_channels = 1};
    near_split s;
    CHECK_EQ_INT(ddof_split_near(ctx, &r0, 8.0f, &s), DDOF_OK);
    CHECK(s.filled && s.holes > 0 && s.element_pixels > s.holes); /* the fringe: split */
    CHECK(s.box.x0 <= (uint32_t)(cx - r) && s.box.x1 >= (uint32_t)(cx + r) + 1);
    CHECK(s.max_coc == 12.0f);
    CHECK(s.carried_alpha == NULL); /* every element pixel is opaque */
    size_t outside = 0, not_input = 0, fringe = 0;
    double worst = 0.0;
    for (size_t i = 0; i < NPX; i++) {
        const float *e = s.element + i * 4, *rest = s.rest + i * CH;
        const int hole = ddof_near_matte(coc[i], 8.0f) >= 1.0f;
        fringe += !hole && e[3] > 0.0f;
        for (int c = 0; c < 3; c++) {
            const double back = (double)e[c] + (1.0 - e[3]) * rest[c];
            const double d = fabs(back - img[i * CH + c]) / fmax(1.0, fabs(img[i * CH + c]));
            worst = fmax(worst, d);
            not_input += d > 1e-5;
            if (hole)
                outside += !(rest[c] >= lo[c] - 1e-6f && rest[c] <= hi[c] + 1e-6f);
        }
        if (hole)
            outside += !(s.rest_coc[i] >= 0.0f && s.rest_coc[i] <= 1e-6f); /* sources: CoC 0 */
        else
            not_input += s.rest_coc[i] != coc[i];
    }
    printf("split of a bright disc: %zu fringe pixels shared, element over rest = input within "
           "%.2g\n", fringe, worst);
    CHECK_MSG(fringe > 0, "no fringe pixel was split");
    CHECK_MSG(outside == 0, "%zu fill values outside the sources' range", outside);
    CHECK_MSG(not_input == 0, "%zu values: element over rest is not the input", not_input);

    /* The whole frame, every CPU solver; no highlight pass (its discs are not the heat
     * kernel's convex combinations, by design). */
    for (int k = 0; k < TEST_CPU_SOLVER_COUNT; k++) {
        ddof_params p = near_params();
        p.solver = (ddof_solver)k;
        p.highlights = DDOF_LAYER_OFF;
        ddof_stats st;
        fill_const(out, NPX * CH, NAN);
        CHECK_EQ_INT(layers(&p, img, coc, NULL, out, CH, &st), DDOF_OK);
        CHECK(st.effects & DDOF_EFFECT_NEAR_LAYER);
        CHECK(all_finite(out, NPX * CH));
        /* Beyond the element's box grown by its blur's reach (the layers' own bound). */
        size_t changed = 0, far_pixels = 0;
        const pixel_box area =
            box_grow(s.box, ddof_kernel_reach_px(NULL, p.beta_scale, 12.0f), W, H);
        for (uint32_t y = 0; y < H; y++)
            for (uint32_t x = 0; x < W; x++) {
                const size_t i = (size_t)y * W + x;
                if (x >= area.x0 && x < area.x1 && y >= area.y0 && y < area.y1)
                    continue;
                far_pixels++;
                changed += memcmp(&out[i * CH], &img[i * CH], CH * sizeof(float)) != 0;
            }
        CHECK_MSG(far_pixels > NPX / 4 && changed == 0,
                  "%s: %zu of %zu in-focus pixels beyond the element's reach changed",
                  ddof_solver_name(p.solver), changed, far_pixels);
        /* Each output a convex mix of the element's colour (5) and the surround's range. */
        size_t bad = 0;
        for (size_t i = 0; i < NPX; i++)
            for (int c = 0; c < 3; c++)
                bad += !(out[i * CH + c] >= lo[c] - 1e-5f && out[i * CH + c] <= 5.0f + 1e-5f);
        CHECK_MSG(bad == 0, "%s: %zu values out of range", ddof_solver_name(p.solver), bad);
    }
    free(img);
    free(coc);
    free(out);
}

/* A small near light whose anti-aliased rim has the depth behind it (a pinhole's depth is not
 * anti-aliased): the rim is shared between the element and the rest, so the light's hole is
 * filled with the background, not with its own rim, and the frame keeps its light instead of
 * adding a blurred copy of it underneath. */
static void test_light_rim(void)
{
    float *img = alloc_f(NPX * CH), *coc = alloc_f(NPX), *out = alloc_f(NPX * CH);
    const uint32_t cx = W / 2, cy = H / 2;
    double light = 0.0;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            const size_t i = (size_t)y * W + x;
            const uint32_t dx = x > cx ? x - cx : cx - x, dy = y > cy ? y - cy : cy - y;
            const int core = dx <= 2 && dy <= 2, rim = !core && dx <= 3 && dy <= 3;
            const float v = core ? 30.0f : rim ? 12.0f : 0.1f;
            for (int c = 0; c < 3; c++)
                img[i * CH + c] = v;
            img[i * CH + 3] = 1.0f;
            coc[i] = core ? -20.0f : 0.0f;
            light += v - 0.1;
        }
    ddof_params p = near_params();
    ddof_stats st;
    CHECK_EQ_INT(layers(&p, img, coc, NULL, out, CH, &st), DDOF_OK);
    CHECK(st.effects & DDOF_EFFECT_NEAR_LAYER);
    double got = 0.0;
    for (size_t i = 0; i < NPX; i++)
        got += out[i * CH] - 0.1;
    printf("a near light with a rim at the depth behind: %.4f of its light in the frame\n",
           got / light);
    CHECK_MSG(fabs(got / light - 1.0) < 0.02, "the frame holds %.3f of the light", got / light);
    free(img);
    free(coc);
    free(out);
}

/* A frame whose alpha is 0.5 everywhere keeps it: the element carries its part of the alpha
 * channel (matte x 0.5) instead of covering with the matte (which would give 0.5 + m / 2). */
static void test_alpha_channel_kept(void)
{
    float *img = alloc_f(NPX * CH), *coc = alloc_f(NPX), *out = alloc_f(NPX * CH);
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            const size_t i = (size_t)y * W + x;
            const int in = in_disc(x, y, W / 2.0, H / 2.0, 10.0);
            coc[i] = in ? -16.0f : 0.0f;
            for (int c = 0; c < 3; c++)
                img[i * CH + c] = in ? 0.45f : 0.1f * (float)c;
            img[i * CH + 3] = 0.5f;
        }
    ddof_params p = near_params();
    ddof_stats st;
    CHECK_EQ_INT(layers(&p, img, coc, NULL, out, CH, &st), DDOF_OK);
    CHECK(st.effects & DDOF_EFFECT_NEAR_LAYER);
    double worst = 0.0;
    for (size_t i = 0; i < NPX; i++)
        worst = fmax(worst, fabs(out[i * CH + 3] - 0.5));
    printf("alpha 0.5 everywhere: largest change of the alpha channel %.3g\n", worst);
    CHECK_MSG(worst <= 1e-6, "the alpha channel moved by %g", worst);
    free(img);
    free(coc);
    free(out);
}

/* No source for the fill: every pixel near. The rest keeps the input; the result is the
 * element's blur over it, finite and within the input's range. */
static void test_all_near(void)
{
    float *img = alloc_f(NPX * CH), *coc = alloc_f(NPX), *out = alloc_f(NPX * CH);
    block_texture(img, W, H, CH, 9, 0.05, 0.55);
    fill_const(coc, NPX, -25.0f);
    adi_request r0 = {.color = img, .color_stride = (size_t)W * CH, .channels = CH, .width = W,
                      .height = H, .coc = coc, .coc_stride = W, .coc_channels = 1};
    near_split s;
    CHECK_EQ_INT(ddof_split_near(ctx, &r0, 8.0f, &s), DDOF_OK);
    CHECK(!s.filled && s.holes == 0 && s.element_pixels == NPX);
    CHECK(memcmp(s.rest, img, NPX * CH * sizeof(float)) == 0);
    ddof_params p = near_params();
    p.near_layer = DDOF_LAYER_ON;
    ddof_stats st;
    fill_const(out, NPX * CH, NAN);
    CHECK_EQ_INT(layers(&p, img, coc, NULL, out, CH, &st), DDOF_OK);
    CHECK(all_finite(out, NPX * CH));
    float lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; i < NPX * CH; i++) {
        lo = fminf(lo, img[i]);
        hi = fmaxf(hi, img[i]);
    }
    size_t bad = 0;
    for (size_t i = 0; i < NPX * CH; i++)
        bad += !(out[i] >= lo - 1e-5f && out[i] <= hi + 1e-5f);
    CHECK_MSG(bad == 0, "all near: %zu values outside the input's range", bad);
    free(img);
    free(coc);
    free(out);
}

/* A near object over the corner, and a 1-pixel near island: finite, in range, and the island's
 * light spreads (a single pixel of CoC 20 is a silhouette of its own). */
static void test_border_and_island(void)
{
    float *img = alloc_f(NPX * CH), *coc = alloc_f(NPX), *out = alloc_f(NPX * CH);
    for (int island = 0; island < 2; island++) {
        for (uint32_t y = 0; y < H; y++)
            for (uint32_t x = 0; x < W; x++) {
                const size_t i = (size_t)y * W + x;
                const int in = island ? x == W / 2 && y == H / 2 : in_disc(x, y, 0.0, 0.0, 20.0);
                coc[i] = in ? -20.0f : 0.0f;
                for (int c = 0; c < CH; c++)
                    img[i * CH + c] = in ? 2.0f : 0.25f;
            }
        ddof_params p = near_params();
        ddof_stats st;
        fill_const(out, NPX * CH, NAN);
        CHECK_EQ_INT(layers(&p, img, coc, NULL, out, CH, &st), DDOF_OK);
        CHECK_MSG(st.effects & DDOF_EFFECT_NEAR_LAYER, "%s: effects 0x%x",
                  island ? "island" : "corner", st.effects);
        CHECK(all_finite(out, NPX * CH));
        size_t bad = 0;
        for (size_t i = 0; i < NPX * CH; i++)
            bad += !(out[i] >= 0.25f - 1e-5f && out[i] <= 2.0f + 1e-5f);
        CHECK_MSG(bad == 0, "%s: %zu values out of range", island ? "island" : "corner", bad);
        if (island) {
            const size_t c = (size_t)(H / 2) * W + W / 2;
            printf("1-pixel near island: its value 2 -> %.4f\n", (double)out[c * CH]);
            CHECK_MSG(out[c * CH] < 0.5f, "the island stays at %g", (double)out[c * CH]);
        }
    }
    free(img);
    free(coc);
    free(out);
}

/* A near field blurred below the threshold stays out (matte 0 below half of it); between, the
 * matte's ramp splits it without a seam: at zero blur the composite gives the pixel back. */
static void test_matte(void)
{
    CHECK(ddof_near_matte(0.0f, 8.0f) == 0.0f);
    CHECK(ddof_near_matte(30.0f, 8.0f) == 0.0f);
    CHECK(ddof_near_matte(-4.0f, 8.0f) == 0.0f);
    CHECK(ddof_near_matte(-6.0f, 8.0f) == 0.5f);
    CHECK(ddof_near_matte(-8.0f, 8.0f) == 1.0f);
    CHECK(ddof_near_matte(-1e4f, 8.0f) == 1.0f);

    /* Largest near CoC 3 px: the planner leaves the layer off. */
    float *img = alloc_f(NPX * CH), *coc = alloc_f(NPX), *out = alloc_f(NPX * CH);
    block_texture(img, W, H, CH, 3, 0.05, 0.55);
    for (size_t i = 0; i < NPX; i++)
        coc[i] = (i % W) < W / 2 ? -3.0f : 0.0f;
    ddof_params p = near_params();
    ddof_stats st;
    CHECK_EQ_INT(layers(&p, img, coc, NULL, out, CH, &st), DDOF_OK);
    CHECK_MSG(!(st.effects & DDOF_EFFECT_NEAR_LAYER) &&
                  strstr(st.plan, "near layer: off: no blurred near silhouette"),
              "mild near field: effects 0x%x, plan:\n%s", st.effects, st.plan);
    free(img);
    free(coc);
    free(out);
}

static void test_parameters(void)
{
    float *img = alloc_f(NPX * CH), *coc = alloc_f(NPX), *out = alloc_f(NPX * CH);
    block_texture(img, W, H, CH, 1, 0.05, 0.55);
    for (size_t i = 0; i < NPX; i++)
        coc[i] = (i % W) < 10 ? -20.0f : 0.0f;
    ddof_params p = near_params();
    ddof_params bad = p;
    bad.near_layer = (ddof_layer_mode)7;
    CHECK_EQ_INT(ddof_params_check(ctx, &bad), DDOF_ERROR_BAD_PARAMETER);
    bad = p;
    bad.near_layer_threshold_px = 0.0f;
    CHECK_EQ_INT(ddof_params_check(ctx, &bad), DDOF_ERROR_BAD_PARAMETER);
    bad.near_layer_threshold_px = NAN;
    CHECK_EQ_INT(ddof_params_check(ctx, &bad), DDOF_ERROR_BAD_PARAMETER);
    bad.near_layer_threshold_px = 2.0f * DDOF_MAX_COC_PX;
    CHECK_EQ_INT(ddof_params_check(ctx, &bad), DDOF_ERROR_BAD_PARAMETER);
    bad = p;
    bad.near_layer = DDOF_LAYER_ON;
    bad.near_spread = DDOF_LAYER_ON;
    CHECK_EQ_INT(ddof_params_check(ctx, &bad), DDOF_ERROR_BAD_PARAMETER);
    CHECK(strstr(ddof_context_last_error(ctx), "near_layer and near_spread"));

    /* Forced on: unsigned CoC, or beside a foreground element. */
    bad = p;
    bad.near_layer = DDOF_LAYER_ON;
    bad.coc_signed = 0;
    fill_const(coc, NPX, 3.0f);
    CHECK_EQ_INT(layers(&bad, img, coc, NULL, out, CH, NULL), DDOF_ERROR_BAD_PARAMETER);
    bad.coc_signed = 1;
    float *fgc = alloc_f(NPX * 4), *fgz = alloc_f(NPX);
    fill_const(fgc, NPX * 4, 0.5f);
    fill_const(fgz, NPX, 10.0f);
    ddof_foreground fg;
    ddof_foreground_init(&fg);
    fg.color = (ddof_image_in){fgc, W, H, 4, 0};
    fg.coc = (ddof_image_in){fgz, W, H, 1, 0};
    CHECK_EQ_INT(layers(&bad, img, coc, &fg, out, CH, NULL), DDOF_ERROR_BAD_PARAMETER);
    CHECK(strstr(ddof_context_last_error(ctx), "near_layer is forced on"));
    /* AUTO beside an element: the element is the near field. */
    ddof_stats st;
    for (size_t i = 0; i < NPX; i++)
        coc[i] = (i % W) < 10 ? -20.0f : 0.0f;
    CHECK_EQ_INT(layers(&p, img, coc, &fg, out, CH, &st), DDOF_OK);
    CHECK(!(st.effects & DDOF_EFFECT_NEAR_LAYER));
    CHECK(strstr(st.plan, "near layer: off: the foreground element covers the near field"));
    /* One channel: no RGB to split. */
    float *one = alloc_f(NPX), *one_out = alloc_f(NPX);
    fill_const(one, NPX, 0.5f);
    CHECK_EQ_INT(layers(&p, one, coc, NULL, one_out, 1, &st), DDOF_OK);
    CHECK(!(st.effects & DDOF_EFFECT_NEAR_LAYER));
    CHECK_MSG(strstr(st.plan, "near layer: off: 1 colour channel"), "plan:\n%s", st.plan);
    /* An older caller (the 0.5 struct) gets the default, AUTO. */
    ddof_params old = p;
    old.struct_size = (uint32_t)offsetof(ddof_params, near_layer);
    old.near_layer = (ddof_layer_mode)99; /* beyond its size: never read */
    CHECK_EQ_INT(layers(&old, img, coc, NULL, out, CH, &st), DDOF_OK);
    CHECK(st.effects & DDOF_EFFECT_NEAR_LAYER);
    free(one);
    free(one_out);
    free(fgc);
    free(fgz);
    free(img);
    free(coc);
    free(out);
}

/* Holes whose row, or whose column, holds no source (a near band across the whole frame, a
 * near strip down its side): the fill writes every hole, so the result does not depend on what
 * the scratch memory held before, and is finite. */
static void test_fill_independent_of_scratch(void)
{
    float *img = alloc_f(NPX * CH), *coc = alloc_f(NPX);
    float *out_nan = alloc_f(NPX * CH), *out_zero = alloc_f(NPX * CH);
    block_texture(img, W, H, CH, 5, 0.05, 0.55);
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++)
            coc[(size_t)y * W + x] = (y >= 30 && y < 40) || x < 10 ? -20.0f : 0.0f;
    ddof_context *poisoned = patterned_context(0xff), *zeroed = patterned_context(0);
    CHECK(poisoned && zeroed);
    const ddof_params p = near_params();
    ddof_stats st = stats_init();
    CHECK_EQ_INT(diffuse_layers(poisoned, &p, img, coc, NULL, out_nan, W, H, CH, &st), DDOF_OK);
    CHECK(st.effects & DDOF_EFFECT_NEAR_LAYER);
    CHECK_EQ_INT(diffuse_layers(zeroed, &p, img, coc, NULL, out_zero, W, H, CH, NULL), DDOF_OK);
    size_t bad = 0, differ = 0;
    for (size_t i = 0; i < NPX * CH; i++) {
        bad += !isfinite(out_nan[i]);
        differ += memcmp(&out_nan[i], &out_zero[i], sizeof(float)) != 0;
    }
    CHECK_MSG(bad == 0 && differ == 0, "%zu values not finite, %zu differ with the scratch's bytes",
              bad, differ);
    ddof_context_free(poisoned);
    ddof_context_free(zeroed);
    free(img);
    free(coc);
    free(out_nan);
    free(out_zero);
}

/* Tiles of 12 x 10 px (the joints 2 px and 1 px wide, shaded within each tile and different in
 * each channel), times `scale`. */
static float brick(uint32_t x, uint32_t y, uint32_t c, float scale)
{
    const uint32_t u = x % 12, v = y % 10;
    const float mortar = v < 2 || u == 0 ? 0.45f : 0.0f;
    return scale * (0.1f + 0.02f * (float)u * (float)(c + 1) + 0.015f * (float)v + mortar);
}

/* A near bar (CoC -20, 16 px wide, the whole height) over an in-focus brick wall: what it hides
 * is the wall one period away, and the fill copies it, exactly (a smooth fill misses it by the
 * bricks' contrast). At the colour limit the fill stays finite. */
static void test_fill_repeats_pattern(void)
{
    float *img = alloc_f(NPX * CH), *coc = alloc_f(NPX);
    const float scales[2] = {1.0f, DDOF_MAX_COLOR / 2.0f};
    for (int sc = 0; sc < 2; sc++) {
        for (uint32_t y = 0; y < H; y++)
            for (uint32_t x = 0; x < W; x++) {
                const size_t i = (size_t)y * W + x;
                const int bar = x >= 40 && x < 56;
                coc[i] = bar ? -20.0f : 0.0f;
                for (uint32_t c = 0; c < 3; c++)
                    img[i * CH + c] = bar ? 0.3f * scales[sc] : brick(x, y, c, scales[sc]);
                img[i * CH + 3] = 1.0f;
            }
        adi_request r0 = {.color = img, .color_stride = (size_t)W * CH, .channels = CH,
                          .width = W, .height = H, .coc = coc, .coc_stride = W,
                          .coc_channels = 1};
        near_split s;
        CHECK_EQ_INT(ddof_split_near(ctx, &r0, 8.0f, &s), DDOF_OK);
        CHECK(s.filled && s.holes == 16u * H);
        double worst = 0.0, sum = 0.0, contrast = 0.0;
        size_t values = 0, finite = 0;
        for (uint32_t y = 0; y < H; y++)
            for (uint32_t x = 40; x < 56; x++) {
                const size_t i = (size_t)y * W + x;
                for (uint32_t c = 0; c < 3; c++) {
                    const double want = brick(x, y, c, scales[sc]);
                    const double d = fabs((double)s.rest[i * CH + c] - want);
                    finite += isfinite(s.rest[i * CH + c]) != 0;
                    worst = fmax(worst, d);
                    sum += d * d;
                    contrast = fmax(contrast, fabs(want - brick(x + 6, y + 5, c, scales[sc])));
                    values++;
                }
                finite += isfinite(s.rest_coc[i]) && s.rest_coc[i] == 0.0f;
            }
        CHECK_MSG(finite == values + 16u * H, "scale %g: %zu of %zu fill values not finite",
                  scales[sc], values + 16u * H - finite, values + 16u * H);
        if (sc == 0) {
            printf("bricks behind a near bar: fill within %.2g of the hidden wall (RMS %.2g; "
                   "the bricks' contrast %.2f)\n",
                   worst, sqrt(sum / values), contrast);
            CHECK_MSG(worst < 1e-5, "the fill misses the hidden bricks by up to %.3g (RMS %.3g)",
                      worst, sqrt(sum / values));
        }
    }
    free(img);
    free(coc);
}

int main(void)
{
    if (ddof_context_create(NULL, &ctx) != DDOF_OK)
        return 1;
    test_matte();
    test_flat_background_is_exact();
    test_textured_surround();
    test_light_rim();
    test_alpha_channel_kept();
    test_all_near();
    test_border_and_island();
    test_parameters();
    test_fill_independent_of_scratch();
    test_fill_repeats_pattern();
    ddof_context_free(ctx);
    return test_report("test_near_layer");
}
