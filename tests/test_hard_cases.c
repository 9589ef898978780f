/* SPDX-License-Identifier: MIT */
/* test_hard_cases.c - numerical stability of ddof_diffuse on hard inputs: huge CoC (beta up to
 * 1e10 in float), insulating checkerboards, degenerate and odd image sizes, a lone blurred pixel,
 * CoC at exactly DDOF_MAX_COC_PX, HDR values. The float solvers are compared with the library's
 * DDOF_SOLVER_REFERENCE_F64, which is itself checked against an independent double ADI here.
 *
 * Tolerances (absolute, for colour in [0, 1]) were measured on the implementation and set with
 * about a 10x margin; DDOF_TEST_VERBOSE=1 prints the measured errors. */
#include "ddof.h"
#include "test_util.h"
#include "test_images.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

/* Exact float solvers vs REFERENCE_F64, colour in [0, 1]; measured <= 3e-7 on lines up to
 * 257 px (Thomas, CR, PCR). */
#define TOL_FLOAT_VS_F64 3e-6
/* Long lines (4096 px) at beta 1e8: measured <= 6.6e-7 (Thomas, which carries its running
 * value in double; 3.5e-5 before it did), CR and PCR <= 2e-7. */
#define TOL_FLOAT_VS_F64_LONG 3e-6
/* REFERENCE_F64 vs the independent double ADI (float output rounding dominates); measured
 * <= 4e-8. */
#define TOL_F64_VS_DOUBLE 5e-7

static int verbose;

/* All outputs finite and within the input's [min, max] (over all channels; a few ulps slack). */
static int in_range(const float *in, const float *out, size_t n)
{
    float lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; i < n; i++) {
        lo = fminf(lo, in[i]);
        hi = fmaxf(hi, in[i]);
    }
    const double tol = 4.0 * FLT_EPSILON * fmax(fabs(lo), fabs(hi));
    for (size_t i = 0; i < n; i++)
        if (!isfinite(out[i]) || out[i] < lo - tol || out[i] > hi + tol)
            return 0;
    return 1;
}

/* Each value `a` with probability `frac`, else `b` (one draw per value): sparse masks. */
static void fill_choice(float *p, size_t n, test_rng *rng, double frac, float a, float b)
{
    for (size_t i = 0; i < n; i++)
        p[i] = test_uniform(rng) < frac ? a : b;
}

static const ddof_solver exact_solvers[] = {DDOF_SOLVER_THOMAS, DDOF_SOLVER_CYCLIC_REDUCTION,
                                            DDOF_SOLVER_PCR};

static double worst_float_err, worst_float_err_long, worst_f64_err; /* measured, reported */

/* Runs REFERENCE_F64 (checked against the independent double ADI) and every exact float solver
 * (checked against REFERENCE_F64, in range, finite) on one case; im->out is scratch. `scale` is
 * the colour range. */
static void check_case_tol(ddof_context *ctx, const char *name, test_image *im, float beta_scale,
                           uint32_t substeps, double scale, double tol)
{
    const size_t n = im->n;
    float *ref = alloc_f(n);
    double *dref = malloc(n * sizeof(double));
    ddof_params p = params_for(DDOF_SOLVER_REFERENCE_F64, substeps);
    p.beta_scale = beta_scale;
    ddof_status s = diffuse(ctx, &p, im->color, im->coc, ref, im->w, im->h, im->ch, NULL);
    CHECK_MSG(s == DDOF_OK, "%s: reference status %d (%s)", name, (int)s,
              ddof_context_last_error(ctx));
    for (size_t i = 0; i < n; i++)
        dref[i] = im->color[i];
    ref_adi(dref, im->coc, im->w, im->h, im->ch, beta_scale, 1.0, substeps,
            p.in_focus_threshold_px);
    double e64 = max_abs_diff_fd(ref, dref, n) / scale;
    worst_f64_err = fmax(worst_f64_err, e64);
    CHECK_MSG(e64 <= TOL_F64_VS_DOUBLE, "%s: REFERENCE_F64 vs double ADI %.3g", name, e64);
    CHECK_MSG(in_range(im->color, ref, n), "%s: REFERENCE_F64 out of range or not finite", name);
    for (int i = 0; i < 3; i++) {
        p.solver = exact_solvers[i];
        s = image_diffuse(ctx, &p, im, NULL);
        CHECK_MSG(s == DDOF_OK, "%s/%s: status %d (%s)", name, ddof_solver_name(p.solver), (int)s,
                  ddof_context_last_error(ctx));
        double e = max_abs_diff_ff(im->out, ref, n) / scale;
        if (tol > TOL_FLOAT_VS_F64)
            worst_float_err_long = fmax(worst_float_err_long, e);
        else
            worst_float_err = fmax(worst_float_err, e);
        CHECK_MSG(e <= tol, "%s/%s vs reference: %.3g (relative to range)", name,
                  ddof_solver_name(p.solver), e);
        CHECK_MSG(in_range(im->color, im->out, n), "%s/%s: output out of range or not finite",
                  name, ddof_solver_name(p.solver));
        if (verbose)
            printf("  %-28s %-7s err %.3g   f64 vs double %.3g\n", name,
                   ddof_solver_name(p.solver), e, e64);
    }
    /* Jacobi is approximate but each sweep is a convex combination: in range, finite. */
    p.solver = DDOF_SOLVER_JACOBI;
    p.jacobi_iterations = 7;
    CHECK_EQ_INT(image_diffuse(ctx, &p, im, NULL), DDOF_OK);
    CHECK_MSG(in_range(im->color, im->out, n), "%s/jacobi: output out of range or not finite",
              name);
    free(ref);
    free(dref);
}

static void check_case(ddof_context *ctx, const char *name, test_image *im, float beta_scale,
                       uint32_t substeps, double scale)
{
    check_case_tol(ctx, name, im, beta_scale, substeps, scale, TOL_FLOAT_VS_F64);
}

/* Output must equal input bitwise for every solver (no conductive link anywhere). */
static void check_identity(ddof_context *ctx, const char *name, test_image *im)
{
    for (int solver = 0; solver < TEST_CPU_SOLVER_COUNT; solver++) {
        ddof_params p = params_for((ddof_solver)solver, 2);
        p.beta_scale = 1.0f;
        CHECK_EQ_INT(image_diffuse(ctx, &p, im, NULL), DDOF_OK);
        CHECK_MSG(!memcmp(im->color, im->out, im->n * sizeof(float)),
                  "%s/%s: output differs from input", name, ddof_solver_name(p.solver));
    }
}

static void test_huge_coc(ddof_context *ctx)
{
    test_rng rng = {0xC0C};
    const uint32_t w = test_quick() ? 33 : 64, h = test_quick() ? 24 : 48;
    test_image im = image_alloc(w, h, 3);
    fill_uniform(im.color, im.n, &rng, 0.0, 1.0);
    const float scales[] = {DDOF_DEFAULT_BETA_SCALE, 1.0f}; /* beta ~3e6 and ~1e8 */
    for (int si = 0; si < 2; si++) {
        char name[64];
        fill_const(im.coc, im.px, 10000.0f);
        snprintf(name, sizeof name, "uniform 1e4, k=%g", (double)scales[si]);
        check_case(ctx, name, &im, scales[si], 1, 1.0);
        fill_coc(im.coc, im.px, &rng, 10000.0, 0.2);
        snprintf(name, sizeof name, "random 0..1e4, k=%g", (double)scales[si]);
        check_case(ctx, name, &im, scales[si], 1, 1.0);
        snprintf(name, sizeof name, "random 0..1e4, n=4, k=%g", (double)scales[si]);
        check_case(ctx, name, &im, scales[si], 4, 1.0);
        fill_choice(im.coc, im.px, &rng, 0.5, 0.0f, 10000.0f);
        snprintf(name, sizeof name, "mix 0/1e4, k=%g", (double)scales[si]);
        check_case(ctx, name, &im, scales[si], 1, 1.0);
        /* Huge and tiny links side by side: CoC alternating 1e4 and 0.01 per 3-pixel block. */
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++)
                im.coc[y * w + x] = ((x / 3 + y / 3) % 2) ? 10000.0f : 0.01f;
        snprintf(name, sizeof name, "blocks 1e4/0.01, k=%g", (double)scales[si]);
        check_case(ctx, name, &im, scales[si], 1, 1.0);
    }
    image_free(&im);
    /* Long lines (a 4K row and a 4K column) at beta 3e6 and 1e8. */
    {
        const uint32_t n = 4096;
        test_image row = image_alloc(n, 1, 1), col = image_alloc(1, n, 1);
        fill_const(row.coc, n, 10000.0f);
        fill_const(col.coc, n, 10000.0f);
        /* The error depends on the data: several random fills and a step. */
        for (int fill = 0; fill < 4; fill++) {
            if (fill < 3)
                fill_uniform(row.color, n, &rng, 0.0, 1.0);
            else
                for (uint32_t i = 0; i < n; i++)
                    row.color[i] = i < n / 2 ? 1.0f : 0.0f;
            memcpy(col.color, row.color, n * sizeof(float)); /* the same data as a column */
            for (int si = 0; si < 2; si++) {
                char name[64];
                snprintf(name, sizeof name, "4096x1 #%d CoC 1e4, k=%g", fill, (double)scales[si]);
                check_case_tol(ctx, name, &row, scales[si], 1, 1.0, TOL_FLOAT_VS_F64_LONG);
                snprintf(name, sizeof name, "1x4096 #%d CoC 1e4, k=%g", fill, (double)scales[si]);
                check_case_tol(ctx, name, &col, scales[si], 1, 1.0, TOL_FLOAT_VS_F64_LONG);
            }
        }
        image_free(&row);
        image_free(&col);
    }
    /* Thomas keeps a batch's running value in float while its memory is short (beta <= 65536
     * times the smallest positive gamma: 256 px) and in double beyond. Both sides of the
     * switch on 4096-px lines, beta 255^2 (float) and 257^2 (double), with random data and a
     * step: measured <= 6e-7 on the float side. The double side's step is 4.4e-6 from the
     * reference, and so it is with the running value in float or in double: that error is
     * the float weights' rounding, which no running precision removes, so its bound is 1e-5.
     * (The CoC 1e4 lines above fail with the running value in float at every length: 1.2e-5.) */
    {
        const uint32_t n = 4096;
        test_image row = image_alloc(n, 1, 1), col = image_alloc(1, n, 1);
        const float cocs[2] = {255.0f, 257.0f};
        for (int side = 0; side < 2; side++)
            for (int fill = 0; fill < 2; fill++) {
                fill_const(row.coc, n, cocs[side]);
                fill_const(col.coc, n, cocs[side]);
                if (fill == 0)
                    fill_uniform(row.color, n, &rng, 0.0, 1.0);
                else
                    for (uint32_t i = 0; i < n; i++)
                        row.color[i] = i < n / 2 ? 1.0f : 0.0f;
                memcpy(col.color, row.color, n * sizeof(float));
                const double tol = side == 0 ? TOL_FLOAT_VS_F64_LONG : 1e-5;
                char name[64];
                snprintf(name, sizeof name, "4096x1 #%d CoC %g, k=1", fill, (double)cocs[side]);
                check_case_tol(ctx, name, &row, 1.0f, 1, 1.0, tol);
                snprintf(name, sizeof name, "1x4096 #%d CoC %g, k=1", fill, (double)cocs[side]);
                check_case_tol(ctx, name, &col, 1.0f, 1, 1.0, tol);
            }
        image_free(&row);
        image_free(&col);
    }
    /* Huge uniform CoC on a single row: the row's mean, up to O(n^2 / beta). */
    {
        const uint32_t n = 100;
        test_image row = image_alloc(n, 1, 1);
        fill_uniform(row.color, n, &rng, 0.0, 1.0);
        fill_const(row.coc, n, 10000.0f);
        double mean = 0;
        for (uint32_t i = 0; i < n; i++)
            mean += row.color[i] / n;
        ddof_params p;
        heat_params_init(&p);
        p.beta_scale = 1.0f; /* beta = 1e8, n^2 / beta = 1e-4 */
        for (int i = 0; i < 3; i++) {
            p.solver = exact_solvers[i];
            CHECK_EQ_INT(image_diffuse(ctx, &p, &row, NULL), DDOF_OK);
            double e = 0;
            for (uint32_t j = 0; j < n; j++)
                e = fmax(e, fabs(row.out[j] - mean));
            CHECK_MSG(e <= 1e-4, "%s: a 1e4-px CoC row is not flat: %.3g from the mean",
                      ddof_solver_name(p.solver), e);
        }
        image_free(&row);
    }
}

static void test_insulators(ddof_context *ctx)
{
    test_rng rng = {3};
    const uint32_t w = 37, h = 29, ch = 4;
    test_image im = image_alloc(w, h, ch);
    float *coc = im.coc;
    fill_uniform(im.color, im.n, &rng, -5.0, 5.0);
    /* Checkerboard 0 / 1e4: every link has a 0 end, so nothing moves. */
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++)
            coc[y * w + x] = ((x + y) % 2) ? 10000.0f : 0.0f;
    check_identity(ctx, "checkerboard 0/1e4", &im);
    /* One blurred pixel in a sharp image: it has no partner, nothing moves. */
    fill_const(coc, im.px, 0.0f);
    coc[(h / 2) * w + w / 2] = 10000.0f;
    check_identity(ctx, "single CoC pixel", &im);
    /* ... two adjacent blurred pixels average (almost exactly, beta = 1e8). */
    coc[(h / 2) * w + w / 2 + 1] = 10000.0f;
    check_case(ctx, "two CoC pixels", &im, 1.0f, 1, 10.0);
    {
        ddof_params p;
        heat_params_init(&p);
        p.beta_scale = 1.0f;
        CHECK_EQ_INT(image_diffuse(ctx, &p, &im, NULL), DDOF_OK);
        size_t i0 = ((size_t)(h / 2) * w + w / 2) * ch, i1 = i0 + ch;
        for (uint32_t c = 0; c < ch; c++) {
            double mean = 0.5 * ((double)im.color[i0 + c] + im.color[i1 + c]);
            CHECK_NEAR(im.out[i0 + c], mean, 1e-6);
            CHECK_NEAR(im.out[i1 + c], mean, 1e-6);
        }
    }
    /* Tiny CoC (beta underflows or is denormal in float): finite, in range, near identity. */
    for (size_t i = 0; i < im.px; i++)
        coc[i] = (i % 3) ? 1e-20f : 1e-3f;
    check_case(ctx, "tiny CoC", &im, DDOF_DEFAULT_BETA_SCALE, 1, 10.0);
    image_free(&im);
}

static void test_sizes(ddof_context *ctx)
{
    test_rng rng = {1};
    /* Degenerate and awkward sizes: 1x1, single rows and columns, around the 16-lane batch
     * width and powers of two (cyclic reduction levels), odd and non-power-of-two. */
    const uint32_t dims[][2] = {{1, 1},   {1, 50},  {50, 1},  {2, 2},   {3, 7},  {7, 3},
                                {2, 1},   {1, 2},   {3, 1},   {1, 3},   {5, 4},  {15, 17},
                                {16, 16}, {17, 15}, {31, 2},  {32, 3},  {33, 5}, {63, 64},
                                {64, 65}, {65, 63}, {257, 129}};
    const int cases = (int)(sizeof dims / sizeof dims[0]);
    for (int t = 0; t < cases; t++) {
        uint32_t w = dims[t][0], h = dims[t][1];
        if (test_quick() && w * h > 5000) {
            w = 97;
            h = 33;
        }
        const uint32_t ch = 1 + t % 4;
        test_image im = image_alloc(w, h, ch);
        fill_uniform(im.color, im.n, &rng, 0.0, 1.0);
        char name[64];
        fill_uniform(im.coc, im.px, &rng, 0.0, 30.0);
        snprintf(name, sizeof name, "%ux%ux%u CoC<30", w, h, ch);
        check_case(ctx, name, &im, DDOF_DEFAULT_BETA_SCALE, 2, 1.0);
        fill_const(im.coc, im.px, 10000.0f);
        snprintf(name, sizeof name, "%ux%ux%u CoC 1e4", w, h, ch);
        check_case(ctx, name, &im, DDOF_DEFAULT_BETA_SCALE, 1, 1.0);
        if (w == 1 && h == 1)
            check_identity(ctx, "1x1", &im);
        image_free(&im);
    }
}

static void test_max_coc(ddof_context *ctx)
{
    test_rng rng = {17};
    test_image im = image_alloc(40, 30, 2);
    fill_uniform(im.color, im.n, &rng, 0.0, 1.0);
    fill_const(im.coc, im.px, DDOF_MAX_COC_PX);
    /* beta = 3.1e8 (k = 1/32) and 1e10 (k = 1). */
    check_case(ctx, "CoC = MAX, k=1/32", &im, DDOF_DEFAULT_BETA_SCALE, 1, 1.0);
    check_case(ctx, "CoC = MAX, k=1", &im, 1.0f, 1, 1.0);
    fill_choice(im.coc, im.px, &rng, 0.3, 0.0f, DDOF_MAX_COC_PX);
    check_case(ctx, "CoC 0/MAX, k=1", &im, 1.0f, 3, 1.0);
    image_free(&im);
}

static void test_hdr(ddof_context *ctx)
{
    test_rng rng = {23};
    test_image im = image_alloc(80, 60, 4);
    float *color = im.color;
    /* Sparse 1e4 highlights on black. */
    fill_choice(color, im.n, &rng, 0.02, 1e4f, 0.0f);
    fill_uniform(im.coc, im.px, &rng, 0.0, 40.0);
    check_case(ctx, "HDR 1e4 on 0", &im, DDOF_DEFAULT_BETA_SCALE, 2, 1e4);
    fill_const(im.coc, im.px, 10000.0f);
    check_case(ctx, "HDR 1e4 on 0, CoC 1e4", &im, 1.0f, 1, 1e4);
    /* Values up to 1e20 with beta 1e8: no intermediate may overflow. */
    for (size_t i = 0; i < im.n; i++)
        color[i] = test_uniform(&rng) < 0.1 ? 1e20f : (float)test_uniform(&rng);
    check_case(ctx, "values 1e20, CoC 1e4", &im, 1.0f, 1, 1e20);
    /* Negative (signed) values are colour too. */
    for (size_t i = 0; i < im.n; i++)
        color[i] = (float)(1e4 * (test_uniform(&rng) - 0.5));
    fill_uniform(im.coc, im.px, &rng, 0.0, 2000.0);
    check_case(ctx, "signed 1e4", &im, DDOF_DEFAULT_BETA_SCALE, 1, 1e4);
    image_free(&im);
}

int main(void)
{
    verbose = getenv("DDOF_TEST_VERBOSE") != NULL;
    ddof_context *ctx = make_context(2);
    test_huge_coc(ctx);
    test_insulators(ctx);
    test_sizes(ctx);
    test_max_coc(ctx);
    test_hdr(ctx);
    printf("worst float solver vs REFERENCE_F64: %.3g, on 4096-px lines %.3g; REFERENCE_F64 vs "
           "double ADI: %.3g (relative to the colour range)\n",
           worst_float_err, worst_float_err_long, worst_f64_err);
    ddof_context_free(ctx);
    return test_report("test_hard_cases");
}
