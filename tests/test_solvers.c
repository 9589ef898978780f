/* SPDX-License-Identifier: MIT */
/* test_solvers.c - the tridiagonal line solvers (solver.h) against a long-double reference.
 *
 * The reference is textbook Gaussian elimination with partial pivoting on the tridiagonal matrix
 * (LAPACK dgtsv's algorithm): it forms the diagonal gamma + beta_{i-1} + beta_i and eliminates
 * by subtraction, so it shares nothing with the solvers' excess bookkeeping. long double (64-bit
 * mantissa on x86-64) keeps it far ahead of float even where beta ~ 1e8 makes the subtraction
 * lose digits. For small n it is itself checked against a dense n x n elimination.
 *
 * Set DDOF_TEST_VERBOSE=1 to print the measured errors. */
#include "solvers/solver.h"
#include "test_util.h"

#include <float.h>
#include <stdint.h>
#include <string.h>

enum { L = DDOF_LANES };
typedef long double real;

static int verbose;

static const solver_ops *const exact_solvers[] = {&ddof_solver_thomas, &ddof_solver_cr,
                                                   &ddof_solver_pcr};
enum { EXACT = sizeof exact_solvers / sizeof exact_solvers[0] };

/* Bound on max |y - y_ref| / max |x| per line for the exact solvers. Measured worst cases here
 * (GCC 12, x86-64, -O3): thomas 5.7e-7, cr 2.3e-7, pcr 2.1e-7 at every beta range, 1e-3..1e8
 * included. The bound is about 10x that. Thomas once reached 8.8e-6 at beta 1e6..1e8 when its
 * back substitution formed 1 - w and rounded its running value to float; this bound catches
 * that. Forming diagonals by subtraction
 * (textbook float Thomas) gives Inf/NaN or O(1) errors at beta ~ 1e8. */
static const double exact_tolerance = 3e-6;

/* ---------------------------------------------------------------------------------------------
 * Problems: n unknowns x channels, all lanes, in the batch layout of solver.h. */

typedef struct problem {
    uint32_t n, ch;
    float *beta, *gamma, *x; /* [n][L], [n][L], [n][L][ch] */
} problem;

#define BETA(p, i, l) ((p)->beta[(size_t)(i) * L + (l)])
#define GAMMA(p, i, l) ((p)->gamma[(size_t)(i) * L + (l)])
#define AT(p, v, i, l, c) ((v)[((size_t)(i) * L + (l)) * (p)->ch + (c)]) /* x, y or ref */

static void *xcalloc(size_t count, size_t size)
{
    void *ptr = calloc(count ? count : 1, size);
    if (!ptr) {
        fprintf(stderr, "out of memory\n");
        exit(2);
    }
    return ptr;
}

static problem problem_new(uint32_t n, uint32_t ch)
{
    problem p = {n, ch, xcalloc((size_t)n * L, sizeof(float)),
                 xcalloc((size_t)n * L, sizeof(float)), xcalloc((size_t)n * L * ch, sizeof(float))};
    return p;
}

static void problem_free(problem *p)
{
    free(p->beta);
    free(p->gamma);
    free(p->x);
}

static double uniform(test_rng *rng, double lo, double hi)
{
    return lo + (hi - lo) * test_uniform(rng);
}

/* beta log-uniform in [blo, bhi] (an exact 0 with probability pzero), gamma uniform in
 * (0.1, 2], x uniform in [0, 1]; different in every lane. beta[n-1] is 0 as solver.h asks. */
static problem problem_random(test_rng *rng, uint32_t n, uint32_t ch, double blo, double bhi,
                              double pzero)
{
    problem p = problem_new(n, ch);
    for (uint32_t i = 0; i < n; i++)
        for (int l = 0; l < L; l++) {
            const int zero = i + 1 == n || test_uniform(rng) < pzero;
            BETA(&p, i, l) = zero ? 0.0f : (float)exp(uniform(rng, log(blo), log(bhi)));
            GAMMA(&p, i, l) = (float)uniform(rng, 0.1, 2.0);
            if (GAMMA(&p, i, l) <= 0.1f) GAMMA(&p, i, l) = 2.0f;
            for (uint32_t c = 0; c < ch; c++) AT(&p, p.x, i, l, c) = (float)test_uniform(rng);
        }
    return p;
}

/* ---------------------------------------------------------------------------------------------
 * Reference solutions, ref[(i * L + l) * ch + c] in double. */

/* Row i of lane l: sub-diagonal -left, diagonal, super-diagonal -right, rhs gamma x. */
static void matrix_row(const problem *p, int l, uint32_t i, real *left, real *diag, real *right)
{
    *left = i > 0 ? BETA(p, i - 1, l) : 0;
    *right = i + 1 < p->n ? BETA(p, i, l) : 0;
    *diag = (real)GAMMA(p, i, l) + *left + *right;
}

/* One lane by tridiagonal elimination with partial pivoting. Returns 0 if a pivot is 0. */
static int reference_lane(const problem *p, int lane, double *ref)
{
    const uint32_t n = p->n, ch = p->ch;
    real *dl = xcalloc(n, sizeof(real)), *d = xcalloc(n, sizeof(real));
    real *du = xcalloc(n, sizeof(real)), *du2 = xcalloc(n, sizeof(real));
    real *b = xcalloc((size_t)n * ch, sizeof(real));
    int ok = 1;
    for (uint32_t i = 0; i < n; i++) {
        real left, right;
        matrix_row(p, lane, i, &left, &d[i], &right);
        du[i] = -right;
        dl[i] = -right; /* the sub-diagonal entry of row i + 1: the matrix is symmetric */
        for (uint32_t c = 0; c < ch; c++)
            b[i * ch + c] = (real)GAMMA(p, i, lane) * AT(p, p->x, i, lane, c);
    }
    for (uint32_t i = 0; ok && i + 1 < n; i++) {
        real *bi = b + i * ch, *bn = bi + ch;
        if (fabsl(d[i]) >= fabsl(dl[i])) {
            ok = d[i] != 0;
            const real f = ok ? dl[i] / d[i] : 0;
            d[i + 1] -= f * du[i];
            for (uint32_t c = 0; c < ch; c++) bn[c] -= f * bi[c];
        } else { /* swap rows i and i + 1, which fills in du2[i] */
            const real f = d[i] / dl[i], t = d[i + 1];
            d[i] = dl[i];
            d[i + 1] = du[i] - f * t;
            du[i] = t;
            if (i + 2 < n) {
                du2[i] = du[i + 1];
                du[i + 1] = -f * du2[i];
            }
            for (uint32_t c = 0; c < ch; c++) {
                const real old = bi[c];
                bi[c] = bn[c];
                bn[c] = old - f * bn[c];
            }
        }
    }
    ok = ok && d[n - 1] != 0;
    for (uint32_t i = n; ok && i-- > 0;)
        for (uint32_t c = 0; c < ch; c++) {
            real s = b[i * ch + c];
            if (i + 1 < n) s -= du[i] * b[(i + 1) * ch + c];
            if (i + 2 < n) s -= du2[i] * b[(i + 2) * ch + c];
            b[i * ch + c] = s / d[i];
            AT(p, ref, i, lane, c) = (double)b[i * ch + c];
        }
    free(dl);
    free(d);
    free(du);
    free(du2);
    free(b);
    return ok;
}

static double *reference(const problem *p)
{
    double *ref = xcalloc((size_t)p->n * L * p->ch, sizeof(double));
    for (int l = 0; l < L; l++) CHECK(reference_lane(p, l, ref));
    return ref;
}

/* The dense n x n elimination with partial pivoting, to check the banded one. */
static void reference_dense_lane(const problem *p, int lane, double *ref)
{
    const uint32_t n = p->n, ch = p->ch, w = n + ch; /* a row: n coefficients, then ch rhs */
    real *m = xcalloc((size_t)n * w, sizeof(real));
    for (uint32_t i = 0; i < n; i++) {
        real left, right;
        matrix_row(p, lane, i, &left, &m[i * w + i], &right);
        if (i > 0) m[i * w + i - 1] = -left;
        if (i + 1 < n) m[i * w + i + 1] = -right;
        for (uint32_t c = 0; c < ch; c++)
            m[i * w + n + c] = (real)GAMMA(p, i, lane) * AT(p, p->x, i, lane, c);
    }
    for (uint32_t k = 0; k < n; k++) {
        uint32_t piv = k;
        for (uint32_t r = k + 1; r < n; r++)
            if (fabsl(m[r * w + k]) > fabsl(m[piv * w + k])) piv = r;
        for (uint32_t j = 0; j < w; j++) {
            const real t = m[k * w + j];
            m[k * w + j] = m[piv * w + j];
            m[piv * w + j] = t;
        }
        for (uint32_t r = k + 1; r < n; r++) {
            const real f = m[r * w + k] / m[k * w + k];
            for (uint32_t j = k; j < w; j++) m[r * w + j] -= f * m[k * w + j];
        }
    }
    for (uint32_t i = n; i-- > 0;)
        for (uint32_t c = 0; c < ch; c++) {
            real s = m[i * w + n + c];
            for (uint32_t j = i + 1; j < n; j++) s -= m[i * w + j] * (real)AT(p, ref, j, lane, c);
            AT(p, ref, i, lane, c) = (double)(s / m[i * w + i]);
        }
    free(m);
}

/* ---------------------------------------------------------------------------------------------
 * Running a solver: scratch of exactly the size it asks for, poisoned with NaN (it is promised
 * uninitialised) and followed by a guard zone that must survive. Returns y. */

static float *run_solver(const solver_ops *s, const problem *p, uint32_t iterations)
{
    const size_t nx = (size_t)p->n * L * p->ch, guard = 64;
    const size_t floats = s->scratch_floats(p->n, p->ch);
    const size_t bytes = ((floats + guard) * sizeof(float) + 63) / 64 * 64;
    float *scratch = aligned_alloc(64, bytes), *y = xcalloc(nx, sizeof(float));
    if (!scratch) {
        fprintf(stderr, "out of memory\n");
        exit(2);
    }
    for (size_t k = 0; k < floats; k++) scratch[k] = NAN;
    for (size_t k = floats; k < floats + guard; k++) scratch[k] = 12345.0f;
    memcpy(y, p->x, nx * sizeof(float));
    const line_batch batch = {p->n, p->ch, p->beta, p->gamma, y, scratch, iterations, 0,
                              LINE_RUNNING_BY_BATCH};
    s->solve(&batch);
    int guard_ok = 1;
    for (size_t k = floats; k < floats + guard; k++) guard_ok &= scratch[k] == 12345.0f;
    CHECK_MSG(guard_ok, "%s wrote past scratch_floats(%u, %u)", s->name, p->n, p->ch);
    free(scratch);
    return y;
}

/* max |y - ref| / max |x| over each line (a lane, all channels), worst line. Only unknowns
 * with mask[i * L + l] set count (all if mask is NULL). NaN counts as infinitely wrong. */
static double line_error(const problem *p, const float *y, const double *ref,
                         const unsigned char *mask)
{
    double worst = 0;
    for (int l = 0; l < L; l++) {
        double scale = 0, err = 0;
        for (uint32_t i = 0; i < p->n; i++)
            for (uint32_t c = 0; c < p->ch; c++) {
                scale = fmax(scale, fabs(AT(p, p->x, i, l, c)));
                if (mask && !mask[i * L + l]) continue;
                const double e = fabs((double)AT(p, y, i, l, c) - AT(p, ref, i, l, c));
                err = e == e ? fmax(err, e) : INFINITY;
            }
        worst = fmax(worst, scale > 0 ? err / scale : err);
    }
    return worst;
}

/* ---------------------------------------------------------------------------------------------
 * Tests. */

static void test_names(void)
{
    CHECK(strcmp(ddof_solver_thomas.name, "thomas") == 0);
    CHECK(strcmp(ddof_solver_cr.name, "cr") == 0);
    CHECK(strcmp(ddof_solver_pcr.name, "pcr") == 0);
    CHECK(strcmp(ddof_solver_jacobi.name, "jacobi") == 0);
}

/* The banded reference agrees with the dense one. */
static void test_reference(void)
{
    test_rng rng = {0x5eed0001ULL};
    const uint32_t sizes[] = {1, 2, 3, 5, 17, 64};
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
        problem p = problem_random(&rng, sizes[k], 2, 1e-3, 1e8, 0.05);
        const size_t count = (size_t)p.n * L * p.ch;
        double *band = reference(&p), *dense = xcalloc(count, sizeof(double));
        for (int l = 0; l < L; l++) reference_dense_lane(&p, l, dense);
        double err = 0;
        for (size_t j = 0; j < count; j++) err = fmax(err, fabs(band[j] - dense[j]));
        CHECK_MSG(err <= 1e-12, "n %u: banded vs dense reference %.3g", p.n, err);
        free(band);
        free(dense);
        problem_free(&p);
    }
}

/* Every exact solver on one problem against its reference; tracks the worst error. */
static void compare_exact(const problem *p, const double *ref, const char *what, double *worst)
{
    for (int s = 0; s < EXACT; s++) {
        float *y = run_solver(exact_solvers[s], p, 1);
        const double err = line_error(p, y, ref, NULL);
        CHECK_MSG(err <= exact_tolerance, "%s, n %u, %u channels, %s: error %.3g",
                  exact_solvers[s]->name, p->n, p->ch, what, err);
        worst[s] = fmax(worst[s], err);
        free(y);
    }
}

static void print_worst(const char *what, const double *worst)
{
    if (verbose)
        for (int s = 0; s < EXACT; s++)
            printf("  %-7s %-15s max |y - ref| / max |x| = %.3g\n", exact_solvers[s]->name, what,
                   worst[s]);
}

/* Random systems, three ranges of beta, every size and channel count. */
static void test_exact_random(void)
{
    const struct { const char *name; double lo, hi, pzero; } ranges[] = {
        {"beta 1e-3..1e8", 1e-3, 1e8, 0.05},
        {"beta 1e6..1e8", 1e6, 1e8, 0.002},
        {"beta 1e-3..1", 1e-3, 1.0, 0.05},
    };
    const uint32_t sizes[] = {1, 2, 3, 4, 5, 7, 8, 255, 256, 257, 1920, 4097};
    const size_t nsizes = sizeof sizes / sizeof sizes[0] - (test_quick() ? 2 : 0);
    test_rng rng = {0x5eed0002ULL};
    for (size_t r = 0; r < sizeof ranges / sizeof ranges[0]; r++) {
        double worst[EXACT] = {0};
        for (size_t k = 0; k < nsizes; k++)
            for (uint32_t ch = 1; ch <= 4; ch++) {
                problem p = problem_random(&rng, sizes[k], ch, ranges[r].lo, ranges[r].hi,
                                           ranges[r].pzero);
                double *ref = reference(&p);
                compare_exact(&p, ref, ranges[r].name, worst);
                free(ref);
                problem_free(&p);
            }
        print_worst(ranges[r].name, worst);
    }
}

/* gamma = 0 on a third of the pixels; every run of beta-linked pixels keeps one gamma > 0, so
 * the system stays regular and must still match the reference. */
static void test_gamma_zero(void)
{
    test_rng rng = {0x5eed0003ULL};
    const uint32_t sizes[] = {1, 2, 3, 8, 257, 1920};
    const size_t nsizes = sizeof sizes / sizeof sizes[0] - (test_quick() ? 1 : 0);
    double worst[EXACT] = {0};
    for (size_t k = 0; k < nsizes; k++)
        for (uint32_t ch = 1; ch <= 4; ch += 3) {
            problem p = problem_random(&rng, sizes[k], ch, 1e-3, 1e8, 0.05);
            for (int l = 0; l < L; l++) {
                uint32_t start = 0; /* of the current run */
                int warm = 0;       /* the run has some gamma > 0 */
                for (uint32_t i = 0; i < p.n; i++) {
                    if (test_uniform(&rng) < 0.35) GAMMA(&p, i, l) = 0.0f;
                    warm |= GAMMA(&p, i, l) > 0.0f;
                    if (BETA(&p, i, l) == 0.0f) {
                        if (!warm) GAMMA(&p, start + (i - start) / 2, l) = 0.5f;
                        start = i + 1;
                        warm = 0;
                    }
                }
            }
            double *ref = reference(&p);
            compare_exact(&p, ref, "gamma partly 0", worst);
            free(ref);
            problem_free(&p);
        }
    print_worst("gamma partly 0", worst);
}

/* A run with gamma = 0 everywhere, cut off by zero betas, is singular: any constant solves it.
 * The output there only has to be finite, and the rest of the line must not notice. */
static void test_singular_runs(void)
{
    test_rng rng = {0x5eed0004ULL};
    const uint32_t sizes[] = {1, 2, 7, 64, 257};
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
        const uint32_t n = sizes[k];
        problem p = problem_random(&rng, n, 3, 1e-3, 1e8, 0.02);
        unsigned char *regular = xcalloc((size_t)n * L, 1);
        memset(regular, 1, (size_t)n * L);
        for (int l = 0; l < L; l++) {
            /* lane 0: the whole line; the others: [lo, hi) and the single pixel hi + 3 */
            const uint32_t lo = l == 0 ? 0 : (uint32_t)(test_uniform(&rng) * n);
            const uint32_t hi = l == 0 ? n : lo + 1 + (uint32_t)(test_uniform(&rng) * (n - lo));
            for (uint32_t i = lo; i < hi; i++) {
                GAMMA(&p, i, l) = 0.0f;
                regular[i * L + l] = 0;
            }
            if (lo > 0) BETA(&p, lo - 1, l) = 0.0f;
            BETA(&p, hi - 1, l) = 0.0f;
            if (hi + 3 < n) {
                GAMMA(&p, hi + 3, l) = 0.0f;
                BETA(&p, hi + 2, l) = BETA(&p, hi + 3, l) = 0.0f;
                regular[(hi + 3) * L + l] = 0;
            }
        }
        /* The reference for the rest: singular runs are independent, any gamma there will do. */
        problem q = problem_new(n, 3);
        memcpy(q.beta, p.beta, (size_t)n * L * sizeof(float));
        memcpy(q.x, p.x, (size_t)n * L * 3 * sizeof(float));
        for (size_t j = 0; j < (size_t)n * L; j++) q.gamma[j] = regular[j] ? p.gamma[j] : 1.0f;
        double *ref = reference(&q);
        for (int s = 0; s <= EXACT; s++) {
            const solver_ops *solver = s < EXACT ? exact_solvers[s] : &ddof_solver_jacobi;
            float *y = run_solver(solver, &p, 10);
            int finite = 1;
            for (size_t j = 0; j < (size_t)n * L * 3; j++) finite &= isfinite(y[j]) != 0;
            CHECK_MSG(finite, "%s, n %u: a singular run gives NaN or Inf", solver->name, n);
            if (s < EXACT) {
                const double err = line_error(&p, y, ref, regular);
                CHECK_MSG(err <= exact_tolerance, "%s, n %u: next to a singular run: error %.3g",
                          solver->name, n, err);
            }
            free(y);
        }
        free(ref);
        free(regular);
        problem_free(&q);
        problem_free(&p);
    }
}

/* Every output within [min, max] of its line's inputs, up to a few ulps. */
static void check_range(const solver_ops *solver, const problem *p, uint32_t sweeps)
{
    float *y = run_solver(solver, p, sweeps);
    int inside = 1;
    for (int l = 0; l < L; l++)
        for (uint32_t c = 0; c < p->ch; c++) {
            float lo = INFINITY, hi = -INFINITY;
            for (uint32_t i = 0; i < p->n; i++) {
                lo = fminf(lo, AT(p, p->x, i, l, c));
                hi = fmaxf(hi, AT(p, p->x, i, l, c));
            }
            const float slack = 4 * FLT_EPSILON * fmaxf(fabsf(lo), fabsf(hi));
            for (uint32_t i = 0; i < p->n; i++) {
                const float v = AT(p, y, i, l, c);
                inside &= v >= lo - slack && v <= hi + slack;
            }
        }
    CHECK_MSG(inside, "%s, n %u, %u channels: output outside the input range", solver->name,
              p->n, p->ch);
    free(y);
}

/* With gamma = 1 (plain diffusion, insulated ends) each line's sum is conserved. */
static void check_conservation(const solver_ops *solver, problem *p)
{
    for (size_t j = 0; j < (size_t)p->n * L; j++) p->gamma[j] = 1.0f;
    float *y = run_solver(solver, p, 1);
    double worst = 0;
    for (int l = 0; l < L; l++)
        for (uint32_t c = 0; c < p->ch; c++) {
            double sx = 0, sy = 0;
            for (uint32_t i = 0; i < p->n; i++) {
                sx += AT(p, p->x, i, l, c);
                sy += AT(p, y, i, l, c);
            }
            worst = fmax(worst, fabs(sy - sx) / fmax(sx, 1e-30));
        }
    CHECK_MSG(worst <= 1e-5, "%s, n %u, %u channels: the sum changes by %.3g", solver->name,
              p->n, p->ch, worst);
    free(y);
}

/* Pixels cut off by zero links on both sides are untouched, bit for bit; then with every link
 * zero, all of them are. */
static void check_insulated(const solver_ops *solver, problem *p, uint32_t sweeps)
{
    for (int l = 0; l < L; l++)
        for (uint32_t i = (uint32_t)l % 5; i < p->n; i += 5) {
            if (i > 0) BETA(p, i - 1, l) = 0.0f;
            BETA(p, i, l) = 0.0f;
        }
    float *y = run_solver(solver, p, sweeps);
    int same = 1;
    for (int l = 0; l < L; l++)
        for (uint32_t i = (uint32_t)l % 5; i < p->n; i += 5)
            for (uint32_t c = 0; c < p->ch; c++) same &= AT(p, y, i, l, c) == AT(p, p->x, i, l, c);
    CHECK_MSG(same, "%s, n %u, %u channels: an isolated pixel changed", solver->name, p->n, p->ch);
    free(y);

    memset(p->beta, 0, (size_t)p->n * L * sizeof(float));
    y = run_solver(solver, p, sweeps);
    CHECK_MSG(memcmp(y, p->x, (size_t)p->n * L * p->ch * sizeof(float)) == 0,
              "%s, n %u, %u channels: beta = 0 changes x", solver->name, p->n, p->ch);
    free(y);
}

/* Properties of the exact solve that every solver keeps (Jacobi too, except conservation). */
static void test_invariants(void)
{
    test_rng rng = {0x5eed0005ULL};
    const uint32_t sizes[] = {1, 2, 5, 64, 255, 1920};
    const size_t nsizes = sizeof sizes / sizeof sizes[0] - (test_quick() ? 1 : 0);
    const solver_ops *const solvers[] = {&ddof_solver_thomas, &ddof_solver_cr, &ddof_solver_pcr,
                                         &ddof_solver_jacobi};
    for (size_t k = 0; k < nsizes; k++)
        for (uint32_t ch = 1; ch <= 4; ch++)
            for (int s = 0; s < 4; s++) {
                problem p = problem_random(&rng, sizes[k], ch, 1e-3, 1e8, 0.05);
                check_range(solvers[s], &p, 30);
                check_insulated(solvers[s], &p, 30);
                problem_free(&p);
                if (s < EXACT) {
                    p = problem_random(&rng, sizes[k], ch, 1e-3, 1e8, 0.05);
                    check_conservation(solvers[s], &p);
                    problem_free(&p);
                }
            }
}

/* Jacobi approaches the exact solution as sweeps are added, and reaches it on a weakly linked
 * line. */
static void test_jacobi_convergence(void)
{
    test_rng rng = {0x5eed0006ULL};
    const uint32_t sweeps[] = {1, 10, 50, 200, 1000};
    problem p = problem_random(&rng, 512, 2, 50.0, 200.0, 0.0); /* moderately conductive */
    double *ref = reference(&p), err[5];
    for (int k = 0; k < 5; k++) {
        float *y = run_solver(&ddof_solver_jacobi, &p, sweeps[k]);
        err[k] = line_error(&p, y, ref, NULL);
        free(y);
        if (k > 0)
            CHECK_MSG(err[k] < err[k - 1], "jacobi error %.3g after %u sweeps, %.3g after %u",
                      err[k], sweeps[k], err[k - 1], sweeps[k - 1]);
    }
    if (verbose)
        printf("  jacobi  beta 50..200     error after 1/10/50/200/1000 sweeps:"
               " %.3g %.3g %.3g %.3g %.3g\n", err[0], err[1], err[2], err[3], err[4]);
    free(ref);
    problem_free(&p);

    /* Each sweep shrinks the error by at least 2 / 2.1 here; measured 1.5e-7 after 1000. */
    p = problem_random(&rng, 257, 4, 1e-3, 1.0, 0.05);
    ref = reference(&p);
    float *y = run_solver(&ddof_solver_jacobi, &p, 1000);
    const double e = line_error(&p, y, ref, NULL);
    CHECK_MSG(e <= 2e-6, "jacobi, weak links, 1000 sweeps: error %.3g", e);
    if (verbose) printf("  jacobi  beta 1e-3..1     error after 1000 sweeps: %.3g\n", e);
    free(y);
    free(ref);
    problem_free(&p);
}

int main(void)
{
    const char *v = getenv("DDOF_TEST_VERBOSE");
    verbose = v && v[0] == '1';
    test_names();
    test_reference();
    test_exact_random();
    test_gamma_zero();
    test_singular_runs();
    test_invariants();
    test_jacobi_convergence();
    return test_report("test_solvers");
}
