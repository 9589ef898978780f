/* SPDX-License-Identifier: MIT */
/* test_util.h - the few assertion helpers the unit tests share.
 *
 * Every CHECK counts; a failing one prints file:line and what was compared, and the test keeps
 * going so one run shows every failure. main() ends with `return test_report("name");`. */
#ifndef DDOF_TEST_UTIL_H
#define DDOF_TEST_UTIL_H

#include "ddof.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static int test_checks_run;
static int test_checks_failed;

#define CHECK(cond)                                                                        \
    do {                                                                                   \
        test_checks_run++;                                                                 \
        if (!(cond)) {                                                                     \
            test_checks_failed++;                                                          \
            fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond);       \
        }                                                                                  \
    } while (0)

#define CHECK_MSG(cond, ...)                                                               \
    do {                                                                                   \
        test_checks_run++;                                                                 \
        if (!(cond)) {                                                                     \
            test_checks_failed++;                                                          \
            fprintf(stderr, "%s:%d: CHECK failed: %s: ", __FILE__, __LINE__, #cond);       \
            fprintf(stderr, __VA_ARGS__);                                                  \
            fputc('\n', stderr);                                                           \
        }                                                                                  \
    } while (0)

#define CHECK_EQ_INT(a, b) CHECK_MSG((long long)(a) == (long long)(b), "%lld != %lld",     \
                                     (long long)(a), (long long)(b))

/* |a - b| <= tol */
#define CHECK_NEAR(a, b, tol) CHECK_MSG(fabs((double)(a) - (double)(b)) <= (double)(tol),  \
                                        "%.9g vs %.9g (|diff| %.3g > %.3g)", (double)(a),   \
                                        (double)(b), fabs((double)(a) - (double)(b)),       \
                                        (double)(tol))

static inline int test_report(const char *name)
{
    printf("%s: %d checks, %d failed\n", name, test_checks_run, test_checks_failed);
    return test_checks_failed ? 1 : 0;
}

/* Small deterministic PRNG (xorshift64*), so tests are reproducible everywhere. */
typedef struct test_rng { unsigned long long state; } test_rng;

static inline double test_uniform(test_rng *rng)
{
    rng->state ^= rng->state >> 12;
    rng->state ^= rng->state << 25;
    rng->state ^= rng->state >> 27;
    return (double)((rng->state * 2685821657736338717ULL) >> 11) * (1.0 / 9007199254740992.0);
}

/* The solvers the CPU backend runs: every ddof_solver before the GL-only Gruen solver. */
#define TEST_CPU_SOLVER_COUNT ((int)DDOF_SOLVER_GRUEN)

/* The default preset with the heat kernel, without the far field's gather and the
 * silhouettes' split: for the tests of the real diffusion's properties (convex combinations,
 * the solvers, the layers' heat behaviour), which the default disc kernel does not share, the
 * gather replaces away from depth edges and the split changes at in-focus silhouettes.
 * test_disc_kernel.c tests the disc, test_far_field.c the gather, test_silhouettes.c the
 * split. */
static inline void heat_params_init(ddof_params *params)
{
    ddof_params_init(params);
    params->kernel = DDOF_KERNEL_HEAT;
    params->far_field = DDOF_LAYER_OFF;
    params->silhouettes = DDOF_LAYER_OFF;
}

/* DDOF_TEST_QUICK=1 (set for the valgrind run) shrinks the largest cases. */
static inline int test_quick(void)
{
    const char *q = getenv("DDOF_TEST_QUICK");
    return q && q[0] && q[0] != '0';
}

#endif
