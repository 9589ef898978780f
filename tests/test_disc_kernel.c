/* SPDX-License-Identifier: MIT */
/* test_disc_kernel.c - the disc (lens) kernel: its point spread against a uniform disc, the
 * float driver against the double-precision complex reference on the hard cases, and the
 * invariants it keeps from the heat kernel (in-focus pixels bit for bit, nothing crossing them,
 * flat stays flat, energy kept, cost independent of the CoC), through the layers too.
 *
 * Tolerances were measured on the implementation and set with a margin (DDOF_TEST_VERBOSE=1
 * prints the measured values). */
#include "ddof.h"
#include "point_spread.h"
#include "test_images.h"
#include "test_util.h"

#include <float.h>
#include <math.h>
#include <string.h>

static int verbose;

/* Float driver vs the double reference, colour in [0, 1]: relative to the colour's range. */
#define TOL_DISC_VS_F64 2e-5
/* Lines of 4096 px at CoC 1e4 (|beta| ~ 1e6): the float running values' rounding adds up. */
#define TOL_DISC_VS_F64_LONG 2e-4
/* The fitted kernels reach at least this against the disc at CoC 12, 32 and 80 (measured in
 * study/lens/fit_disc_kernel.py and printed by ddof-bench). */
#define DISC_MIN_SNR_DB 11.0
/* What the default preset draws of an HDR point (the highlight pass): a disc. */
#define BRIGHT_MIN_SNR_DB 30.0

static ddof_params disc_params(ddof_kernel kernel, ddof_solver solver)
{
    ddof_params p;
    ddof_params_init(&p);
    p.kernel = kernel;
    p.solver = solver;
    return p;
}

static const ddof_kernel disc_kernels[] = {DDOF_KERNEL_DISC_2X2, DDOF_KERNEL_DISC_2X3,
                                           DDOF_KERNEL_DISC_3X3};

/* ---- the point spread ------------------------------------------------------------------- */

/* The disc kernels' point spread: kernel SNR, energy and rings at CoC 12, 32 and 80 px. The
 * default preset draws discs: with a disc kernel, or with the far field's gather, which draws
 * the exact disc wherever no depth edge is near (the study chose which). */
static void test_point_spread(ddof_context *ctx)
{
    const float sizes[] = {12.0f, 32.0f, 80.0f};
    ddof_params def;
    ddof_params_init(&def);
    CHECK_MSG(def.kernel != DDOF_KERNEL_HEAT || def.far_field != DDOF_LAYER_OFF,
              "the default preset draws blobs, not discs");
    for (size_t k = 0; k < sizeof disc_kernels / sizeof disc_kernels[0]; k++) {
        ddof_params p = disc_params(disc_kernels[k], DDOF_SOLVER_THOMAS);
        for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++) {
            const point_spread ps = point_spread_measure(ctx, &p, sizes[i]);
            CHECK_EQ_INT(ps.status, DDOF_OK);
            if (verbose)
                printf("%s CoC %g: %.2f dB, energy %.6f, ring %.3f\n",
                       ddof_kernel_name(p.kernel), (double)sizes[i], ps.snr_db, ps.energy,
                       ps.ring);
            CHECK_MSG(fabs(ps.energy - 1.0) <= 0.01, "%s CoC %g: energy %g",
                      ddof_kernel_name(p.kernel), (double)sizes[i], ps.energy);
            CHECK_MSG(ps.ring >= -0.12, "%s CoC %g: ring %.3f of the disc's height",
                      ddof_kernel_name(p.kernel), (double)sizes[i], ps.ring);
            CHECK_MSG(ps.snr_db >= DISC_MIN_SNR_DB, "%s CoC %g: kernel SNR %.2f dB",
                      ddof_kernel_name(p.kernel), (double)sizes[i], ps.snr_db);
        }
    }
    /* On black the ring would be negative light: the output stays within the input's range
     * (>= 0), which adds the clipped ring's share of energy (printed). */
    {
        const uint32_t w = point_spread_size(32.0f);
        test_image im = image_alloc(w, w, 1);
        fill_const(im.color, im.n, 0.0f);
        fill_const(im.coc, im.px, 32.0f);
        im.color[(size_t)(w / 2) * w + w / 2] = 1000.0f;
        CHECK_EQ_INT(image_diffuse(ctx, &def, &im, NULL), DDOF_OK);
        double lowest = 0, energy = 0;
        for (size_t i = 0; i < im.n; i++) {
            lowest = fmin(lowest, im.out[i]);
            energy += im.out[i];
        }
        if (verbose)
            printf("HDR point of 1000 on black: energy %.4f x, lowest %g\n", energy / 1000.0,
                   lowest);
        CHECK_MSG(lowest == 0.0, "negative output %g next to an HDR highlight", lowest);
        CHECK_MSG(energy / 1000.0 >= 1.0 && energy / 1000.0 <= 1.1, "energy %g x", energy / 1e3);
        image_free(&im);
    }

    /* An HDR highlight through the frame call: the highlight pass draws it as the disc (the
     * diffusion kernel alone stays near 12 dB, above). */
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++) {
        const point_spread ps = point_spread_measure_bright(ctx, &def, sizes[i], 100.0f);
        CHECK_EQ_INT(ps.status, DDOF_OK);
        if (verbose)
            printf("default, RGB point of 100, CoC %g: %.2f dB, energy %.6f, ring %.4f\n",
                   (double)sizes[i], ps.snr_db, ps.energy, ps.ring);
        CHECK_MSG(ps.snr_db >= BRIGHT_MIN_SNR_DB, "bright point at CoC %g: %.2f dB",
                  (double)sizes[i], ps.snr_db);
        CHECK_MSG(fabs(ps.energy - 1.0) <= 0.01, "bright point at CoC %g: energy %g",
                  (double)sizes[i], ps.energy);
        CHECK_MSG(ps.ring >= -0.02, "bright point at CoC %g: ring %.4f", (double)sizes[i],
                  ps.ring);
    }

    /* The heat kernel, for the record: far from a disc. */
    ddof_params heat;
    heat_params_init(&heat);
    const point_spread ps = point_spread_measure(ctx, &heat, 32.0f);
    CHECK_EQ_INT(ps.status, DDOF_OK);
    CHECK_MSG(ps.snr_db < 8.0, "heat kernel at CoC 32: %.2f dB (a Gaussian cannot pass ~7.5)",
              ps.snr_db);
}

/* ---- against the double reference --------------------------------------------------------- */

static double worst, worst_long;

static void compare_with_reference(ddof_context *ctx, const char *name, test_image *im,
                                   ddof_kernel kernel, double range, double tol, int long_line)
{
    ddof_params pf = disc_params(kernel, DDOF_SOLVER_THOMAS);
    ddof_params pr = disc_params(kernel, DDOF_SOLVER_REFERENCE_F64);
    float *ref = alloc_f(im->n);
    ddof_stats sf = stats_init(), sr = stats_init();
    CHECK_EQ_INT(diffuse(ctx, &pr, im->color, im->coc, ref, im->w, im->h, im->ch, &sr), DDOF_OK);
    CHECK_EQ_INT(diffuse(ctx, &pf, im->color, im->coc, im->out, im->w, im->h, im->ch, &sf),
                 DDOF_OK);
    CHECK_MSG(all_finite(im->out, im->n), "%s %s: non-finite output", name,
              ddof_kernel_name(kernel));
    const double e = max_abs_diff_ff(im->out, ref, im->n) / range;
    if (long_line)
        worst_long = fmax(worst_long, e);
    else
        worst = fmax(worst, e);
    if (verbose)
        printf("%-28s %s: float vs double %.3g\n", name, ddof_kernel_name(kernel), e);
    CHECK_MSG(e <= tol, "%s %s: float vs double %.3g > %.3g", name, ddof_kernel_name(kernel), e,
              tol);
    CHECK_EQ_INT(sf.kernel, kernel);
    CHECK_EQ_INT(sf.lines_solved, sr.lines_solved);
    /* In-focus pixels (no link on any side) are untouched, bit for bit. */
    size_t changed = 0;
    for (uint32_t y = 0; y < im->h; y++)
        for (uint32_t x = 0; x < im->w; x++) {
            const size_t p = (size_t)y * im->w + x;
            if (im->coc[p] != 0.0f)
                continue;
            for (uint32_t c = 0; c < im->ch; c++)
                changed += memcmp(&im->out[p * im->ch + c], &im->color[p * im->ch + c],
                                  sizeof(float)) != 0;
        }
    CHECK_MSG(changed == 0, "%s %s: %zu values of CoC-0 pixels changed", name,
              ddof_kernel_name(kernel), changed);
    free(ref);
}

static void test_hard_cases(ddof_context *ctx)
{
    test_rng rng = {0xd15c};
    for (size_t k = 0; k < sizeof disc_kernels / sizeof disc_kernels[0]; k++) {
        const ddof_kernel kernel = disc_kernels[k];
        /* Random CoC with in-focus pixels, RGBA texture. */
        test_image im = image_alloc(61, 47, 4);
        fill_uniform(im.color, im.n, &rng, 0.0, 1.0);
        fill_coc(im.coc, im.px, &rng, 40.0, 0.2);
        compare_with_reference(ctx, "random CoC 0..40", &im, kernel, 1.0, TOL_DISC_VS_F64, 0);
        /* CoC 0 next to CoC 10,000: columns alternate. */
        for (uint32_t y = 0; y < im.h; y++)
            for (uint32_t x = 0; x < im.w; x++)
                im.coc[(size_t)y * im.w + x] = (x / 3) % 2 ? 1e4f : 0.0f;
        compare_with_reference(ctx, "CoC 0 | CoC 1e4 stripes", &im, kernel, 1.0,
                               TOL_DISC_VS_F64_LONG, 1);
        /* Single-pixel islands of blur in an in-focus frame, and whole insulated rows. */
        fill_const(im.coc, im.px, 0.0f);
        for (int i = 0; i < 40; i++)
            im.coc[(size_t)(test_uniform(&rng) * (double)im.px)] = 50.0f;
        for (uint32_t y = 10; y < im.h; y += 10)
            for (uint32_t x = 0; x < im.w; x++)
                im.coc[(size_t)y * im.w + x] = 30.0f;
        compare_with_reference(ctx, "islands + blurred rows", &im, kernel, 1.0, TOL_DISC_VS_F64,
                               0);
        /* HDR: a 1000x highlight on a dim texture. */
        fill_uniform(im.color, im.n, &rng, 0.0, 0.1);
        im.color[(size_t)(20 * im.w + 30) * 4] = 1000.0f;
        fill_coc(im.coc, im.px, &rng, 25.0, 0.1);
        compare_with_reference(ctx, "HDR highlight", &im, kernel, 1000.0, TOL_DISC_VS_F64, 0);
        image_free(&im);

        /* 4096-pixel lines at CoC 1e4: |beta| ~ 1e6..1e8 depending on the step. */
        const uint32_t n = test_quick() ? 1024 : 4096;
        test_image line = image_alloc(n, 3, 1);
        fill_uniform(line.color, line.n, &rng, 0.0, 1.0);
        fill_const(line.coc, line.px, 1e4f);
        line.coc[n / 2] = 0.0f; /* one in-focus pixel splits the middle row */
        compare_with_reference(ctx, "4096 px at CoC 1e4", &line, kernel, 1.0,
                               TOL_DISC_VS_F64_LONG, 1);
        image_free(&line);
    }
}

/* ---- invariants --------------------------------------------------------------------------- */

static void test_invariants(ddof_context *ctx)
{
    test_rng rng = {77};
    test_image im = image_alloc(53, 41, 3);
    ddof_params p;
    ddof_params_init(&p);

    /* Flat stays flat, whatever the CoC. */
    fill_const(im.color, im.n, 0.75f);
    fill_coc(im.coc, im.px, &rng, 60.0, 0.1);
    CHECK_EQ_INT(image_diffuse(ctx, &p, &im, NULL), DDOF_OK);
    double flat = 0;
    for (size_t i = 0; i < im.n; i++)
        flat = fmax(flat, fabs(im.out[i] - 0.75));
    CHECK_MSG(flat <= 1e-5, "flat 0.75 came out within %g", flat);

    /* Energy: each step keeps every line's sum, so the image's sum is kept. */
    fill_uniform(im.color, im.n, &rng, 0.0, 1.0);
    CHECK_EQ_INT(image_diffuse(ctx, &p, &im, NULL), DDOF_OK);
    for (uint32_t c = 0; c < im.ch; c++) {
        double in = 0, out = 0;
        for (size_t i = 0; i < im.px; i++) {
            in += im.color[i * im.ch + c];
            out += im.out[i * im.ch + c];
        }
        CHECK_MSG(fabs(in - out) <= 1e-5 * in, "channel %u: sum %.7g -> %.7g", c, in, out);
    }

    /* Nothing crosses an in-focus column: a bright left half does not reach the right half. */
    for (uint32_t y = 0; y < im.h; y++)
        for (uint32_t x = 0; x < im.w; x++) {
            const size_t i = (size_t)y * im.w + x;
            im.coc[i] = x == 26 ? 0.0f : 30.0f;
            for (uint32_t c = 0; c < im.ch; c++)
                im.color[i * im.ch + c] = x < 26 ? 100.0f : 0.0f;
        }
    CHECK_EQ_INT(image_diffuse(ctx, &p, &im, NULL), DDOF_OK);
    double leaked = 0;
    for (uint32_t y = 0; y < im.h; y++)
        for (uint32_t x = 27; x < im.w; x++)
            for (uint32_t c = 0; c < im.ch; c++)
                leaked = fmax(leaked, fabs(im.out[((size_t)y * im.w + x) * im.ch + c]));
    CHECK_MSG(leaked == 0.0, "%g leaked across an in-focus column", leaked);

    /* In place equals out of place. */
    fill_uniform(im.color, im.n, &rng, 0.0, 1.0);
    fill_coc(im.coc, im.px, &rng, 20.0, 0.2);
    CHECK_EQ_INT(image_diffuse(ctx, &p, &im, NULL), DDOF_OK);
    CHECK_EQ_INT(diffuse(ctx, &p, im.color, im.coc, im.color, im.w, im.h, im.ch, NULL), DDOF_OK);
    CHECK_MSG(max_abs_diff_ff(im.out, im.color, im.n) == 0.0, "in place differs");

    /* The cost does not depend on the CoC: the same lines are solved at CoC 2 and 200. */
    ddof_stats small = stats_init(), large = stats_init();
    fill_const(im.coc, im.px, 2.0f);
    CHECK_EQ_INT(image_diffuse(ctx, &p, &im, &small), DDOF_OK);
    fill_const(im.coc, im.px, 200.0f);
    CHECK_EQ_INT(image_diffuse(ctx, &p, &im, &large), DDOF_OK);
    CHECK_EQ_INT(small.lines_solved, large.lines_solved);
    CHECK_MSG(small.lines_solved > 0, "nothing solved");

    /* Nothing out of focus: a copy. */
    fill_const(im.coc, im.px, 0.0f);
    ddof_stats none = stats_init();
    CHECK_EQ_INT(image_diffuse(ctx, &p, &im, &none), DDOF_OK);
    CHECK_EQ_INT(none.lines_solved, 0);
    CHECK_MSG(memcmp(im.out, im.color, im.n * sizeof(float)) == 0, "CoC 0 frame changed");
    image_free(&im);
}

/* Anamorphic pixels: column links use d * pixel_aspect, so the spread is taller by the aspect. */
static void test_pixel_aspect(ddof_context *ctx)
{
    const uint32_t w = 81;
    test_image im = image_alloc(w, w, 1);
    fill_const(im.color, im.n, 0.0f);
    fill_const(im.coc, im.px, 16.0f);
    im.color[(size_t)(w / 2) * w + w / 2] = 1.0f;
    ddof_params p;
    ddof_params_init(&p);
    p.pixel_aspect = 1.5f;
    CHECK_EQ_INT(image_diffuse(ctx, &p, &im, NULL), DDOF_OK);
    double vx = 0, vy = 0;
    for (uint32_t y = 0; y < w; y++)
        for (uint32_t x = 0; x < w; x++) {
            const double v = im.out[(size_t)y * w + x], dx = (double)x - w / 2,
                         dy = (double)y - w / 2;
            vx += v * dx * dx;
            vy += v * dy * dy;
        }
    CHECK_MSG(fabs(sqrt(vy / vx) - 1.5) <= 0.05, "height / width of the spread %.3f, want 1.5",
              sqrt(vy / vx));
    image_free(&im);
}

/* ---- the layers with the disc kernel -------------------------------------------------------- */

static void test_layers(ddof_context *ctx)
{
    const uint32_t w = 64, h = 48, ch = 4;
    test_image im = image_alloc(w, h, ch);
    block_texture(im.color, w, h, ch, 5, 0.0, 1.0);
    /* A far background (CoC 24), a sharp bar (0) and a near blurred square (-18). */
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            float c = 24.0f;
            if (x >= 30 && x < 34)
                c = 0.0f;
            if (x >= 8 && x < 20 && y >= 10 && y < 22)
                c = -18.0f;
            im.coc[(size_t)y * w + x] = c;
        }
    float *ref = alloc_f(im.n);
    for (int mode = 0; mode < 2; mode++) {
        ddof_params pf = disc_params(DDOF_KERNEL_DISC_2X2, DDOF_SOLVER_THOMAS);
        pf.coc_signed = 1;
        pf.background = DDOF_LAYER_ON;
        pf.near_spread = mode ? DDOF_LAYER_ON : DDOF_LAYER_OFF;
        ddof_params pr = pf;
        pr.solver = DDOF_SOLVER_REFERENCE_F64;
        ddof_stats st = stats_init();
        CHECK_EQ_INT(diffuse_layers(ctx, &pr, im.color, im.coc, NULL, ref, w, h, ch, NULL),
                     DDOF_OK);
        CHECK_EQ_INT(diffuse_layers(ctx, &pf, im.color, im.coc, NULL, im.out, w, h, ch, &st),
                     DDOF_OK);
        CHECK(st.effects & DDOF_EFFECT_BACKGROUND);
        CHECK_EQ_INT(st.kernel, DDOF_KERNEL_DISC_2X2);
        const double e = max_abs_diff_ff(im.out, ref, im.n);
        if (verbose)
            printf("layers (near spread %s): float vs double %.3g\n", mode ? "on" : "off", e);
        CHECK_MSG(all_finite(im.out, im.n), "layers: non-finite output");
        CHECK_MSG(e <= TOL_DISC_VS_F64, "layers (near spread %d): float vs double %.3g", mode, e);
    }

    /* A foreground element. */
    float *fg = alloc_f((size_t)w * h * 4), *fg_coc = alloc_f((size_t)w * h);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            const size_t i = (size_t)y * w + x;
            const int inside = x >= 40 && x < 50 && y >= 20 && y < 30;
            for (uint32_t c = 0; c < 4; c++)
                fg[i * 4 + c] = inside ? (c == 3 ? 1.0f : 0.8f) : 0.0f;
            fg_coc[i] = inside ? 14.0f : 0.0f;
            im.coc[i] = fabsf(im.coc[i]);
        }
    ddof_foreground f;
    ddof_foreground_init(&f);
    f.color = (ddof_image_in){fg, w, h, 4, 0};
    f.coc = (ddof_image_in){fg_coc, w, h, 1, 0};
    ddof_params pf = disc_params(DDOF_KERNEL_DISC_2X2, DDOF_SOLVER_THOMAS);
    ddof_params pr = disc_params(DDOF_KERNEL_DISC_2X2, DDOF_SOLVER_REFERENCE_F64);
    ddof_stats st = stats_init();
    CHECK_EQ_INT(diffuse_layers(ctx, &pr, im.color, im.coc, &f, ref, w, h, ch, NULL), DDOF_OK);
    CHECK_EQ_INT(diffuse_layers(ctx, &pf, im.color, im.coc, &f, im.out, w, h, ch, &st), DDOF_OK);
    CHECK(st.effects & DDOF_EFFECT_FOREGROUND);
    const double e = max_abs_diff_ff(im.out, ref, im.n);
    if (verbose)
        printf("foreground element: float vs double %.3g\n", e);
    CHECK_MSG(e <= TOL_DISC_VS_F64, "foreground: float vs double %.3g", e);
    free(fg);
    free(fg_coc);
    free(ref);
    image_free(&im);
}

/* ---- bad combinations and cancelling ------------------------------------------------------- */

static int cancel_at_once(void *user, float fraction)
{
    (void)user;
    return fraction > 0.0f;
}

static void test_params_and_cancel(ddof_context *ctx)
{
    test_image im = image_alloc(40, 30, 4);
    test_rng rng = {3};
    fill_uniform(im.color, im.n, &rng, 0.0, 1.0);
    fill_coc(im.coc, im.px, &rng, 20.0, 0.1);
    ddof_params p;
    ddof_params_init(&p);
    p.kernel = (ddof_kernel)DDOF_KERNEL_COUNT_;
    CHECK_EQ_INT(image_diffuse(ctx, &p, &im, NULL), DDOF_ERROR_BAD_PARAMETER);
    /* Another solver runs the heat kernel, and the stats say so. */
    p.kernel = DDOF_KERNEL_DISC_2X3;
    p.solver = DDOF_SOLVER_PCR;
    ddof_stats st = stats_init();
    CHECK_EQ_INT(image_diffuse(ctx, &p, &im, &st), DDOF_OK);
    CHECK_EQ_INT(st.kernel, DDOF_KERNEL_HEAT);
    p.solver = DDOF_SOLVER_THOMAS;
    CHECK_EQ_INT(image_diffuse(ctx, &p, &im, &st), DDOF_OK);
    CHECK_EQ_INT(st.kernel, DDOF_KERNEL_DISC_2X3);
    p.precision = DDOF_PRECISION_PACKED_HALF;
    CHECK_EQ_INT(image_diffuse(ctx, &p, &im, NULL), DDOF_ERROR_UNSUPPORTED);
    p.precision = DDOF_PRECISION_FLOAT;
    CHECK(ddof_kernel_name(DDOF_KERNEL_DISC_3X3) && !ddof_kernel_name(DDOF_KERNEL_COUNT_));

    /* A cancelled disc diffusion gives back the input. */
    p.progress = cancel_at_once;
    memset(im.out, 0, im.n * sizeof(float));
    CHECK_EQ_INT(image_diffuse(ctx, &p, &im, NULL), DDOF_ERROR_CANCELLED);
    CHECK_MSG(memcmp(im.out, im.color, im.n * sizeof(float)) == 0,
              "a cancelled call did not give back the input");
    image_free(&im);
}

/* The library's scratch holds whatever an earlier call left, or what a fresh allocation holds:
 * NaN bytes here, from an allocator that fills every block with 0xFF. A column block of
 * in-focus pixels runs no chain, and its fold must not read the chain's results at all (a
 * product of a NaN with 0 is NaN: the pixels came out as the range's floor, not as they went
 * in). With one thread the blocks run in order, and no row conducts (the blurred columns
 * alternate with in-focus ones), so nothing has written the chain's results before the
 * in-focus band's blocks, two whole blocks wherever they fall. With two threads it depended
 * on which thread took which block: the check of the Blender add-on's ABI failed once. */
static void test_stale_scratch(void)
{
    ddof_context *ctx = patterned_context(0xff);
    CHECK(ctx != NULL);
    test_image im = image_alloc(96, 24, 4);
    test_rng rng = {8};
    fill_uniform(im.color, im.n, &rng, 0.0, 1.0);
    for (uint32_t y = 0; y < im.h; y++)
        for (uint32_t x = 0; x < im.w; x++)
            im.coc[y * im.w + x] = x >= 48 && x % 2 ? 12.0f : 0.0f;
    ddof_params p = disc_params(DDOF_KERNEL_DISC_2X2, DDOF_SOLVER_THOMAS);
    ddof_stats st = stats_init();
    CHECK_EQ_INT(image_diffuse(ctx, &p, &im, &st), DDOF_OK);
    CHECK(st.lines_solved > 0); /* the blurred columns did run */
    size_t changed = 0;
    for (uint32_t y = 0; y < im.h; y++)
        for (uint32_t x = 0; x < 48; x++)
            for (uint32_t c = 0; c < 4; c++) {
                const size_t i = ((size_t)y * im.w + x) * 4 + c;
                changed += memcmp(&im.out[i], &im.color[i], sizeof(float)) != 0;
            }
    CHECK_MSG(changed == 0, "%zu in-focus values changed over NaN-filled scratch", changed);
    image_free(&im);
    ddof_context_free(ctx);
}

int main(void)
{
    const char *v = getenv("DDOF_TEST_VERBOSE");
    verbose = v && v[0] == '1';
    ddof_context *ctx = make_context(2);
    test_point_spread(ctx);
    test_hard_cases(ctx);
    test_invariants(ctx);
    test_pixel_aspect(ctx);
    test_layers(ctx);
    test_params_and_cancel(ctx);
    test_stale_scratch();
    if (verbose)
        printf("worst float vs double: %.3g (long lines %.3g)\n", worst, worst_long);
    ddof_context_free(ctx);
    return test_report("test_disc_kernel");
}
