/* SPDX-License-Identifier: MIT */
/* test_far_field.c - the far field (ddof_params.far_field): away from depth edges the smooth
 * blur is gathered in the lens's disc.
 *
 *  - on a receding plane (a textured frame, its CoC linear in y, no depth edge) the result is
 *    the lens's: each pixel's light spread over its own disc, in double precision with the
 *    frame continued by its edge pixels; far closer than the diffusion alone, at every CoC
 *    from a few pixels to one that needs several image levels;
 *  - a constant frame stays constant (the weights are normalised, the continuation is the edge),
 *    whatever the CoC, the pixel aspect or the frame's size;
 *  - next to depth edges the layers' result is kept bit for bit, and in-focus pixels keep theirs;
 *  - the planner's line and the effect bit, OFF bit for bit the diffusion alone, the bad mode;
 *  - a foreground element's blur too: a textured disc of CoC 12 over a sharp background against
 *    the lens (its premultiplied colour and coverage over each point's disc), far closer than
 *    its diffusion alone;
 *  - the hard cases: CoC far beyond the frame, pixel aspects of 0.01 and 100, colours at
 *    DDOF_MAX_COLOR, a 1-pixel-high frame, 3 and 4 channels alike, in place. */
#include "ddof.h"
#include "test_images.h"
#include "test_util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { W = 96, H = 72, CH = 4 };
#define NPX ((size_t)W * H)

static ddof_context *ctx;
static int verbose; /* DDOF_TEST_VERBOSE=1: the measured errors */

static ddof_params far_params(ddof_layer_mode far_field)
{
    ddof_params p;
    heat_params_init(&p);
    p.far_field = far_field;
    p.coc_signed = 1;
    return p;
}

/* The lens on a plane: pixel q (the frame continued by its edge pixels) spreads its light
 * evenly over its disc of radius r(q) = (c0 + slope * y_q) / 2, each pixel of the output taking
 * the part of the disc that covers it (4 x 4 samples a pixel); normalised by the weights, as
 * the frame's border is. */
static void lens_reference(const float *color, float c0, float slope, double *out)
{
    const int reach = (int)ceil(0.5 * (c0 + slope * (H + 40)) + 2);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double sum[CH] = {0}, weights = 0.0;
            for (int qy = y - reach; qy <= y + reach; qy++)
                for (int qx = x - reach; qx <= x + reach; qx++) {
                    const double r = 0.5 * (c0 + slope * qy);
                    if (r <= 0.0)
                        continue;
                    int covered = 0;
                    for (int sy = 0; sy < 4; sy++)
                        for (int sx = 0; sx < 4; sx++) {
                            const double dx = x + (sx + 0.5) / 4 - 0.5 - qx;
                            const double dy = y + (sy + 0.5) / 4 - 0.5 - qy;
                            covered += dx * dx + dy * dy < r * r;
                        }
                    if (!covered)
                        continue;
                    const double w = covered / 16.0 / (r * r);
                    const int cx = qx < 0 ? 0 : qx >= W ? W - 1 : qx;
                    const int cy = qy < 0 ? 0 : qy >= H ? H - 1 : qy;
                    for (int c = 0; c < CH; c++)
                        sum[c] += w * color[((size_t)cy * W + cx) * CH + c];
                    weights += w;
                }
            for (int c = 0; c < CH; c++)
                out[((size_t)y * W + x) * CH + c] = sum[c] / weights;
        }
}

static double rms_vs(const float *a, const double *ref, size_t n)
{
    double s = 0.0;
    for (size_t i = 0; i < n; i++)
        s += (a[i] - ref[i]) * (a[i] - ref[i]);
    return sqrt(s / (double)n);
}

/* A textured plane receding from c0 to c0 + slope * H px: the gather against the lens, and the
 * diffusion alone (the default disc kernel) for scale. */
static void plane_case(float c0, float slope, double tol_rms, double tol_max)
{
    const size_t n = NPX * CH;
    float *color = alloc_f(n), *coc = alloc_f(NPX), *on = alloc_f(n), *off = alloc_f(n);
    double *ref = malloc(n * sizeof *ref);
    block_texture(color, W, H, CH, 99, 0.05, 0.95);
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++)
            coc[(size_t)y * W + x] = c0 + slope * (float)y;
    ddof_params p;
    ddof_params_init(&p);
    p.far_field = DDOF_LAYER_ON;
    ddof_stats st = stats_init();
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, on, W, H, CH, &st), DDOF_OK);
    CHECK_MSG(st.effects & DDOF_EFFECT_FAR_FIELD, "plane %g + %g y: %s", (double)c0,
              (double)slope, st.plan);
    p.far_field = DDOF_LAYER_OFF;
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, off, W, H, CH, NULL), DDOF_OK);
    lens_reference(color, c0, slope, ref);
    const double e_on = rms_vs(on, ref, n), e_off = rms_vs(off, ref, n);
    const double worst = max_abs_diff_fd(on, ref, n);
    if (verbose)
        printf("  plane CoC %g + %g y: RMS vs the lens %.4f (diffusion %.4f), max %.4f\n",
               (double)c0, (double)slope, e_on, e_off, worst);
    CHECK_MSG(e_on <= tol_rms, "plane %g + %g y: RMS %.4f > %.4f", (double)c0, (double)slope,
              e_on, tol_rms);
    CHECK_MSG(worst <= tol_max, "plane %g + %g y: max %.4f > %.4f", (double)c0, (double)slope,
              worst, tol_max);
    CHECK_MSG(e_on < 0.5 * e_off, "plane %g + %g y: gather %.4f not well below the diffusion %.4f",
              (double)c0, (double)slope, e_on, e_off);
    free(color);
    free(coc);
    free(on);
    free(off);
    free(ref);
}

static void test_plane_is_the_lens(void)
{
    /* Measured (RMS / max against the lens; the diffusion's RMS): 0.0012 / 0.0058 (0.0060),
     * 0.0022 / 0.0217 (0.0067), 0.0017 / 0.0185 (0.0125), 0.0023 / 0.0280 (0.0154). */
    plane_case(6.0f, 0.0f, 0.002, 0.01);   /* flat, small discs, level 0 only */
    plane_case(4.0f, 0.25f, 0.0035, 0.03); /* 4 -> 22 px, level 0 and 1 */
    plane_case(12.0f, 0.5f, 0.003, 0.03);  /* 12 -> 48 px: levels to 2, gradient clamped */
    plane_case(40.0f, 0.0f, 0.0035, 0.04); /* a wide flat blur, 40 px */
}

/* A constant frame is constant after the gather, for any CoC, aspect and size. */
static void constant_case(uint32_t w, uint32_t h, uint32_t ch, float c0, float slope,
                          float aspect)
{
    const size_t n = (size_t)w * h * ch;
    float *color = alloc_f(n), *coc = alloc_f((size_t)w * h), *out = alloc_f(n);
    for (size_t i = 0; i < n; i++)
        color[i] = (i % ch) == 3 ? 1.0f : 0.375f + 0.125f * (float)(i % ch);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++)
            coc[(size_t)y * w + x] = c0 + slope * (float)(x + y);
    ddof_params p = far_params(DDOF_LAYER_ON);
    p.pixel_aspect = aspect;
    ddof_stats st = stats_init();
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, out, w, h, ch, &st), DDOF_OK);
    CHECK_MSG(max_abs_diff_ff(out, color, n) <= 2e-6, "constant %ux%u x%u, CoC %g + %g, aspect %g: "
              "off by %.3g", w, h, ch, (double)c0, (double)slope, (double)aspect,
              max_abs_diff_ff(out, color, n));
    CHECK_MSG(st.effects & DDOF_EFFECT_FAR_FIELD, "constant %ux%u: %s", w, h, st.plan);
    free(color);
    free(coc);
    free(out);
}

static void test_constant_stays_constant(void)
{
    constant_case(W, H, 4, 8.0f, 0.1f, 1.0f);
    constant_case(W, H, 3, 30.0f, 0.0f, 1.0f);
    constant_case(W, H, 1, 3000.0f, 0.0f, 1.0f); /* far beyond the frame: levels to 1 x 1 */
    constant_case(W, H, 4, 20.0f, 0.2f, 0.01f);  /* rows squeezed to a line */
    constant_case(W, H, 4, 20.0f, 0.2f, 100.0f); /* rows stretched */
    constant_case(W, 1, 4, 16.0f, 0.0f, 1.0f);   /* one row */
    constant_case(1, H, 2, 16.0f, 0.0f, 1.0f);   /* one column */
}

/* An in-focus bar across a far field of CoC 16: in-focus pixels keep their values, pixels
 * within the edges' reach keep the layers' result (the diffusion) bit for bit, and the far
 * field changes pixels well away from it. */
static void test_edges_keep_the_layers(void)
{
    const size_t n = NPX * CH;
    float *color = alloc_f(n), *coc = alloc_f(NPX), *on = alloc_f(n), *off = alloc_f(n);
    block_texture(color, W, H, CH, 5, 0.1, 0.9);
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++)
            coc[(size_t)y * W + x] = (x >= 44 && x < 48) ? 0.0f : 16.0f;
    ddof_params p = far_params(DDOF_LAYER_ON);
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, on, W, H, CH, NULL), DDOF_OK);
    p.far_field = DDOF_LAYER_OFF;
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, off, W, H, CH, NULL), DDOF_OK);
    size_t focus_changed = 0, near_changed = 0, far_changed = 0;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            const size_t i = ((size_t)y * W + x) * CH;
            const int differs = memcmp(on + i, off + i, CH * sizeof(float)) != 0;
            const uint32_t d = x < 44 ? 43 - x : x >= 48 ? x - 48 : 0; /* to the edge pixel */
            if (x >= 44 && x < 48)
                focus_changed += memcmp(on + i, color + i, CH * sizeof(float)) != 0;
            else if (d < 9) /* the edge's reach: 16 / 2 + 1 */
                near_changed += differs;
            else if (d >= 9 + 4)
                far_changed += !differs;
        }
    CHECK_EQ_INT(focus_changed, 0);
    CHECK_EQ_INT(near_changed, 0);
    CHECK_MSG(far_changed == 0, "%zu pixels away from the bar kept the diffusion's result",
              far_changed);
    free(color);
    free(coc);
    free(on);
    free(off);
}

static void test_plan(void)
{
    const size_t n = NPX * CH;
    float *color = alloc_f(n), *coc = alloc_f(NPX), *a = alloc_f(n), *b = alloc_f(n);
    block_texture(color, W, H, CH, 3, 0.1, 0.9);
    fill_const(coc, NPX, 10.0f);
    ddof_params p = far_params(DDOF_LAYER_AUTO);
    ddof_stats st = stats_init();
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, a, W, H, CH, &st), DDOF_OK);
    CHECK(st.effects & DDOF_EFFECT_FAR_FIELD);
    CHECK_MSG(strstr(st.plan, "far field: on: 100.0% of pixels") != NULL, "%s", st.plan);
    CHECK(st.seconds_far_field > 0.0 && st.seconds_far_field <= st.seconds_total);

    /* OFF is the diffusion alone, bit for bit (ddof_diffuse's single layer here). */
    p.far_field = DDOF_LAYER_OFF;
    st = stats_init();
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, a, W, H, CH, &st), DDOF_OK);
    CHECK(!(st.effects & DDOF_EFFECT_FAR_FIELD));
    CHECK_MSG(strstr(st.plan, "far field: forced off") != NULL, "%s", st.plan);
    CHECK_EQ_INT(diffuse(ctx, &p, color, coc, b, W, H, CH, NULL), DDOF_OK);
    CHECK(memcmp(a, b, n * sizeof(float)) == 0);

    /* Every blurred pixel next to an edge: it looks and says so. */
    for (size_t i = 0; i < NPX; i++)
        coc[i] = (i % W) % 6 < 3 ? 0.0f : 4.0f;
    p.far_field = DDOF_LAYER_AUTO;
    st = stats_init();
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, a, W, H, CH, &st), DDOF_OK);
    CHECK(!(st.effects & DDOF_EFFECT_FAR_FIELD));
    CHECK_MSG(strstr(st.plan, "far field: off: every blurred pixel is near") != NULL, "%s", st.plan);

    /* Nothing out of focus: a copy, and the line says why. */
    fill_const(coc, NPX, 0.25f);
    st = stats_init();
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, a, W, H, CH, &st), DDOF_OK);
    CHECK(st.copied_only && memcmp(a, color, n * sizeof(float)) == 0);
    CHECK_MSG(strstr(st.plan, "far field: off: nothing is out of focus") != NULL, "%s", st.plan);

    p.far_field = (ddof_layer_mode)7;
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, a, W, H, CH, NULL),
                 DDOF_ERROR_BAD_PARAMETER);
    free(color);
    free(coc);
    free(a);
    free(b);
}

/* A separately rendered element: a textured disc of radius 20 (alpha 1), CoC 12 everywhere,
 * over a flat sharp background of 0.5. The lens: its premultiplied colour and coverage each
 * spread over the disc of radius 6 around every point (4 x 4 samples a pixel), the background
 * showing through what the coverage leaves. */
static void test_element_is_the_lens(void)
{
    const size_t n = NPX * CH;
    float *color = alloc_f(n), *coc = alloc_f(NPX), *fg_color = alloc_f(n), *fg_coc = alloc_f(NPX);
    float *on = alloc_f(n), *off = alloc_f(n);
    double *ref = malloc(n * sizeof *ref);
    block_texture(fg_color, W, H, CH, 31, 0.1, 0.9);
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            const size_t i = (size_t)y * W + x;
            const double dx = x - 48.0, dy = y - 36.0;
            const float a = dx * dx + dy * dy < 400.0 ? 1.0f : 0.0f;
            for (int c = 0; c < CH; c++) {
                fg_color[i * CH + c] = c == 3 ? a : a * fg_color[i * CH + c];
                color[i * CH + c] = c == 3 ? 1.0f : 0.5f;
            }
            fg_coc[i] = 12.0f;
            coc[i] = 0.0f;
        }
    const double r = 6.0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double sum[CH] = {0}, weights = 0.0;
            for (int qy = y - 8; qy <= y + 8; qy++)
                for (int qx = x - 8; qx <= x + 8; qx++) {
                    int covered = 0;
                    for (int sy = 0; sy < 4; sy++)
                        for (int sx = 0; sx < 4; sx++) {
                            const double dx = x + (sx + 0.5) / 4 - 0.5 - qx;
                            const double dy = y + (sy + 0.5) / 4 - 0.5 - qy;
                            covered += dx * dx + dy * dy < r * r;
                        }
                    weights += covered;
                    if (!covered || qx < 0 || qy < 0 || qx >= W || qy >= H)
                        continue;
                    for (int c = 0; c < CH; c++)
                        sum[c] += covered * fg_color[((size_t)qy * W + qx) * CH + c];
                }
            const double cover = sum[3] / weights;
            for (int c = 0; c < CH; c++)
                ref[((size_t)y * W + x) * CH + c] =
                    sum[c] / weights + (1.0 - cover) * (c == 3 ? 1.0 : 0.5);
        }
    ddof_foreground fg;
    ddof_foreground_init(&fg);
    fg.color = (ddof_image_in){fg_color, W, H, CH, 0};
    fg.coc = (ddof_image_in){fg_coc, W, H, 1, 0};
    fg.premultiplied = 1;
    ddof_params p = far_params(DDOF_LAYER_AUTO);
    p.highlights = DDOF_LAYER_OFF;
    ddof_stats st = stats_init();
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, &fg, on, W, H, CH, &st), DDOF_OK);
    CHECK(st.effects & DDOF_EFFECT_FAR_FIELD);
    p.far_field = DDOF_LAYER_OFF;
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, &fg, off, W, H, CH, NULL), DDOF_OK);
    const double e_on = rms_vs(on, ref, n), e_off = rms_vs(off, ref, n);
    if (verbose)
        printf("  element CoC 12: RMS vs the lens %.4f (diffusion %.4f)\n", e_on, e_off);
    CHECK_MSG(e_on <= 0.002, "element: RMS %.4f against the lens (measured 0.0012)", e_on);
    CHECK_MSG(e_on < 0.6 * e_off, "element: gather %.4f not well below the diffusion %.4f", e_on,
              e_off);
    free(color);
    free(coc);
    free(fg_color);
    free(fg_coc);
    free(on);
    free(off);
    free(ref);
}

/* Colours at DDOF_MAX_COLOR stay finite; 3 and 4 channels give the same RGB; in place is the
 * same as out of place. */
static void test_hard_inputs(void)
{
    const size_t n = NPX * CH;
    float *color = alloc_f(n), *coc = alloc_f(NPX), *out = alloc_f(n);
    test_rng rng = {21};
    fill_uniform(color, n, &rng, -DDOF_MAX_COLOR, DDOF_MAX_COLOR);
    for (size_t i = 0; i < NPX; i++)
        coc[i] = 5.0f + 0.3f * (float)(i / W);
    ddof_params p = far_params(DDOF_LAYER_ON);
    ddof_stats st = stats_init();
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, out, W, H, CH, &st), DDOF_OK);
    CHECK(st.effects & DDOF_EFFECT_FAR_FIELD);
    CHECK(all_finite(out, n));

    block_texture(color, W, H, CH, 8, 0.0, 1.0);
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, out, W, H, CH, NULL), DDOF_OK);
    check_rgb_and_in_place(ctx, &p, color, coc, out, W, H);
    free(color);
    free(coc);
    free(out);
}

int main(void)
{
    const char *v = getenv("DDOF_TEST_VERBOSE");
    verbose = v && v[0] == '1';
    ctx = make_context(0);
    test_plane_is_the_lens();
    test_constant_stays_constant();
    test_edges_keep_the_layers();
    test_plan();
    test_element_is_the_lens();
    test_hard_inputs();
    ddof_context_free(ctx);
    return test_report("test_far_field");
}
