/* SPDX-License-Identifier: MIT */
/* test_gl_layers.c - the layers of ddof_diffuse_layers with their diffusions on the GPU: the
 * background layer (forced on: heat capacity = matte, CoC filled into the holes, singular
 * runs where no background reaches), the near-field spread (signed CoC), and a foreground
 * element (gamma = its alpha, CoC filled outwards). Each against the same call with the
 * double-precision reference solver, which always runs on the CPU, while every GPU solver runs
 * the whole frame on the device (run_layers: mattes, blends and dilations too; test_gl_frame
 * compares it with the CPU's Thomas frame). Argument: "osmesa" or "egl".
 * DDOF_TEST_VERBOSE=1 prints the measured errors. */
#include "gl_test.h"

/* Float GPU solvers through every layer: measured <= 6e-7 on llvmpipe. */
#define TOL_FLOAT 1e-5
/* Gruen PACKED_HALF: half-float levels, measured <= 1.2e-3. */
#define TOL_PACKED 4e-3

enum { W = 67, H = 45, CH = 4 };

static ddof_context *ctx;
static int verbose;

static void scene(float *color, float *coc, int signed_near)
{
    test_rng rng = {7};
    fill_uniform(color, (size_t)W * H * CH, &rng, 0.05, 0.9);
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            float d = 24.0f; /* far background */
            if (x % 16 < 2)
                d = 0.0f; /* thin in-focus bars */
            const float dx = (float)x - 45.0f, dy = (float)y - 20.0f;
            if (dx * dx + dy * dy < 64.0f)
                d = signed_near ? -30.0f : 30.0f; /* a near disc */
            coc[(size_t)y * W + x] = d;
        }
}

static void compare(const char *name, ddof_params p, const float *color, const float *coc,
                    const ddof_foreground *fg, uint32_t expect_effect)
{
    float *ref = alloc_f((size_t)W * H * CH), *out = alloc_f((size_t)W * H * CH);
    p.solver = DDOF_SOLVER_REFERENCE_F64;
    ddof_stats st = stats_init();
    ddof_status s = diffuse_layers(ctx, &p, color, coc, fg, ref, W, H, CH, &st);
    CHECK_MSG(s == DDOF_OK, "%s: reference %d (%s)", name, (int)s, ddof_context_last_error(ctx));
    CHECK_MSG(st.effects & expect_effect, "%s: effect %u did not run (%s)", name, expect_effect,
              st.plan);
    static const struct {
        const char *name;
        ddof_solver solver;
        ddof_precision precision;
        double tol;
    } solvers[] = {{"thomas", DDOF_SOLVER_THOMAS, DDOF_PRECISION_FLOAT, TOL_FLOAT},
                   {"cr", DDOF_SOLVER_CYCLIC_REDUCTION, DDOF_PRECISION_FLOAT, TOL_FLOAT},
                   {"pcr", DDOF_SOLVER_PCR, DDOF_PRECISION_FLOAT, TOL_FLOAT},
                   {"gruen", DDOF_SOLVER_GRUEN, DDOF_PRECISION_FLOAT, TOL_FLOAT},
                   {"gruen-packed", DDOF_SOLVER_GRUEN, DDOF_PRECISION_PACKED_HALF, TOL_PACKED}};
    for (size_t k = 0; k < sizeof solvers / sizeof *solvers; k++) {
        p.solver = solvers[k].solver;
        p.precision = solvers[k].precision;
        st = stats_init();
        s = diffuse_layers(ctx, &p, color, coc, fg, out, W, H, CH, &st);
        CHECK_MSG(s == DDOF_OK, "%s/%s: %d (%s)", name, solvers[k].name, (int)s,
                  ddof_context_last_error(ctx));
        const double e = max_diff(out, ref, (size_t)W * H * CH);
        if (verbose)
            printf("  %-22s %-13s max error %.3g\n", name, solvers[k].name, e);
        CHECK_MSG(e <= solvers[k].tol, "%s/%s: max error %.3g > %.3g", name, solvers[k].name, e,
                  solvers[k].tol);
        CHECK_MSG(st.device_bytes > 0, "%s/%s: nothing ran on the device", name,
                  solvers[k].name);
    }
    free(ref);
    free(out);
}

int main(int argc, char **argv)
{
    verbose = verbose_test();
    ctx = gl_context_for(backend_from_name(argc > 1 ? argv[1] : NULL));
    if (!ctx)
        return GL_TEST_SKIP;
    float *color = alloc_f((size_t)W * H * CH), *coc = alloc_f((size_t)W * H);

    ddof_params p;
    heat_params_init(&p);
    scene(color, coc, 0);
    p.background = DDOF_LAYER_ON;
    p.near_spread = DDOF_LAYER_OFF;
    compare("background on", p, color, coc, NULL, DDOF_EFFECT_BACKGROUND);
    p.background_levels = 2;
    p.substeps = 2;
    compare("background 2 levels x2", p, color, coc, NULL, DDOF_EFFECT_BACKGROUND);

    heat_params_init(&p);
    scene(color, coc, 1);
    p.coc_signed = 1;
    p.near_spread = DDOF_LAYER_ON;
    compare("near spread", p, color, coc, NULL, DDOF_EFFECT_NEAR_SPREAD);

    /* A foreground element: a premultiplied disc with soft alpha, NaN colour where alpha = 0. */
    float *fg_color = alloc_f((size_t)W * H * 4), *fg_coc = alloc_f((size_t)W * H);
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            const float dx = (float)x - 20.0f, dy = (float)y - 25.0f;
            const float r = sqrtf(dx * dx + dy * dy);
            const float a = r < 6.0f ? 1.0f : r < 9.0f ? (9.0f - r) / 3.0f : 0.0f;
            float *px = fg_color + ((size_t)y * W + x) * 4;
            px[0] = a > 0 ? 0.9f * a : NAN;
            px[1] = a > 0 ? 0.3f * a : NAN;
            px[2] = a > 0 ? 0.1f * a : NAN;
            px[3] = a;
            fg_coc[(size_t)y * W + x] = 18.0f;
        }
    ddof_foreground fg;
    ddof_foreground_init(&fg);
    fg.color = (ddof_image_in){fg_color, W, H, 4, 0};
    fg.coc = (ddof_image_in){fg_coc, W, H, 1, 0};
    heat_params_init(&p);
    scene(color, coc, 0);
    p.background = DDOF_LAYER_ON;
    compare("foreground element", p, color, coc, &fg, DDOF_EFFECT_FOREGROUND);

    free(fg_color);
    free(fg_coc);
    free(color);
    free(coc);
    ddof_context_free(ctx);
    return test_report("test_gl_layers");
}
