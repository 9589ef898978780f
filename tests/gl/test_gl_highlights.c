/* SPDX-License-Identifier: MIT */
/* test_gl_highlights.c - the highlight pass on the device (libddof/src/passes/gl: the
 * highlights taken out of the colour and drawn, highlights.comp) against the CPU's
 * (highlights_find.c's base, highlights_draw.c, aperture.c): far and near lights over a
 * receding wall with a thin in-focus post across one (its hidden part drawn too), drawn as
 * discs, a rotated pentagon, a hexagon with an anamorphic ratio, an aperture image, with the
 * cat's eye; a large disc (its weights over several dispatches), a class of 600 lights (its
 * rows over several), rows of 5000 pixels (their sums over several). Each must match the CPU
 * within the frames' tolerance (relative to the light's size), say the same highlights line
 * (found on the device: the same counts, threshold, hidden parts and cost), and stay on the
 * device: one upload, one read-back, and neither the colour without the highlights nor the
 * discs' differences on the host (channels + 3 floats a pixel); a frame with the pass holds
 * no more host scratch than one without (no list on the host).
 * Usage: test_gl_highlights osmesa|egl */
#include "gl_test.h"
#include "test_util.h"

#define TOL 1e-4

static ddof_context *cpu, *gl;

/* A wall whose CoC grows from 8 to 30 px down the frame, a near band (CoC -20) at the bottom,
 * an in-focus post (2 px wide) at x = w / 3, and `lights` bright pixels scattered (one on the
 * post's edge, one in the near band); `big`: one light of CoC 160 in the middle. */
static void scene(float *color, float *coc, uint32_t w, uint32_t h, uint32_t lights, int big)
{
    block_texture(color, w, h, 4, 3, 0.05, 0.6);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            float c = 8.0f + 22.0f * (float)y / (float)h;
            if (y > h - h / 6)
                c = -20.0f;
            if (x == w / 3 || x == w / 3 + 1)
                c = 0.0f;
            coc[(size_t)y * w + x] = c;
        }
    test_rng rng = {17};
    for (uint32_t k = 0; k < lights; k++) {
        uint32_t x = (uint32_t)(test_uniform(&rng) * w), y = (uint32_t)(test_uniform(&rng) * h);
        if (k == 0) {
            x = w / 3 + 2; /* beside the post: its hidden part lies behind it */
            y = h / 3;
        } else if (k == 1) {
            x = w / 2;
            y = h - h / 12; /* in the near band */
        }
        float *px = color + ((size_t)y * w + x) * 4;
        px[0] = 30.0f + (float)(k % 7);
        px[1] = 20.0f;
        px[2] = 10.0f + (float)(k % 3);
    }
    if (big) {
        coc[(size_t)(h / 2) * w + w / 2] = 160.0f;
        float *px = color + ((size_t)(h / 2) * w + w / 2) * 4;
        px[0] = px[1] = px[2] = 500.0f;
    }
}

static void highlights_line(const ddof_stats *st, char *line, size_t size)
{
    const char *at = strstr(st->plan, "highlights:");
    line[0] = '\0';
    if (at)
        snprintf(line, size, "%.*s", (int)strcspn(at, "\n"), at);
}

/* The largest |GL - CPU| over the frame, each relative to 1 + |CPU|. */
static double relative_diff(const float *got, const float *want, size_t n)
{
    double worst = 0.0;
    for (size_t i = 0; i < n; i++) {
        const double d = fabs((double)got[i] - want[i]) / (1.0 + fabs((double)want[i]));
        if (!(d <= worst))
            worst = isnan(d) ? INFINITY : d;
    }
    return worst;
}

static void compare(const char *name, const ddof_camera *cam, uint32_t w, uint32_t h,
                    uint32_t lights, int big)
{
    const size_t n = (size_t)w * h * 4;
    float *color = alloc_f(n), *coc = alloc_f((size_t)w * h);
    float *want = alloc_f(n), *got = alloc_f(n);
    scene(color, coc, w, h, lights, big);
    ddof_params p;
    ddof_params_init(&p);
    p.coc_signed = 1;
    p.highlights = DDOF_LAYER_ON;
    p.far_field = DDOF_LAYER_OFF;
    p.near_layer = DDOF_LAYER_OFF;
    ddof_frame f;
    ddof_frame_init(&f);
    f.color = (ddof_image_in){color, w, h, 4, 0};
    f.coc = (ddof_image_in){coc, w, h, 1, 0};
    f.camera = cam;
    ddof_stats sc = stats_init(), sg = stats_init();
    ddof_status s = ddof_render_frame(cpu, &p, &f, &(ddof_image){want, w, h, 4, 0}, &sc);
    CHECK_MSG(s == DDOF_OK, "%s: CPU %d (%s)", name, (int)s, ddof_context_last_error(cpu));
    s = ddof_render_frame(gl, &p, &f, &(ddof_image){got, w, h, 4, 0}, &sg);
    CHECK_MSG(s == DDOF_OK, "%s: GL %d (%s)", name, (int)s, ddof_context_last_error(gl));
    const double e = relative_diff(got, want, n);
    char cl[200], gll[200];
    highlights_line(&sc, cl, sizeof cl);
    highlights_line(&sg, gll, sizeof gll);
    if (verbose_test())
        printf("  %-28s GL vs CPU %.3g; %s; host %.2f MB (CPU %.2f MB)\n", name, e, gll,
               (double)sg.host_bytes / 1e6, (double)sc.host_bytes / 1e6);
    CHECK_MSG(e <= TOL, "%s: GL vs CPU %.3g > %.3g", name, e, TOL);
    CHECK_MSG(strcmp(cl, gll) == 0, "%s: the CPU says \"%s\", GL \"%s\"", name, cl, gll);
    CHECK_MSG(sc.effects & DDOF_EFFECT_HIGHLIGHTS, "%s: no highlights (%s)", name, cl);
    CHECK_PASS_ON_DEVICE(name, sc, sg, (uint64_t)w * h * (4 + 3) * sizeof(float));
    free(color);
    free(coc);
    free(want);
    free(got);
}

/* The host scratch of one frame on a fresh GL context, with the highlight pass on or off. */
static uint64_t fresh_host_bytes(ddof_backend_kind kind, const float *color, const float *coc,
                                 uint32_t w, uint32_t h, int lights, ddof_stats *st)
{
    ddof_context *ctx = gl_context_for(kind);
    float *out = alloc_f((size_t)w * h * 4);
    ddof_params p;
    ddof_params_init(&p);
    p.coc_signed = 1;
    p.highlights = lights ? DDOF_LAYER_ON : DDOF_LAYER_OFF;
    p.far_field = DDOF_LAYER_OFF;
    p.near_layer = DDOF_LAYER_OFF;
    ddof_camera cam;
    ddof_camera_init(&cam);
    ddof_frame f;
    ddof_frame_init(&f);
    f.color = (ddof_image_in){color, w, h, 4, 0};
    f.coc = (ddof_image_in){coc, w, h, 1, 0};
    f.camera = &cam;
    *st = stats_init();
    CHECK_EQ_INT(ddof_render_frame(ctx, &p, &f, &(ddof_image){out, w, h, 4, 0}, st), DDOF_OK);
    free(out);
    ddof_context_free(ctx);
    return st->host_bytes;
}

/* The pass is found, taken out and drawn on the device: a frame with it holds no more host
 * scratch than one without (the host once held the list, its weights and landing counts). */
static void no_host_scratch(ddof_backend_kind kind)
{
    enum { W = 160, H = 120 };
    float *color = alloc_f((size_t)W * H * 4), *coc = alloc_f((size_t)W * H);
    scene(color, coc, W, H, 40, 0);
    ddof_stats on, off;
    const uint64_t with = fresh_host_bytes(kind, color, coc, W, H, 1, &on);
    const uint64_t without = fresh_host_bytes(kind, color, coc, W, H, 0, &off);
    if (verbose_test())
        printf("  host scratch with the pass %llu, without %llu\n", (unsigned long long)with,
               (unsigned long long)without);
    CHECK_MSG(on.effects & DDOF_EFFECT_HIGHLIGHTS, "no highlights: %s", on.plan);
    CHECK_MSG(with == without, "host scratch %llu with the pass, %llu without",
              (unsigned long long)with, (unsigned long long)without);
    free(color);
    free(coc);
}

int main(int argc, char **argv)
{
    const ddof_backend_kind kind = backend_from_name(argc > 1 ? argv[1] : NULL);
    gl = gl_context_for(kind);
    if (!gl)
        return GL_TEST_SKIP;
    no_host_scratch(kind);
    cpu = make_context(0);
    ddof_camera cam;
    ddof_camera_init(&cam);
    compare("discs", &cam, 160, 120, 40, 0);
    cam.aperture_blades = 5;
    cam.aperture_rotation_deg = 17.0;
    compare("a pentagon", &cam, 160, 120, 40, 0);
    cam.aperture_blades = 6;
    cam.aperture_ratio = 2.0;
    compare("a hexagon, ratio 2", &cam, 160, 120, 40, 0);
    cam.aperture_ratio = 1.0;
    cam.aperture_catseye = 0.8;
    compare("a hexagon, cat's eye", &cam, 160, 120, 40, 0);
    enum { IW = 24, IH = 20 };
    static float ring[IW * IH];
    for (int y = 0; y < IH; y++)
        for (int x = 0; x < IW; x++) {
            const double u = (x + 0.5) / IW - 0.5, v = (y + 0.5) / IH - 0.5, r = sqrt(u * u + v * v);
            ring[y * IW + x] = r < 0.5 && r > 0.3 ? 1.0f : (r < 0.1 ? 0.5f : 0.0f);
        }
    cam.aperture_image = ring;
    cam.aperture_image_width = IW;
    cam.aperture_image_height = IH;
    compare("an aperture image", &cam, 160, 120, 40, 0);
    ddof_camera_init(&cam);
    compare("a disc of CoC 160", &cam, 240, 200, 4, 1);
    compare("600 lights", &cam, 320, 240, 600, 0);
    compare("rows of 5000 pixels", &cam, 5000, 24, 30, 0);
    ddof_context_free(cpu);
    ddof_context_free(gl);
    return test_report("test_gl_highlights");
}
