/* SPDX-License-Identifier: MIT */
/* test_struct_abi.c - the struct rules of ddof.h (issue 22): sized initialisers write only the
 * caller's size, so an older caller's smaller struct is never overrun; the old init symbols
 * still write the whole struct; each input struct is accepted from its named first size; a
 * newer caller's larger struct is read when the fields this library does not know are zero
 * and refused, with a message, when one is set. */
#include "test_util.h"

#include <ddof.h>

#include <math.h>
#include <string.h>

enum { W = 24, H = 16, N = W * H };

static float color[N * 4], depth[N], out[N * 4];

/* A struct of `size` bytes inside a canary-filled buffer: what lies beyond must stay 0xAB. */
typedef union buffer {
    unsigned char bytes[1024];
    ddof_params params;
    ddof_frame frame;
    ddof_camera camera;
    ddof_curve curve;
    ddof_foreground foreground;
    ddof_context_options options;
} buffer;

static int canary_kept(const buffer *b, size_t from)
{
    for (size_t i = from; i < sizeof b->bytes; i++)
        if (b->bytes[i] != 0xAB)
            return 0;
    return 1;
}

static void test_sized_init_writes_only_the_callers_size(void)
{
    static buffer b;
    /* ddof_params as 0.4 callers had it: up to `kernel`. */
    const size_t p04 = offsetof(ddof_params, kernel) + sizeof(ddof_kernel);
    memset(&b, 0xAB, sizeof b);
    ddof_params_init_sized(&b.params, p04);
    CHECK_EQ_INT(b.params.struct_size, p04);
    CHECK(canary_kept(&b, p04));
    CHECK(b.params.substeps >= 1 && b.params.pixel_aspect == 1.0f);
    memset(&b, 0xAB, sizeof b);
    CHECK_EQ_INT(ddof_params_init_preset_sized(&b.params, p04, DDOF_PRESET_FINAL), DDOF_OK);
    CHECK(canary_kept(&b, p04));
    /* Each init, at a size of 12 bytes, writes 12. */
    memset(&b, 0xAB, sizeof b);
    ddof_camera_init_sized(&b.camera, 12);
    CHECK(canary_kept(&b, 12) && b.camera.struct_size == 12);
    memset(&b, 0xAB, sizeof b);
    ddof_curve_init_sized(&b.curve, 12);
    CHECK(canary_kept(&b, 12) && b.curve.struct_size == 12);
    memset(&b, 0xAB, sizeof b);
    ddof_frame_init_sized(&b.frame, 12);
    CHECK(canary_kept(&b, 12) && b.frame.struct_size == 12);
    memset(&b, 0xAB, sizeof b);
    ddof_foreground_init_sized(&b.foreground, 12);
    CHECK(canary_kept(&b, 12) && b.foreground.struct_size == 12);
    memset(&b, 0xAB, sizeof b);
    ddof_context_options_init_sized(&b.options, 8);
    CHECK(canary_kept(&b, 8) && b.options.struct_size == 8);
    /* Below the size field: nothing written. */
    memset(&b, 0xAB, sizeof b);
    ddof_params_init_sized(&b.params, 3);
    CHECK(canary_kept(&b, 0));
    /* A larger (newer) caller's struct: only the library's own size is written. */
    memset(&b, 0xAB, sizeof b);
    ddof_frame_init_sized(&b.frame, sizeof(ddof_frame) + 16);
    CHECK_EQ_INT(b.frame.struct_size, sizeof(ddof_frame));
    CHECK(canary_kept(&b, sizeof(ddof_frame)));
    /* The macros pass sizeof. */
    ddof_params a;
    memset(&a, 0x11, sizeof a);
    ddof_params_init(&a);
    CHECK_EQ_INT(a.struct_size, sizeof a);
    CHECK(a.near_layer_threshold_px > 0.0f);
}

/* The plain-named functions are what binaries built against 0.5 call, with structs of the 0.5
 * layout: each writes exactly that layout (the whole of today's struct would overrun them),
 * the same bytes as the sized function at that size. */
static void test_plain_names_write_the_0_5_layout(void)
{
    static buffer b, sized;
#define PLAIN(call_plain, call_sized, size)                                                       \
    do {                                                                                         \
        memset(&b, 0xAB, sizeof b);                                                              \
        memset(&sized, 0xAB, sizeof sized);                                                      \
        call_plain;                                                                              \
        call_sized;                                                                              \
        CHECK_MSG(canary_kept(&b, (size)) && memcmp(&b, &sized, sizeof b) == 0 &&                \
                      *(uint32_t *)(void *)&b == (size),                                         \
                  "%s: struct_size %u, want %zu", #call_plain, *(uint32_t *)(void *)&b,          \
                  (size_t)(size));                                                               \
    } while (0)
    PLAIN((ddof_params_init)(&b.params), ddof_params_init_sized(&sized.params, DDOF_PARAMS_SIZE_0_5),
          DDOF_PARAMS_SIZE_0_5);
    PLAIN((void)(ddof_params_init_preset)(&b.params, DDOF_PRESET_FINAL),
          (void)ddof_params_init_preset_sized(&sized.params, DDOF_PARAMS_SIZE_0_5,
                                              DDOF_PRESET_FINAL),
          DDOF_PARAMS_SIZE_0_5);
    PLAIN((ddof_camera_init)(&b.camera), ddof_camera_init_sized(&sized.camera, DDOF_CAMERA_SIZE_0_5),
          DDOF_CAMERA_SIZE_0_5);
    PLAIN((ddof_curve_init)(&b.curve), ddof_curve_init_sized(&sized.curve, DDOF_CURVE_SIZE_0_5),
          DDOF_CURVE_SIZE_0_5);
    PLAIN((ddof_frame_init)(&b.frame), ddof_frame_init_sized(&sized.frame, DDOF_FRAME_SIZE_0_5),
          DDOF_FRAME_SIZE_0_5);
    PLAIN((ddof_foreground_init)(&b.foreground),
          ddof_foreground_init_sized(&sized.foreground, DDOF_FOREGROUND_SIZE_0_5),
          DDOF_FOREGROUND_SIZE_0_5);
    PLAIN((ddof_context_options_init)(&b.options),
          ddof_context_options_init_sized(&sized.options, DDOF_CONTEXT_OPTIONS_SIZE_0_5),
          DDOF_CONTEXT_OPTIONS_SIZE_0_5);
#undef PLAIN
    /* The 0.5 params are those a 0.5 binary had: its preset's values, the highlight pass last. */
    ddof_params full;
    ddof_params_init(&full);
    memset(&b, 0xAB, sizeof b);
    (ddof_params_init)(&b.params);
    CHECK(memcmp((char *)&b.params + 4, (char *)&full + 4, DDOF_PARAMS_SIZE_0_5 - 4) == 0);
    CHECK(b.params.highlight_threshold == full.highlight_threshold);
}

/* A 0.4 caller's params (the layout before in_focus_threshold_px and the highlight pass) run
 * with the defaults of what it lacks: the same pixels as today's defaults. */
static void test_older_caller(ddof_context *ctx)
{
    static buffer b;
    ddof_camera cam;
    ddof_camera_init(&cam);
    cam.focus_distance_m = 3.0;
    ddof_frame f;
    ddof_frame_init(&f);
    f.color = (ddof_image_in){color, W, H, 4, 0};
    f.depth = (ddof_image_in){depth, W, H, 1, 0};
    f.camera = &cam;
    const ddof_image o = {out, W, H, 4, 0};
    static float want[N * 4];
    ddof_params p;
    ddof_params_init(&p);
    CHECK_EQ_INT(ddof_render_frame(ctx, &p, &f, &(ddof_image){want, W, H, 4, 0}, NULL), DDOF_OK);
    memset(&b, 0xAB, sizeof b);
    ddof_params_init_sized(&b.params, offsetof(ddof_params, in_focus_threshold_px));
    CHECK_EQ_INT(ddof_render_frame(ctx, &b.params, &f, &o, NULL), DDOF_OK);
    CHECK(memcmp(out, want, sizeof want) == 0);
    /* A binary built against 0.5: every struct of the 0.5 layout, filled by the plain-named
     * functions it calls; the fields it lacks take their defaults, so the same pixels. */
    static buffer p05, f05, c05;
    memset(&p05, 0xAB, sizeof p05);
    memset(&f05, 0xAB, sizeof f05);
    memset(&c05, 0xAB, sizeof c05);
    (ddof_params_init)(&p05.params);
    (ddof_camera_init)(&c05.camera);
    c05.camera.focus_distance_m = 3.0;
    (ddof_frame_init)(&f05.frame);
    f05.frame.color = f.color;
    f05.frame.depth = f.depth;
    f05.frame.camera = &c05.camera;
    unsigned char stats05[sizeof(ddof_stats)];
    memset(stats05, 0xAB, sizeof stats05);
    const uint32_t stats05_size = (uint32_t)offsetof(ddof_stats, seconds_near_layer);
    memcpy(stats05, &stats05_size, sizeof stats05_size);
    CHECK_EQ_INT(ddof_render_frame(ctx, &p05.params, &f05.frame, &o, (ddof_stats *)(void *)stats05),
                 DDOF_OK);
    CHECK(memcmp(out, want, sizeof want) == 0);
    CHECK(stats05[stats05_size] == 0xAB && memcmp(stats05, &stats05_size, 4) == 0);
    /* The frame at its named 0.5 size is accepted, one byte less is not. */
    f.struct_size = (uint32_t)DDOF_FRAME_SIZE_0_5;
    CHECK_EQ_INT(ddof_render_frame(ctx, &p, &f, &o, NULL), DDOF_OK);
    f.struct_size = (uint32_t)DDOF_FRAME_SIZE_0_5 - 1;
    CHECK_EQ_INT(ddof_render_frame(ctx, &p, &f, &o, NULL), DDOF_ERROR_BAD_PARAMETER);
}

/* A newer caller (this library's structs with a field appended): read when the field is zero,
 * refused when it is set. */
static void test_newer_caller(ddof_context *ctx)
{
    struct { ddof_params p; uint64_t future; } np;
    struct { ddof_frame f; uint64_t future; } nf;
    struct { ddof_camera c; uint64_t future; } nc;
    struct { ddof_context_options o; uint64_t future; } no;
    memset(&np, 0, sizeof np);
    memset(&nf, 0, sizeof nf);
    memset(&nc, 0, sizeof nc);
    memset(&no, 0, sizeof no);
    ddof_params_init_sized(&np.p, sizeof np);
    ddof_frame_init_sized(&nf.f, sizeof nf);
    ddof_camera_init_sized(&nc.c, sizeof nc);
    ddof_context_options_init_sized(&no.o, sizeof no);
    np.p.struct_size = sizeof np;
    nf.f.struct_size = sizeof nf;
    nc.c.struct_size = sizeof nc;
    no.o.struct_size = sizeof no;
    nc.c.focus_distance_m = 3.0;
    nf.f.color = (ddof_image_in){color, W, H, 4, 0};
    nf.f.depth = (ddof_image_in){depth, W, H, 1, 0};
    nf.f.camera = &nc.c;
    const ddof_image o = {out, W, H, 4, 0};
    CHECK_EQ_INT(ddof_render_frame(ctx, &np.p, &nf.f, &o, NULL), DDOF_OK);
    ddof_context *other = NULL;
    CHECK_EQ_INT(ddof_context_create(&no.o, &other), DDOF_OK);
    ddof_context_free(other);

    np.future = 1;
    CHECK_EQ_INT(ddof_render_frame(ctx, &np.p, &nf.f, &o, NULL), DDOF_ERROR_BAD_PARAMETER);
    CHECK(strstr(ddof_context_last_error(ctx), "params.struct_size") &&
          strstr(ddof_context_last_error(ctx), "does not know is set"));
    CHECK_EQ_INT(ddof_params_check(ctx, &np.p), DDOF_ERROR_BAD_PARAMETER);
    np.future = 0;
    nf.future = 1;
    CHECK_EQ_INT(ddof_render_frame(ctx, &np.p, &nf.f, &o, NULL), DDOF_ERROR_BAD_PARAMETER);
    CHECK(strstr(ddof_context_last_error(ctx), "frame.struct_size") != NULL);
    nf.future = 0;
    nc.future = 1;
    CHECK_EQ_INT(ddof_camera_check(ctx, &nc.c), DDOF_ERROR_BAD_PARAMETER);
    nc.future = 0;
    CHECK_EQ_INT(ddof_camera_check(ctx, &nc.c), DDOF_OK);
    no.future = 1;
    CHECK_EQ_INT(ddof_context_create(&no.o, &other), DDOF_ERROR_BAD_PARAMETER);
    CHECK(other == NULL);
}

/* Output structs: written up to the smaller of the caller's size and the library's, struct_size
 * then the bytes written; below the first layout a status, and nothing runs. */
static void test_output_structs(ddof_context *ctx)
{
    ddof_params p;
    ddof_params_init(&p);
    ddof_camera cam;
    ddof_camera_init(&cam);
    cam.focus_distance_m = 3.0;
    const ddof_image_in ci = {color, W, H, 4, 0}, di = {depth, W, H, 1, 0};
    const ddof_image o = {out, W, H, 4, 0};
    /* A newer caller's stats: the library's own fields, the rest untouched. */
    struct { ddof_stats s; unsigned char future[16]; } ns;
    memset(&ns, 0xAB, sizeof ns);
    ns.s.struct_size = sizeof ns;
    CHECK_EQ_INT(ddof_depth_of_field(ctx, &p, &cam, &ci, &di, &o, &ns.s), DDOF_OK);
    CHECK_EQ_INT(ns.s.struct_size, sizeof(ddof_stats));
    CHECK_MSG(ns.future[0] == 0xAB && ns.future[15] == 0xAB && ns.s.max_coc_px > 0.0f,
              "future %x %x, lines %llu, plan %s", ns.future[0], ns.future[15],
              (unsigned long long)ns.s.lines_solved, ns.s.plan);
    /* Smaller than the first layout: refused before the output is touched. */
    static float before[N * 4];
    for (int i = 0; i < N * 4; i++)
        out[i] = before[i] = -1.0f;
    ddof_stats small;
    memset(&small, 0, sizeof small);
    small.struct_size = (uint32_t)DDOF_STATS_SIZE_0_1 - 1;
    CHECK_EQ_INT(ddof_depth_of_field(ctx, &p, &cam, &ci, &di, &o, &small),
                 DDOF_ERROR_BAD_PARAMETER);
    CHECK(strstr(ddof_context_last_error(ctx), "stats.struct_size") != NULL);
    CHECK(memcmp(out, before, sizeof before) == 0 && small.lines_solved == 0);
    const ddof_image_in zi = {depth, W, H, 1, 0};
    CHECK_EQ_INT(ddof_diffuse(ctx, &p, &ci, &zi, &o, &small), DDOF_ERROR_BAD_PARAMETER);
    CHECK_EQ_INT(ddof_diffuse_layers(ctx, &p, &ci, &zi, NULL, &o, &small),
                 DDOF_ERROR_BAD_PARAMETER);
    small.struct_size = (uint32_t)DDOF_STATS_SIZE_0_1;
    CHECK_EQ_INT(ddof_diffuse(ctx, &p, &ci, &zi, &o, &small), DDOF_OK);
    CHECK_EQ_INT(small.struct_size, DDOF_STATS_SIZE_0_1);
    CHECK(small.effects == 0 && small.lines_solved > 0);

    /* The info structs by the same rule. */
    struct { ddof_backend_info i; unsigned char future[16]; } nb;
    memset(&nb, 0xAB, sizeof nb);
    nb.i.struct_size = sizeof nb;
    CHECK_EQ_INT(ddof_context_backend_info(ctx, &nb.i), DDOF_OK);
    CHECK_EQ_INT(nb.i.struct_size, sizeof(ddof_backend_info));
    CHECK(nb.future[0] == 0xAB && strstr(nb.i.renderer, "CPU") != NULL);
    nb.i.struct_size = (uint32_t)DDOF_BACKEND_INFO_SIZE_0_3 - 1;
    CHECK_EQ_INT(ddof_context_backend_info(ctx, &nb.i), DDOF_ERROR_BAD_PARAMETER);
    struct { ddof_kernel_info i; unsigned char future[16]; } nk;
    memset(&nk, 0xAB, sizeof nk);
    nk.i.struct_size = sizeof nk;
    CHECK_EQ_INT(ddof_kernel_get_info(DDOF_KERNEL_DISC_2X2, &nk.i), DDOF_OK);
    CHECK_EQ_INT(nk.i.struct_size, sizeof(ddof_kernel_info));
    CHECK(nk.future[0] == 0xAB && nk.i.components == 2);
    nk.i.struct_size = (uint32_t)DDOF_KERNEL_INFO_SIZE_0_4 - 1;
    CHECK_EQ_INT(ddof_kernel_get_info(DDOF_KERNEL_DISC_2X2, &nk.i), DDOF_ERROR_BAD_PARAMETER);
}

/* ddof_param_bounds: each range is what ddof_params_check accepts, at both ends, and a step
 * beyond either end is refused. */
static void test_param_bounds(ddof_context *ctx)
{
    static const char *const fields[] = {
        "substeps", "beta_scale", "pixel_aspect", "jacobi_iterations", "background_threshold_px",
        "background_ramp_start_px", "background_levels", "near_spread_threshold_px",
        "in_focus_threshold_px", "highlight_threshold", "near_layer_threshold_px"};
    for (size_t k = 0; k < sizeof fields / sizeof fields[0]; k++) {
        double lo = NAN, hi = NAN;
        CHECK_EQ_INT(ddof_param_bounds(fields[k], &lo, &hi), DDOF_OK);
        CHECK_MSG(lo <= hi, "%s: %g..%g", fields[k], lo, hi);
        for (int end = 0; end < 2; end++)
            for (int beyond = 0; beyond < 2; beyond++) {
                ddof_params p;
                ddof_params_init(&p);
                p.solver = DDOF_SOLVER_JACOBI; /* jacobi_iterations is read */
                p.background_ramp_start_px = 0.0f;
                p.background_threshold_px = DDOF_MAX_COC_PX;
                double v = end ? hi : lo;
                int is_int = 0;
                /* One step beyond: the next integer, or the next float. */
#define SET(field, type, integral)                                                            \
    if (strcmp(fields[k], #field) == 0) {                                                        \
        is_int = integral;                                                                       \
        if (beyond)                                                                              \
            v = integral ? v + (end ? 1.0 : -1.0)                                                \
                         : (double)nextafterf((float)v, end ? INFINITY : -INFINITY);             \
        p.field = (type)v;                                                                       \
    }
                SET(substeps, uint32_t, 1)
                SET(beta_scale, float, 0)
                SET(pixel_aspect, float, 0)
                SET(jacobi_iterations, uint32_t, 1)
                SET(background_threshold_px, float, 0)
                SET(background_ramp_start_px, float, 0)
                SET(background_levels, uint32_t, 1)
                SET(near_spread_threshold_px, float, 0)
                SET(in_focus_threshold_px, float, 0)
                SET(highlight_threshold, float, 0)
                SET(near_layer_threshold_px, float, 0)
#undef SET
                if (strcmp(fields[k], "background_threshold_px") == 0)
                    p.background_ramp_start_px = 0.0f; /* below it at either end */
                if (strcmp(fields[k], "background_ramp_start_px") == 0 && end)
                    continue; /* its top is tied to the threshold: ddof_params_check's rule */
                if (is_int && beyond && !end && v < 0.0)
                    continue; /* below 0 an unsigned field cannot go */
                const ddof_status want = beyond ? DDOF_ERROR_BAD_PARAMETER : DDOF_OK;
                CHECK_MSG(ddof_params_check(ctx, &p) == want, "%s = %.9g (%s end%s): status %d",
                          fields[k], v, end ? "top" : "bottom", beyond ? ", beyond" : "",
                          (int)ddof_params_check(ctx, &p));
            }
    }
    double lo = 7.0, hi = 7.0;
    CHECK_EQ_INT(ddof_param_bounds("solver", &lo, &hi), DDOF_ERROR_BAD_PARAMETER);
    CHECK_EQ_INT(ddof_param_bounds("struct_size", &lo, &hi), DDOF_ERROR_BAD_PARAMETER);
    CHECK(lo == 7.0 && hi == 7.0);
    CHECK_EQ_INT(ddof_param_bounds(NULL, &lo, &hi), DDOF_ERROR_NULL_POINTER);
    CHECK_EQ_INT(ddof_param_bounds("substeps", NULL, &hi), DDOF_ERROR_NULL_POINTER);
}

int main(void)
{
    for (int i = 0; i < N; i++) {
        for (int c = 0; c < 4; c++)
            color[i * 4 + c] = c == 3 ? 1.0f : (float)((i * 7 + c * 5) % 13) / 13.0f;
        depth[i] = 1.0f + 0.5f * (float)(i % W);
    }
    test_sized_init_writes_only_the_callers_size();
    test_plain_names_write_the_0_5_layout();
    ddof_context *ctx = NULL;
    CHECK(ddof_context_create(NULL, &ctx) == DDOF_OK);
    test_older_caller(ctx);
    test_newer_caller(ctx);
    test_output_structs(ctx);
    test_param_bounds(ctx);
    ddof_context_free(ctx);
    return test_report("test_struct_abi");
}
