/* SPDX-License-Identifier: MIT */
/* test_silhouettes.c - mixed pixels where an in-focus object meets a blurred background
 * (ddof_params.silhouettes).
 *
 *  - an in-focus bar over a flat far wall, its edge columns partly covered, the depth saying
 *    "wall" there: the lens shows the bar's share sharp over the (flat) blurred wall, exactly
 *    cov O + (1 - cov) W; the split gives that, the diffusion alone smears the share away;
 *  - the light is kept; the bar's interior keeps its bits; 3 and 4 channels agree, in place too;
 *  - the plan's line and effect bit, OFF, unsigned CoC, one channel, a bad mode. */
#include "ddof.h"
#include "test_images.h"
#include "test_util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { W = 96, H = 48, CH = 4 };
#define NPX ((size_t)W * H)

static const float object[3] = {0.9f, 0.2f, 0.1f}, wall[3] = {0.1f, 0.3f, 0.8f};

/* The bar's coverage of column x: it spans [40.7, 44.3]. */
static float coverage(uint32_t x)
{
    const double lo = 40.7, hi = 44.3;
    const double a = fmax(lo, (double)x), b = fmin(hi, (double)x + 1.0);
    return b > a ? (float)(b - a) : 0.0f;
}

/* The pinhole frame and its CoC: 0 where the bar covers a pixel at least half, 16 (behind). */
static void bar_frame(float *color, float *coc, uint32_t ch)
{
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            const float cov = coverage(x);
            float *px = color + ((size_t)y * W + x) * ch;
            for (uint32_t c = 0; c < ch; c++)
                px[c] = c < 3 ? cov * object[c] + (1.0f - cov) * wall[c] : 1.0f;
            coc[(size_t)y * W + x] = cov >= 0.5f ? 0.0f : 16.0f;
        }
}

static ddof_params split_params(ddof_layer_mode silhouettes)
{
    ddof_params p;
    heat_params_init(&p);
    p.coc_signed = 1;
    p.silhouettes = silhouettes;
    return p;
}

static double worst_vs_lens(const float *out, uint32_t ch)
{
    double worst = 0.0;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            const float cov = coverage(x);
            for (int c = 0; c < 3; c++) {
                const double lens = cov * object[c] + (1.0 - cov) * wall[c];
                worst = fmax(worst, fabs(out[((size_t)y * W + x) * ch + (size_t)c] - lens));
            }
        }
    return worst;
}

static void test_bar_over_flat_wall(void)
{
    ddof_context *ctx = make_context(0);
    const size_t n = NPX * CH;
    float *color = alloc_f(n), *coc = alloc_f(NPX), *on = alloc_f(n), *off = alloc_f(n);
    bar_frame(color, coc, CH);
    ddof_params p = split_params(DDOF_LAYER_AUTO);
    ddof_stats st = stats_init();
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, on, W, H, CH, &st), DDOF_OK);
    CHECK(st.effects & DDOF_EFFECT_SILHOUETTES);
    /* Columns 40 and 44 (the blurred side) and 41 and 43 (the sharp side), every row. */
    CHECK_MSG(strstr(st.plan, "silhouettes: on: 192 mixed pixels split") != NULL, "%s", st.plan);
    p.silhouettes = DDOF_LAYER_OFF;
    st = stats_init();
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, off, W, H, CH, &st), DDOF_OK);
    CHECK(!(st.effects & DDOF_EFFECT_SILHOUETTES));
    CHECK_MSG(strstr(st.plan, "silhouettes: forced off") != NULL, "%s", st.plan);

    const double e_on = worst_vs_lens(on, CH), e_off = worst_vs_lens(off, CH);
    CHECK_MSG(e_on < 2e-3, "split: %.4g from the lens", e_on);
    CHECK_MSG(e_off > 0.1, "the diffusion alone is %.4g from the lens: the test shows nothing",
              e_off);
    /* The light is kept: over the frame each colour sums to the input's. */
    for (int c = 0; c < 3; c++) {
        double in_sum = 0.0, out_sum = 0.0;
        for (size_t i = 0; i < NPX; i++) {
            in_sum += color[i * CH + (size_t)c];
            out_sum += on[i * CH + (size_t)c];
        }
        CHECK_NEAR(out_sum / in_sum, 1.0, 1e-5);
    }
    /* The bar's interior and the alpha channel keep their bits. */
    size_t changed = 0;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 42; x < 43; x++)
            changed += memcmp(on + ((size_t)y * W + x) * CH, color + ((size_t)y * W + x) * CH,
                              CH * sizeof(float)) != 0;
    for (size_t i = 0; i < NPX; i++)
        changed += on[i * CH + 3] != off[i * CH + 3];
    CHECK_EQ_INT(changed, 0);

    /* 3 channels give the 4-channel RGB; in place gives the same. */
    float *rgb = alloc_f(NPX * 3), *out3 = alloc_f(NPX * 3);
    bar_frame(rgb, coc, 3);
    p.silhouettes = DDOF_LAYER_ON;
    CHECK_EQ_INT(diffuse_layers(ctx, &p, rgb, coc, NULL, out3, W, H, 3, NULL), DDOF_OK);
    double worst = 0.0;
    for (size_t i = 0; i < NPX; i++)
        for (int c = 0; c < 3; c++)
            worst = fmax(worst, fabs((double)out3[i * 3 + (size_t)c] - on[i * CH + (size_t)c]));
    CHECK_MSG(worst == 0.0, "3 and 4 channels differ by %.3g", worst);
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, color, W, H, CH, NULL), DDOF_OK);
    CHECK(memcmp(color, on, n * sizeof(float)) == 0);
    free(rgb);
    free(out3);
    free(color);
    free(coc);
    free(on);
    free(off);
    ddof_context_free(ctx);
}

static void test_plan(void)
{
    ddof_context *ctx = make_context(1);
    const size_t n = NPX * CH;
    float *color = alloc_f(n), *coc = alloc_f(NPX), *out = alloc_f(n);
    bar_frame(color, coc, CH);
    ddof_params p = split_params(DDOF_LAYER_ON);
    ddof_stats st = stats_init();
    p.coc_signed = 0;
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, out, W, H, CH, &st), DDOF_OK);
    CHECK_MSG(strstr(st.plan, "silhouettes: off: the CoC is unsigned") != NULL, "%s", st.plan);
    p.coc_signed = 1;
    st = stats_init();
    float *grey = alloc_f(NPX), *grey_out = alloc_f(NPX);
    for (size_t i = 0; i < NPX; i++)
        grey[i] = color[i * CH];
    CHECK_EQ_INT(diffuse_layers(ctx, &p, grey, coc, NULL, grey_out, W, H, 1, &st), DDOF_OK);
    CHECK_MSG(strstr(st.plan, "silhouettes: off: 1 colour channel") != NULL, "%s", st.plan);
    /* A bar over a wall of CoC 3: too little blur to split. */
    for (size_t i = 0; i < NPX; i++)
        coc[i] = coc[i] > 0.0f ? 3.0f : 0.0f;
    st = stats_init();
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, out, W, H, CH, &st), DDOF_OK);
    CHECK_MSG(strstr(st.plan, "silhouettes: off: the largest CoC is below 4") != NULL, "%s",
              st.plan);
    p.silhouettes = (ddof_layer_mode)9;
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, out, W, H, CH, NULL),
                 DDOF_ERROR_BAD_PARAMETER);
    free(grey);
    free(grey_out);
    free(color);
    free(coc);
    free(out);
    ddof_context_free(ctx);
}

int main(void)
{
    test_bar_over_flat_wall();
    test_plan();
    return test_report("test_silhouettes");
}
