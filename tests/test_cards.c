/* SPDX-License-Identifier: MIT */
/* test_cards.c - ddof_render_cards against a double-precision brute force written here from
 * the definition (not from the library's code): per pixel, the ray through its centre meets
 * the card's plane at depth Z; the Cycles CoC of Z gives the radius r (at least 0.5 px); the
 * result is the average, over a dense grid of points of the screen disc of radius r, of the
 * texel each point's own ray meets (transparent off the card). Then order, a card hidden
 * behind an opaque one, focus, huge CoC, and bad inputs (each a clear status, nothing
 * written). */
#ifndef DDOF_EXPERIMENTAL
#define DDOF_EXPERIMENTAL
#endif
#include "cards_reference.h"
#include "test_util.h"

#include <string.h>

#define W 96
#define H 64
#define TW 24
#define TH 16

static float texture_a[TH * TW * 4], texture_b[TH * TW * 4];

static void make_texture(float *t, unsigned long long seed)
{
    test_rng rng = {seed};
    for (int i = 0; i < TW * TH; i++) {
        double a = 0.2 + 0.8 * test_uniform(&rng);
        for (int c = 0; c < 3; c++)
            t[i * 4 + c] = (float)(a * test_uniform(&rng));
        t[i * 4 + 3] = (float)a;
    }
}

static ddof_camera test_camera(void)
{
    ddof_camera cam;
    ddof_camera_init(&cam);
    cam.focal_length_mm = 50.0;
    cam.sensor_width_mm = 36.0;
    cam.fstop = 1.0;
    cam.focus_distance_m = 0.5;
    return cam;
}

/* A rectangle card: corners bottom-left, bottom-right, top-right, top-left; uv the unit square. */
static ddof_card rect_card(double c[4][3], const float *texture)
{
    ddof_card card;
    memset(&card, 0, sizeof card);
    card.vertex_count = 4;
    const float uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int k = 0; k < 4; k++) {
        for (int a = 0; a < 3; a++)
            card.position[k][a] = (float)c[k][a];
        card.uv[k][0] = uv[k][0];
        card.uv[k][1] = uv[k][1];
    }
    card.texture = (ddof_image_in){texture, TW, TH, 4, 0};
    return card;
}

/* ---- the brute force ---------------------------------------------------------------------- */

/* The rectangle card's plane point on ray d: its depth, and u, v along its edges. */
static int hit(const ddof_card *card, const double d[3], double *z, double *u, double *v)
{
    double p[4][3];
    for (int k = 0; k < 4; k++)
        for (int a = 0; a < 3; a++)
            p[k][a] = card->position[k][a];
    return cards_ref_hit(&p[0][0], d, z, u, v);
}

static void reference_card(const ddof_camera *cam, const ddof_card *card, int x, int y,
                           double out[4])
{
    memset(out, 0, 4 * sizeof *out);
    double d[3], z, u, v;
    cards_ref_ray(cam, W, H, x + 0.5, y + 0.5, d);
    if (!hit(card, d, &z, &u, &v))
        return;
    const double f = cam->focal_length_mm, s1 = cam->focus_distance_m * 1000.0;
    const double coc_mm = f * f / (cam->fstop * s1) * fabs(z * 1000.0 - s1) / (z * 1000.0);
    const double r = fmax(0.5 * coc_mm / (cam->sensor_width_mm / W), 0.5);
    const int grid = 40;
    int count = 0;
    for (int j = 0; j < grid; j++)
        for (int i = 0; i < grid; i++) {
            const double ex = -1.0 + (2.0 * i + 1.0) / grid, ey = -1.0 + (2.0 * j + 1.0) / grid;
            if (ex * ex + ey * ey > 1.0)
                continue;
            count++;
            double e[3];
            cards_ref_ray(cam, W, H, x + 0.5 + r * ex, y + 0.5 + r * ey, e);
            if (!hit(card, e, &z, &u, &v) || u < 0.0 || u >= 1.0 || v <= 0.0 || v > 1.0)
                continue;
            const int tx = (int)(u * TW), ty = (int)((1.0 - v) * TH);
            for (int c = 0; c < 4; c++)
                out[c] += card->texture.pixels[(ty * TW + tx) * 4 + c];
        }
    for (int c = 0; c < 4; c++)
        out[c] /= count;
}

/* ---- comparisons -------------------------------------------------------------------------- */

static ddof_status render(ddof_context *ctx, const ddof_cards_params *p, const ddof_camera *cam,
                          const ddof_card *cards, uint32_t n, float *out)
{
    ddof_image img = {out, W, H, 4, 0};
    return ddof_render_cards(ctx, p, cam, cards, n, &img);
}

typedef struct errors {
    double max_abs, rms, missed_alpha;
} errors;

static errors compare_one(ddof_context *ctx, const ddof_cards_params *p, const ddof_card *card)
{
    static float out[W * H * 4];
    const ddof_camera cam = test_camera();
    errors e = {0, 0, 0};
    CHECK_EQ_INT(render(ctx, p, &cam, card, 1, out), DDOF_OK);
    double sum = 0.0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double ref[4];
            reference_card(&cam, card, x, y, ref);
            for (int c = 0; c < 4; c++) {
                const double diff = out[(y * W + x) * 4 + c] - ref[c];
                e.max_abs = fmax(e.max_abs, fabs(diff));
                sum += diff * diff;
            }
            if (out[(y * W + x) * 4 + 3] == 0.0f)
                e.missed_alpha += ref[3];
        }
    e.rms = sqrt(sum / (W * H * 4));
    return e;
}

static double fronto[4][3] = {{-0.36, -0.24, -2}, {0.36, -0.24, -2},
                                    {0.36, 0.24, -2},   {-0.36, 0.24, -2}};
static double slanted[4][3] = {{-0.3, -0.2, -1}, {0.9, -0.2, -3.5},
                                     {0.9, 0.2, -3.5}, {-0.3, 0.2, -1}};

static void test_against_reference(ddof_context *ctx)
{
    ddof_cards_params p;
    ddof_cards_params_init(&p);
    const ddof_card cards[2] = {rect_card(fronto, texture_a), rect_card(slanted, texture_a)};
    const char *names[2] = {"fronto-parallel", "slanted"};
    const double max_tol[2] = {0.03, 0.06}, rms_tol[2] = {0.004, 0.008};
    for (int i = 0; i < 2; i++) {
        for (uint32_t strips = 1; strips <= 16; strips *= strips == 1 ? 4 : 2) {
            p.strips = strips;
            errors e = compare_one(ctx, &p, &cards[i]);
            printf("%s card, %2u strips: max |err| %.4f, rms %.5f, missed alpha %.3f px\n",
                   names[i], strips, e.max_abs, e.rms, e.missed_alpha);
            if (strips == 8) {
                CHECK_MSG(e.max_abs < max_tol[i], "%s max %g", names[i], e.max_abs);
                CHECK_MSG(e.rms < rms_tol[i], "%s rms %g", names[i], e.rms);
                CHECK_MSG(e.missed_alpha < 0.05, "%s missed %g", names[i], e.missed_alpha);
            }
        }
        p.strips = 8;
        p.expansion = DDOF_CARDS_EXPAND_CENTROID;
        errors c = compare_one(ctx, &p, &cards[i]);
        printf("%s card, centroid push: missed alpha %.3f px (of the reference's footprint)\n",
               names[i], c.missed_alpha);
        CHECK_MSG(c.missed_alpha > 1.0, "the patent's push should clip corners: %g",
                  c.missed_alpha);
        p.expansion = DDOF_CARDS_EXPAND_OFFSET;
    }
}

/* In focus: the radius is the half-pixel minimum, so the card is its texture resampled. */
static void test_in_focus(ddof_context *ctx)
{
    double focus[4][3];
    memcpy(focus, fronto, sizeof focus);
    for (int k = 0; k < 4; k++) {
        focus[k][0] *= 0.25;
        focus[k][1] *= 0.25;
        focus[k][2] = -0.5;
    }
    const ddof_card card = rect_card(focus, texture_a);
    errors e = compare_one(ctx, NULL, &card);
    printf("in-focus card: max |err| %.4f, rms %.5f\n", e.max_abs, e.rms);
    CHECK_MSG(e.max_abs < 0.03 && e.rms < 0.004, "max %g rms %g", e.max_abs, e.rms);
}

/* Two overlapping cards: the same image whatever the list order; the near one over the far. */
static void test_order(ddof_context *ctx)
{
    static float one[W * H * 4], two[W * H * 4];
    const ddof_camera cam = test_camera();
    double near_c[4][3];
    memcpy(near_c, fronto, sizeof near_c);
    for (int k = 0; k < 4; k++) {
        near_c[k][0] = near_c[k][0] * 0.3 + 0.1;
        near_c[k][1] *= 0.3;
        near_c[k][2] = -0.6;
    }
    ddof_card cards[2] = {rect_card(fronto, texture_a), rect_card(near_c, texture_b)};
    CHECK_EQ_INT(render(ctx, NULL, &cam, cards, 2, one), DDOF_OK);
    ddof_card swapped[2] = {cards[1], cards[0]};
    CHECK_EQ_INT(render(ctx, NULL, &cam, swapped, 2, two), DDOF_OK);
    CHECK(memcmp(one, two, sizeof one) == 0);
    /* Where the near card is opaque-ish, the result is near over far, by the reference. */
    int checked = 0;
    for (int y = 0; y < H; y += 3)
        for (int x = 0; x < W; x += 3) {
            double f[4], n[4];
            reference_card(&cam, &cards[0], x, y, f);
            reference_card(&cam, &cards[1], x, y, n);
            const double want = n[0] + (1.0 - n[3]) * f[0];
            if (fabs(one[(y * W + x) * 4] - want) > 0.06)
                CHECK_MSG(0, "(%d, %d): %g vs %g", x, y, one[(y * W + x) * 4], want);
            checked++;
        }
    CHECK(checked > 100);
}

/* A card wholly behind an opaque, larger card in focus adds nothing: the output is the front
 * card's alone, bit for bit (the pixels it makes opaque skip the cards behind them); where the
 * front card is not opaque the card behind still shows. */
static void test_hidden_card(ddof_context *ctx)
{
    static float opaque[TH * TW * 4], front[W * H * 4], both[W * H * 4];
    for (int i = 0; i < TW * TH; i++) {
        for (int c = 0; c < 3; c++)
            opaque[i * 4 + c] = 0.25f + 0.5f * (float)((i + c) % 3) / 2.0f;
        opaque[i * 4 + 3] = 1.0f;
    }
    ddof_camera cam = test_camera();
    double big[4][3], small[4][3];
    for (int k = 0; k < 4; k++) {
        big[k][0] = fronto[k][0] * 3.0; /* the focus plane, wider than the frame */
        big[k][1] = fronto[k][1] * 3.0;
        big[k][2] = -0.5;
        small[k][0] = fronto[k][0] * 0.5;
        small[k][1] = fronto[k][1] * 0.5;
        small[k][2] = -2.0;
    }
    ddof_card cards[2] = {rect_card(big, opaque), rect_card(small, texture_a)};
    CHECK_EQ_INT(render(ctx, NULL, &cam, cards, 1, front), DDOF_OK);
    CHECK_EQ_INT(render(ctx, NULL, &cam, cards, 2, both), DDOF_OK);
    CHECK(memcmp(front, both, sizeof front) == 0);
    /* The front card with a transparent texel column: the card behind shows through it. */
    for (int j = 0; j < TH; j++)
        for (int c = 0; c < 4; c++)
            opaque[(j * TW + TW / 2) * 4 + c] = 0.0f;
    CHECK_EQ_INT(render(ctx, NULL, &cam, cards, 1, front), DDOF_OK);
    CHECK_EQ_INT(render(ctx, NULL, &cam, cards, 2, both), DDOF_OK);
    CHECK(memcmp(front, both, sizeof front) != 0);
}

/* Card at 1 cm from an f/1 lens: CoC clamped, output finite, alpha within 0..1. */
static void test_huge_coc(ddof_context *ctx)
{
    static float out[W * H * 4];
    const ddof_camera cam = test_camera();
    double c[4][3];
    memcpy(c, fronto, sizeof c);
    for (int k = 0; k < 4; k++) {
        c[k][0] *= 0.005;
        c[k][1] *= 0.005;
        c[k][2] = -0.01;
    }
    const ddof_card card = rect_card(c, texture_a);
    CHECK_EQ_INT(render(ctx, NULL, &cam, &card, 1, out), DDOF_OK);
    int ok = 1;
    double alpha = 0.0;
    for (int i = 0; i < W * H * 4; i++)
        ok &= isfinite(out[i]) && out[i] >= -1e-6f && out[i] <= 1.0f + 1e-5f;
    for (int i = 0; i < W * H; i++)
        alpha += out[i * 4 + 3];
    CHECK(ok);
    /* 1 cm from the lens, focused at 0.5 m: spread over a disc far larger than the frame. */
    CHECK(alpha > 0.0 && alpha < 0.01 * W * H);
}

static void expect_refused(ddof_context *ctx, const ddof_card *cards, uint32_t n,
                           ddof_status want, const char *words, const char *what)
{
    static float out[W * H * 4];
    const ddof_camera cam = test_camera();
    for (int i = 0; i < W * H * 4; i++)
        out[i] = 7.0f;
    const ddof_status got = render(ctx, NULL, &cam, cards, n, out);
    CHECK_MSG(got == want, "%s: status %d, wanted %d (%s)", what, got, want,
              ddof_context_last_error(ctx));
    CHECK_MSG(strstr(ddof_context_last_error(ctx), words) != NULL, "%s: message '%s'", what,
              ddof_context_last_error(ctx));
    int untouched = 1;
    for (int i = 0; i < W * H * 4; i++)
        untouched &= out[i] == 7.0f;
    CHECK_MSG(untouched, "%s: output written", what);
}

static void test_bad_input(ddof_context *ctx)
{
    ddof_card c[2] = {rect_card(fronto, texture_a), rect_card(fronto, texture_a)};
    c[1].position[2][2] = 0.5f; /* crosses the camera's plane */
    expect_refused(ctx, c, 2, DDOF_ERROR_BAD_PARAMETER, "card 1: vertex 2", "crossing");
    for (int k = 0; k < 4; k++)
        c[1].position[k][2] = 2.0f;
    expect_refused(ctx, c, 2, DDOF_ERROR_BAD_PARAMETER, "behind", "behind");
    c[1] = c[0];
    c[1].position[1][0] = NAN;
    expect_refused(ctx, c, 2, DDOF_ERROR_BAD_PARAMETER, "NaN", "NaN position");
    c[1] = c[0];
    c[1].uv[3][1] = INFINITY;
    expect_refused(ctx, c, 2, DDOF_ERROR_BAD_PARAMETER, "NaN", "inf uv");
    static float nan_texture[TW * TH * 4];
    memcpy(nan_texture, texture_a, sizeof nan_texture);
    nan_texture[4 * 37 + 2] = NAN;
    c[1] = c[0];
    c[1].texture.pixels = nan_texture;
    expect_refused(ctx, c, 2, DDOF_ERROR_BAD_COLOR, "card 1 texture", "NaN texel");
    c[1] = c[0];
    c[1].texture.channels = 3;
    expect_refused(ctx, c, 2, DDOF_ERROR_BAD_CHANNELS, "card 1", "3 channels");
    c[1] = c[0];
    for (int k = 0; k < 4; k++) /* all on one line: zero area */
        c[1].position[k][1] = c[1].position[k][0] = (float)(0.1 * k);
    expect_refused(ctx, c, 2, DDOF_ERROR_BAD_PARAMETER, "degenerate", "collinear");
    c[1] = c[0];
    for (int k = 0; k < 4; k++)
        memcpy(c[1].position[k], c[1].position[0], sizeof c[1].position[0]);
    expect_refused(ctx, c, 2, DDOF_ERROR_BAD_PARAMETER, "degenerate", "one point");
    c[1] = c[0];
    c[1].position[2][0] = -0.2f; /* the top-right corner pulled in past the diagonal */
    c[1].position[2][1] = -0.1f;
    expect_refused(ctx, c, 2, DDOF_ERROR_BAD_PARAMETER, "not convex", "concave");
    c[1] = c[0];
    c[1].position[2][2] = -2.5f;
    expect_refused(ctx, c, 2, DDOF_ERROR_BAD_PARAMETER, "not on one plane", "non-planar");
    c[1] = c[0];
    c[1].uv[2][0] = 0.5f;
    expect_refused(ctx, c, 2, DDOF_ERROR_BAD_PARAMETER, "not affine", "warped uv");
    c[1] = c[0];
    c[1].vertex_count = 2;
    expect_refused(ctx, c, 2, DDOF_ERROR_BAD_PARAMETER, "2 vertices", "2 vertices");
    c[1].vertex_count = 9;
    expect_refused(ctx, c, 2, DDOF_ERROR_BAD_PARAMETER, "9 vertices", "9 vertices");
    /* Two cards crossing each other in depth: no order exists. */
    c[1] = rect_card(slanted, texture_b);
    for (int k = 0; k < 4; k++)
        c[1].position[k][2] = k == 0 || k == 3 ? -1.0f : -3.0f;
    expect_refused(ctx, c, 2, DDOF_ERROR_BAD_PARAMETER, "cards 0 and 1 intersect",
                   "intersecting");
    ddof_cards_params p;
    ddof_cards_params_init(&p);
    p.strips = 0;
    static float out[W * H * 4];
    const ddof_camera cam = test_camera();
    CHECK_EQ_INT(render(ctx, &p, &cam, c, 1, out), DDOF_ERROR_BAD_PARAMETER);
    ddof_camera bad = cam;
    bad.fstop = NAN;
    CHECK_EQ_INT(render(ctx, NULL, &bad, c, 1, out), DDOF_ERROR_BAD_CAMERA);
    CHECK_EQ_INT(render(ctx, NULL, &cam, NULL, 1, out), DDOF_ERROR_NULL_POINTER);
    /* No cards: a transparent image. */
    for (int i = 0; i < W * H * 4; i++)
        out[i] = 3.0f;
    CHECK_EQ_INT(render(ctx, NULL, &cam, NULL, 0, out), DDOF_OK);
    CHECK(out[0] == 0.0f && out[W * H * 4 - 1] == 0.0f);
}

/* Issue 40: a card at z = -1e-10 drew nothing with DDOF_OK (a texel covered so many pixels
 * that the disc's area in texels fell below what the average resolves); nearer than
 * DDOF_CARD_MIN_DEPTH_M it is refused naming the vertex, and at that depth it is drawn (an
 * opaque card over the whole view: opaque everywhere). */
static void test_near_camera(ddof_context *ctx)
{
    static float white[TW * TH * 4], out[W * H * 4];
    for (int i = 0; i < TW * TH * 4; i++)
        white[i] = 1.0f;
    double c[4][3] = {{-1, -1, -1e-10}, {1, -1, -1e-10}, {1, 1, -1e-10}, {-1, 1, -1e-10}};
    ddof_card card = rect_card(c, white);
    expect_refused(ctx, &card, 1, DDOF_ERROR_BAD_PARAMETER, "card 0: vertex 0 has z = -1e-10",
                   "z = -1e-10");
    for (int k = 0; k < 4; k++)
        card.position[k][2] = -(float)DDOF_CARD_MIN_DEPTH_M;
    const ddof_camera cam = test_camera();
    CHECK_EQ_INT(render(ctx, NULL, &cam, &card, 1, out), DDOF_OK);
    double lo = 1.0;
    for (int i = 0; i < W * H; i++)
        lo = fmin(lo, out[i * 4 + 3]);
    CHECK_MSG(lo > 1.0 - 1e-6, "a card over the view at 1e-6 m: alpha down to %g", lo);
}

/* Issue 40: a texture sharing bytes with the output was accepted (the CPU read texels it had
 * already overwritten); refused naming the card, nothing written. */
static void test_texture_in_output(ddof_context *ctx)
{
    static float out[W * H * 4];
    const ddof_camera cam = test_camera();
    ddof_card c[2] = {rect_card(fronto, texture_a), rect_card(fronto, texture_a)};
    c[1].position[0][2] = c[1].position[1][2] = c[1].position[2][2] = c[1].position[3][2] = -3;
    for (int i = 0; i < W * H * 4; i++)
        out[i] = 7.0f;
    c[1].texture.pixels = out + W * 4 * 5 + 4; /* a 24x16 texture inside the 96x64 output */
    CHECK_EQ_INT(render(ctx, NULL, &cam, c, 2, out), DDOF_ERROR_BAD_PARAMETER);
    CHECK_MSG(strstr(ddof_context_last_error(ctx), "overlaps card 1 texture") != NULL, "%s",
              ddof_context_last_error(ctx));
    int untouched = 1;
    for (int i = 0; i < W * H * 4; i++)
        untouched &= out[i] == 7.0f;
    CHECK(untouched);
}

/* ddof_cards_params_init_sized writes only the caller's size (the struct rules of ddof.h): an
 * older caller's struct is never overrun; the plain name writes the 0.5 layout. */
static void test_params_sized(ddof_context *ctx)
{
    unsigned char bytes[sizeof(ddof_cards_params) + 8];
    memset(bytes, 0xab, sizeof bytes);
    ddof_cards_params_init_sized((ddof_cards_params *)(void *)bytes, 8);
    uint32_t size;
    memcpy(&size, bytes, sizeof size);
    CHECK_EQ_INT(size, 8);
    CHECK(bytes[8] == 0xab && bytes[sizeof bytes - 1] == 0xab);
    ddof_cards_params p;
    memset(&p, 0xab, sizeof p);
    (ddof_cards_params_init)(&p);
    CHECK_EQ_INT(p.struct_size, DDOF_CARDS_PARAMS_SIZE_0_5);
    CHECK_EQ_INT(p.strips, 8);
    ddof_cards_params_init(&p);
    CHECK_EQ_INT(p.struct_size, sizeof p);
    CHECK_EQ_INT(p.expansion, DDOF_CARDS_EXPAND_OFFSET);
    /* Below the first layout: refused before anything runs. */
    p.struct_size = 8;
    static float out[W * H * 4];
    const ddof_camera cam = test_camera();
    const ddof_card card = rect_card(fronto, texture_a);
    CHECK_EQ_INT(render(ctx, &p, &cam, &card, 1, out), DDOF_ERROR_BAD_PARAMETER);
}

/* A pixel aspect of 4.9e82 (a camera as a scene file may give it) and a card 10 um from the
 * lens: the discs' boxes on the texture reach 9e62 texels, which became an index outside
 * size_t's range (undefined behaviour; fuzz_cards_scene under UBSan). Every end is clamped to
 * the texture now: the call succeeds and writes finite premultiplied values. */
static void test_extreme_aspect(ddof_context *ctx)
{
    static float out[W * H * 4];
    ddof_camera cam = test_camera(); /* the scene's: 85 mm, 24 mm fit vertically, f/1.4 at 5 m */
    cam.focal_length_mm = 85.0;
    cam.sensor_width_mm = 24.0;
    cam.sensor_fit = DDOF_SENSOR_FIT_VERTICAL;
    cam.fstop = 1.4;
    cam.focus_distance_m = 5.0;
    cam.pixel_aspect = 4.888888888888889e82;
    double far[4][3] = {{-500, -500, -2}, {500, -500, -2}, {500, 500, -2}, {-500, 500, -2}};
    double near[4][3] = {{-0.1, -0.1, -1e-5}, {0.1, -0.1, -1e-5}, {0.1, 0.1, -1e-5},
                         {-0.1, 0.1, -1e-5}};
    const ddof_card cards[2] = {rect_card(far, texture_a), rect_card(near, texture_b)};
    CHECK_EQ_INT(render(ctx, NULL, &cam, cards, 2, out), DDOF_OK);
    int ok = 1;
    for (int i = 0; i < W * H * 4; i++)
        ok &= isfinite(out[i]) && out[i] >= -1e-6f && out[i] <= 1.0f + 1e-5f;
    CHECK(ok);
}

/* Seen exactly edge-on, a card draws nothing (and is no error). */
static void test_edge_on(ddof_context *ctx)
{
    static float out[W * H * 4];
    const ddof_camera cam = test_camera();
    double c[4][3] = {{0, -0.2, -1}, {0, -0.2, -3}, {0, 0.2, -3}, {0, 0.2, -1}};
    const ddof_card card = rect_card(c, texture_a);
    CHECK_EQ_INT(render(ctx, NULL, &cam, &card, 1, out), DDOF_OK);
    double sum = 0.0;
    for (int i = 0; i < W * H * 4; i++)
        sum += fabs(out[i]);
    CHECK(sum == 0.0);
}

int main(void)
{
    make_texture(texture_a, 12345);
    make_texture(texture_b, 777);
    ddof_context *ctx = NULL;
    if (ddof_context_create(NULL, &ctx) != DDOF_OK)
        return 1;
    test_against_reference(ctx);
    test_in_focus(ctx);
    test_order(ctx);
    test_hidden_card(ctx);
    test_huge_coc(ctx);
    test_bad_input(ctx);
    test_edge_on(ctx);
    test_extreme_aspect(ctx);
    test_near_camera(ctx);
    test_texture_in_output(ctx);
    test_params_sized(ctx);
    ddof_context_free(ctx);
    return test_report("test_cards");
}
