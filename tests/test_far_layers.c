/* SPDX-License-Identifier: MIT */
/* test_far_layers.c - the far field's depth slices (ddof_params.blurred_edges): where two
 * blurred surfaces meet, each is drawn with the lens's shape and the nearer covers the farther.
 *
 *  - a blurred disc before a blurred bright background (a crown before the sky) against a lens
 *    in double precision that traces the aperture through both surfaces, the background known
 *    behind the disc: far closer than the diffusion there, on the image and on the band around
 *    the disc's edge, for a far and a near disc;
 *  - a constant frame stays constant across edges between blurred surfaces, and a textured one
 *    stays within its range (every output a convex mix of the input);
 *  - the plan's lines, OFF and a frame without such edges bit for bit the far field alone, an
 *    in-focus pixel untouched, the conditions (unsigned CoC, the far field off), the bad mode;
 *  - the hard cases: colours at DDOF_MAX_COLOR, CoC far beyond the frame, a staircase of more
 *    depths than slices, one row, 3 and 4 channels alike, in place. */
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

static ddof_params edge_params(ddof_layer_mode blurred_edges)
{
    ddof_params p;
    ddof_params_init(&p);
    p.far_field = DDOF_LAYER_AUTO;
    p.silhouettes = DDOF_LAYER_OFF;
    p.highlights = DDOF_LAYER_OFF;
    p.blurred_edges = blurred_edges;
    p.coc_signed = 1;
    return p;
}

/* The scene: a disc of radius DISC_R at (DISC_X, DISC_Y) with signed CoC c_disc before a
 * background plane of CoC c_back (both signed: the disc nearer, its CoC smaller). Each surface's
 * colour is a smooth pattern defined everywhere, so the lens can see the background behind the
 * disc. */
#define DISC_X 44.0
#define DISC_Y 34.0
#define DISC_R 17.0

static int in_disc(double x, double y)
{
    return (x - DISC_X) * (x - DISC_X) + (y - DISC_Y) * (y - DISC_Y) < DISC_R * DISC_R;
}

static double surface(int disc, int c, double x, double y)
{
    if (c == 3)
        return 1.0;
    if (disc) /* a dark crown */
        return 0.12 + 0.08 * sin(0.45 * x + 1.3 * c) * cos(0.37 * y - 0.7 * c);
    return 0.75 + 0.15 * sin(0.11 * x + 0.9 * c) + 0.05 * cos(0.17 * y + c); /* a bright sky */
}

static void pinhole(float c_disc, float c_back, float *color, float *coc)
{
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            const size_t i = (size_t)y * W + x;
            const int disc = in_disc(x, y);
            coc[i] = disc ? c_disc : c_back;
            for (int c = 0; c < CH; c++)
                color[i * CH + c] = (float)surface(disc, c, x, y);
        }
}

/* The lens: from each pixel (2 x 2 points of it) through each point u of the aperture (a
 * 24 x 24 grid over the unit disc, 12 x 12 in the quick run), a ray meets a surface of signed
 * CoC c at the image point p + c / 2 u; it sees the disc where that point of the disc's plane
 * is on the disc, else the background. Outside the frame the surfaces go on (the lens sees
 * past it). */
static void lens_reference(double c_disc, double c_back, double *out)
{
    enum { S = 2 };
    const int U = test_quick() ? 12 : 24; /* valgrind's run: a coarser aperture */
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double sum[CH] = {0};
            int n = 0;
            for (int sy = 0; sy < S; sy++)
                for (int sx = 0; sx < S; sx++)
                    for (int j = 0; j < U; j++)
                        for (int i = 0; i < U; i++) {
                            const double ux = (i + 0.5) / U * 2.0 - 1.0;
                            const double uy = (j + 0.5) / U * 2.0 - 1.0;
                            if (ux * ux + uy * uy >= 1.0)
                                continue;
                            const double px = x + (sx + 0.5) / S - 0.5;
                            const double py = y + (sy + 0.5) / S - 0.5;
                            const double dx = px + 0.5 * c_disc * ux, dy = py + 0.5 * c_disc * uy;
                            const int disc = in_disc(dx, dy);
                            const double bx = px + 0.5 * c_back * ux, by = py + 0.5 * c_back * uy;
                            for (int c = 0; c < CH; c++)
                                sum[c] += disc ? surface(1, c, dx, dy) : surface(0, c, bx, by);
                            n++;
                        }
            for (int c = 0; c < CH; c++)
                out[((size_t)y * W + x) * CH + c] = sum[c] / n;
        }
}

/* RMS over RGB, over the pixels within `band` px of the disc's edge (band < 0: all). */
static double rms_vs(const float *a, const double *ref, double band)
{
    double s = 0.0;
    size_t n = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const double d =
                fabs(sqrt((x - DISC_X) * (x - DISC_X) + (y - DISC_Y) * (y - DISC_Y)) - DISC_R);
            if (band >= 0.0 && d > band)
                continue;
            for (int c = 0; c < 3; c++) {
                const size_t i = ((size_t)y * W + x) * CH + (size_t)c;
                s += (a[i] - ref[i]) * (a[i] - ref[i]);
                n++;
            }
        }
    return sqrt(s / (double)n);
}

static void lens_case(float c_disc, float c_back, double tol_band, double tol_image)
{
    const size_t n = NPX * CH;
    float *color = alloc_f(n), *coc = alloc_f(NPX), *on = alloc_f(n), *off = alloc_f(n);
    double *ref = malloc(n * sizeof *ref);
    pinhole(c_disc, c_back, color, coc);
    ddof_params p = edge_params(DDOF_LAYER_AUTO);
    ddof_stats st = stats_init();
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, on, W, H, CH, &st), DDOF_OK);
    CHECK_MSG(strstr(st.plan, "depth slices") != NULL, "disc %g before %g: %s",
              (double)c_disc, (double)c_back, st.plan);
    p.blurred_edges = DDOF_LAYER_OFF;
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, off, W, H, CH, NULL), DDOF_OK);
    lens_reference(c_disc, c_back, ref);
    const double band = 0.5 * fabs((double)c_back) + 2.0;
    const double on_band = rms_vs(on, ref, band), off_band = rms_vs(off, ref, band);
    const double on_image = rms_vs(on, ref, -1.0), off_image = rms_vs(off, ref, -1.0);
    if (verbose)
        printf("  disc CoC %g before %g: RMS vs the lens, band %.4f (diffusion %.4f), image "
               "%.4f (%.4f)\n",
               (double)c_disc, (double)c_back, on_band, off_band, on_image, off_image);
    CHECK_MSG(on_band <= tol_band, "disc %g before %g: band RMS %.4f > %.4f", (double)c_disc,
              (double)c_back, on_band, tol_band);
    CHECK_MSG(on_image <= tol_image, "disc %g before %g: image RMS %.4f > %.4f", (double)c_disc,
              (double)c_back, on_image, tol_image);
    CHECK_MSG(on_band < 0.6 * off_band, "disc %g before %g: band %.4f not well below the "
              "diffusion's %.4f", (double)c_disc, (double)c_back, on_band, off_band);
    free(color);
    free(coc);
    free(on);
    free(off);
    free(ref);
}

static void test_disc_before_the_sky_is_the_lens(void)
{
    /* Measured (RMS against the lens, band / image; the diffusion's): 0.0098 / 0.0071 (0.0337
     * / 0.0193), 0.0131 / 0.0116 (0.0452 / 0.0307), 0.0265 / 0.0116 (0.0601 / 0.0261). */
    lens_case(10.0f, 16.0f, 0.015, 0.011); /* both behind the focus: a crown before the sky */
    lens_case(6.0f, 24.0f, 0.02, 0.017);   /* the sky far more blurred than the crown */
    lens_case(-14.0f, 8.0f, 0.04, 0.017);  /* the disc before the focus, the sky behind */
}

/* A constant frame stays constant however the CoC steps between blurred surfaces; a textured
 * one stays within the range of its input. */
static void test_constant_and_range(void)
{
    const size_t n = NPX * CH;
    float *color = alloc_f(n), *coc = alloc_f(NPX), *out = alloc_f(n);
    for (size_t i = 0; i < n; i++)
        color[i] = (i % CH) == 3 ? 1.0f : 0.375f + 0.125f * (float)(i % CH);
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++)
            coc[(size_t)y * W + x] = ((x / 12 + y / 9) % 3 == 0) ? 6.0f
                                     : ((x / 12 + y / 9) % 3 == 1) ? 13.0f : -9.0f;
    ddof_params p = edge_params(DDOF_LAYER_ON);
    ddof_stats st = stats_init();
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, out, W, H, CH, &st), DDOF_OK);
    CHECK_MSG(strstr(st.plan, "depth slices") != NULL, "%s", st.plan);
    CHECK_MSG(max_abs_diff_ff(out, color, n) <= 2e-6, "constant: off by %.3g",
              max_abs_diff_ff(out, color, n));

    block_texture(color, W, H, CH, 17, 0.05, 0.95);
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, out, W, H, CH, NULL), DDOF_OK);
    for (int c = 0; c < CH; c++) {
        float lo = color[c], hi = color[c], olo = out[c], ohi = out[c];
        for (size_t i = 0; i < NPX; i++) {
            lo = fminf(lo, color[i * CH + c]);
            hi = fmaxf(hi, color[i * CH + c]);
            olo = fminf(olo, out[i * CH + c]);
            ohi = fmaxf(ohi, out[i * CH + c]);
        }
        CHECK_MSG(olo >= lo - 1e-6f && ohi <= hi + 1e-6f,
                  "channel %d: output %g..%g outside the input's %g..%g", c, (double)olo,
                  (double)ohi, (double)lo, (double)hi);
    }
    free(color);
    free(coc);
    free(out);
}

static void test_plan_and_off(void)
{
    const size_t n = NPX * CH;
    float *color = alloc_f(n), *coc = alloc_f(NPX), *a = alloc_f(n), *b = alloc_f(n);
    pinhole(10.0f, 16.0f, color, coc);
    /* An in-focus bar through the frame: untouched. */
    for (uint32_t y = 0; y < H; y++)
        coc[(size_t)y * W + 80] = 0.0f;
    ddof_params p = edge_params(DDOF_LAYER_AUTO);
    ddof_stats st = stats_init();
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, a, W, H, CH, &st), DDOF_OK);
    CHECK_MSG(strstr(st.plan, "2 depth slices") != NULL,
              "%s", st.plan);
    for (uint32_t y = 0; y < H; y++)
        CHECK(memcmp(a + ((size_t)y * W + 80) * CH, color + ((size_t)y * W + 80) * CH,
                      CH * sizeof(float)) == 0);

    /* OFF: the far field alone; the pass leaves the diffusion's result at those edges. */
    p.blurred_edges = DDOF_LAYER_OFF;
    st = stats_init();
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, b, W, H, CH, &st), DDOF_OK);
    CHECK_MSG(strstr(st.plan, "; blurred edges: forced off") != NULL, "%s", st.plan);
    CHECK(memcmp(a, b, n * sizeof(float)) != 0);

    /* No edge between blurred surfaces (the disc in focus): AUTO is OFF bit for bit. */
    for (size_t i = 0; i < NPX; i++)
        if (coc[i] == 10.0f)
            coc[i] = 0.0f;
    p.blurred_edges = DDOF_LAYER_AUTO;
    st = stats_init();
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, a, W, H, CH, &st), DDOF_OK);
    CHECK_MSG(strstr(st.plan, "; blurred edges: none") != NULL, "%s",
              st.plan);
    p.blurred_edges = DDOF_LAYER_OFF;
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, b, W, H, CH, NULL), DDOF_OK);
    CHECK(memcmp(a, b, n * sizeof(float)) == 0);

    /* The conditions. */
    pinhole(10.0f, 16.0f, color, coc);
    p = edge_params(DDOF_LAYER_ON);
    p.coc_signed = 0;
    st = stats_init();
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, a, W, H, CH, &st), DDOF_OK);
    CHECK_MSG(strstr(st.plan, "; blurred edges: off (unsigned CoC)") != NULL, "%s", st.plan);
    p = edge_params(DDOF_LAYER_ON);
    p.far_field = DDOF_LAYER_OFF;
    st = stats_init();
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, a, W, H, CH, &st), DDOF_OK);
    CHECK_MSG(strstr(st.plan, "far field: forced off") != NULL &&
                  strstr(st.plan, "blurred edges") == NULL, "%s", st.plan);
    p = edge_params((ddof_layer_mode)7);
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, a, W, H, CH, NULL),
                 DDOF_ERROR_BAD_PARAMETER);
    CHECK_EQ_INT(ddof_params_check(ctx, &p), DDOF_ERROR_BAD_PARAMETER);
    free(color);
    free(coc);
    free(a);
    free(b);
}

/* Colours at DDOF_MAX_COLOR, CoC far beyond the frame, more depths than slices, one row: finite
 * and within range; 3 and 4 channels the same RGB; in place the same as out of place. */
static void test_hard_inputs(void)
{
    const size_t n = NPX * CH;
    float *color = alloc_f(n), *coc = alloc_f(NPX), *out = alloc_f(n);
    test_rng rng = {23};
    fill_uniform(color, n, &rng, -DDOF_MAX_COLOR, DDOF_MAX_COLOR);
    for (size_t i = 0; i < NPX; i++) /* a staircase: 12 depths, 4 px apart */
        coc[i] = 4.0f + 4.0f * (float)((i % W) / 8);
    ddof_params p = edge_params(DDOF_LAYER_ON);
    ddof_stats st = stats_init();
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, out, W, H, CH, &st), DDOF_OK);
    CHECK_MSG(strstr(st.plan, "4 depth slices") != NULL, "%s", st.plan);
    CHECK(all_finite(out, n));

    for (size_t i = 0; i < NPX; i++) /* far beyond the frame */
        coc[i] = (i % W) < W / 2 ? 3000.0f : 2000.0f;
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, out, W, H, CH, &st), DDOF_OK);
    CHECK(all_finite(out, n));
    CHECK_EQ_INT(diffuse_layers(ctx, &p, color, coc, NULL, out, W, 1, CH, &st), DDOF_OK);
    CHECK(all_finite(out, (size_t)W * CH));

    block_texture(color, W, H, CH, 8, 0.0, 1.0);
    for (size_t i = 0; i < NPX; i++)
        coc[i] = 4.0f + 4.0f * (float)((i % W) / 8);
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
    test_disc_before_the_sky_is_the_lens();
    test_constant_and_range();
    test_plan_and_off();
    test_hard_inputs();
    ddof_context_free(ctx);
    return test_report("test_far_layers");
}
