/* SPDX-License-Identifier: MIT */
/* test_invariants.c - image-level properties of ddof_diffuse (the contract in ddof.h and
 * docs/design.md section 1): agreement with an independent double-precision ADI step, no
 * overshoot, conservation, CoC-0 insulation, symmetry, the second moment of the kernel, the
 * solvers' agreement. test_invariants_calls.c: what holds whatever the call's form. */
#include "ddof.h"
#include "test_util.h"
#include "test_images.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

/* The default path (float Thomas) and REFERENCE_F64 against the independent double ADI. */
static void test_matches_independent_double(ddof_context *ctx)
{
    test_rng rng = {0x1234567ULL};
    test_image im = image_alloc(23, 17, 3);
    double *ref = malloc(im.n * sizeof(double));
    fill_uniform(im.color, im.n, &rng, 0.0, 1.0);
    fill_coc(im.coc, im.px, &rng, 12.0, 0.2);

    const uint32_t substeps[] = {1, 3};
    const float aspects[] = {1.0f, 1.5f};
    for (int si = 0; si < 2; si++) {
        for (int ai = 0; ai < 2; ai++) {
            for (size_t i = 0; i < im.n; i++)
                ref[i] = im.color[i];
            ddof_params p;
            heat_params_init(&p); /* default solver: Thomas, float */
            ref_adi(ref, im.coc, im.w, im.h, im.ch, DDOF_MOMENT_BETA_SCALE, aspects[ai],
                    substeps[si], p.in_focus_threshold_px);

            p.beta_scale = DDOF_MOMENT_BETA_SCALE; /* the k of ref_adi, not the preset's */
            p.substeps = substeps[si];
            p.pixel_aspect = aspects[ai];
            CHECK_EQ_INT(image_diffuse(ctx, &p, &im, NULL), DDOF_OK);
            double e_default = max_abs_diff_fd(im.out, ref, im.n);
            /* Float solve of a well-conditioned system, values in [0, 1]: ~1e-7 expected. */
            CHECK_MSG(e_default <= 2e-6, "default vs double ADI: %.3g (substeps %u, aspect %g)",
                      e_default, substeps[si], (double)aspects[ai]);

            p.solver = DDOF_SOLVER_REFERENCE_F64;
            CHECK_EQ_INT(image_diffuse(ctx, &p, &im, NULL), DDOF_OK);
            double e_ref = max_abs_diff_fd(im.out, ref, im.n);
            /* Only the final rounding to float (and beta computed from float d) may differ. */
            CHECK_MSG(e_ref <= 3e-7, "REFERENCE_F64 vs double ADI: %.3g (substeps %u, aspect %g)",
                      e_ref, substeps[si], (double)aspects[ai]);
            if (getenv("DDOF_TEST_VERBOSE"))
                printf("  double ADI: default err %.3g, reference err %.3g (n=%u, aspect %g)\n",
                       e_default, e_ref, substeps[si], (double)aspects[ai]);
        }
    }
    image_free(&im);
    free(ref);
}

/* Every output channel stays within the input channel's [min, max] (image-wide), and for a
 * single row within that row's range. */
static void check_in_range(const float *in, const float *out, size_t pixels, uint32_t ch,
                           const char *what)
{
    for (uint32_t c = 0; c < ch; c++) {
        float lo = INFINITY, hi = -INFINITY;
        for (size_t i = 0; i < pixels; i++) {
            lo = fminf(lo, in[i * ch + c]);
            hi = fmaxf(hi, in[i * ch + c]);
        }
        const double tol = 4.0 * FLT_EPSILON * fmax(fabs(lo), fabs(hi));
        size_t bad = 0;
        double worst = 0;
        for (size_t i = 0; i < pixels; i++) {
            double v = out[i * ch + c];
            double excess = fmax(lo - v, v - hi);
            if (!(excess <= tol)) {
                bad++;
                worst = fmax(worst, excess);
            }
        }
        CHECK_MSG(bad == 0, "%s channel %u: %zu outputs outside [%g, %g], worst by %.3g", what,
                  c, bad, (double)lo, (double)hi, worst);
    }
}

static void test_no_overshoot(ddof_context *ctx)
{
    test_rng rng = {42};
    /* A general image with signed values and a rough CoC field. */
    {
        test_image im = image_alloc(64, 48, 4);
        fill_uniform(im.color, im.n, &rng, -2.0, 5.0);
        fill_coc(im.coc, im.px, &rng, 30.0, 0.3);
        for (uint32_t sub = 1; sub <= 4; sub += 3) {
            ddof_params p = params_for(DDOF_SOLVER_THOMAS, sub);
            CHECK_EQ_INT(image_diffuse(ctx, &p, &im, NULL), DDOF_OK);
            check_in_range(im.color, im.out, im.px, im.ch, "64x48 image");
        }
        image_free(&im);
    }
    /* A single row: the row's own range; a step edge is the classic ringing trigger. */
    {
        const uint32_t w = 500, ch = 2;
        test_image im = image_alloc(w, 1, ch);
        for (uint32_t x = 0; x < w; x++) {
            im.color[x * ch] = x < w / 2 ? 3.0f : -1.0f;
            im.color[x * ch + 1] = (float)test_uniform(&rng);
        }
        fill_coc(im.coc, w, &rng, 80.0, 0.1);
        ddof_params p = params_for(DDOF_SOLVER_THOMAS, 1);
        CHECK_EQ_INT(image_diffuse(ctx, &p, &im, NULL), DDOF_OK);
        check_in_range(im.color, im.out, w, ch, "single row");
        image_free(&im);
    }
}

static double sum_channel(const float *p, size_t pixels, uint32_t ch, uint32_t c)
{
    double s = 0;
    for (size_t i = 0; i < pixels; i++)
        s += p[i * ch + c];
    return s;
}

static void test_conservation(ddof_context *ctx)
{
    test_rng rng = {7};
    /* (w, h): a single row, a single column, a general image (uniform and rough CoC). The row
     * pass conserves each row sum and the column pass each column sum, so the total is
     * conserved for any CoC field. */
    const uint32_t dims[4][2] = {{1000, 1}, {1, 1000}, {64, 64}, {64, 64}};
    for (int t = 0; t < 4; t++) {
        const uint32_t w = dims[t][0], h = dims[t][1], ch = 2;
        test_image im = image_alloc(w, h, ch);
        fill_uniform(im.color, im.n, &rng, 0.0, 1.0);
        if (t == 2)
            fill_const(im.coc, im.px, 20.0f);
        else
            fill_coc(im.coc, im.px, &rng, 50.0, 0.1);
        for (uint32_t sub = 1; sub <= 3; sub += 2) {
            ddof_params p = params_for(DDOF_SOLVER_THOMAS, sub);
            CHECK_EQ_INT(image_diffuse(ctx, &p, &im, NULL), DDOF_OK);
            for (uint32_t c = 0; c < ch; c++) {
                double s0 = sum_channel(im.color, im.px, ch, c);
                double s1 = sum_channel(im.out, im.px, ch, c);
                CHECK_MSG(fabs(s1 - s0) <= 1e-5 * fabs(s0),
                          "%ux%u substeps %u channel %u: sum %.9g -> %.9g (rel %.3g)", w, h, sub,
                          c, s0, s1, fabs(s1 - s0) / fabs(s0));
            }
        }
        image_free(&im);
    }
    /* Each row sum on its own: every other row in focus cuts all column links, so only the
     * row pass acts and every row keeps its sum; likewise every other column for columns. */
    for (int axis = 0; axis < 2; axis++) {
        const uint32_t w = 48, h = 40;
        test_image im = image_alloc(w, h, 1);
        fill_uniform(im.color, im.n, &rng, 0.0, 1.0);
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++)
                im.coc[y * w + x] =
                    ((axis ? x : y) % 2) ? 0.0f : (float)(1 + 40 * test_uniform(&rng));
        ddof_params p = params_for(DDOF_SOLVER_THOMAS, 2);
        CHECK_EQ_INT(image_diffuse(ctx, &p, &im, NULL), DDOF_OK);
        double worst = 0;
        const uint32_t lines = axis ? w : h, len = axis ? h : w;
        for (uint32_t l = 0; l < lines; l++) {
            double s0 = 0, s1 = 0;
            for (uint32_t i = 0; i < len; i++) {
                size_t idx = axis ? (size_t)i * w + l : (size_t)l * w + i;
                s0 += im.color[idx];
                s1 += im.out[idx];
            }
            worst = fmax(worst, fabs(s1 - s0) / fabs(s0));
        }
        CHECK_MSG(worst <= 1e-5, "%s sums not conserved: worst relative change %.3g",
                  axis ? "column" : "row", worst);
        CHECK(memcmp(im.color, im.out, im.px * sizeof(float)) != 0); /* it did diffuse */
        image_free(&im);
    }
}

static void test_coc_zero_insulates(ddof_context *ctx)
{
    test_rng rng = {99};
    /* Every CoC-0 pixel is bitwise unchanged, whatever its neighbours do. */
    {
        const uint32_t ch = 4;
        test_image im = image_alloc(57, 43, ch);
        fill_uniform(im.color, im.n, &rng, -1.0, 3.0);
        fill_coc(im.coc, im.px, &rng, 40.0, 0.3);
        for (int solver = 0; solver < TEST_CPU_SOLVER_COUNT; solver++) {
            ddof_params p = params_for((ddof_solver)solver, 2);
            CHECK_EQ_INT(image_diffuse(ctx, &p, &im, NULL), DDOF_OK);
            size_t changed = 0;
            for (size_t i = 0; i < im.px; i++)
                if (im.coc[i] == 0.0f &&
                    memcmp(&im.color[i * ch], &im.out[i * ch], ch * sizeof(float)))
                    changed++;
            CHECK_MSG(changed == 0, "solver %s: %zu CoC-0 pixels changed",
                      ddof_solver_name((ddof_solver)solver), changed);
        }
        image_free(&im);
    }
    /* A full-height wall of CoC 0 at x = 20: 1.0 left, 0.0 right, 0.5 on the wall. */
    {
        const uint32_t w = 40, h = 30, wall = 20;
        test_image im = image_alloc(w, h, 1);
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++) {
                im.color[y * w + x] = x < wall ? 1.0f : x == wall ? 0.5f : 0.0f;
                im.coc[y * w + x] = x == wall ? 0.0f : 10.0f;
            }
        ddof_params p = params_for(DDOF_SOLVER_THOMAS, 2);
        CHECK_EQ_INT(image_diffuse(ctx, &p, &im, NULL), DDOF_OK);
        size_t leaked = 0, wall_changed = 0;
        double left_err = 0;
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++) {
                float v = im.out[y * w + x];
                if (x > wall && v != 0.0f)
                    leaked++;
                if (x == wall && v != 0.5f)
                    wall_changed++;
                if (x < wall)
                    left_err = fmax(left_err, fabs(v - 1.0));
            }
        CHECK_MSG(leaked == 0, "%zu pixels right of the wall are not exactly 0", leaked);
        CHECK_MSG(wall_changed == 0, "%zu wall pixels changed", wall_changed);
        CHECK_MSG(left_err <= 1e-6, "a constant region drifted by %.3g", left_err);
        image_free(&im);
    }
    /* The right side of a wall does not depend on the left side at all (bitwise): b is a with
     * the same CoC and another colour left of the wall. */
    {
        const uint32_t w = 33, h = 21, wall = 11, ch = 3;
        test_image a = image_alloc(w, h, ch), b = image_alloc(w, h, ch);
        fill_uniform(a.color, a.n, &rng, 0.0, 1.0);
        memcpy(b.color, a.color, a.n * sizeof(float));
        fill_coc(a.coc, a.px, &rng, 25.0, 0.0);
        for (uint32_t y = 0; y < h; y++) {
            a.coc[y * w + wall] = 0.0f;
            for (uint32_t x = 0; x < wall; x++)
                for (uint32_t c = 0; c < ch; c++)
                    b.color[((size_t)y * w + x) * ch + c] = 1000.0f;
        }
        memcpy(b.coc, a.coc, a.px * sizeof(float));
        ddof_params p = params_for(DDOF_SOLVER_THOMAS, 3);
        CHECK_EQ_INT(image_diffuse(ctx, &p, &a, NULL), DDOF_OK);
        CHECK_EQ_INT(image_diffuse(ctx, &p, &b, NULL), DDOF_OK);
        size_t differ = 0;
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = wall; x < w; x++)
                if (memcmp(&a.out[((size_t)y * w + x) * ch], &b.out[((size_t)y * w + x) * ch],
                           ch * sizeof(float)))
                    differ++;
        CHECK_MSG(differ == 0, "%zu pixels behind the wall depend on the other side", differ);
        image_free(&a);
        image_free(&b);
    }
}

typedef struct moments {
    double mass, mx, my, vx, vy;
} moments;

static moments image_moments(const float *p, uint32_t w, uint32_t h)
{
    moments m = {0, 0, 0, 0, 0};
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            double v = p[(size_t)y * w + x];
            m.mass += v;
            m.mx += v * x;
            m.my += v * y;
        }
    m.mx /= m.mass;
    m.my /= m.mass;
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            double v = p[(size_t)y * w + x];
            m.vx += v * (x - m.mx) * (x - m.mx);
            m.vy += v * (y - m.my) * (y - m.my);
        }
    m.vx /= m.mass;
    m.vy /= m.mass;
    return m;
}

/* A unit impulse at the centre of a w x h one-channel image, uniform CoC d: the kernel. */
static test_image impulse_image(uint32_t w, uint32_t h, float d)
{
    test_image im = image_alloc(w, h, 1);
    fill_const(im.color, im.px, 0.0f);
    im.color[(h / 2) * w + w / 2] = 1.0f;
    fill_const(im.coc, im.px, d);
    return im;
}

static void test_symmetry(ddof_context *ctx)
{
    const uint32_t w = 41, h = 41;
    test_image im = impulse_image(w, h, 10.0f);
    const float *out = im.out;
    for (uint32_t sub = 1; sub <= 4; sub += 3) {
        ddof_params p = params_for(DDOF_SOLVER_THOMAS, sub);
        CHECK_EQ_INT(image_diffuse(ctx, &p, &im, NULL), DDOF_OK);
        double peak = 0, e_lr = 0, e_ud = 0, e_tr = 0;
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++) {
                double v = out[y * w + x];
                peak = fmax(peak, v);
                e_lr = fmax(e_lr, fabs(v - out[y * w + (w - 1 - x)]));
                e_ud = fmax(e_ud, fabs(v - out[(h - 1 - y) * w + x]));
                e_tr = fmax(e_tr, fabs(v - out[x * w + y])); /* separable: k(x) k(y) */
            }
        CHECK_MSG(e_lr <= 1e-6 * peak, "substeps %u: left/right asymmetry %.3g (peak %.3g)", sub,
                  e_lr, peak);
        CHECK_MSG(e_ud <= 1e-6 * peak, "substeps %u: up/down asymmetry %.3g (peak %.3g)", sub,
                  e_ud, peak);
        CHECK_MSG(e_tr <= 1e-6 * peak, "substeps %u: x/y asymmetry %.3g (peak %.3g)", sub, e_tr,
                  peak);
        moments m = image_moments(out, w, h);
        CHECK_NEAR(m.mx, w / 2, 1e-4);
        CHECK_NEAR(m.my, h / 2, 1e-4);
        CHECK_MSG(fabs(m.vx - m.vy) <= 1e-4 * m.vx, "substeps %u: var x %.9g, var y %.9g", sub,
                  m.vx, m.vy);
    }
    image_free(&im);
}

/* A kernel variance within 1% of the expected one; `what` starts the message. */
static void check_variance(const char *what, uint32_t sub, char axis, double var, double expect)
{
    CHECK_MSG(fabs(var - expect) <= 0.01 * expect, "%ssubsteps %u: var %c %.6g, expected %.6g",
              what, sub, axis, var, expect);
}

/* One implicit step has per-axis variance 2 beta = 2 k d^2; with k = 1/32 that is d^2 / 16.
 * n substeps of beta/n add up to the same variance. */
static void test_second_moment(ddof_context *ctx)
{
    const int quick = test_quick();
    const uint32_t w = quick ? 161 : 401, h = w;
    const float d = quick ? 16.0f : 40.0f;
    test_image im = impulse_image(w, h, d);
    const double expect = (double)d * d / 16.0;
    for (uint32_t sub = 1; sub <= 4; sub += 3) {
        ddof_params p = params_for(DDOF_SOLVER_THOMAS, sub);
        CHECK_EQ_INT(image_diffuse(ctx, &p, &im, NULL), DDOF_OK);
        moments m = image_moments(im.out, w, h);
        CHECK_NEAR(m.mass, 1.0, 1e-5);
        check_variance("", sub, 'x', m.vx, expect);
        check_variance("", sub, 'y', m.vy, expect);

        /* pixel_aspect 2: column links use 2d, so the vertical variance is 4x. Uses half the
         * CoC so the vertical spread still fits the image. */
        fill_const(im.coc, im.px, d / 2);
        p.pixel_aspect = 2.0f;
        CHECK_EQ_INT(image_diffuse(ctx, &p, &im, NULL), DDOF_OK);
        m = image_moments(im.out, w, h);
        CHECK_NEAR(m.mass, 1.0, 1e-5);
        check_variance("aspect 2, ", sub, 'x', m.vx, expect / 4);
        check_variance("aspect 2, ", sub, 'y', m.vy, expect);
        fill_const(im.coc, im.px, d);
    }
    /* beta_scale is k: doubling it doubles the variance. */
    {
        ddof_params p = params_for(DDOF_SOLVER_THOMAS, 1);
        p.beta_scale = 2.0f * DDOF_MOMENT_BETA_SCALE;
        fill_const(im.coc, im.px, d / 2);
        CHECK_EQ_INT(image_diffuse(ctx, &p, &im, NULL), DDOF_OK);
        moments m = image_moments(im.out, w, h);
        CHECK_MSG(fabs(m.vx - expect / 2) <= 0.01 * expect / 2,
                  "beta_scale 1/16: var x %.6g, expected %.6g", m.vx, expect / 2);
    }
    image_free(&im);
}

static void test_solvers_agree(ddof_context *ctx)
{
    test_rng rng = {2024};
    test_image im = image_alloc(97, 61, 3);
    float *ref = alloc_f(im.n);
    fill_uniform(im.color, im.n, &rng, 0.0, 1.0);
    fill_coc(im.coc, im.px, &rng, 25.0, 0.15);

    for (uint32_t sub = 1; sub <= 2; sub++) {
        ddof_params p = params_for(DDOF_SOLVER_REFERENCE_F64, sub);
        ddof_stats st = stats_init();
        CHECK_EQ_INT(diffuse(ctx, &p, im.color, im.coc, ref, im.w, im.h, im.ch, &st), DDOF_OK);
        CHECK_EQ_INT(st.solver, DDOF_SOLVER_REFERENCE_F64);
        CHECK_EQ_INT(st.threads, 1); /* "double precision throughout, one thread" */
        const ddof_solver exact[] = {DDOF_SOLVER_THOMAS, DDOF_SOLVER_CYCLIC_REDUCTION,
                                     DDOF_SOLVER_PCR};
        for (int i = 0; i < 3; i++) {
            p = params_for(exact[i], sub);
            st.struct_size = sizeof st;
            CHECK_EQ_INT(image_diffuse(ctx, &p, &im, &st), DDOF_OK);
            CHECK_EQ_INT(st.solver, exact[i]);
            double e = max_abs_diff_ff(im.out, ref, im.n);
            /* Values in [0, 1], beta up to 20: float error of an exact solve ~1e-7. */
            CHECK_MSG(e <= 2e-6, "solver %s substeps %u vs reference: %.3g",
                      ddof_solver_name(exact[i]), sub, e);
            if (getenv("DDOF_TEST_VERBOSE"))
                printf("  %s vs reference (substeps %u): %.3g\n", ddof_solver_name(exact[i]), sub,
                       e);
        }
    }

    /* Jacobi converges to the exact answer; on small CoC (beta <= 2, spectral radius of the
     * sweep <= 4/5) 300 sweeps are exact to float precision, 3 sweeps clearly are not. */
    fill_coc(im.coc, im.px, &rng, 8.0, 0.1);
    ddof_params p = params_for(DDOF_SOLVER_REFERENCE_F64, 1);
    CHECK_EQ_INT(diffuse(ctx, &p, im.color, im.coc, ref, im.w, im.h, im.ch, NULL), DDOF_OK);
    p = params_for(DDOF_SOLVER_JACOBI, 1);
    const uint32_t iters[] = {3, 20, 300};
    double err[3];
    for (int i = 0; i < 3; i++) {
        p.jacobi_iterations = iters[i];
        CHECK_EQ_INT(image_diffuse(ctx, &p, &im, NULL), DDOF_OK);
        err[i] = max_abs_diff_ff(im.out, ref, im.n);
        check_in_range(im.color, im.out, im.px, im.ch, "jacobi");
        if (getenv("DDOF_TEST_VERBOSE"))
            printf("  jacobi %u sweeps vs reference: %.3g\n", iters[i], err[i]);
    }
    CHECK_MSG(err[0] > 1e-3, "3 Jacobi sweeps are suspiciously exact: %.3g", err[0]);
    CHECK_MSG(err[1] < err[0], "Jacobi error does not fall: %.3g -> %.3g", err[0], err[1]);
    CHECK_MSG(err[2] <= 2e-6, "300 Jacobi sweeps vs reference: %.3g", err[2]);

    image_free(&im);
    free(ref);
}

int main(void)
{
    ddof_context *ctx = make_context(2);
    test_matches_independent_double(ctx);
    test_no_overshoot(ctx);
    test_conservation(ctx);
    test_coc_zero_insulates(ctx);
    test_symmetry(ctx);
    test_second_moment(ctx);
    test_solvers_agree(ctx);
    ddof_context_free(ctx);
    return test_report("test_invariants");
}
