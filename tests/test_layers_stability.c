/* SPDX-License-Identifier: MIT */
/* test_layers_stability.c - every layer stays numerically stable on the hard cases: gamma exactly
 * 0 over whole lines, alpha 0/1 checkerboards, one blurred pixel, CoC 10,000 px, NaN where
 * alpha is 0; with and without a foreground element. */
#include "layers_test.h"

enum { F_CROSS, F_CHECKER1, F_CHECKER2, F_ONE_PIXEL, F_HUGE_BARS, F_HUGE_CHECKER, F_RANDOM,
       F_COUNT };
static const char *field_names[F_COUNT] = {"in-focus row+column", "checker 1px", "checker 2x2",
                                           "one blurred pixel", "CoC 10000 + bars",
                                           "CoC 10000 checker 2x2", "random 30% zeros"};

static void make_field(int f, float *coc)
{
    test_rng rng = {77};
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            float v = 0;
            switch (f) {
            case F_CROSS: v = (y == H / 2 || x == W / 2) ? 0.0f : 20.0f; break;
            case F_CHECKER1: v = ((x + y) & 1) ? 20.0f : 0.0f; break;
            case F_CHECKER2: v = (((x / 2) + (y / 2)) & 1) ? 20.0f : 0.0f; break;
            case F_ONE_PIXEL: v = (x == W / 3 && y == H / 3) ? 20.0f : 0.0f; break;
            case F_HUGE_BARS: v = (is_bar(x) || y == H / 2) ? 0.0f : 10000.0f; break;
            case F_HUGE_CHECKER: v = (((x / 2) + (y / 2)) & 1) ? 10000.0f : 0.0f; break;
            case F_RANDOM:
                v = test_uniform(&rng) < 0.3 ? 0.0f : (float)(40.0 * test_uniform(&rng));
                break;
            }
            coc[(size_t)y * W + x] = v;
        }
}

static void test_stability(void)
{
    const size_t npx = (size_t)W * H, n = npx * CH;
    float *color = alloc_f(n), *coc = alloc_f(npx), *scoc = alloc_f(npx), *out = alloc_f(n);
    float lo[CH], hi[CH];
    noise(color, CH, 41);
    channel_range(color, CH, lo, hi);
    const double tol = 1e-5;
    size_t runs = 0;
    for (int f = 0; f < F_COUNT; f++) {
        make_field(f, coc);
        for (size_t s = 0; s < N_SOLVERS; s++) {
            for (int mode = 0; mode < 2; mode++) {
                for (uint32_t levels = 1; levels <= 4; levels++) {
                    ddof_params p;
                    heat_params_init(&p);
                    p.solver = all_solvers[s];
                    p.background = mode ? DDOF_LAYER_ON : DDOF_LAYER_AUTO;
                    p.background_levels = levels;
                    fill_const(out, n, NAN);
                    ddof_stats st;
                    ddof_status status = layers(&p, color, coc, NULL, out, CH, &st);
                    runs++;
                    CHECK_MSG(status == DDOF_OK, "%s, %s, bg %s, %u levels: status %d (%s)",
                              field_names[f], ddof_solver_name(p.solver), mode ? "on" : "auto",
                              levels, (int)status, ddof_context_last_error(ctx));
                    double worst;
                    size_t bad = out_of_range(out, CH, lo, hi, tol, &worst);
                    CHECK_MSG(bad == 0,
                              "%s, %s, bg %s, %u levels: %zu values non-finite or out of the "
                              "input range (worst by %g)",
                              field_names[f], ddof_solver_name(p.solver), mode ? "on" : "auto",
                              levels, bad, worst);
                    if (mode)
                        CHECK(st.effects & DDOF_EFFECT_BACKGROUND);
                    /* In-focus pixels keep their input exactly (matte 0). */
                    size_t changed = 0;
                    for (size_t i = 0; i < npx; i++)
                        if (coc[i] == 0.0f &&
                            memcmp(&out[i * CH], &color[i * CH], CH * sizeof(float)))
                            changed++;
                    CHECK_MSG(changed == 0, "%s, %s, bg %s, %u levels: %zu in-focus pixels changed",
                              field_names[f], ddof_solver_name(p.solver), mode ? "on" : "auto",
                              levels, changed);
                }
            }
            /* Signed: the left half of the field near (negative), the near spread AUTO and ON. */
            for (size_t i = 0; i < npx; i++)
                scoc[i] = (i % W) < W / 2 ? -coc[i] : coc[i];
            for (int mode = 0; mode < 2; mode++) {
                ddof_params p;
                heat_params_init(&p);
                p.solver = all_solvers[s];
                p.coc_signed = 1;
                p.near_spread = mode ? DDOF_LAYER_ON : DDOF_LAYER_AUTO;
                p.background = mode ? DDOF_LAYER_ON : DDOF_LAYER_AUTO;
                /* A near pixel brighter than the threshold is a light, drawn over what lies
                 * behind it (test_highlights): added light leaves the input's range by design
                 * (the one blurred pixel of the 64x48 frame is one). */
                p.highlights = DDOF_LAYER_OFF;
                fill_const(out, n, NAN);
                ddof_stats st;
                ddof_status status = layers(&p, color, scoc, NULL, out, CH, &st);
                runs++;
                CHECK_MSG(status == DDOF_OK, "%s signed, %s, %s: status %d (%s)", field_names[f],
                          ddof_solver_name(p.solver), mode ? "on" : "auto", (int)status,
                          ddof_context_last_error(ctx));
                double worst;
                size_t bad = out_of_range(out, CH, lo, hi, tol, &worst);
                CHECK_MSG(bad == 0, "%s signed, %s, %s: %zu values bad (worst by %g)",
                          field_names[f], ddof_solver_name(p.solver), mode ? "on" : "auto", bad,
                          worst);
                if (mode)
                    CHECK(st.effects & DDOF_EFFECT_NEAR_SPREAD);
            }
        }
    }
    if (verbose)
        printf("stability: %zu runs\n", runs);

    /* One channel too (the background layer on a grey image). */
    {
        float *g = alloc_f(npx), *go = alloc_f(npx);
        float glo[1], ghi[1];
        for (size_t i = 0; i < npx; i++)
            g[i] = color[i * CH];
        channel_range(g, 1, glo, ghi);
        make_field(F_CROSS, coc);
        ddof_params p;
        heat_params_init(&p);
        p.background = DDOF_LAYER_ON;
        CHECK_EQ_INT(layers(&p, g, coc, NULL, go, 1, NULL), DDOF_OK);
        double worst;
        CHECK_MSG(out_of_range(go, 1, glo, ghi, tol, &worst) == 0, "grey: worst %g", worst);
        free(g);
        free(go);
    }
    free(color);
    free(coc);
    free(scoc);
    free(out);
}

/* The composite with hard foreground alphas: premultiplied alpha in [0, 1], colour within the
 * range of the main image and the element's (straight) colour, for every solver. */
static void test_foreground_stability(void)
{
    const size_t npx = (size_t)W * H, n = npx * CH;
    float *color = alloc_f(n), *coc = alloc_f(npx), *out = alloc_f(n);
    float *fgc = alloc_f(npx * 4), *fgz = alloc_f(npx);
    float lo[CH], hi[CH];
    noise(color, CH, 51); /* main alpha in [0.35, 0.85] */
    channel_range(color, CH, lo, hi);
    /* Element straight colour in [0.05, 0.95]: the composite colour lies within
     * [min(main, 0.05), max(main, 0.95)]; its alpha within [min main alpha, 1]. */
    float clo[CH], chi[CH];
    for (uint32_t c = 0; c < 3; c++) {
        clo[c] = fminf(lo[c], 0.05f);
        chi[c] = fmaxf(hi[c], 0.95f);
    }
    clo[3] = lo[3];
    chi[3] = 1.0f;
    test_rng rng = {52};
    for (size_t i = 0; i < npx; i++)
        coc[i] = test_uniform(&rng) < 0.3 ? 0.0f : (float)(30.0 * test_uniform(&rng));
    static const char *alpha_names[] = {"checker 1px", "checker 2x2", "one pixel", "all 1",
                                        "random", "half"};
    static const float fg_cocs[] = {20.0f, 10000.0f};
    for (int a_kind = 0; a_kind < 6; a_kind++) {
        for (int zi = 0; zi < 2; zi++) {
            for (uint32_t y = 0; y < H; y++)
                for (uint32_t x = 0; x < W; x++) {
                    size_t i = (size_t)y * W + x;
                    float a = 0;
                    switch (a_kind) {
                    case 0: a = (float)((x + y) & 1); break;
                    case 1: a = (float)(((x / 2) + (y / 2)) & 1); break;
                    case 2: a = (x == W / 2 && y == H / 2) ? 1.0f : 0.0f; break;
                    case 3: a = 1.0f; break;
                    case 4: a = (float)test_uniform(&rng); break;
                    case 5: a = x < W / 2 ? 1.0f : 0.0f; break;
                    }
                    for (uint32_t c = 0; c < 3; c++)
                        fgc[i * 4 + c] = a > 0 ? a * (float)(0.05 + 0.9 * test_uniform(&rng))
                                               : NAN;
                    fgc[i * 4 + 3] = a;
                    fgz[i] = fg_cocs[zi];
                }
            ddof_foreground fg = make_fg(fgc, fgz, 1);
            for (size_t s = 0; s < N_SOLVERS; s++) {
                ddof_params p;
                heat_params_init(&p);
                p.solver = all_solvers[s];
                fill_const(out, n, NAN);
                ddof_stats st;
                ddof_status status = layers(&p, color, coc, &fg, out, CH, &st);
                CHECK_MSG(status == DDOF_OK, "element alpha %s, CoC %g, %s: status %d (%s)",
                          alpha_names[a_kind], (double)fg_cocs[zi], ddof_solver_name(p.solver),
                          (int)status, ddof_context_last_error(ctx));
                CHECK(st.effects & DDOF_EFFECT_FOREGROUND);
                double worst;
                size_t bad = out_of_range(out, CH, clo, chi, 1e-5, &worst);
                CHECK_MSG(bad == 0,
                          "element alpha %s, CoC %g, %s: %zu values non-finite or out of range "
                          "(worst by %g)",
                          alpha_names[a_kind], (double)fg_cocs[zi], ddof_solver_name(p.solver),
                          bad, worst);
            }
        }
    }
    free(color);
    free(coc);
    free(out);
    free(fgc);
    free(fgz);
}

int main(void)
{
    layers_test_begin();
    test_stability();
    test_foreground_stability();
    return layers_test_end("test_layers_stability");
}
