/* SPDX-License-Identifier: MIT */
/* test_gl_disc.c - the disc kernel on a GL backend (libddof/src/adi/gl/gl_lens.c, lens_thomas.comp)
 * against the CPU's (libddof/src/adi/lens_adi.c): ddof_diffuse on random CoC with in-focus pixels
 * (every kernel, 1..4 channels, a pixel aspect, in place, CoC 0 next to CoC 10,000, lines of
 * one pixel, cancelled), ddof_diffuse_layers with the
 * background forced on (heat capacities, singular runs) and a foreground element, the in-focus
 * pixels bit for bit, and ddof_stats saying which kernel ran where. Argument: "osmesa" or
 * "egl". DDOF_TEST_VERBOSE=1 prints the measured differences. */
#include "gl_test.h"

/* Both sides in float with the same operations; the GPU may contract them differently.
 * Relative to the colour range (the images here span [0, 1)). Measured on llvmpipe: at most
 * 1.1e-6 on these cases (DDOF_TEST_VERBOSE=1), 1.7e-6 at 1920x1080 (docs/gl-backend.md). */
#define TOL_DISC 1e-4

static ddof_context *gl, *cpu;
static ddof_backend_kind gl_kind;
static int verbose;

static const ddof_kernel kernels[] = {DDOF_KERNEL_DISC_2X2, DDOF_KERNEL_DISC_2X3,
                                      DDOF_KERNEL_DISC_3X3};

static ddof_params disc_params(ddof_kernel kernel)
{
    ddof_params p;
    ddof_params_init(&p);
    p.kernel = kernel;
    p.solver = DDOF_SOLVER_THOMAS;
    return p;
}

/* Values of CoC-0 pixels (no link on any side) that differ from the input, bit for bit. */
static size_t in_focus_changed(const test_image *im, const float *out)
{
    size_t changed = 0;
    for (size_t p = 0; p < im->px; p++)
        if (im->coc[p] == 0.0f)
            for (uint32_t c = 0; c < im->ch; c++)
                changed += memcmp(&out[p * im->ch + c], &im->color[p * im->ch + c],
                                  sizeof(float)) != 0;
    return changed;
}

static void check_stats(const char *name, const ddof_stats *g, const ddof_stats *c,
                        ddof_kernel kernel)
{
    CHECK_MSG(g->kernel == (uint32_t)kernel, "%s: the GL call ran kernel %u", name, g->kernel);
    CHECK_MSG(c->kernel == (uint32_t)kernel, "%s: the CPU call ran kernel %u", name, c->kernel);
    CHECK_EQ_INT(g->backend, gl_kind);
    CHECK_MSG(g->device_bytes > 0, "%s: nothing ran on the device", name);
    CHECK_EQ_INT(g->effects, c->effects);
}

static void compare_diffuse(const char *name, const test_image *im, ddof_params p, int in_place)
{
    float *ref = alloc_f(im->n), *out = alloc_f(im->n);
    ddof_stats sg = stats_init(), sc = stats_init();
    CHECK_EQ_INT(diffuse(cpu, &p, im->color, im->coc, ref, im->w, im->h, im->ch, &sc), DDOF_OK);
    ddof_status s;
    if (in_place) {
        memcpy(out, im->color, im->n * sizeof(float));
        ddof_image_in ci = {out, im->w, im->h, im->ch, 0};
        ddof_image_in zi = {im->coc, im->w, im->h, 1, 0};
        ddof_image oi = {out, im->w, im->h, im->ch, 0};
        s = ddof_diffuse(gl, &p, &ci, &zi, &oi, &sg);
    } else {
        s = diffuse(gl, &p, im->color, im->coc, out, im->w, im->h, im->ch, &sg);
    }
    CHECK_MSG(s == DDOF_OK, "%s: %d (%s)", name, (int)s, ddof_context_last_error(gl));
    const double e = max_diff(out, ref, im->n);
    if (verbose)
        printf("  %-34s %-8s GL vs CPU %.3g\n", name, ddof_kernel_name(p.kernel), e);
    CHECK_MSG(e <= TOL_DISC, "%s %s: GL vs CPU %.3g > %.3g", name, ddof_kernel_name(p.kernel),
              e, TOL_DISC);
    const size_t changed = in_focus_changed(im, out);
    CHECK_MSG(changed == 0, "%s %s: %zu values of CoC-0 pixels changed", name,
              ddof_kernel_name(p.kernel), changed);
    check_stats(name, &sg, &sc, p.kernel);
    CHECK_EQ_INT(sg.lines_solved, sc.lines_solved);
    CHECK_EQ_INT(sg.lines_skipped, sc.lines_skipped);
    CHECK_EQ_INT(sg.copied_only, sc.copied_only);
    CHECK_NEAR(sg.max_coc_px, sc.max_coc_px, 0.0);
    free(ref);
    free(out);
}

static void test_diffuse(void)
{
    static const struct {
        uint32_t w, h, ch;
        double max_coc, zeros;
    } cases[] = {{67, 45, 4, 40.0, 0.2}, {53, 71, 3, 25.0, 0.3}, {31, 29, 1, 12.0, 0.1},
                 {40, 33, 2, 60.0, 0.5}};
    for (size_t k = 0; k < sizeof kernels / sizeof *kernels; k++)
        for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
            test_image im = image_alloc(cases[i].w, cases[i].h, cases[i].ch);
            test_rng rng = {11 + i};
            fill_uniform(im.color, im.n, &rng, 0.0, 1.0);
            fill_coc(im.coc, im.px, &rng, cases[i].max_coc, cases[i].zeros);
            char name[64];
            snprintf(name, sizeof name, "random CoC %ux%ux%u", im.w, im.h, im.ch);
            compare_diffuse(name, &im, disc_params(kernels[k]), 0);
            image_free(&im);
        }

    /* A smooth CoC field (the blur of a scene: large runs of links) with an in-focus band, a
     * pixel aspect (column links scaled), and the same call in place. */
    test_image im = image_alloc(96, 64, 4);
    test_rng rng = {3};
    fill_uniform(im.color, im.n, &rng, 0.0, 1.0);
    for (uint32_t y = 0; y < im.h; y++)
        for (uint32_t x = 0; x < im.w; x++)
            im.coc[(size_t)y * im.w + x] =
                x >= 40 && x < 44 ? 0.0f : 30.0f * fabsf((float)x - 42.0f) / 54.0f + 0.5f;
    ddof_params p = disc_params(DDOF_KERNEL_DISC_3X3);
    compare_diffuse("smooth CoC", &im, p, 0);
    p.pixel_aspect = 1.5f;
    compare_diffuse("smooth CoC, pixel aspect 1.5", &im, p, 0);
    p.pixel_aspect = 1.0f;
    compare_diffuse("smooth CoC, in place", &im, p, 1);

    /* CoC 0 next to CoC 10,000 (|beta| ~ 1e8 next to no link), single-pixel islands of blur
     * in an in-focus frame with whole blurred rows, and nothing conducting at all (the input
     * comes back, counted as the CPU counts it). */
    for (uint32_t y = 0; y < im.h; y++)
        for (uint32_t x = 0; x < im.w; x++)
            im.coc[(size_t)y * im.w + x] = (x / 3) % 2 ? 1e4f : 0.0f;
    compare_diffuse("CoC 0 | CoC 1e4 stripes", &im, p, 0);
    fill_const(im.coc, im.px, 0.0f);
    for (int i = 0; i < 40; i++)
        im.coc[(size_t)(test_uniform(&rng) * (double)im.px)] = 50.0f;
    for (uint32_t y = 10; y < im.h; y += 10)
        for (uint32_t x = 0; x < im.w; x++)
            im.coc[(size_t)y * im.w + x] = 30.0f;
    compare_diffuse("islands + blurred rows", &im, p, 0);
    fill_const(im.coc, im.px, 0.0f);
    compare_diffuse("all in focus", &im, p, 0);
    image_free(&im);

    /* Lines of one pixel, and a single pixel. */
    static const uint32_t sizes[][2] = {{1, 37}, {41, 1}, {1, 1}};
    for (size_t i = 0; i < sizeof sizes / sizeof *sizes; i++) {
        test_image line = image_alloc(sizes[i][0], sizes[i][1], 4);
        fill_uniform(line.color, line.n, &rng, 0.0, 1.0);
        fill_coc(line.coc, line.px, &rng, 20.0, 0.2);
        char name[64];
        snprintf(name, sizeof name, "%ux%u", line.w, line.h);
        compare_diffuse(name, &line, disc_params(DDOF_KERNEL_DISC_2X3), 0);
        image_free(&line);
    }
}

static void test_other_solvers(void)
{
    /* Only Thomas has a complex form on the GPU: PCR draws the heat kernel, and says so. */
    test_image im = image_alloc(32, 24, 4);
    test_rng rng = {9};
    fill_uniform(im.color, im.n, &rng, 0.0, 1.0);
    fill_coc(im.coc, im.px, &rng, 20.0, 0.2);
    ddof_params p = disc_params(DDOF_KERNEL_DISC_2X2);
    p.solver = DDOF_SOLVER_PCR;
    ddof_stats st = stats_init();
    CHECK_EQ_INT(diffuse(gl, &p, im.color, im.coc, im.out, im.w, im.h, im.ch, &st), DDOF_OK);
    CHECK_EQ_INT(st.kernel, DDOF_KERNEL_HEAT);
    /* The reference runs on the CPU whatever the backend, so it keeps the disc. */
    p.solver = DDOF_SOLVER_REFERENCE_F64;
    st = stats_init();
    CHECK_EQ_INT(diffuse(gl, &p, im.color, im.coc, im.out, im.w, im.h, im.ch, &st), DDOF_OK);
    CHECK_EQ_INT(st.kernel, DDOF_KERNEL_DISC_2X2);
    image_free(&im);
}

static int cancel_at_half(void *user, float fraction)
{
    (void)user;
    return fraction >= 0.5f;
}

static void test_cancel(void)
{
    /* Cancelled between passes: the input comes back, as from the CPU. */
    test_image im = image_alloc(32, 24, 4);
    test_rng rng = {13};
    fill_uniform(im.color, im.n, &rng, 0.0, 1.0);
    fill_coc(im.coc, im.px, &rng, 20.0, 0.2);
    ddof_params p = disc_params(DDOF_KERNEL_DISC_3X3);
    p.progress = cancel_at_half;
    CHECK_EQ_INT(diffuse(gl, &p, im.color, im.coc, im.out, im.w, im.h, im.ch, NULL),
                 DDOF_ERROR_CANCELLED);
    CHECK(memcmp(im.out, im.color, im.n * sizeof(float)) == 0);
    image_free(&im);
}

/* ---- the layers --------------------------------------------------------------------------- */

enum { LW = 67, LH = 45, LCH = 4 };

static void layers_scene(float *color, float *coc)
{
    test_rng rng = {7};
    fill_uniform(color, (size_t)LW * LH * LCH, &rng, 0.05, 0.9);
    for (uint32_t y = 0; y < LH; y++)
        for (uint32_t x = 0; x < LW; x++) {
            float d = 20.0f + (float)((x * 7 + y * 3) % 11); /* far background */
            if (x % 16 < 2)
                d = 0.0f; /* thin in-focus bars */
            const float dx = (float)x - 45.0f, dy = (float)y - 20.0f;
            if (dx * dx + dy * dy < 64.0f)
                d = 30.0f; /* a near disc */
            coc[(size_t)y * LW + x] = d;
        }
}

static void compare_layers(const char *name, const ddof_params *p, const float *color,
                           const float *coc, const ddof_foreground *fg, uint32_t expect_effect)
{
    const size_t n = (size_t)LW * LH * LCH;
    float *ref = alloc_f(n), *out = alloc_f(n);
    ddof_stats sg = stats_init(), sc = stats_init();
    ddof_status s = diffuse_layers(cpu, p, color, coc, fg, ref, LW, LH, LCH, &sc);
    CHECK_MSG(s == DDOF_OK, "%s: CPU %d (%s)", name, (int)s, ddof_context_last_error(cpu));
    s = diffuse_layers(gl, p, color, coc, fg, out, LW, LH, LCH, &sg);
    CHECK_MSG(s == DDOF_OK, "%s: GL %d (%s)", name, (int)s, ddof_context_last_error(gl));
    CHECK_MSG(sg.effects & expect_effect, "%s: effect %u did not run (%s)", name, expect_effect,
              sg.plan);
    const double e = max_diff(out, ref, n);
    if (verbose)
        printf("  %-34s %-8s GL vs CPU %.3g\n", name, ddof_kernel_name(p->kernel), e);
    CHECK_MSG(e <= TOL_DISC, "%s: GL vs CPU %.3g > %.3g", name, e, TOL_DISC);
    check_stats(name, &sg, &sc, p->kernel);
    free(ref);
    free(out);
}

static void test_layers(void)
{
    float *color = alloc_f((size_t)LW * LH * LCH), *coc = alloc_f((size_t)LW * LH);
    layers_scene(color, coc);
    ddof_params p = disc_params(DDOF_KERNEL_DISC_3X3);
    p.background = DDOF_LAYER_ON;
    p.near_spread = DDOF_LAYER_OFF;
    compare_layers("layers: background on", &p, color, coc, NULL, DDOF_EFFECT_BACKGROUND);
    p.kernel = DDOF_KERNEL_DISC_2X2;
    p.background_levels = 2;
    compare_layers("layers: background 2 levels", &p, color, coc, NULL,
                   DDOF_EFFECT_BACKGROUND);

    /* A foreground element: a premultiplied disc with soft alpha, NaN colour where alpha = 0. */
    float *fg_color = alloc_f((size_t)LW * LH * 4), *fg_coc = alloc_f((size_t)LW * LH);
    for (uint32_t y = 0; y < LH; y++)
        for (uint32_t x = 0; x < LW; x++) {
            const float dx = (float)x - 20.0f, dy = (float)y - 25.0f;
            const float r = sqrtf(dx * dx + dy * dy);
            const float a = r < 6.0f ? 1.0f : r < 9.0f ? (9.0f - r) / 3.0f : 0.0f;
            float *px = fg_color + ((size_t)y * LW + x) * 4;
            px[0] = a > 0 ? 0.9f * a : NAN;
            px[1] = a > 0 ? 0.3f * a : NAN;
            px[2] = a > 0 ? 0.1f * a : NAN;
            px[3] = a;
            fg_coc[(size_t)y * LW + x] = 18.0f;
        }
    ddof_foreground fg;
    ddof_foreground_init(&fg);
    fg.color = (ddof_image_in){fg_color, LW, LH, 4, 0};
    fg.coc = (ddof_image_in){fg_coc, LW, LH, 1, 0};
    p = disc_params(DDOF_KERNEL_DISC_2X3);
    p.background = DDOF_LAYER_ON;
    compare_layers("layers: foreground element", &p, color, coc, &fg, DDOF_EFFECT_FOREGROUND);

    free(fg_color);
    free(fg_coc);
    free(color);
    free(coc);
}

int main(int argc, char **argv)
{
    verbose = verbose_test();
    gl_kind = backend_from_name(argc > 1 ? argv[1] : NULL);
    gl = gl_context_for(gl_kind);
    if (!gl)
        return GL_TEST_SKIP;
    cpu = make_context(0);
    test_diffuse();
    test_other_solvers();
    test_cancel();
    test_layers();
    ddof_context_free(cpu);
    ddof_context_free(gl);
    return test_report("test_gl_disc");
}
