/* SPDX-License-Identifier: MIT */
/* test_gl_frame.c - whole layered frames on a GL backend against the same frames on the CPU
 * (Thomas on both, float): the midground alone, the background layer with 1 and 3 levels, the
 * near spread, a foreground element, HDR highlights, each with the heat kernel and with a disc
 * kernel. The GL result must match the CPU's within TOL_FRAME, leave every pixel the CPU leaves
 * untouched bit for bit, report the same effects, and make the host <-> device transfers
 * expect_uploads / expect_readbacks say (ddof_stats.device_uploads, device_readbacks). Argument: "osmesa" or
 * "egl". DDOF_TEST_VERBOSE=1 prints the measured differences and counts. */
#include "gl_test.h"

/* Both sides in float with the same operations; the GPU may contract them differently.
 * Relative to the colour range (the images here span [0.05, 0.9]); test_gl_disc's tolerance. */
#define TOL_FRAME 1e-4

/* The frame size; larger_frame() changes it. */
static uint32_t W = 83, H = 61;
enum { CH = 4 };

static ddof_context *gl, *cpu;
static const char *gl_name; /* its backend, as the plan names it */
static int verbose;

/* In-focus bars, a far background of CoC 12..40, and a disc of CoC 30 (near when signed). */
static void scene(float *color, float *coc, int signed_near)
{
    test_rng rng = {7};
    fill_uniform(color, (size_t)W * H * CH, &rng, 0.05, 0.9);
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            float d = 12.0f + 28.0f * (float)y / (float)H; /* far background */
            if (x % 19 < 3)
                d = 0.0f; /* thin in-focus bars */
            const float dx = (float)x - 55.0f, dy = (float)y - 28.0f;
            if (dx * dx + dy * dy < 81.0f)
                d = signed_near ? -30.0f : 30.0f; /* a near disc */
            coc[(size_t)y * W + x] = d;
        }
}

/* A premultiplied disc of soft alpha at (24, 30), NaN colour where alpha = 0. */
static void element(float *fg_color, float *fg_coc)
{
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            const float dx = (float)x - 24.0f, dy = (float)y - 30.0f;
            const float r = sqrtf(dx * dx + dy * dy);
            const float a = r < 6.0f ? 1.0f : r < 9.0f ? (9.0f - r) / 3.0f : 0.0f;
            float *px = fg_color + ((size_t)y * W + x) * 4;
            px[0] = a > 0 ? 0.9f * a : NAN;
            px[1] = a > 0 ? 0.3f * a : NAN;
            px[2] = a > 0 ? 0.1f * a : NAN;
            px[3] = a;
            fg_coc[(size_t)y * W + x] = 16.0f;
        }
}

/* Values the CPU left equal to the input that GL changed (bit for bit). */
static size_t untouched_changed(const float *input, const float *cpu_out, const float *gl_out,
                                size_t n)
{
    size_t changed = 0;
    for (size_t i = 0; i < n; i++)
        if (memcmp(&cpu_out[i], &input[i], sizeof(float)) == 0)
            changed += memcmp(&gl_out[i], &input[i], sizeof(float)) != 0;
    return changed;
}

/* The transfers of a frame on the device: the images up in one, the result back in one (one
 * request at a time it was 2 + 5 per background level + 6 for an element up, one back per
 * diffusion). A near layer is split on the device first: the frame goes up for the split, and
 * the layers' run then uploads only what else it reads (the highlights' aperture), if any. */
static uint32_t expect_uploads(const ddof_stats *sc, const ddof_params *p)
{
    const int near = (sc->effects & DDOF_EFFECT_NEAR_LAYER) != 0;
    return near && p->highlights == DDOF_LAYER_OFF ? 1 : 1 + (uint32_t)near;
}

static uint32_t expect_readbacks(void)
{
    return 1;
}

/* What a frame's progress callback saw. */
typedef struct progress_seen {
    float last;
    uint32_t calls, backwards;
} progress_seen;

static int see_progress(void *user, float fraction)
{
    progress_seen *s = user;
    s->backwards += fraction < s->last;
    s->last = fraction;
    s->calls++;
    return 0;
}

/* The CPU's midground alone, to see that an effect changed something. */
static float *midground_alone(ddof_params p, const float *color, const float *coc)
{
    float *mid = alloc_f((size_t)W * H * CH);
    p.background = DDOF_LAYER_OFF;
    p.near_spread = DDOF_LAYER_OFF;
    p.near_layer = DDOF_LAYER_OFF;
    p.far_field = DDOF_LAYER_OFF;
    p.silhouettes = DDOF_LAYER_OFF;
    CHECK_EQ_INT(diffuse_layers(cpu, &p, color, coc, NULL, mid, W, H, CH, NULL), DDOF_OK);
    return mid;
}

/* The device's plan is the CPU's with one line more, where the layers ran (the element inside
 * the run goes unsaid); whole plans (ddof_context_last_plan) are compared, and the stats' copy
 * is their first 512 bytes, cut at a line. */
static void expect_plan_line(const char *name, const ddof_stats *sg)
{
    char where[64], without[DDOF_PLAN_MAX_BYTES];
    const char *gl_plan = ddof_context_last_plan(gl), *cpu_plan = ddof_context_last_plan(cpu);
    snprintf(where, sizeof where, "layers: on %s\n", gl_name);
    const char *at = strstr(gl_plan, where);
    CHECK_MSG(at != NULL, "%s: the device's plan \"%s\"", name, gl_plan);
    if (!at)
        return;
    plan_without_device_line(gl_plan, without, sizeof without);
    CHECK_MSG(strcmp(without, cpu_plan) == 0, "%s: the device's plan \"%s\", the CPU's \"%s\"",
              name, gl_plan, cpu_plan);
    CHECK_MSG(strstr(gl_plan, "(the plan goes on)") == NULL, "%s: a whole plan cut", name);
    const size_t kept = strlen(sg->plan);
    const char *cut = "(the plan goes on)\n";
    if (strlen(gl_plan) < sizeof sg->plan)
        CHECK_MSG(strcmp(sg->plan, gl_plan) == 0, "%s: the stats' plan is not the whole", name);
    else
        CHECK_MSG(kept >= strlen(cut) && strcmp(sg->plan + kept - strlen(cut), cut) == 0 &&
                      strncmp(sg->plan, gl_plan, kept - strlen(cut)) == 0,
                  "%s: the stats' plan \"%s\" is not the whole one's start, marked", name,
                  sg->plan);
}

static void compare(const char *name, ddof_params p, const float *color, const float *coc,
                    const ddof_foreground *fg, uint32_t expect_effects)
{
    const size_t n = (size_t)W * H * CH;
    float *ref = alloc_f(n), *out = alloc_f(n);
    ddof_stats sc = stats_init(), sg = stats_init();
    ddof_status s = diffuse_layers(cpu, &p, color, coc, fg, ref, W, H, CH, &sc);
    CHECK_MSG(s == DDOF_OK, "%s: CPU %d (%s)", name, (int)s, ddof_context_last_error(cpu));
    s = diffuse_layers(gl, &p, color, coc, fg, out, W, H, CH, &sg);
    CHECK_MSG(s == DDOF_OK, "%s: GL %d (%s)", name, (int)s, ddof_context_last_error(gl));
    const double e = max_diff(out, ref, n);
    const size_t changed = untouched_changed(color, ref, out, n);
    if (verbose)
        printf("  %-34s %-8s GL vs CPU %.3g, uploads %u, read-backs %u, %.1f MB/MP\n", name,
               ddof_kernel_name(p.kernel), e, sg.device_uploads, sg.device_readbacks,
               (double)sg.device_bytes / ((double)W * H));
    CHECK_MSG(e <= TOL_FRAME, "%s %s: GL vs CPU %.3g > %.3g", name, ddof_kernel_name(p.kernel),
              e, TOL_FRAME);
    CHECK_MSG(changed == 0, "%s %s: %zu values the CPU leaves as they are changed", name,
              ddof_kernel_name(p.kernel), changed);
    CHECK_MSG((sc.effects & expect_effects) == expect_effects, "%s: effects %u, wanted %u (%s)",
              name, sc.effects, expect_effects, sc.plan);
    CHECK_EQ_INT(sg.effects, sc.effects);
    CHECK_EQ_INT(sg.kernel, sc.kernel);
    CHECK_MSG(sg.device_bytes > 0, "%s: nothing ran on the device", name);
    CHECK_EQ_INT(sc.device_uploads, 0);
    CHECK_EQ_INT(sc.device_readbacks, 0);
    CHECK_MSG(sg.device_uploads == expect_uploads(&sc, &p) &&
                  sg.device_readbacks == expect_readbacks(),
              "%s: %u uploads and %u read-backs", name, sg.device_uploads, sg.device_readbacks);
    expect_plan_line(name, &sg);
    if (expect_effects == DDOF_EFFECT_MIDGROUND) {
        /* The one diffusion through ddof_diffuse (the seam's run()): one upload too. */
        sg = stats_init();
        CHECK_EQ_INT(diffuse(gl, &p, color, coc, out, W, H, CH, &sg), DDOF_OK);
        CHECK_EQ_INT(sg.device_uploads, 1);
        CHECK_EQ_INT(sg.device_readbacks, 1);
        CHECK_MSG(max_diff(out, ref, n) <= TOL_FRAME, "%s: ddof_diffuse", name);
    }
    if (expect_effects != DDOF_EFFECT_MIDGROUND) {
        float *mid = midground_alone(p, color, coc);
        const double effect = max_diff(ref, mid, n);
        CHECK_MSG(effect > 1e-2, "%s: the layers changed the midground by %.3g only", name,
                  effect);
        free(mid);
    }
    free(ref);
    free(out);
}

static void frames(ddof_kernel kernel)
{
    float *color = alloc_f((size_t)W * H * CH), *coc = alloc_f((size_t)W * H);
    ddof_params p;
    ddof_params_init(&p);
    p.solver = DDOF_SOLVER_THOMAS;
    p.kernel = kernel;

    scene(color, coc, 0);
    p.background = DDOF_LAYER_OFF;
    compare("midground only", p, color, coc, NULL, DDOF_EFFECT_MIDGROUND);
    p.background = DDOF_LAYER_AUTO;
    p.background_levels = 1;
    compare("background, 1 level", p, color, coc, NULL, DDOF_EFFECT_BACKGROUND);
    p.background_levels = 3;
    compare("background, 3 levels", p, color, coc, NULL, DDOF_EFFECT_BACKGROUND);
    p.background = DDOF_LAYER_ON;
    p.background_levels = 1;
    p.substeps = kernel == DDOF_KERNEL_HEAT ? 2 : p.substeps;
    compare("background forced on", p, color, coc, NULL, DDOF_EFFECT_BACKGROUND);

    ddof_params_init(&p);
    p.solver = DDOF_SOLVER_THOMAS;
    p.kernel = kernel;
    scene(color, coc, 1);
    p.coc_signed = 1;
    p.near_layer = DDOF_LAYER_OFF;
    compare("near spread + background", p, color, coc, NULL,
            DDOF_EFFECT_NEAR_SPREAD | DDOF_EFFECT_BACKGROUND);
    p.background = DDOF_LAYER_OFF;
    compare("near spread alone", p, color, coc, NULL, DDOF_EFFECT_NEAR_SPREAD);

    /* The near layer: split on the device, the element and the filled rest left there for the
     * layers' run, the rest as for an element. Opaque pixels and no highlights: the frame up
     * once, for the split. */
    for (size_t i = 0; i < (size_t)W * H; i++)
        color[i * CH + 3] = 1.0f;
    p.far_field = DDOF_LAYER_OFF;   /* it goes under the element: far_field_frames() */
    p.silhouettes = DDOF_LAYER_OFF; /* likewise */
    p.near_layer = DDOF_LAYER_AUTO;
    p.background = DDOF_LAYER_AUTO;
    p.highlights = DDOF_LAYER_OFF;
    compare("near layer + background", p, color, coc, NULL,
            DDOF_EFFECT_NEAR_LAYER | DDOF_EFFECT_FOREGROUND | DDOF_EFFECT_BACKGROUND);
    p.background = DDOF_LAYER_OFF;
    compare("near layer alone", p, color, coc, NULL,
            DDOF_EFFECT_NEAR_LAYER | DDOF_EFFECT_FOREGROUND);

    float *fg_color = alloc_f((size_t)W * H * 4), *fg_coc = alloc_f((size_t)W * H);
    element(fg_color, fg_coc);
    ddof_foreground fg;
    ddof_foreground_init(&fg);
    fg.color = (ddof_image_in){fg_color, W, H, 4, 0};
    fg.coc = (ddof_image_in){fg_coc, W, H, 1, 0};
    ddof_params_init(&p);
    p.solver = DDOF_SOLVER_THOMAS;
    p.kernel = kernel;
    /* The element (0.9 red) is above the highlight threshold: its highlights are the CPU's
     * and take the frame off the device (highlights(), below); here the device runs it all. */
    p.highlights = DDOF_LAYER_OFF;
    p.far_field = DDOF_LAYER_OFF;
    p.silhouettes = DDOF_LAYER_OFF;
    scene(color, coc, 0);
    compare("foreground element + background", p, color, coc, &fg,
            DDOF_EFFECT_FOREGROUND | DDOF_EFFECT_BACKGROUND);
    p.background_levels = 3;
    compare("foreground + background 3 levels", p, color, coc, &fg,
            DDOF_EFFECT_FOREGROUND | DDOF_EFFECT_BACKGROUND);

    free(fg_color);
    free(fg_coc);
    free(color);
    free(coc);
}

/* The far field and the silhouettes (ddof_params.far_field, .silhouettes): stages of the
 * device's run (tests/gl/test_gl_far_field.c, test_gl_silhouettes.c for their cases), so a
 * frame is 1 upload and 1 read-back and matches the CPU, with an element too (its blur
 * gathered by the far field, then composited over them). */
static void far_field_frames(ddof_kernel kernel)
{
    const size_t n = (size_t)W * H * CH;
    float *color = alloc_f(n), *coc = alloc_f((size_t)W * H);
    test_rng rng = {11};
    fill_uniform(color, n, &rng, 0.05, 0.9);
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++)
            coc[(size_t)y * W + x] = 6.0f + 20.0f * (float)y / (float)H; /* a receding plane */
    ddof_params p;
    ddof_params_init(&p);
    p.solver = DDOF_SOLVER_THOMAS;
    p.kernel = kernel;
    p.far_field = DDOF_LAYER_AUTO;
    compare("far field", p, color, coc, NULL, DDOF_EFFECT_FAR_FIELD);
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 30; x < 34; x++)
            coc[(size_t)y * W + x] = 0.0f; /* an in-focus bar: silhouettes */
    p.coc_signed = 1;
    compare("far field + silhouettes", p, color, coc, NULL,
            DDOF_EFFECT_FAR_FIELD | DDOF_EFFECT_SILHOUETTES);

    float *fg_color = alloc_f(n), *fg_coc = alloc_f((size_t)W * H);
    element(fg_color, fg_coc);
    ddof_foreground fg;
    ddof_foreground_init(&fg);
    fg.color = (ddof_image_in){fg_color, W, H, 4, 0};
    fg.coc = (ddof_image_in){fg_coc, W, H, 1, 0};
    p.highlights = DDOF_LAYER_OFF;
    /* The far field, the silhouettes and the far field's gather of the element's blur are
     * stages of the device's run, before the element's composite: one upload, one read-back. */
    compare("far field + element", p, color, coc, &fg,
            DDOF_EFFECT_FAR_FIELD | DDOF_EFFECT_SILHOUETTES | DDOF_EFFECT_FOREGROUND);
    /* One rising fraction over the device's run. */
    float *out = alloc_f(n);
    progress_seen seen = {0};
    p.progress = see_progress;
    p.progress_user = &seen;
    CHECK_EQ_INT(diffuse_layers(gl, &p, color, coc, &fg, out, W, H, CH, NULL), DDOF_OK);
    CHECK_MSG(seen.calls > 3 && seen.backwards == 0 && seen.last > 0.999f,
              "far field + element: %u calls, %u backwards, the last %g", seen.calls,
              seen.backwards, seen.last);
    p.progress = NULL;
    /* A sharp frame under the blurred element: the frame calls for no far field, but the
     * element's CoC does (the device once composited the element without it: GL vs CPU 0.070
     * with heat, 0.0073 with disc-2x3, effects 5 against 69); the device gathers it too. */
    for (size_t i = 0; i < (size_t)W * H; i++)
        coc[i] = 0.5f;
    compare("sharp frame + element", p, color, coc, &fg,
            DDOF_EFFECT_FAR_FIELD | DDOF_EFFECT_FOREGROUND);
    free(out);
    free(fg_color);
    free(fg_coc);
    free(color);
    free(coc);
}

/* HDR highlights (the highlight pass, ddof_params.highlights): found, taken out and drawn on
 * the device (tests/gl/test_gl_highlights.c for the shapes), so 1 upload and 1 read-back, with
 * an element over them too, and with highlights in the element itself (taken out of it and
 * drawn into its blur), and a near layer whose element carries part of the frame's alpha. */
static void highlights(ddof_kernel kernel)
{
    const size_t n = (size_t)W * H * CH;
    float *color = alloc_f(n), *coc = alloc_f((size_t)W * H);
    ddof_params p;
    ddof_params_init(&p);
    p.solver = DDOF_SOLVER_THOMAS;
    p.kernel = kernel;
    scene(color, coc, 0);
    static const uint32_t spots[][2] = {{40, 10}, {70, 50}, {12, 45}};
    for (size_t k = 0; k < sizeof spots / sizeof spots[0]; k++)
        for (int c = 0; c < 3; c++)
            color[((size_t)spots[k][1] * W + spots[k][0]) * CH + (size_t)c] = 60.0f;
    compare("highlights + background", p, color, coc, NULL,
            DDOF_EFFECT_HIGHLIGHTS | DDOF_EFFECT_BACKGROUND);

    float *fg_color = alloc_f((size_t)W * H * 4), *fg_coc = alloc_f((size_t)W * H);
    element(fg_color, fg_coc);
    ddof_foreground fg;
    ddof_foreground_init(&fg);
    fg.color = (ddof_image_in){fg_color, W, H, 4, 0};
    fg.coc = (ddof_image_in){fg_coc, W, H, 1, 0};
    compare("highlights + element", p, color, coc, &fg,
            DDOF_EFFECT_HIGHLIGHTS | DDOF_EFFECT_FOREGROUND);
    /* A dim element over the frame's highlights: they are drawn on the device before the
     * element's composite, all in the one run. */
    float *dim = alloc_f((size_t)W * H * 4);
    for (size_t i = 0; i < (size_t)W * H * 4; i++)
        dim[i] = (i % 4 == 3) ? fg_color[i] : 0.2f * fg_color[i];
    ddof_foreground dim_fg = fg;
    dim_fg.color.pixels = dim;
    compare("highlights under an element", p, color, coc, &dim_fg,
            DDOF_EFFECT_HIGHLIGHTS | DDOF_EFFECT_FOREGROUND);
    free(dim);

    /* The element's own highlights alone (the rest dimmed below the threshold): taken out of
     * it and drawn into its blur on the device too. */
    for (size_t i = 0; i < n; i++)
        color[i] *= 0.1f;
    compare("element's highlights", p, color, coc, &fg,
            DDOF_EFFECT_HIGHLIGHTS | DDOF_EFFECT_FOREGROUND);

    /* The near layer of a frame whose alpha is not 1 under the near field: the element carries
     * its part of the alpha channel, blurred as its colour is (a fourth diffusion of the
     * element's) and composited as the frame's alpha, in the one run; and with highlights in
     * the near field, as for an element. */
    scene(color, coc, 1);
    p.coc_signed = 1;
    p.highlights = DDOF_LAYER_OFF;
    compare("near layer, alpha not 1", p, color, coc, NULL, DDOF_EFFECT_NEAR_LAYER);
    for (size_t i = 0; i < (size_t)W * H; i++)
        color[i * CH + 3] = 1.0f;
    p.highlights = DDOF_LAYER_AUTO;
    compare("near layer, highlights", p, color, coc, NULL,
            DDOF_EFFECT_NEAR_LAYER | DDOF_EFFECT_HIGHLIGHTS);
    free(fg_color);
    free(fg_coc);
    free(color);
    free(coc);
}

/* Copies a tight w x ch image into rows `stride` floats apart, the padding set to `pad`. */
static float *padded(const float *tight, uint32_t ch, size_t stride, float pad)
{
    float *p = alloc_f(stride * H);
    fill_const(p, stride * H, pad);
    for (uint32_t y = 0; y < H; y++)
        memcpy(p + y * stride, tight + (size_t)y * W * ch, (size_t)W * ch * sizeof(float));
    return p;
}

/* The frame with strided images (CoC as the first of 2 channels, padded rows everywhere) on
 * the device, out of place and in place, against the CPU's frame of tight images: the same
 * rows, the padding never written. */
static void layouts(uint32_t ch, int with_element)
{
    float *color = alloc_f((size_t)W * H * CH), *coc = alloc_f((size_t)W * H);
    float *fg_color = alloc_f((size_t)W * H * 4), *fg_coc = alloc_f((size_t)W * H);
    scene(color, coc, 1);
    element(fg_color, fg_coc);
    float *tight = alloc_f((size_t)W * H * ch), *ref = alloc_f((size_t)W * H * ch);
    for (size_t i = 0; i < (size_t)W * H; i++)
        memcpy(tight + i * ch, color + i * CH, ch * sizeof(float));
    ddof_params p;
    ddof_params_init(&p);
    p.solver = DDOF_SOLVER_THOMAS;
    p.coc_signed = 1;
    p.background_levels = 2;
    p.highlights = DDOF_LAYER_OFF; /* on the device throughout (the element is bright) */
    p.far_field = DDOF_LAYER_OFF;  /* likewise (it goes under the element) */
    p.silhouettes = DDOF_LAYER_OFF;
    ddof_foreground fg;
    ddof_foreground_init(&fg);
    fg.color = (ddof_image_in){fg_color, W, H, 4, 0};
    fg.coc = (ddof_image_in){fg_coc, W, H, 1, 0};
    const ddof_foreground *element_or = with_element ? &fg : NULL;
    CHECK_EQ_INT(diffuse_layers(cpu, &p, tight, coc, element_or, ref, W, H, ch, NULL), DDOF_OK);

    const size_t cs = (size_t)W * ch + 5, zs = (size_t)W * 2 + 3, fs = (size_t)W * 4 + 7;
    float *coc2 = padded(coc, 1, zs, NAN); /* channel 2 and the padding are never read */
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            coc2[y * zs + x * 2] = coc[(size_t)y * W + x];
            coc2[y * zs + x * 2 + 1] = NAN;
        }
    float *fgc = padded(fg_color, 4, fs, NAN), *fgz = padded(fg_coc, 1, W + 1, NAN);
    fg.color = (ddof_image_in){fgc, W, H, 4, fs * sizeof(float)};
    fg.coc = (ddof_image_in){fgz, W, H, 1, (W + 1) * sizeof(float)};
    for (int in_place = 0; in_place < 2; in_place++) {
        float *in = padded(tight, ch, cs, 555.0f), *out = padded(tight, ch, cs, 777.0f);
        float *target = in_place ? in : out;
        ddof_image_in ci = {in, W, H, ch, cs * sizeof(float)};
        ddof_image_in zi = {coc2, W, H, 2, zs * sizeof(float)};
        ddof_image oi = {target, W, H, ch, cs * sizeof(float)};
        ddof_stats st = stats_init();
        ddof_status s = ddof_diffuse_layers(gl, &p, &ci, &zi, element_or, &oi, &st);
        CHECK_MSG(s == DDOF_OK, "layouts %u ch: %d (%s)", ch, (int)s, ddof_context_last_error(gl));
        const size_t rows = padded_rows_differ(target, cs, ref, (size_t)W * ch, H);
        double e = 0.0;
        for (uint32_t y = 0; y < H; y++)
            e = fmax(e, max_diff(target + y * cs, ref + (size_t)y * W * ch, (size_t)W * ch));
        if (verbose)
            printf("  layouts, %u channels%s%s: GL vs CPU %.3g, uploads %u, read-backs %u\n", ch,
                   with_element ? ", element" : "", in_place ? ", in place" : "", e,
                   st.device_uploads, st.device_readbacks);
        CHECK_MSG(e <= TOL_FRAME, "layouts %u ch, in place %d: GL vs CPU %.3g (%zu rows differ)",
                  ch, in_place, e, rows);
        CHECK_EQ_INT(padding_changed(target, cs, (size_t)W * ch, H, in_place ? 555.0f : 777.0f),
                     0);
        CHECK_EQ_INT(st.device_uploads, 1);
        CHECK_EQ_INT(st.device_readbacks, 1);
        char where[96];
        snprintf(where, sizeof where, "layers: on %s\n", gl_name);
        CHECK_MSG(strstr(st.plan, where) != NULL, "layouts: %s", st.plan);
        free(in);
        free(out);
    }
    free(coc2);
    free(fgc);
    free(fgz);
    free(tight);
    free(ref);
    free(color);
    free(coc);
    free(fg_color);
    free(fg_coc);
}

static int cancel_at_half(void *user, float fraction)
{
    (void)user;
    return fraction >= 0.5f;
}

/* A layered frame cancelled halfway (in the background layer): CANCELLED, out finite. */
static void cancelled(void)
{
    float *color = alloc_f((size_t)W * H * CH), *coc = alloc_f((size_t)W * H);
    float *out = alloc_f((size_t)W * H * CH);
    scene(color, coc, 0);
    ddof_params p;
    ddof_params_init(&p);
    p.solver = DDOF_SOLVER_THOMAS;
    p.background_levels = 3;
    p.progress = cancel_at_half;
    CHECK_EQ_INT(diffuse_layers(gl, &p, color, coc, NULL, out, W, H, CH, NULL),
                 DDOF_ERROR_CANCELLED);
    CHECK(all_finite(out, (size_t)W * H * CH));
    free(color);
    free(coc);
    free(out);
}

/* A frame whose proximity cone (the whole 300 x 160 background area) runs more than 65,535
 * steps along its rows: one pass in one invocation would stop there on llvmpipe. */
static void larger_frame(void)
{
    W = 300;
    H = 160;
    float *color = alloc_f((size_t)W * H * CH), *coc = alloc_f((size_t)W * H);
    ddof_params p;
    ddof_params_init(&p);
    p.solver = DDOF_SOLVER_THOMAS;
    p.kernel = DDOF_KERNEL_HEAT;
    p.coc_signed = 1;
    p.near_layer = DDOF_LAYER_OFF;
    scene(color, coc, 1);
    compare("300x160, near spread + background", p, color, coc, NULL,
            DDOF_EFFECT_NEAR_SPREAD | DDOF_EFFECT_BACKGROUND);
    free(color);
    free(coc);
    W = 83;
    H = 61;
}

int main(int argc, char **argv)
{
    verbose = verbose_test();
    gl = gl_context_for(backend_from_name(argc > 1 ? argv[1] : NULL));
    gl_name = ddof_backend_name(backend_from_name(argc > 1 ? argv[1] : NULL));
    if (!gl)
        return GL_TEST_SKIP;
    cpu = make_context(0);
    frames(DDOF_KERNEL_HEAT);
    frames(DDOF_KERNEL_DISC_2X3);
    highlights(DDOF_KERNEL_HEAT);
    highlights(DDOF_KERNEL_DISC_2X3);
    far_field_frames(DDOF_KERNEL_HEAT);
    far_field_frames(DDOF_KERNEL_DISC_2X3);
    layouts(4, 1);
    layouts(3, 1);
    layouts(1, 0);
    cancelled();
    larger_frame();
    ddof_context_free(cpu);
    ddof_context_free(gl);
    return test_report("test_gl_frame");
}
