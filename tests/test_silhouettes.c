/* SPDX-License-Identifier: MIT */
/* test_silhouettes.c - mixed pixels where an in-focus object meets a blurred background
 * (ddof_params.silhouettes).
 *
 *  - an in-focus bar over a flat far wall, its edge columns partly covered, the depth saying
 *    "wall" there: the lens shows the bar's share sharp over the (flat) blurred wall, exactly
 *    cov O + (1 - cov) W; the split gives that, the diffusion alone smears the share away;
 *  - the light is kept; the bar's interior keeps its bits; 3 and 4 channels agree, in place too;
 *  - a strand of 1.2 px (no pixel wholly inside it) with an object matte
 *    (ddof_render_frame_with_matte): the shares and colour from the matte match the lens, the
 *    matte's share is the one used, over the world (no id behind the strand) too, its bad
 *    shapes, values and an overlap with the output are refused; across a far light, the
 *    matte's shares hide and show the light's disc;
 *  - a wire thinner than a pixel before brick and mortar courses, with the colours alone: the
 *    thin pixel and its neighbours against the lens;
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

/* The largest difference from the lens: cov O + (1 - cov) W over the flat wall, the object's
 * coverage of column x given by `cover`. */
static double worst_vs_lens(const float *out, uint32_t ch, float (*cover)(uint32_t))
{
    double worst = 0.0;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            const float cov = cover(x);
            for (int c = 0; c < 3; c++) {
                const double lens = cov * object[c] + (1.0 - cov) * wall[c];
                worst = fmax(worst, fabs(out[((size_t)y * W + x) * ch + (size_t)c] - lens));
            }
        }
    return worst;
}

/* The light is kept: over the frame each colour of out sums to the input's. */
static void check_light_kept(const float *color, const float *out)
{
    for (int c = 0; c < 3; c++) {
        double in_sum = 0.0, out_sum = 0.0;
        for (size_t i = 0; i < NPX; i++) {
            in_sum += color[i * CH + (size_t)c];
            out_sum += out[i * CH + (size_t)c];
        }
        CHECK_NEAR(out_sum / in_sum, 1.0, 1e-5);
    }
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

    const double e_on = worst_vs_lens(on, CH, coverage);
    const double e_off = worst_vs_lens(off, CH, coverage);
    CHECK_MSG(e_on < 2e-3, "split: %.4g from the lens", e_on);
    CHECK_MSG(e_off > 0.1, "the diffusion alone is %.4g from the lens: the test shows nothing",
              e_off);
    check_light_kept(color, on);
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

/* A strand over [40.6, 41.8]: columns 40 (0.4, its depth the wall's) and 41 (0.8) partly
 * covered, none wholly. */
static float strand_coverage(uint32_t x)
{
    const double lo = 40.6, hi = 41.8;
    const double a = fmax(lo, (double)x), b = fmin(hi, (double)x + 1.0);
    return b > a ? (float)(b - a) : 0.0f;
}

/* The strand's frame, CoC (0 where it covers half a pixel or more, else 16 behind) and its
 * matte: two ranks per pixel, the strand's id (bits 0x3f000001) and the wall's (0x3f000002). */
static void strand_frame(float *color, float *coc, float *matte)
{
    const uint32_t strand_id = 0x3f000001u, wall_id = 0x3f000002u;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            const float cov = strand_coverage(x);
            const size_t i = (size_t)y * W + x;
            for (uint32_t c = 0; c < CH; c++)
                color[i * CH + c] = c < 3 ? cov * object[c] + (1.0f - cov) * wall[c] : 1.0f;
            coc[i] = cov >= 0.5f ? 0.0f : 16.0f;
            const int strand_first = cov >= 0.5f;
            const uint32_t first = strand_first ? strand_id : wall_id;
            const uint32_t second = strand_first ? wall_id : strand_id;
            memcpy(&matte[i * 4 + 0], &first, sizeof first);
            matte[i * 4 + 1] = strand_first ? cov : 1.0f - cov;
            memcpy(&matte[i * 4 + 2], &second, sizeof second);
            matte[i * 4 + 3] = strand_first ? 1.0f - cov : cov;
        }
}

static ddof_status render_strand(ddof_context *ctx, const ddof_params *p, const float *color,
                                 const float *coc, const ddof_image_in *matte, float *out,
                                 ddof_stats *st)
{
    ddof_frame f;
    ddof_frame_init(&f);
    f.color = (ddof_image_in){color, W, H, CH, 0};
    f.coc = (ddof_image_in){coc, W, H, 1, 0};
    return ddof_render_frame_with_matte(ctx, p, &f, matte, &(ddof_image){out, W, H, CH, 0},
                                        st);
}

static void test_strand_with_matte(void)
{
    ddof_context *ctx = make_context(0);
    const size_t n = NPX * CH;
    float *color = alloc_f(n), *coc = alloc_f(NPX), *matte = alloc_f(NPX * 4);
    float *with = alloc_f(n), *without = alloc_f(n);
    strand_frame(color, coc, matte);
    ddof_params p = split_params(DDOF_LAYER_AUTO);
    const ddof_image_in m = {matte, W, H, 4, 0};
    ddof_stats st = stats_init();
    CHECK_EQ_INT(render_strand(ctx, &p, color, coc, &m, with, &st), DDOF_OK);
    CHECK_MSG(strstr(st.plan, "mixed pixels split by the object matte") != NULL, "%s", st.plan);
    st = stats_init();
    CHECK_EQ_INT(render_strand(ctx, &p, color, coc, NULL, without, &st), DDOF_OK);
    CHECK_MSG(strstr(st.plan, "by the object matte") == NULL, "%s", st.plan);
    /* Over a flat wall the colours' guess is exact too (its share and colour err together:
     * their product is right); the matte must be as exact; the diffusion alone is not. */
    float *off = alloc_f(n), *wrong = alloc_f(n), *lie = alloc_f(NPX * 4);
    ddof_params q = p;
    q.silhouettes = DDOF_LAYER_OFF;
    CHECK_EQ_INT(render_strand(ctx, &q, color, coc, NULL, off, NULL), DDOF_OK);
    const double e_with = worst_vs_lens(with, CH, strand_coverage);
    const double e_without = worst_vs_lens(without, CH, strand_coverage);
    CHECK_MSG(e_with < 2e-3, "with the matte: %.4g from the lens", e_with);
    CHECK_MSG(e_without < 2e-3, "the colours alone: %.4g from the lens", e_without);
    const double e_off = worst_vs_lens(off, CH, strand_coverage);
    CHECK_MSG(e_off > 0.1, "the diffusion alone is %.4g from the lens: the test shows nothing",
              e_off);
    /* The matte's share is the one used: a matte that says the strand misses column 40 leaves
     * that pixel's share smeared, as the diffusion alone does, though its colours tell. */
    memcpy(lie, matte, NPX * 4 * sizeof(float));
    for (uint32_t y = 0; y < H; y++) {
        float *pair = lie + ((size_t)y * W + 40) * 4;
        pair[1] = 1.0f; /* the wall's rank: all of it */
        pair[3] = 0.0f; /* the strand's */
    }
    const ddof_image_in lying = {lie, W, H, 4, 0};
    CHECK_EQ_INT(render_strand(ctx, &p, color, coc, &lying, wrong, NULL), DDOF_OK);
    double off_40 = 0.0, exact_40 = 0.0;
    for (uint32_t y = 0; y < H; y++)
        for (int c = 0; c < 3; c++) {
            const size_t i = ((size_t)y * W + 40) * CH + (size_t)c;
            off_40 = fmax(off_40, fabs((double)wrong[i] - off[i]));
            exact_40 = fmax(exact_40, fabs((double)wrong[i] - with[i]));
        }
    CHECK_MSG(off_40 < 1e-5 && exact_40 > 0.1,
              "column 40 with a matte of no strand: %.3g from the diffusion alone, %.3g from "
              "the split", off_40, exact_40);
    free(off);
    free(wrong);
    free(lie);
    check_light_kept(color, with);
    /* A strided matte (a row of 8 floats more) gives the same bits. */
    const size_t row = (size_t)W * 4 + 8;
    float *strided = alloc_f(row * H), *again = alloc_f(n);
    for (uint32_t y = 0; y < H; y++)
        memcpy(strided + y * row, matte + (size_t)y * W * 4, (size_t)W * 4 * sizeof(float));
    const ddof_image_in ms = {strided, W, H, 4, row * sizeof(float)};
    CHECK_EQ_INT(render_strand(ctx, &p, color, coc, &ms, again, NULL), DDOF_OK);
    CHECK(memcmp(again, with, n * sizeof(float)) == 0);

    /* A wall that is the world (the sky: no object, so no id; Cryptomatte's coverages then sum
     * below 1): only the strand's ranks are left, and the split is the same. */
    float *sky = alloc_f(NPX * 4);
    for (size_t i = 0; i < NPX; i++) {
        uint32_t id;
        memcpy(&id, &matte[i * 4], sizeof id);
        const int strand_first = id == 0x3f000001u;
        const float cov = strand_first ? matte[i * 4 + 1] : matte[i * 4 + 3];
        memcpy(&sky[i * 4], cov > 0.0f ? &(uint32_t){0x3f000001u} : &(uint32_t){0u}, 4);
        sky[i * 4 + 1] = cov;
        sky[i * 4 + 2] = sky[i * 4 + 3] = 0.0f; /* empty ranks: id 0, coverage 0 */
    }
    const ddof_image_in world = {sky, W, H, 4, 0};
    CHECK_EQ_INT(render_strand(ctx, &p, color, coc, &world, again, NULL), DDOF_OK);
    const double e_world = worst_vs_lens(again, CH, strand_coverage);
    CHECK_MSG(e_world < 2e-3, "a matte of the strand over the world: %.4g from the lens",
              e_world);
    free(sky);

    /* Bad mattes: refused before anything is written. */
    memcpy(again, color, n * sizeof(float));
    const ddof_image_in odd = {matte, W, H, 3, 0}, wide = {matte, W, H, 34, 0};
    const ddof_image_in small = {matte, W - 1, H, 4, 0}, none = {NULL, W, H, 4, 0};
    const ddof_image_in short_stride = {matte, W, H, 4, (size_t)W * 4 * sizeof(float) - 4};
    CHECK_EQ_INT(render_strand(ctx, &p, color, coc, &odd, again, NULL), DDOF_ERROR_BAD_CHANNELS);
    CHECK_EQ_INT(render_strand(ctx, &p, color, coc, &wide, again, NULL), DDOF_ERROR_BAD_CHANNELS);
    /* another size than the frame's: a mismatch between the call's images (issue 40) */
    CHECK_EQ_INT(render_strand(ctx, &p, color, coc, &small, again, NULL),
                 DDOF_ERROR_SIZE_MISMATCH);
    CHECK_EQ_INT(render_strand(ctx, &p, color, coc, &none, again, NULL), DDOF_ERROR_NULL_POINTER);
    CHECK_EQ_INT(render_strand(ctx, &p, color, coc, &short_stride, again, NULL),
                 DDOF_ERROR_BAD_STRIDE);
    const ddof_image_in in_output = {again, W, H, 4, 0}; /* the output's own bytes */
    CHECK_EQ_INT(render_strand(ctx, &p, color, coc, &in_output, again, NULL),
                 DDOF_ERROR_BAD_PARAMETER);
    {
        /* coc_out inside the matte (issue 40): the CoC would be written over the caller's
         * const matte before the split reads it; refused as coc_out over any other input,
         * the matte untouched. */
        ddof_frame f;
        ddof_frame_init(&f);
        f.color = (ddof_image_in){color, W, H, CH, 0};
        f.coc = (ddof_image_in){coc, W, H, 1, 0};
        float *kept = alloc_f(NPX * 4);
        memcpy(kept, matte, NPX * 4 * sizeof(float));
        f.coc_out = (ddof_image){matte + 1, W, H, 1, 0};
        CHECK_EQ_INT(ddof_render_frame_with_matte(ctx, &p, &f, &m,
                                                  &(ddof_image){again, W, H, CH, 0}, NULL),
                     DDOF_ERROR_BAD_PARAMETER);
        CHECK_MSG(strstr(ddof_context_last_error(ctx), "coc_out overlaps the matte") != NULL,
                  "%s", ddof_context_last_error(ctx));
        CHECK(memcmp(kept, matte, NPX * 4 * sizeof(float)) == 0);
        free(kept);
    }
    matte[(7 * W + 5) * 4 + 3] = NAN;
    CHECK_EQ_INT(render_strand(ctx, &p, color, coc, &m, again, NULL), DDOF_ERROR_BAD_PARAMETER);
    CHECK_MSG(strstr(ddof_context_last_error(ctx), "(5, 7)") != NULL, "%s",
              ddof_context_last_error(ctx));
    CHECK(memcmp(again, color, n * sizeof(float)) == 0);
    free(strided);
    free(again);
    free(color);
    free(coc);
    free(matte);
    free(with);
    free(without);
    ddof_context_free(ctx);
}

/* The increase of out's red over its row 5 (outside every disc) at (x, 23), the disc's row. */
static double lift(const float *out, uint32_t x)
{
    return (double)out[((size_t)23 * W + x) * CH] - out[((size_t)5 * W + x) * CH];
}

/* The strand across a far light (3 x 3 pixels at columns 35-37, CoC 16: its disc reaches 28-44):
 * through a lens the strand's mixed pixels show the disc behind their uncovered share, and their
 * covered share hides it. With the matte the discs are drawn before the split: the sharp pixel
 * (column 41, 0.8 covered) gains 0.2 of the disc beside it, the blurred one (column 40, 0.4
 * covered) keeps 0.6 of the disc; the disc is what the frame without the strand gets. The
 * colours' guess keeps the discs whole behind the split: the sharp pixel, thin, blurs its
 * background share of what the layers drew, the disc comes after: it gains next to nothing. */
static void test_strand_across_a_light(void)
{
    ddof_context *ctx = make_context(0);
    const size_t n = NPX * CH;
    float *color = alloc_f(n), *coc = alloc_f(NPX), *matte = alloc_f(NPX * 4);
    float *bare = alloc_f(n), *bare_coc = alloc_f(NPX);
    float *with = alloc_f(n), *without = alloc_f(n), *bare_out = alloc_f(n);
    strand_frame(color, coc, matte);
    static const float dark[3] = {0.05f, 0.04f, 0.03f}, light[3] = {20.0f, 18.0f, 15.0f};
    for (size_t i = 0; i < NPX; i++) {
        const uint32_t x = (uint32_t)(i % W), y = (uint32_t)(i / W);
        const int lit = x >= 35 && x <= 37 && y >= 22 && y <= 24;
        const float cov = strand_coverage(x);
        for (int c = 0; c < 3; c++) {
            const float behind = lit ? light[c] : dark[c];
            color[i * CH + (size_t)c] = cov * object[c] + (1.0f - cov) * behind;
            bare[i * CH + (size_t)c] = behind;
        }
        bare[i * CH + 3] = 1.0f;
        bare_coc[i] = 16.0f;
    }
    ddof_params p = split_params(DDOF_LAYER_AUTO);
    const ddof_image_in m = {matte, W, H, 4, 0};
    CHECK_EQ_INT(render_strand(ctx, &p, color, coc, &m, with, NULL), DDOF_OK);
    CHECK_EQ_INT(render_strand(ctx, &p, color, coc, NULL, without, NULL), DDOF_OK);
    CHECK_EQ_INT(render_strand(ctx, &p, bare, bare_coc, NULL, bare_out, NULL), DDOF_OK);
    const double disc_40 = lift(bare_out, 40), disc_beside_41 =
        0.5 * (lift(bare_out, 40) + lift(bare_out, 42));
    CHECK_MSG(disc_40 > 0.05, "the disc reaches column 40 with %.4g: the test shows nothing",
              disc_40);
    CHECK_NEAR(lift(with, 41) / (0.2 * disc_beside_41), 1.0, 0.25);
    CHECK_NEAR(lift(with, 40) / (0.6 * disc_40), 1.0, 0.25);
    CHECK_MSG(fabs(lift(without, 41)) < 0.02 * disc_beside_41, "the colours' split: %.4g of %.4g",
              lift(without, 41), disc_beside_41);
    free(color);
    free(coc);
    free(matte);
    free(bare);
    free(bare_coc);
    free(with);
    free(without);
    free(bare_out);
    ddof_context_free(ctx);
}

/* A wire thinner than a pixel (0.6 of column 48, 0.1 of 47, 0.05 of 49; only column 48 has
 * the wire's depth) before a far wall of brick and mortar courses (constant along the wire,
 * so the pixels two steps away show exactly what lies behind it). No pixel shows the wire
 * unmixed, so the colours cannot give its coverage; the split takes the thin pixel as 0.7
 * covered and blurs the rest, and its neighbours hold their share of it. The lens: each pixel
 * cov W + (1 - cov) times the blurred wall, the wall's blur being what the same frame without
 * the wire gets. Before, the thin pixel kept its wall share sharp (the courses showing through
 * the wire) and its neighbours took that sharp wall back with the wire's share. */
static float wire_coverage(uint32_t x)
{
    return x == 48 ? 0.6f : x == 47 ? 0.1f : x == 49 ? 0.05f : 0.0f;
}

static void course_color(uint32_t y, float rgb[3])
{
    static const float brick[3] = {0.6f, 0.3f, 0.2f}, mortar[3] = {0.8f, 0.75f, 0.7f};
    for (int c = 0; c < 3; c++)
        rgb[c] = (y / 3) % 2 ? mortar[c] : brick[c];
}

static void test_thin_wire_over_courses(void)
{
    ddof_context *ctx = make_context(0);
    const size_t n = NPX * CH;
    float *color = alloc_f(n), *coc = alloc_f(NPX), *bare = alloc_f(n), *bare_coc = alloc_f(NPX);
    float *on = alloc_f(n), *off = alloc_f(n), *wall_blur = alloc_f(n);
    static const float wire[3] = {0.1f, 0.1f, 0.12f};
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            const size_t i = (size_t)y * W + x;
            const float cov = wire_coverage(x);
            float behind[3];
            course_color(y, behind);
            for (int c = 0; c < 3; c++) {
                color[i * CH + (size_t)c] = cov * wire[c] + (1.0f - cov) * behind[c];
                bare[i * CH + (size_t)c] = behind[c];
            }
            color[i * CH + 3] = bare[i * CH + 3] = 1.0f;
            coc[i] = x == 48 ? 0.0f : 16.0f;
            bare_coc[i] = 16.0f;
        }
    ddof_params p = split_params(DDOF_LAYER_ON);
    CHECK_EQ_INT(diffuse_layers(ctx, &p, bare, bare_coc, NULL, wall_blur, W, H, CH, NULL),
                 DDOF_OK);
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, on, W, H, CH, NULL), DDOF_OK);
    p.silhouettes = DDOF_LAYER_OFF;
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, off, W, H, CH, NULL), DDOF_OK);
    /* RMS from the lens over the three mixed columns, away from the top and bottom rows. */
    double e_on = 0.0, e_off = 0.0, e_sharp_wall = 0.0;
    size_t count = 0;
    for (uint32_t y = 8; y < H - 8; y++)
        for (uint32_t x = 47; x <= 49; x++)
            for (int c = 0; c < 3; c++) {
                const size_t i = ((size_t)y * W + x) * CH + (size_t)c;
                const float cov = wire_coverage(x);
                const double lens = cov * wire[c] + (1.0 - cov) * wall_blur[i];
                e_on += (on[i] - lens) * (on[i] - lens);
                e_off += (off[i] - lens) * (off[i] - lens);
                /* What the old split gave the thin pixel: its colour, unchanged. */
                if (x == 48)
                    e_sharp_wall += (color[i] - lens) * (color[i] - lens);
                count++;
            }
    e_on = sqrt(e_on / (double)count);
    e_off = sqrt(e_off / (double)count);
    e_sharp_wall = sqrt(e_sharp_wall / ((double)count / 3.0));
    printf("thin wire over courses: %.4f RMS from the lens (without the split %.4f)\n", e_on,
           e_off);
    CHECK_MSG(e_on < 0.02, "the wire's three columns are %.4g RMS from the lens", e_on);
    CHECK_MSG(e_sharp_wall > 0.05,
              "the thin pixel unchanged is %.4g RMS from the lens: the test shows nothing",
              e_sharp_wall);
    free(color);
    free(coc);
    free(bare);
    free(bare_coc);
    free(on);
    free(off);
    free(wall_blur);
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
    test_strand_with_matte();
    test_strand_across_a_light();
    test_thin_wire_over_courses();
    test_plan();
    return test_report("test_silhouettes");
}
