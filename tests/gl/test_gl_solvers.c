/* SPDX-License-Identifier: MIT */
/* test_gl_solvers.c - every GPU solver against the CPU's double-precision reference on the hard
 * cases of test_hard_cases.c: odd (non-power-of-two) sizes, 1xN and Nx1, CoC 0 / huge
 * checkerboards, CoC 10,000 px (beta ~ 1e8), lines longer than the shared-memory PCR fits, 1..4
 * channels, several substeps. Jacobi is approximate by design, so it is compared with the CPU's
 * Jacobi (same sweeps from the same start). Argument: the backend ("osmesa" or "egl").
 *
 * Tolerances (absolute, colour in [0, 1]) were measured on llvmpipe and set with a margin;
 * DDOF_TEST_VERBOSE=1 prints the measured errors. */
#include "gl_test.h"

/* Thomas (double running value), CR, PCR, Gruen in float: measured <= 2.5e-6 on llvmpipe. */
#define TOL_FLOAT 1e-5
/* Gruen PACKED_HALF: levels hold half-float values (11-bit significand, one rounding per level
 * and per back-substitution): measured <= 1.3e-3. */
#define TOL_PACKED 4e-3
/* Jacobi on the GPU against Jacobi on the CPU (same arithmetic order, float): measured 1e-7. */
#define TOL_JACOBI 1e-5

typedef struct solver_case {
    const char *name;
    ddof_solver solver;
    ddof_precision precision;
    double tol;
} solver_case;

static const solver_case solvers[] = {
    {"thomas", DDOF_SOLVER_THOMAS, DDOF_PRECISION_FLOAT, TOL_FLOAT},
    {"cr", DDOF_SOLVER_CYCLIC_REDUCTION, DDOF_PRECISION_FLOAT, TOL_FLOAT},
    {"pcr", DDOF_SOLVER_PCR, DDOF_PRECISION_FLOAT, TOL_FLOAT},
    {"gruen", DDOF_SOLVER_GRUEN, DDOF_PRECISION_FLOAT, TOL_FLOAT},
    {"gruen-packed", DDOF_SOLVER_GRUEN, DDOF_PRECISION_PACKED_HALF, TOL_PACKED},
    {"jacobi", DDOF_SOLVER_JACOBI, DDOF_PRECISION_FLOAT, TOL_JACOBI},
};

static ddof_context *gl_ctx, *cpu_ctx;
static int verbose;
static double worst[sizeof solvers / sizeof *solvers];

/* Runs every solver on the GPU on one image against the reference (Jacobi: the CPU's Jacobi). */
static void check(const char *name, test_image *im, float beta_scale, uint32_t substeps)
{
    float *ref = alloc_f(im->n), *cpu_jacobi = alloc_f(im->n);
    ddof_params p = params_for(DDOF_SOLVER_REFERENCE_F64, substeps);
    p.beta_scale = beta_scale;
    p.jacobi_iterations = 20;
    ddof_status s = diffuse(cpu_ctx, &p, im->color, im->coc, ref, im->w, im->h, im->ch, NULL);
    CHECK_MSG(s == DDOF_OK, "%s: reference %d", name, (int)s);
    p.solver = DDOF_SOLVER_JACOBI;
    s = diffuse(cpu_ctx, &p, im->color, im->coc, cpu_jacobi, im->w, im->h, im->ch, NULL);
    CHECK_MSG(s == DDOF_OK, "%s: CPU jacobi %d", name, (int)s);
    for (size_t k = 0; k < sizeof solvers / sizeof *solvers; k++) {
        p.solver = solvers[k].solver;
        p.precision = solvers[k].precision;
        ddof_stats st = stats_init();
        memset(im->out, 0xff, im->n * sizeof(float)); /* NaN: every value must be written */
        s = image_diffuse(gl_ctx, &p, im, &st);
        CHECK_MSG(s == DDOF_OK, "%s/%s: status %d (%s)", name, solvers[k].name, (int)s,
                  ddof_context_last_error(gl_ctx));
        const float *want = solvers[k].solver == DDOF_SOLVER_JACOBI ? cpu_jacobi : ref;
        const double e = max_diff(im->out, want, im->n);
        worst[k] = fmax(worst[k], e);
        if (verbose)
            printf("  %-26s %-13s max error %.3g  device %.1f KiB\n", name, solvers[k].name, e,
                   (double)st.device_bytes / 1024.0);
        CHECK_MSG(e <= solvers[k].tol, "%s/%s: max error %.3g > %.3g", name, solvers[k].name,
                  e, solvers[k].tol);
        CHECK_MSG(st.backend != DDOF_BACKEND_CPU, "%s/%s: ran on the CPU", name,
                  solvers[k].name);
        CHECK_MSG(st.device_bytes > 0, "%s/%s: no device bytes reported", name,
                  solvers[k].name);
    }
    free(ref);
    free(cpu_jacobi);
}

static void random_case(const char *name, uint32_t w, uint32_t h, uint32_t ch, double max_coc,
                        double zeros, float beta_scale, uint32_t substeps, unsigned long long seed)
{
    test_image im = image_alloc(w, h, ch);
    test_rng rng = {seed};
    fill_uniform(im.color, im.n, &rng, 0.0, 1.0);
    fill_coc(im.coc, im.px, &rng, max_coc, zeros);
    check(name, &im, beta_scale, substeps);
    image_free(&im);
}

/* CoC 0 and `huge` in a checkerboard of `cell`-pixel squares over random colour. */
static void checker_case(const char *name, uint32_t w, uint32_t h, uint32_t cell, float huge,
                         float beta_scale)
{
    test_image im = image_alloc(w, h, 4);
    test_rng rng = {99};
    fill_uniform(im.color, im.n, &rng, 0.0, 1.0);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++)
            im.coc[(size_t)y * w + x] = ((x / cell + y / cell) & 1) ? huge : 0.0f;
    check(name, &im, beta_scale, 1);
    image_free(&im);
}

int main(int argc, char **argv)
{
    verbose = verbose_test();
    gl_ctx = gl_context_for(backend_from_name(argc > 1 ? argv[1] : NULL));
    if (!gl_ctx)
        return GL_TEST_SKIP;
    cpu_ctx = make_context(0);

    random_case("37x23 rgba", 37, 23, 4, 20.0, 0.3, DDOF_MOMENT_BETA_SCALE, 1, 1);
    random_case("37x23 rgba 3 substeps", 37, 23, 4, 20.0, 0.3, DDOF_MOMENT_BETA_SCALE, 3, 2);
    random_case("29x17 1 channel", 29, 17, 1, 40.0, 0.2, DDOF_MOMENT_BETA_SCALE, 1, 3);
    random_case("13x31 2 channels", 13, 31, 2, 40.0, 0.2, DDOF_MOMENT_BETA_SCALE, 1, 4);
    random_case("21x19 3 channels", 21, 19, 3, 40.0, 0.2, DDOF_MOMENT_BETA_SCALE, 1, 5);
    random_case("1x61", 1, 61, 3, 30.0, 0.1, DDOF_MOMENT_BETA_SCALE, 1, 6);
    random_case("61x1", 61, 1, 3, 30.0, 0.1, DDOF_MOMENT_BETA_SCALE, 1, 7);
    random_case("1x1", 1, 1, 4, 30.0, 0.0, DDOF_MOMENT_BETA_SCALE, 1, 8);
    random_case("2x3", 2, 3, 4, 30.0, 0.0, DDOF_MOMENT_BETA_SCALE, 1, 9);
    random_case("5x7", 5, 7, 4, 30.0, 0.0, DDOF_MOMENT_BETA_SCALE, 2, 10);
    checker_case("checker 0/10000 1px", 40, 31, 1, 10000.0f, DDOF_MOMENT_BETA_SCALE);
    checker_case("checker 0/10000 5px", 41, 33, 5, 10000.0f, 1.0f);
    random_case("257x5 coc 10000 beta 1e8", 257, 5, 4, 10000.0, 0.02, 1.0f, 1, 11);
    random_case("all sharp", 16, 9, 4, 0.0, 1.0, DDOF_MOMENT_BETA_SCALE, 1, 12);
    /* Longer than pcr_shared's 1024 rows: the CR+PCR hybrid; 4096 as in test_hard_cases. */
    random_case("4096x2 coc 10000", 4096, 2, 4, 10000.0, 0.01, DDOF_MOMENT_BETA_SCALE, 1, 13);
    random_case("3x1500", 3, 1500, 3, 200.0, 0.05, DDOF_MOMENT_BETA_SCALE, 1, 14);

    for (size_t k = 0; k < sizeof solvers / sizeof *solvers; k++)
        printf("%-13s worst max error %.3g (tolerance %.1g)\n", solvers[k].name, worst[k],
               solvers[k].tol);
    ddof_context_free(gl_ctx);
    ddof_context_free(cpu_ctx);
    return test_report("test_gl_solvers");
}
