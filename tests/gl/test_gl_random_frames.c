/* SPDX-License-Identifier: MIT */
/* test_gl_random_frames.c - the GL backend against the CPU on frames drawn at random: sizes
 * from 1 px a side (with the dispatches' and chunks' edges, 15-17, 31-33, 63-65, ... favoured),
 * 3 or 4 channels with opaque, random or half alpha, blurred and in-focus regions, near discs
 * and bars, bright points, a foreground element in one frame of five, a bladed aperture, any
 * pixel aspect, and every pass's mode at random (auto, on, off). Each frame must give the same
 * status, the same effects and the same whole plan (but for the device's "layers:" line) as on
 * the CPU, and pixels within 1e-3 of the CPU's mean magnitude in RMS, all finite.
 * Usage: test_gl_random_frames osmesa|egl [first count] */
#include "gl_test.h"
#include "test_util.h"

#include <math.h>

#define REL_RMS 1e-3

typedef struct frame_case {
    uint32_t w, h, ch;
    int element;
    float *color, *coc, *fg, *fg_coc;
    ddof_params params;
    ddof_camera camera;
    int bladed;
} frame_case;

static uint32_t pick_size(test_rng *rng)
{
    static const uint32_t edges[] = {1, 2, 3, 5, 7, 15, 16, 17, 31, 32, 33, 47, 63, 64, 65, 97};
    if (test_uniform(rng) < 2.0 / 3.0)
        return edges[(uint32_t)(test_uniform(rng) * 16.0) % 16];
    return 1 + (uint32_t)(test_uniform(rng) * 130.0) % 130;
}

static float between(test_rng *rng, float a, float b)
{
    return a + (b - a) * (float)test_uniform(rng);
}

/* Discs and bars of one CoC each (in focus, near or far) over a blurred or sharp backdrop. */
static void draw_coc(test_rng *rng, frame_case *f)
{
    const size_t n = (size_t)f->w * f->h;
    const float backdrop = test_uniform(rng) < 0.75 ? between(rng, 2.0f, 25.0f) : 0.0f;
    for (size_t i = 0; i < n; i++)
        f->coc[i] = backdrop > 0.0f ? backdrop + between(rng, -0.5f, 0.5f) : 0.0f;
    const float side = (float)(f->w > f->h ? f->w : f->h);
    const int shapes = (int)(test_uniform(rng) * 5.0);
    for (int k = 0; k < shapes; k++) {
        const float cx = between(rng, 0.0f, (float)f->w), cy = between(rng, 0.0f, (float)f->h);
        const float r = between(rng, 0.5f, 0.6f * side);
        const double kind = test_uniform(rng);
        const float c = kind < 1.0 / 3.0   ? between(rng, 0.0f, 0.4f)
                        : kind < 2.0 / 3.0 ? -between(rng, 2.0f, 30.0f)
                                           : between(rng, 1.0f, 30.0f);
        const int disc = test_uniform(rng) < 0.5;
        for (size_t i = 0; i < n; i++) {
            const float dx = (float)(i % f->w) - cx, dy = (float)(i / f->w) - cy;
            if (disc ? dx * dx + dy * dy < r * r : fabsf(dx) < r && fabsf(dy) < 0.5f * r)
                f->coc[i] = c;
        }
    }
}

static void draw_color(test_rng *rng, frame_case *f)
{
    const size_t n = (size_t)f->w * f->h;
    const int alpha = f->ch == 4 ? (int)(test_uniform(rng) * 3.0) : 0;
    for (size_t i = 0; i < n; i++) {
        const uint32_t x = (uint32_t)(i % f->w), y = (uint32_t)(i / f->w);
        float *px = f->color + i * f->ch;
        const int bright = test_uniform(rng) < 0.04;
        for (uint32_t k = 0; k < 3; k++)
            px[k] = bright ? between(rng, 2.0f, 60.0f)
                           : 0.2f + 0.3f * sinf(0.3f * (float)x + (float)k) *
                                        cosf(0.2f * (float)y) +
                                 between(rng, 0.0f, 0.1f);
        if (f->ch == 4)
            px[3] = alpha == 0 ? 1.0f : alpha == 1 ? (float)test_uniform(rng)
                                                   : (x < f->w / 2 ? 1.0f : 0.5f);
    }
}

/* A premultiplied disc with a half-covered rim and a bright point or two, CoC -3..-25. */
static void draw_element(test_rng *rng, frame_case *f)
{
    const size_t n = (size_t)f->w * f->h;
    const float side = (float)(f->w > f->h ? f->w : f->h);
    const float cx = between(rng, 0.0f, (float)f->w), cy = between(rng, 0.0f, (float)f->h);
    const float r = between(rng, 1.0f, 0.5f * side), c = -between(rng, 3.0f, 25.0f);
    for (size_t i = 0; i < n; i++) {
        const float dx = (float)(i % f->w) - cx, dy = (float)(i / f->w) - cy;
        const float d2 = dx * dx + dy * dy;
        const float a = d2 < r * r ? 1.0f : d2 < (r + 1.0f) * (r + 1.0f) ? 0.5f : 0.0f;
        const float g = test_uniform(rng) < 1.0 / 30.0 ? 20.0f : 0.3f;
        f->fg[i * 4 + 0] = a * 0.8f;
        f->fg[i * 4 + 1] = a * g;
        f->fg[i * 4 + 2] = a * 0.1f;
        f->fg[i * 4 + 3] = a;
        f->fg_coc[i] = a > 0.0f ? c : 0.0f;
    }
}

static ddof_layer_mode any_mode(test_rng *rng)
{
    static const ddof_layer_mode modes[3] = {DDOF_LAYER_AUTO, DDOF_LAYER_ON, DDOF_LAYER_OFF};
    return modes[(uint32_t)(test_uniform(rng) * 3.0) % 3];
}

static void draw_params(test_rng *rng, frame_case *f)
{
    ddof_params_init_preset(&f->params, (ddof_preset)((uint32_t)(test_uniform(rng) * 3.0) % 3));
    ddof_params *p = &f->params;
    p->coc_signed = 1;
    p->highlights = any_mode(rng);
    p->highlight_threshold = between(rng, 0.25f, 3.0f);
    p->near_layer = any_mode(rng);
    p->far_field = any_mode(rng);
    p->silhouettes = any_mode(rng);
    p->blurred_edges = any_mode(rng);
    p->background = any_mode(rng);
    p->near_spread = any_mode(rng);
    if (test_uniform(rng) < 0.25)
        p->pixel_aspect = between(rng, 0.5f, 2.0f);
    ddof_camera_init(&f->camera);
    f->bladed = test_uniform(rng) < 1.0 / 3.0;
    f->camera.aperture_blades = 3 + (uint32_t)(test_uniform(rng) * 6.0) % 6;
    f->camera.aperture_rotation_deg = between(rng, 0.0f, 90.0f);
}

static ddof_status render(ddof_context *ctx, const frame_case *f, float *out, ddof_stats *st)
{
    ddof_frame frame;
    ddof_frame_init(&frame);
    frame.color = (ddof_image_in){f->color, f->w, f->h, f->ch, 0};
    frame.coc = (ddof_image_in){f->coc, f->w, f->h, 1, 0};
    if (f->element) {
        frame.foreground_color = (ddof_image_in){f->fg, f->w, f->h, 4, 0};
        frame.foreground_coc = (ddof_image_in){f->fg_coc, f->w, f->h, 1, 0};
    }
    frame.camera = f->bladed ? &f->camera : NULL;
    *st = (ddof_stats){.struct_size = sizeof *st};
    return ddof_render_frame(ctx, &f->params, &frame,
                             &(ddof_image){out, f->w, f->h, f->ch, 0}, st);
}

static void run_case(ddof_context *cpu, ddof_context *gl, int seed)
{
    test_rng rng = {0x9E3779B97F4A7C15ull * (unsigned long long)(seed + 1)};
    frame_case f = {.w = pick_size(&rng), .h = pick_size(&rng)};
    f.ch = test_uniform(&rng) < 0.5 ? 4 : 3;
    const size_t n = (size_t)f.w * f.h;
    f.color = alloc_f(n * f.ch);
    f.coc = alloc_f(n);
    f.fg = alloc_f(n * 4);
    f.fg_coc = alloc_f(n);
    float *want = alloc_f(n * f.ch), *got = alloc_f(n * f.ch);
    draw_color(&rng, &f);
    draw_coc(&rng, &f);
    f.element = test_uniform(&rng) < 0.2;
    if (f.element)
        draw_element(&rng, &f);
    draw_params(&rng, &f);

    ddof_stats sc, sg;
    const ddof_status a = render(cpu, &f, want, &sc);
    const ddof_status b = render(gl, &f, got, &sg);
    char cpu_plan[DDOF_PLAN_MAX_BYTES], gl_plan[DDOF_PLAN_MAX_BYTES];
    snprintf(cpu_plan, sizeof cpu_plan, "%s", ddof_context_last_plan(cpu));
    plan_without_device_line(ddof_context_last_plan(gl), gl_plan, sizeof gl_plan);
    CHECK_MSG(a == b, "seed %d (%ux%ux%u): CPU %d (%s), GL %d (%s)", seed, f.w, f.h, f.ch,
              (int)a, ddof_status_string(a), (int)b, ddof_context_last_error(gl));
    if (a == DDOF_OK && b == DDOF_OK) {
        const double rel = relative_rms(got, want, n * f.ch);
        CHECK_MSG(rel <= REL_RMS, "seed %d (%ux%ux%u): RMS %.3g of the mean magnitude (inf: a "
                  "value not finite)", seed, f.w, f.h, f.ch, rel);
        CHECK_MSG(sg.effects == sc.effects, "seed %d: effects %u on GL, %u on the CPU", seed,
                  sg.effects, sc.effects);
        CHECK_MSG(strcmp(cpu_plan, gl_plan) == 0, "seed %d: the CPU's plan\n%s\nGL's\n%s", seed,
                  cpu_plan, gl_plan);
    }
    free(f.color);
    free(f.coc);
    free(f.fg);
    free(f.fg_coc);
    free(want);
    free(got);
}

int main(int argc, char **argv)
{
    ddof_context *gl = gl_context_for(backend_from_name(argc > 1 ? argv[1] : NULL));
    if (!gl)
        return GL_TEST_SKIP;
    ddof_context *cpu = make_context(0);
    const int first = argc > 3 ? atoi(argv[2]) : 0, count = argc > 3 ? atoi(argv[3]) : 300;
    for (int seed = first; seed < first + count; seed++)
        run_case(cpu, gl, seed);
    ddof_context_free(cpu);
    ddof_context_free(gl);
    return test_report("test_gl_random_frames");
}
