/* SPDX-License-Identifier: MIT */
/* test_layers_errors.c - each layer of ddof_diffuse_layers improves a measured error against a
 * reference for the scene it is made for: the background layer on bars over a blurred
 * background (and only within the reach of in-focus pixels), the near spread and the
 * foreground element on a near blurred object over a sharp background; a small element, and
 * the element's premultiplied and straight forms. References and readings: layers_test.h. */
#include "layers_test.h"

/* ---------------------------------------------------------------------------------------- */
/* Bars over a blurred background                                                           */

/* Band RMSE measured (Thomas): 160x120 vertical bars single 0.0292, background 0.0115 (2.54x),
 * horizontal 0.0319 / 0.0125 (2.56x); 64x48 (DDOF_TEST_QUICK): 2.65x and 2.96x. */
#define BARS_MIN_GAIN 2.0

static void test_bars_error(int horizontal)
{
    bars_horizontal = horizontal;
    const char *orient = horizontal ? "horizontal" : "vertical";
    const size_t npx = (size_t)W * H, n = npx * CH;
    float *bg = alloc_f(n), *img = alloc_f(n), *coc = alloc_f(npx), *flat = alloc_f(npx);
    float *ref = alloc_f(n), *one = alloc_f(n), *lay = alloc_f(n), *tmp = alloc_f(n);
    unsigned char *band = calloc(npx, 1), *nonbar = calloc(npx, 1);
    texture(bg, CH, 11);
    memcpy(img, bg, n * sizeof(float));
    paste_bars(img);
    bars_coc(coc, 20.0f);
    fill_const(flat, npx, 20.0f);

    ddof_params pref;
    heat_params_init(&pref);
    pref.solver = DDOF_SOLVER_REFERENCE_F64;
    CHECK_EQ_INT(single(&pref, bg, flat, ref, CH), DDOF_OK);
    paste_bars(ref);

    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            if (is_bar_xy(x, y))
                continue;
            nonbar[(size_t)y * W + x] = 1;
            for (long d = -4; d <= 4; d++)
                if (horizontal ? is_bar_xy(x, (long)y + d) : is_bar_xy((long)x + d, y))
                    band[(size_t)y * W + x] = 1;
        }

    ddof_params p;
    heat_params_init(&p);
    CHECK_EQ_INT(single(&p, img, coc, one, CH), DDOF_OK);
    p.background = DDOF_LAYER_ON;
    ddof_stats st;
    CHECK_EQ_INT(layers(&p, img, coc, NULL, lay, CH, &st), DDOF_OK);
    CHECK(st.effects & DDOF_EFFECT_BACKGROUND);

    double e1 = rmse_rgb(one, ref, band, CH), el = rmse_rgb(lay, ref, band, CH);
    double e1all = rmse_rgb(one, ref, nonbar, CH), elall = rmse_rgb(lay, ref, nonbar, CH);
    printf("%s bars, band of 4 px: RMSE single layer %.5f, background layer %.5f (%.2fx)\n",
           orient, e1, el, el > 0 ? e1 / el : INFINITY);
    printf("%s bars, all non-bar pixels: RMSE single %.5f, background %.5f\n", orient, e1all,
           elall);
    CHECK_MSG(el * BARS_MIN_GAIN <= e1, "%s bars: background layer RMSE %.5f, single %.5f",
              orient, el, e1);
    CHECK_MSG(elall < e1all, "%s bars, all pixels: background %.5f, single %.5f", orient, elall,
              e1all);
    CHECK(all_finite(lay, n));

    /* The bars (CoC 0, matte 0) are exactly the input. */
    size_t changed = 0;
    for (size_t i = 0; i < npx; i++)
        if (coc[i] == 0.0f && memcmp(&lay[i * CH], &img[i * CH], CH * sizeof(float)))
            changed++;
    CHECK_MSG(changed == 0, "%s bars: %zu in-focus pixels changed by the background layer",
              orient, changed);

    /* AUTO picks the same. */
    p.background = DDOF_LAYER_AUTO;
    CHECK_EQ_INT(layers(&p, img, coc, NULL, tmp, CH, NULL), DDOF_OK);
    CHECK_MSG(max_abs_diff_ff(tmp, lay, n) <= 1e-6, "bars: AUTO vs ON differ by %g", max_abs_diff_ff(tmp, lay, n));

    /* More levels: still better than the single layer (levels above the scene's CoC 20 give
     * CoC-20 pixels a partial matte; the error measured grows with them, printed). */
    for (uint32_t levels = 2; levels <= 4; levels++) {
        p.background_levels = levels;
        CHECK_EQ_INT(layers(&p, img, coc, NULL, tmp, CH, NULL), DDOF_OK);
        double e = rmse_rgb(tmp, ref, band, CH);
        printf("%s bars, %u levels: band RMSE %.5f\n", orient, levels, e);
        CHECK_MSG(e < e1, "%s bars, %u levels: %.5f vs single %.5f", orient, levels, e, e1);
    }
    p.background_levels = 1;

    /* Every exact solver gives the same layered answer; Jacobi is still better than single. */
    for (size_t s = 0; s < N_SOLVERS; s++) {
        p.solver = all_solvers[s];
        CHECK_EQ_INT(layers(&p, img, coc, NULL, tmp, CH, NULL), DDOF_OK);
        double d = max_abs_diff_ff(tmp, lay, n), e = rmse_rgb(tmp, ref, band, CH);
        printf("%s bars, solver %s: max diff to thomas %.3g, band RMSE %.5f\n", orient,
               ddof_solver_name(all_solvers[s]), d, e);
        if (all_solvers[s] != DDOF_SOLVER_JACOBI)
            CHECK_MSG(d <= 1e-4, "%s bars, solver %s vs thomas: %g", orient,
                      ddof_solver_name(p.solver), d);
        /* Jacobi is approximate by design (50 sweeps): only better than the single layer. */
        const double gain = all_solvers[s] == DDOF_SOLVER_JACOBI ? 1.0 : BARS_MIN_GAIN;
        CHECK_MSG(e * gain <= e1 && e < e1, "%s bars, solver %s: band RMSE %.5f vs single %.5f",
                  orient, ddof_solver_name(p.solver), e, e1);
    }
    p.solver = DDOF_SOLVER_THOMAS;

    /* In place (out == colour) gives the same. */
    memcpy(tmp, img, n * sizeof(float));
    {
        ddof_image_in ci = {tmp, W, H, CH, 0};
        ddof_image_in zi = {coc, W, H, 1, 0};
        ddof_image oi = {tmp, W, H, CH, 0};
        CHECK_EQ_INT(ddof_diffuse_layers(ctx, &p, &ci, &zi, NULL, &oi, NULL), DDOF_OK);
        CHECK_MSG(max_abs_diff_ff(tmp, lay, n) <= 1e-6, "%s bars in place: %g", orient,
                  max_abs_diff_ff(tmp, lay, n));
    }

    /* Padded rows, a 2-channel CoC image: the same. */
    {
        const size_t cs = (size_t)W * CH + 8, zs = (size_t)W * 2 + 6, os = (size_t)W * CH + 12;
        float *pc = alloc_f(cs * H), *pz = alloc_f(zs * H), *po = alloc_f(os * H);
        for (uint32_t y = 0; y < H; y++) {
            memcpy(pc + y * cs, img + (size_t)y * W * CH, (size_t)W * CH * sizeof(float));
            for (uint32_t x = 0; x < W; x++) {
                pz[y * zs + 2 * x] = coc[(size_t)y * W + x];
                pz[y * zs + 2 * x + 1] = NAN; /* not read */
            }
        }
        ddof_image_in ci = {pc, W, H, CH, cs * sizeof(float)};
        ddof_image_in zi = {pz, W, H, 2, zs * sizeof(float)};
        ddof_image oi = {po, W, H, CH, os * sizeof(float)};
        CHECK_EQ_INT(ddof_diffuse_layers(ctx, &p, &ci, &zi, NULL, &oi, NULL), DDOF_OK);
        double d = 0;
        for (uint32_t y = 0; y < H; y++)
            d = fmax(d, max_abs_diff_ff(po + y * os, lay + (size_t)y * W * CH, (size_t)W * CH));
        CHECK_MSG(d <= 1e-6, "%s bars, padded layout: %g", orient, d);
        free(pc);
        free(pz);
        free(po);
    }

    free(bg);
    free(img);
    free(coc);
    free(flat);
    free(ref);
    free(one);
    free(lay);
    free(tmp);
    free(band);
    free(nonbar);
}

/* The background layer replaces the midground only within the reach of in-focus pixels: a far
 * field (CoC 16) with an in-focus bar at the left and a near light (CoC -16) at the right, far
 * from the bar. With the layer on, pixels more than 16 px (their CoC) from the bar are exactly
 * the midground's, so the light keeps its halo; near the bar the layer does change the image.
 * A layer applied without regard to the reach (its holes include the near field) would
 * replace the light's halo (value 30) with a background that lacks it: 3.8 max difference. */
static void test_background_reach(void)
{
    const size_t npx = (size_t)W * H, n = npx * CH;
    float *img = alloc_f(n), *coc = alloc_f(npx), *on = alloc_f(n), *off = alloc_f(n);
    const uint32_t bar0 = W / 8, bar1 = W / 8 + 3, lx = bar1 + 40, ly = H / 2;
    texture(img, CH, 77);
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            const size_t i = (size_t)y * W + x;
            const int light = x + 2 >= lx && x <= lx + 2 && y + 2 >= ly && y <= ly + 2;
            coc[i] = x >= bar0 && x <= bar1 ? 0.0f : light ? -16.0f : 16.0f;
            if (light)
                for (uint32_t c = 0; c < CH; c++)
                    img[i * CH + c] = 30.0f;
        }
    ddof_params p;
    heat_params_init(&p);
    p.coc_signed = 1;
    p.near_spread = DDOF_LAYER_OFF;
    ddof_stats st;
    p.background = DDOF_LAYER_ON;
    CHECK_EQ_INT(layers(&p, img, coc, NULL, on, CH, &st), DDOF_OK);
    CHECK(st.effects & DDOF_EFFECT_BACKGROUND);
    p.background = DDOF_LAYER_OFF;
    CHECK_EQ_INT(layers(&p, img, coc, NULL, off, CH, &st), DDOF_OK);
    double far_diff = 0.0, near_diff = 0.0;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            const uint32_t dx = x < bar0 ? bar0 - x : x > bar1 ? x - bar1 : 0;
            for (uint32_t c = 0; c < CH; c++) {
                const size_t i = ((size_t)y * W + x) * CH + c;
                const double d = fabs((double)on[i] - off[i]);
                if (dx > 16)
                    far_diff = fmax(far_diff, d);
                else if (dx >= 1 && dx <= 4)
                    near_diff = fmax(near_diff, d);
            }
        }
    if (verbose)
        printf("background reach: max |on - off| beyond the reach %.3g, beside the bar %.3g\n",
               far_diff, near_diff);
    CHECK_MSG(far_diff == 0.0, "background layer beyond the in-focus reach: %.3g", far_diff);
    CHECK_MSG(near_diff > 1e-3, "background layer did nothing beside the bar: %.3g", near_diff);
    free(img);
    free(coc);
    free(on);
    free(off);
}

/* ---------------------------------------------------------------------------------------- */
/* A near blurred object over a sharp background                                            */

static const float obj_rgb[3] = {0.95f, 0.85f, 0.1f};

/* Band RMSE measured: 160x120 single layer 0.128, near spread 0.049 (2.6x), foreground element
 * 0.0002; 64x48: 0.130, 0.054 (2.4x), 0.0069. The foreground element reproduces the reference up
 * to float rounding once its CoC is filled everywhere (the only source value is 20, so the fill
 * is 20 everywhere and F is the reference's F): so it must be far closer than the near spread,
 * which also blurs the background under the silhouette. */
#define NEAR_SPREAD_MIN_GAIN 1.5 /* single / near spread */
#define FOREGROUND_MIN_GAIN 3.0  /* near spread / foreground element */
#define FOREGROUND_MAX_DIFF 1e-3 /* foreground element vs the reference, any pixel */

static void test_near_error(void)
{
    const size_t npx = (size_t)W * H, n = npx * CH;
    float *bg = alloc_f(n), *img = alloc_f(n), *coc = alloc_f(npx), *flat = alloc_f(npx);
    float *obj = alloc_f(n), *objcoc = alloc_f(npx), *ref = alloc_f(n), *one = alloc_f(n);
    float *spread = alloc_f(n), *fgout = alloc_f(n), *tmp = alloc_f(n), *zero = alloc_f(npx);
    unsigned char *band = calloc(npx, 1);
    const double R = disc_radius();
    texture(bg, CH, 21);
    memcpy(img, bg, n * sizeof(float));
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            size_t i = (size_t)y * W + x;
            int in = disc_dist(x, y) <= R;
            for (uint32_t c = 0; c < 3; c++) {
                obj[i * 4 + c] = in ? obj_rgb[c] : 0.0f;
                if (in)
                    img[i * CH + c] = obj_rgb[c];
            }
            obj[i * 4 + 3] = in ? 1.0f : 0.0f;
            objcoc[i] = in ? 20.0f : 0.0f;
            coc[i] = in ? -20.0f : 0.0f;
            band[i] = fabs(disc_dist(x, y) - R) <= 8.0;
        }
    fill_const(flat, npx, 20.0f);
    fill_const(zero, npx, 0.0f);

    /* Reference: F = the object layer diffused alone, over the sharp background. */
    ddof_params pref;
    heat_params_init(&pref);
    pref.solver = DDOF_SOLVER_REFERENCE_F64;
    CHECK_EQ_INT(single(&pref, obj, flat, tmp, 4), DDOF_OK);
    for (size_t i = 0; i < npx; i++) {
        float a = tmp[i * 4 + 3];
        for (uint32_t c = 0; c < 4; c++)
            ref[i * CH + c] = tmp[i * 4 + c] + (1.0f - a) * bg[i * CH + c];
    }

    /* (a) single layer: |CoC| in ddof_diffuse. */
    ddof_params p;
    heat_params_init(&p);
    CHECK_EQ_INT(single(&p, img, objcoc, one, CH), DDOF_OK);
    /* (b) one image, signed CoC: the near spread (AUTO; the near layer, which would take its
     * place, has its own tests in test_near_layer.c). */
    p.coc_signed = 1;
    p.near_layer = DDOF_LAYER_OFF;
    ddof_stats st;
    CHECK_EQ_INT(layers(&p, img, coc, NULL, spread, CH, &st), DDOF_OK);
    CHECK_MSG(st.effects & DDOF_EFFECT_NEAR_SPREAD, "near object: effects 0x%x", st.effects);
    /* (c) the object as a foreground element over the sharp background (CoC 0). */
    ddof_foreground fg = make_fg(obj, objcoc, 1);
    CHECK_EQ_INT(layers(&p, bg, zero, &fg, fgout, CH, &st), DDOF_OK);
    CHECK_MSG(st.effects & DDOF_EFFECT_FOREGROUND, "foreground: effects 0x%x", st.effects);

    double e1 = rmse_rgb(one, ref, band, CH), es = rmse_rgb(spread, ref, band, CH);
    double ef = rmse_rgb(fgout, ref, band, CH);
    printf("near object, band of 8 px: RMSE single layer %.5f, near spread %.5f (%.2fx), "
           "foreground element %.5f (%.2fx)\n",
           e1, es, es > 0 ? e1 / es : INFINITY, ef, ef > 0 ? e1 / ef : INFINITY);
    CHECK_MSG(es * NEAR_SPREAD_MIN_GAIN <= e1, "near spread %.5f vs single %.5f", es, e1);
    CHECK_MSG(ef * FOREGROUND_MIN_GAIN <= es, "foreground %.5f vs near spread %.5f", ef, es);
    CHECK(all_finite(spread, n) && all_finite(fgout, n));
    {
        double d = max_abs_diff_ff(fgout, ref, n);
        printf("near object: foreground element vs reference, max |diff| %.3g\n", d);
        /* A fill that does not reach the pixels diagonal to the element (outside both the rows
         * and the columns it covers) clips the halo along those lines. */
        CHECK_MSG(d <= FOREGROUND_MAX_DIFF,
                  "foreground element vs reference: max diff %g (is its CoC filled everywhere?)",
                  d);
    }
    /* Every solver: the same element result (Jacobi: approximate, only closer than single). */
    for (size_t s = 0; s < N_SOLVERS; s++) {
        ddof_params ps = p;
        ps.solver = all_solvers[s];
        CHECK_EQ_INT(layers(&ps, bg, zero, &fg, tmp, CH, NULL), DDOF_OK);
        double d = max_abs_diff_ff(tmp, fgout, n), e = rmse_rgb(tmp, ref, band, CH);
        printf("near object, foreground element, solver %s: max diff to thomas %.3g, band RMSE "
               "%.5f\n", ddof_solver_name(ps.solver), d, e);
        if (all_solvers[s] != DDOF_SOLVER_JACOBI)
            CHECK_MSG(d <= 1e-4, "foreground element, solver %s vs thomas: %g",
                      ddof_solver_name(ps.solver), d);
        CHECK_MSG(e < e1, "foreground element, solver %s: %.5f vs single %.5f",
                  ddof_solver_name(ps.solver), e, e1);
    }

    /* The element's CoC where its alpha is 0 is not used. */
    for (size_t i = 0; i < npx; i++)
        tmp[i] = obj[i * 4 + 3] > 0 ? 20.0f : 777.0f;
    {
        float *alt = alloc_f(n);
        ddof_foreground fg2 = make_fg(obj, tmp, 1);
        CHECK_EQ_INT(layers(&p, bg, zero, &fg2, alt, CH, NULL), DDOF_OK);
        double d = max_abs_diff_ff(alt, fgout, n);
        CHECK_MSG(d <= 1e-6, "element CoC under alpha 0 changes the result by %g", d);
        free(alt);
    }

    /* With the near spread off, the near-field result is the single-layer one. */
    p.near_spread = DDOF_LAYER_OFF;
    p.background = DDOF_LAYER_OFF;
    CHECK_EQ_INT(layers(&p, img, coc, NULL, tmp, CH, NULL), DDOF_OK);
    CHECK_MSG(max_abs_diff_ff(tmp, one, n) <= 1e-6, "near spread off vs single: %g",
              max_abs_diff_ff(tmp, one, n));

    free(bg);
    free(img);
    free(coc);
    free(flat);
    free(obj);
    free(objcoc);
    free(ref);
    free(one);
    free(spread);
    free(fgout);
    free(tmp);
    free(zero);
    free(band);
}

/* A small, very blurred element (radius 4 px, CoC 30): its halo is round, as the reference's.
 * (A CoC fill that reaches only the rows and the columns the element covers makes it a plus.) */
static void test_small_element(void)
{
    const size_t npx = (size_t)W * H, n = npx * CH;
    float *bg = alloc_f(n), *obj = alloc_f(npx * 4), *objcoc = alloc_f(npx), *flat = alloc_f(npx);
    float *zero = alloc_f(npx), *F = alloc_f(npx * 4), *out = alloc_f(n);
    texture(bg, CH, 91);
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            size_t i = (size_t)y * W + x;
            int in = disc_dist(x, y) <= 4.0;
            for (uint32_t c = 0; c < 3; c++)
                obj[i * 4 + c] = in ? obj_rgb[c] : 0.0f;
            obj[i * 4 + 3] = in ? 1.0f : 0.0f;
            objcoc[i] = in ? 30.0f : 0.0f;
        }
    fill_const(flat, npx, 30.0f);
    fill_const(zero, npx, 0.0f);
    ddof_params p;
    heat_params_init(&p);
    p.solver = DDOF_SOLVER_REFERENCE_F64;
    CHECK_EQ_INT(single(&p, obj, flat, F, 4), DDOF_OK);
    heat_params_init(&p);
    p.highlights = DDOF_LAYER_OFF; /* the reference is the diffusion; the object is bright */
    ddof_foreground fg = make_fg(obj, objcoc, 1);
    CHECK_EQ_INT(layers(&p, bg, zero, &fg, out, CH, NULL), DDOF_OK);
    double worst = 0;
    uint32_t wx = 0, wy = 0;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            size_t i = (size_t)y * W + x;
            for (uint32_t c = 0; c < 3; c++) {
                double ref = F[i * 4 + c] + (1.0 - F[i * 4 + 3]) * bg[i * CH + c];
                double d = fabs(out[i * CH + c] - ref);
                if (d > worst) {
                    worst = d;
                    wx = x;
                    wy = y;
                }
            }
        }
    printf("small element (r 4, CoC 30): max |diff| to the reference %.4f at (%u, %u)\n", worst,
           wx, wy);
    CHECK_MSG(worst <= FOREGROUND_MAX_DIFF,
              "small element: max diff %g at (%u, %u) (is its CoC filled everywhere?)", worst, wx,
              wy);
    free(bg);
    free(obj);
    free(objcoc);
    free(flat);
    free(zero);
    free(F);
    free(out);
}

/* Foreground element: premultiplied vs straight input, a 3-channel main image, alpha 0
 * everywhere, NaN under alpha 0. */
static void test_foreground_forms(void)
{
    const size_t npx = (size_t)W * H, n = npx * CH;
    float *main_c = alloc_f(n), *main3 = alloc_f(npx * 3), *coc = alloc_f(npx);
    float *pre = alloc_f(npx * 4), *straight = alloc_f(npx * 4), *fcoc = alloc_f(npx);
    float *o1 = alloc_f(n), *o2 = alloc_f(n), *o3 = alloc_f(npx * 3);
    test_rng rng = {31};
    noise(main_c, CH, 32);
    for (size_t i = 0; i < npx; i++) {
        for (uint32_t c = 0; c < 3; c++)
            main3[i * 3 + c] = main_c[i * CH + c];
        coc[i] = (float)(6.0 * test_uniform(&rng));
    }
    /* A soft-edged element: alpha 1 in the disc, 0.5 in a ring, 0 outside. */
    const double R = disc_radius();
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            size_t i = (size_t)y * W + x;
            double d = disc_dist(x, y);
            float a = d <= R ? 1.0f : d <= R + 4 ? 0.5f : 0.0f;
            for (uint32_t c = 0; c < 3; c++) {
                float v = (float)(0.1 + 0.8 * test_uniform(&rng));
                straight[i * 4 + c] = a > 0 ? v : 0.25f;
                pre[i * 4 + c] = a * v;
            }
            straight[i * 4 + 3] = pre[i * 4 + 3] = a;
            fcoc[i] = a > 0 ? 16.0f : 0.0f;
        }
    ddof_params p;
    heat_params_init(&p);
    ddof_foreground fp = make_fg(pre, fcoc, 1), fs = make_fg(straight, fcoc, 0);
    CHECK_EQ_INT(layers(&p, main_c, coc, &fp, o1, CH, NULL), DDOF_OK);
    CHECK_EQ_INT(layers(&p, main_c, coc, &fs, o2, CH, NULL), DDOF_OK);
    CHECK_MSG(max_abs_diff_ff(o1, o2, n) <= 1e-6, "premultiplied vs straight element: %g",
              max_abs_diff_ff(o1, o2, n));

    /* 3-channel main image: the same RGB. */
    CHECK_EQ_INT(layers(&p, main3, coc, &fp, o3, 3, NULL), DDOF_OK);
    {
        double d = 0;
        for (size_t i = 0; i < npx; i++)
            for (uint32_t c = 0; c < 3; c++)
                d = fmax(d, fabs((double)o3[i * 3 + c] - o1[i * CH + c]));
        CHECK_MSG(d <= 1e-6, "3-channel vs 4-channel main image: %g", d);
    }

    /* NaN in the element's colour where its alpha is 0: the same as 0 there (pre holds 0
     * there already), premultiplied and straight. */
    CHECK_EQ_INT(layers(&p, main_c, coc, &fp, o1, CH, NULL), DDOF_OK);
    for (int premultiplied = 1; premultiplied >= 0; premultiplied--) {
        float *src = premultiplied ? pre : straight;
        float *nan_c = alloc_f(npx * 4);
        memcpy(nan_c, src, npx * 4 * sizeof(float));
        for (size_t i = 0; i < npx; i++)
            if (nan_c[i * 4 + 3] == 0.0f)
                for (uint32_t c = 0; c < 3; c++)
                    nan_c[i * 4 + c] = NAN;
        ddof_foreground fn = make_fg(nan_c, fcoc, (uint32_t)premultiplied);
        fill_const(o2, n, -1.0f);
        ddof_status s = layers(&p, main_c, coc, &fn, o2, CH, NULL);
        CHECK_MSG(s == DDOF_OK, "NaN under alpha 0 (%s): status %d (%s)",
                  premultiplied ? "premultiplied" : "straight", (int)s,
                  ddof_context_last_error(ctx));
        CHECK(all_finite(o2, n));
        CHECK_MSG(max_abs_diff_ff(o1, o2, n) <= 1e-6, "NaN under alpha 0 (%s) vs 0: %g",
                  premultiplied ? "premultiplied" : "straight", max_abs_diff_ff(o1, o2, n));
        free(nan_c);
    }

    /* An element with alpha 0 everywhere: the result without it. */
    fill_const(pre, npx * 4, 0.0f);
    fill_const(fcoc, npx, 30.0f);
    CHECK_EQ_INT(layers(&p, main_c, coc, &fp, o1, CH, NULL), DDOF_OK);
    CHECK_EQ_INT(layers(&p, main_c, coc, NULL, o2, CH, NULL), DDOF_OK);
    CHECK(all_finite(o1, n));
    CHECK_MSG(max_abs_diff_ff(o1, o2, n) <= 1e-6, "transparent element changes the result by %g",
              max_abs_diff_ff(o1, o2, n));
    for (size_t i = 0; i < npx * 4; i++) /* and NaN colour everywhere under it */
        if ((i & 3) != 3)
            pre[i] = NAN;
    ddof_status s = layers(&p, main_c, coc, &fp, o1, CH, NULL);
    CHECK_MSG(s == DDOF_OK, "transparent NaN element: status %d", (int)s);
    CHECK_MSG(max_abs_diff_ff(o1, o2, n) <= 1e-6, "transparent NaN element: %g", max_abs_diff_ff(o1, o2, n));

    free(main_c);
    free(main3);
    free(coc);
    free(pre);
    free(straight);
    free(fcoc);
    free(o1);
    free(o2);
    free(o3);
}

int main(void)
{
    layers_test_begin();
    test_bars_error(0);
    test_bars_error(1);
    test_near_error();
    test_background_reach();
    test_small_element();
    test_foreground_forms();
    return layers_test_end("test_layers_errors");
}
