/* SPDX-License-Identifier: MIT */
/* test_struct_abi.c - the struct rules of ddof.h (issue 22): sized initialisers write only the
 * caller's size, so an older caller's smaller struct is never overrun; the old init symbols
 * still write the whole struct; each input struct is accepted from its named first size; a
 * newer caller's larger struct is read when the fields this library does not know are zero
 * and refused, with a message, when one is set. */
#include "test_util.h"

#include <ddof.h>

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
    /* The macros pass sizeof; the old symbols write the whole struct. */
    ddof_params a, c;
    memset(&a, 0x11, sizeof a);
    memset(&c, 0x22, sizeof c);
    ddof_params_init(&a);
    (ddof_params_init)(&c);
    CHECK(memcmp(&a, &c, sizeof a) == 0 && a.struct_size == sizeof a);
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

int main(void)
{
    for (int i = 0; i < N; i++) {
        for (int c = 0; c < 4; c++)
            color[i * 4 + c] = c == 3 ? 1.0f : (float)((i * 7 + c * 5) % 13) / 13.0f;
        depth[i] = 1.0f + 0.5f * (float)(i % W);
    }
    test_sized_init_writes_only_the_callers_size();
    ddof_context *ctx = NULL;
    CHECK(ddof_context_create(NULL, &ctx) == DDOF_OK);
    test_older_caller(ctx);
    test_newer_caller(ctx);
    ddof_context_free(ctx);
    return test_report("test_struct_abi");
}
