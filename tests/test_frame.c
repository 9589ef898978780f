/* SPDX-License-Identifier: MIT */
/* test_frame.c - ddof_render_frame, the one call a host needs: bit for bit what the parts it
 * stands for give (the CoC calls and ddof_diffuse_layers), for every CoC source, with and
 * without a foreground element and a CoC output; every bad combination refused with the
 * output untouched; ddof_params_check, ddof_camera_check and ddof_curve_check judging as the
 * calls do. */
#include "test_util.h"

#include <ddof.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { W = 61, H = 43, N = W * H };

typedef struct scene {
    float color[N * 4], depth[N], fg_color[N * 4], fg_depth[N];
} scene;

/* A receding plane with a bright square, and a foreground disc nearer than the focus. */
static void make_scene(scene *s)
{
    test_rng rng = {12345u};
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const int i = y * W + x;
            for (int c = 0; c < 3; c++)
                s->color[i * 4 + c] = (float)test_uniform(&rng);
            s->color[i * 4 + 3] = 1.0f;
            if (x > 20 && x < 26 && y > 10 && y < 16)
                s->color[i * 4 + 0] = 40.0f;
            s->depth[i] = 1.0f + 0.1f * (float)x;
            const float dx = (float)x - 40.0f, dy = (float)y - 25.0f;
            const float a = dx * dx + dy * dy < 64.0f ? 1.0f : 0.0f;
            for (int c = 0; c < 3; c++)
                s->fg_color[i * 4 + c] = a * 0.5f;
            s->fg_color[i * 4 + 3] = a;
            s->fg_depth[i] = a > 0.0f ? 0.8f : INFINITY;
        }
}

static ddof_camera test_camera(void)
{
    ddof_camera cam;
    ddof_camera_init(&cam);
    cam.focal_length_mm = 85.0;
    cam.fstop = 1.4;
    cam.focus_distance_m = 3.0;
    cam.sensor_width_mm = 6.0; /* a small frame gets large CoCs */
    return cam;
}

static ddof_image_in in_image(const float *p, uint32_t channels)
{
    return (ddof_image_in){p, W, H, channels, 0};
}

static ddof_image out_image(float *p, uint32_t channels)
{
    return (ddof_image){p, W, H, channels, 0};
}

static int same(const float *a, const float *b, size_t n)
{
    return memcmp(a, b, n * sizeof *a) == 0;
}

/* Camera, with the element and the CoC output, against the parts composed by hand. */
static void test_camera_with_foreground(ddof_context *ctx, const scene *s)
{
    static float coc[N], fg_coc[N], want[N * 4], got[N * 4], coc_out[N];
    ddof_camera cam = test_camera();
    ddof_params p;
    ddof_params_init(&p);
    cam.signed_coc = 1;
    CHECK(ddof_coc_from_camera(ctx, &cam, &(ddof_image_in){s->depth, W, H, 1, 0},
                               &(ddof_image){coc, W, H, 1, 0}) == DDOF_OK);
    CHECK(ddof_coc_from_camera(ctx, &cam, &(ddof_image_in){s->fg_depth, W, H, 1, 0},
                               &(ddof_image){fg_coc, W, H, 1, 0}) == DDOF_OK);
    ddof_foreground element;
    ddof_foreground_init(&element);
    element.color = in_image(s->fg_color, 4);
    element.coc = in_image(fg_coc, 1);
    ddof_params hand = p;
    hand.coc_signed = 1;
    hand.pixel_aspect = (float)cam.pixel_aspect;
    ddof_stats want_stats = {.struct_size = sizeof want_stats};
    CHECK(ddof_diffuse_layers(ctx, &hand, &(ddof_image_in){s->color, W, H, 4, 0},
                              &(ddof_image_in){coc, W, H, 1, 0}, &element,
                              &(ddof_image){want, W, H, 4, 0}, &want_stats) == DDOF_OK);

    cam.signed_coc = 0; /* the frame call signs the CoC itself */
    ddof_frame f;
    ddof_frame_init(&f);
    f.color = in_image(s->color, 4);
    f.depth = in_image(s->depth, 1);
    f.camera = &cam;
    f.foreground_color = in_image(s->fg_color, 4);
    f.foreground_depth = in_image(s->fg_depth, 1);
    f.coc_out = out_image(coc_out, 1);
    ddof_stats stats = {.struct_size = sizeof stats};
    CHECK(ddof_render_frame(ctx, &p, &f, &(ddof_image){got, W, H, 4, 0}, &stats) == DDOF_OK);
    CHECK_MSG(same(got, want, N * 4), "camera + foreground: not bit-identical to the parts");
    CHECK_MSG(same(coc_out, coc, N), "coc_out is not the signed CoC of the camera");
    CHECK(stats.effects & DDOF_EFFECT_FOREGROUND);
    CHECK_EQ_INT(stats.effects, want_stats.effects);
    CHECK_EQ_INT(stats.lines_solved, want_stats.lines_solved);
    CHECK(stats.max_coc_px > 10.0f); /* the scene is blurred, the test means something */
    int negative = 0;
    for (int i = 0; i < N; i++)
        negative += coc_out[i] < 0.0f;
    CHECK_MSG(negative > 0, "the CoC output holds no near field (signed CoC expected)");

    /* ddof_depth_of_field is the same call without the element. */
    static float dof[N * 4], frame_only[N * 4];
    CHECK(ddof_depth_of_field(ctx, &p, &cam, &f.color, &f.depth, &(ddof_image){dof, W, H, 4, 0},
                              NULL) == DDOF_OK);
    f.foreground_color = f.foreground_depth = (ddof_image_in){0};
    f.coc_out = (ddof_image){0};
    CHECK(ddof_render_frame(ctx, &p, &f, &(ddof_image){frame_only, W, H, 4, 0}, NULL) ==
          DDOF_OK);
    CHECK(same(dof, frame_only, N * 4));
    CHECK(!same(dof, got, N * 4)); /* and the element did change the frame */
}

/* An element rendered over transparent film: its anti-aliased fringe (0 < alpha < 1) holds
 * the depth of its first sample, the disc's (0.8 m) or "no surface" (1e10, as Blender writes)
 * or +inf. Those fringe pixels take the CoC of the nearest fully covered pixel, so the frame
 * equals the same element whose fringe has the disc's depth; a fringe pixel whose depth is
 * nearer than the covered pixel's keeps its own. */
static void test_element_fringe(ddof_context *ctx, const scene *s)
{
    static float fg_color[N * 4], no_surface[N], covered_depth[N], got[N * 4], want[N * 4];
    int fringe = 0, missed = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const int i = y * W + x;
            const float dx = (float)x - 40.0f, dy = (float)y - 25.0f;
            const float r = sqrtf(dx * dx + dy * dy);
            const float a = r < 7.0f ? 1.0f : r < 9.0f ? (9.0f - r) / 2.0f : 0.0f;
            for (int c = 0; c < 3; c++)
                fg_color[i * 4 + c] = 0.6f * a;
            fg_color[i * 4 + 3] = a;
            covered_depth[i] = a > 0.0f ? 0.8f : 1e10f;
            no_surface[i] = covered_depth[i];
            if (a > 0.0f && a < 1.0f) {
                fringe++;
                if ((x + y) % 2) { /* the first sample missed the disc */
                    no_surface[i] = (x % 3) ? 1e10f : INFINITY;
                    missed++;
                }
            }
        }
    CHECK(fringe > 20 && missed > 10);
    ddof_camera cam = test_camera();
    ddof_params p;
    ddof_params_init(&p);
    ddof_frame f;
    ddof_frame_init(&f);
    f.color = in_image(s->color, 4);
    f.depth = in_image(s->depth, 1);
    f.camera = &cam;
    f.foreground_color = in_image(fg_color, 4);
    f.foreground_depth = in_image(no_surface, 1);
    CHECK_EQ_INT(ddof_render_frame(ctx, &p, &f, &(ddof_image){got, W, H, 4, 0}, NULL), DDOF_OK);
    f.foreground_depth = in_image(covered_depth, 1);
    CHECK_EQ_INT(ddof_render_frame(ctx, &p, &f, &(ddof_image){want, W, H, 4, 0}, NULL), DDOF_OK);
    CHECK_MSG(same(got, want, N * 4), "the element's fringe keeps the far CoC of its "
                                      "missed first samples");

    /* A fringe nearer than the covered pixels keeps its own CoC: the result differs. */
    for (int i = 0; i < N; i++)
        if (fg_color[i * 4 + 3] > 0.0f && fg_color[i * 4 + 3] < 1.0f)
            no_surface[i] = 0.5f;
    f.foreground_depth = in_image(no_surface, 1);
    CHECK_EQ_INT(ddof_render_frame(ctx, &p, &f, &(ddof_image){got, W, H, 4, 0}, NULL), DDOF_OK);
    CHECK(!same(got, want, N * 4));
}

/* A strand 1.4 px wide over transparent film has no fully covered pixel: its pixels whose
 * first sample missed it ("no surface") take the CoC of the most covered pixel beside them
 * that holds the strand's depth, so the frame equals the same strand with its depth
 * everywhere. */
static void test_element_strand(ddof_context *ctx, const scene *s)
{
    static float fg_color[N * 4], missed_depth[N], strand_depth[N], got[N * 4], want[N * 4];
    int missed = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const int i = y * W + x;
            const float a = (y < 8 || y > 40) ? 0.0f : x == 30 ? 0.6f : x == 31 ? 0.8f : 0.0f;
            for (int c = 0; c < 3; c++)
                fg_color[i * 4 + c] = 0.7f * a;
            fg_color[i * 4 + 3] = a;
            strand_depth[i] = a > 0.0f ? 0.8f : 1e10f;
            missed_depth[i] = strand_depth[i];
            if (a > 0.0f && (x + y) % 3 == 0) {
                missed_depth[i] = 1e10f;
                missed++;
            }
        }
    CHECK(missed > 10);
    ddof_camera cam = test_camera();
    ddof_params p;
    ddof_params_init(&p);
    ddof_frame f;
    ddof_frame_init(&f);
    f.color = in_image(s->color, 4);
    f.depth = in_image(s->depth, 1);
    f.camera = &cam;
    f.foreground_color = in_image(fg_color, 4);
    f.foreground_depth = in_image(missed_depth, 1);
    CHECK_EQ_INT(ddof_render_frame(ctx, &p, &f, &(ddof_image){got, W, H, 4, 0}, NULL), DDOF_OK);
    f.foreground_depth = in_image(strand_depth, 1);
    CHECK_EQ_INT(ddof_render_frame(ctx, &p, &f, &(ddof_image){want, W, H, 4, 0}, NULL), DDOF_OK);
    CHECK_MSG(same(got, want, N * 4), "the strand's missed samples keep the far CoC");
}

/* The curve and a given CoC, each with its element. */
static void test_curve_and_given(ddof_context *ctx, const scene *s)
{
    static float coc[N], fg_coc[N], want[N * 4], got[N * 4], coc_out[N];
    ddof_curve curve;
    ddof_curve_init(&curve);
    curve.near_blur_px = 12.0;
    curve.near_start = 0.5;
    curve.near_end = 1.5;
    curve.far_start = 3.0;
    curve.far_end = 6.0;
    curve.far_blur_px = 20.0;
    ddof_params p;
    ddof_params_init(&p);
    p.pixel_aspect = 1.25f;
    ddof_curve signed_curve = curve;
    signed_curve.signed_coc = 1;
    CHECK(ddof_coc_from_curve(ctx, &signed_curve, &(ddof_image_in){s->depth, W, H, 1, 0},
                              &(ddof_image){coc, W, H, 1, 0}) == DDOF_OK);
    CHECK(ddof_coc_from_curve(ctx, &signed_curve, &(ddof_image_in){s->fg_depth, W, H, 1, 0},
                              &(ddof_image){fg_coc, W, H, 1, 0}) == DDOF_OK);
    ddof_foreground element;
    ddof_foreground_init(&element);
    element.color = in_image(s->fg_color, 4);
    element.coc = in_image(fg_coc, 1);
    ddof_params hand = p;
    hand.coc_signed = 1;
    CHECK(ddof_diffuse_layers(ctx, &hand, &(ddof_image_in){s->color, W, H, 4, 0},
                              &(ddof_image_in){coc, W, H, 1, 0}, &element,
                              &(ddof_image){want, W, H, 4, 0}, NULL) == DDOF_OK);
    ddof_frame f;
    ddof_frame_init(&f);
    f.color = in_image(s->color, 4);
    f.depth = in_image(s->depth, 1);
    f.curve = &curve;
    f.foreground_color = in_image(s->fg_color, 4);
    f.foreground_depth = in_image(s->fg_depth, 1);
    f.coc_out = out_image(coc_out, 1);
    CHECK(ddof_render_frame(ctx, &p, &f, &(ddof_image){got, W, H, 4, 0}, NULL) == DDOF_OK);
    CHECK_MSG(same(got, want, N * 4), "curve + foreground: not bit-identical to the parts");
    CHECK(same(coc_out, coc, N));

    /* The CoC handed in: the same frame again, and coc_out a copy of it. */
    static float got_given[N * 4], coc_copy[N];
    ddof_frame g;
    ddof_frame_init(&g);
    g.color = in_image(s->color, 4);
    g.coc = in_image(coc, 1);
    g.foreground_color = in_image(s->fg_color, 4);
    g.foreground_coc = in_image(fg_coc, 1);
    g.coc_out = out_image(coc_copy, 1);
    CHECK(ddof_render_frame(ctx, &hand, &g, &(ddof_image){got_given, W, H, 4, 0}, NULL) ==
          DDOF_OK);
    CHECK(same(got_given, want, N * 4));
    CHECK(same(coc_copy, coc, N));
    /* A given signed CoC without coc_signed is the CoC check's error. */
    CHECK_EQ_INT(ddof_render_frame(ctx, &p, &g, &(ddof_image){got_given, W, H, 4, 0}, NULL),
                 DDOF_ERROR_BAD_COC);
}

/* Calls that must fail, each with out and coc_out untouched. */
static float base_coc_out[N];

static void expect_refused(ddof_context *ctx, const ddof_params *p, const ddof_frame *f,
                           ddof_status want, const char *what)
{
    static float out[N * 4], coc_out[N];
    for (int i = 0; i < N * 4; i++)
        out[i] = -7.0f;
    for (int i = 0; i < N; i++)
        coc_out[i] = -9.0f;
    ddof_frame g = *f;
    if (g.coc_out.pixels == base_coc_out) /* the sentinel-filled one, to see it untouched */
        g.coc_out.pixels = coc_out;
    const ddof_status got = ddof_render_frame(ctx, p, &g, &(ddof_image){out, W, H, 4, 0}, NULL);
    CHECK_MSG(got == want, "%s: status %d (%s), expected %d", what, (int)got,
              ddof_context_last_error(ctx), (int)want);
    CHECK_MSG(strlen(ddof_context_last_error(ctx)) > 10, "%s: no message", what);
    int touched = 0;
    for (int i = 0; i < N * 4; i++)
        touched += out[i] != -7.0f;
    for (int i = 0; i < N; i++)
        touched += coc_out[i] != -9.0f;
    CHECK_MSG(touched == 0, "%s: %d output values written", what, touched);
}

static void test_refusals(ddof_context *ctx, scene *s)
{
    static float coc[N];
    float *other = base_coc_out;
    for (int i = 0; i < N; i++)
        coc[i] = 3.0f;
    ddof_camera cam = test_camera();
    ddof_curve curve;
    ddof_curve_init(&curve);
    ddof_params p;
    ddof_params_init(&p);
    ddof_frame base;
    ddof_frame_init(&base);
    base.color = in_image(s->color, 4);
    base.depth = in_image(s->depth, 1);
    base.camera = &cam;
    base.coc_out = out_image(other, 1);

    ddof_frame f = base;
    f.camera = NULL;
    expect_refused(ctx, &p, &f, DDOF_ERROR_BAD_PARAMETER, "depth without camera or curve");
    f = base;
    f.curve = &curve;
    expect_refused(ctx, &p, &f, DDOF_ERROR_BAD_PARAMETER, "camera and curve");
    f = base;
    f.coc = in_image(coc, 1);
    expect_refused(ctx, &p, &f, DDOF_ERROR_BAD_PARAMETER, "camera and a CoC");
    f = base;
    f.camera = NULL;
    f.coc = in_image(coc, 1);
    expect_refused(ctx, &p, &f, DDOF_ERROR_BAD_PARAMETER, "CoC and depth");
    f = base;
    f.depth = (ddof_image_in){0};
    expect_refused(ctx, &p, &f, DDOF_ERROR_NULL_POINTER, "camera without depth");
    f = base;
    f.foreground_depth = in_image(s->fg_depth, 1);
    expect_refused(ctx, &p, &f, DDOF_ERROR_BAD_PARAMETER, "foreground depth without colour");
    f = base;
    f.foreground_color = in_image(s->fg_color, 4);
    expect_refused(ctx, &p, &f, DDOF_ERROR_BAD_PARAMETER, "element without its depth");
    f.foreground_coc = in_image(coc, 1);
    expect_refused(ctx, &p, &f, DDOF_ERROR_BAD_PARAMETER, "element with a CoC beside a camera");
    f.foreground_coc = (ddof_image_in){0};
    f.foreground_depth = (ddof_image_in){s->fg_depth, W - 1, H, 1, 0};
    expect_refused(ctx, &p, &f, DDOF_ERROR_SIZE_MISMATCH, "element depth of another size");
    f.foreground_depth = in_image(s->fg_depth, 1);
    f.foreground_color = in_image(s->fg_color, 3);
    expect_refused(ctx, &p, &f, DDOF_ERROR_BAD_CHANNELS, "element without alpha");
    f.foreground_color = in_image(s->fg_color, 4);
    ddof_params q = p;
    q.method = DDOF_METHOD_COD4_PREVIEW;
    expect_refused(ctx, &q, &f, DDOF_ERROR_UNSUPPORTED, "CoD4 preview with an element");
    q = p;
    q.near_spread = DDOF_LAYER_ON;
    expect_refused(ctx, &q, &f, DDOF_ERROR_BAD_PARAMETER, "forced near spread with an element");
    /* The element's depth is checked before anything is written. */
    const float keep = s->fg_depth[5];
    s->fg_depth[5] = NAN;
    expect_refused(ctx, &p, &f, DDOF_ERROR_BAD_DEPTH, "NaN in the element's depth");
    s->fg_depth[5] = keep;
    const float alpha = s->fg_color[7 * 4 + 3];
    s->fg_color[7 * 4 + 3] = INFINITY;
    expect_refused(ctx, &p, &f, DDOF_ERROR_BAD_COLOR, "infinite alpha in the element");
    s->fg_color[7 * 4 + 3] = alpha;

    f = base;
    f.coc_out = (ddof_image){other, W, H, 2, 0};
    expect_refused(ctx, &p, &f, DDOF_ERROR_SIZE_MISMATCH, "coc_out with 2 channels");
    f.coc_out = (ddof_image){(float *)s->color, W, H, 1, 0};
    expect_refused(ctx, &p, &f, DDOF_ERROR_BAD_PARAMETER, "coc_out over the colour");
    /* Overlap by byte range, not base pointer: the colour's alpha with the colour's stride,
     * an address inside the colour, the depth, and the output one float on. */
    f.coc_out = (ddof_image){(float *)s->color + 3, W, H, 1, (size_t)W * 4 * sizeof(float)};
    expect_refused(ctx, &p, &f, DDOF_ERROR_BAD_PARAMETER, "coc_out on the colour's alpha");
    f.coc_out = (ddof_image){(float *)s->color + 2 * W * 4, W, H, 1, 0};
    expect_refused(ctx, &p, &f, DDOF_ERROR_BAD_PARAMETER, "coc_out inside the colour");
    f.coc_out = (ddof_image){(float *)s->depth, W, H, 1, 0};
    expect_refused(ctx, &p, &f, DDOF_ERROR_BAD_PARAMETER, "coc_out over the depth");
    {
        static float out1[N * 4 + 1];
        f.coc_out = (ddof_image){out1 + 1, W, H, 1, 0};
        CHECK_EQ_INT(ddof_render_frame(ctx, &p, &f, &(ddof_image){out1, W, H, 4, 0}, NULL),
                     DDOF_ERROR_BAD_PARAMETER);
        CHECK(strstr(ddof_context_last_error(ctx), "overlaps the output") != NULL);
        int touched = 0;
        for (int i = 0; i < N * 4 + 1; i++)
            touched += out1[i] != 0.0f;
        CHECK_MSG(touched == 0, "coc_out at out + 1: %d values written", touched);
    }
    f = base;
    const float d = s->depth[9];
    s->depth[9] = -1.0f;
    expect_refused(ctx, &p, &f, DDOF_ERROR_BAD_DEPTH, "negative depth");
    s->depth[9] = d;
    ddof_camera bad = cam;
    bad.fstop = 0.0;
    f.camera = &bad;
    expect_refused(ctx, &p, &f, DDOF_ERROR_BAD_CAMERA, "f/0");
    bad = cam;
    bad.pixel_aspect = 200.0;
    expect_refused(ctx, &p, &f, DDOF_ERROR_BAD_CAMERA, "camera pixel aspect 200");
    f = base;
    f.struct_size = 8;
    expect_refused(ctx, &p, &f, DDOF_ERROR_BAD_PARAMETER, "a truncated frame struct");
    CHECK_EQ_INT(ddof_render_frame(ctx, &p, NULL, &(ddof_image){other, W, H, 1, 0}, NULL),
                 DDOF_ERROR_NULL_POINTER);
    CHECK_EQ_INT(ddof_render_frame(NULL, &p, &base, &(ddof_image){other, W, H, 1, 0}, NULL),
                 DDOF_ERROR_NULL_POINTER);
}

/* The checks without pixels judge as the calls do. */
static void test_checks(ddof_context *ctx)
{
    ddof_params p;
    ddof_params_init(&p);
    CHECK_EQ_INT(ddof_params_check(ctx, &p), DDOF_OK);
    CHECK_EQ_INT(ddof_params_check(ctx, NULL), DDOF_ERROR_NULL_POINTER);
    CHECK_EQ_INT(ddof_params_check(NULL, &p), DDOF_ERROR_NULL_POINTER);
    ddof_params q = p;
    q.beta_scale = 2.0f;
    CHECK_EQ_INT(ddof_params_check(ctx, &q), DDOF_ERROR_BAD_PARAMETER);
    CHECK(strstr(ddof_context_last_error(ctx), "beta_scale") != NULL);
    q = p;
    q.solver = DDOF_SOLVER_GRUEN; /* GL only: the CPU context cannot run it */
    CHECK_EQ_INT(ddof_params_check(ctx, &q), DDOF_ERROR_UNSUPPORTED);
    q = p;
    q.substeps = 0;
    CHECK_EQ_INT(ddof_params_check(ctx, &q), DDOF_ERROR_BAD_PARAMETER);
    q = p;
    q.near_spread = DDOF_LAYER_ON; /* judged by the call, which knows the CoC's sign */
    CHECK_EQ_INT(ddof_params_check(ctx, &q), DDOF_OK);
    CHECK_EQ_INT(ddof_params_check(ctx, &p), DDOF_OK);
    CHECK_EQ_INT(ddof_context_last_error(ctx)[0], 0);

    ddof_camera cam = test_camera();
    CHECK_EQ_INT(ddof_camera_check(ctx, &cam), DDOF_OK);
    ddof_camera bad = cam;
    bad.fstop = 0.0;
    CHECK_EQ_INT(ddof_camera_check(ctx, &bad), DDOF_ERROR_BAD_CAMERA);
    bad = cam;
    bad.focus_distance_m = 0.05; /* inside the 85 mm focal length */
    CHECK_EQ_INT(ddof_camera_check(ctx, &bad), DDOF_ERROR_BAD_CAMERA);
    bad = cam;
    bad.pixel_aspect = 0.001;
    CHECK_EQ_INT(ddof_camera_check(ctx, &bad), DDOF_ERROR_BAD_CAMERA);
    CHECK_EQ_INT(ddof_camera_check(ctx, NULL), DDOF_ERROR_NULL_POINTER);

    ddof_curve curve;
    ddof_curve_init(&curve);
    CHECK_EQ_INT(ddof_curve_check(ctx, &curve), DDOF_OK);
    curve.far_end = curve.far_start - 1.0; /* out of order */
    CHECK_EQ_INT(ddof_curve_check(ctx, &curve), DDOF_ERROR_BAD_PARAMETER);
}

int main(void)
{
    static scene s;
    make_scene(&s);
    ddof_context *ctx = NULL;
    ddof_context_options co;
    ddof_context_options_init(&co);
    co.thread_count = 2;
    CHECK(ddof_context_create(&co, &ctx) == DDOF_OK);
    test_camera_with_foreground(ctx, &s);
    test_curve_and_given(ctx, &s);
    test_element_fringe(ctx, &s);
    test_element_strand(ctx, &s);
    test_refusals(ctx, &s);
    test_checks(ctx);
    ddof_context_free(ctx);
    return test_report("test_frame");
}
