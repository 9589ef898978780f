/* SPDX-License-Identifier: MIT */
/* fuzz_matte.c - ddof_render_frame_with_matte on fuzzed frames and mattes: the frame from a CoC
 * or from depth and a camera, a foreground element now and then; the matte of any size (its
 * own width and height now and then), 0..2 * DDOF_MATTE_MAX_RANKS + 1 channels (odd counts
 * too), its own row stride, ids of any bits and coverage of any value; the silhouettes' split
 * forced on, automatic or off; and coc_out now and then, in its own buffer, inside the matte or
 * inside the output (both must be refused).
 *
 * Checked: a known status; the matte, an input, never changes; on an error neither the output
 * nor coc_out changes and there is a message; on DDOF_OK every output value is finite. */
#include "fuzz_reader.h"

#define MAX_SIDE 40u
#define MAX_PAD 5u

static void same_or_abort(const char *what, const float *now, const float *before, size_t n,
                          ddof_context *ctx, ddof_status s)
{
    if (memcmp(now, before, n * sizeof *now) != 0) {
        fprintf(stderr, "fuzz_matte: status %d (%s): %s changed\n", (int)s,
                ddof_context_last_error(ctx), what);
        abort();
    }
}

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_reader r = {data, size, 0};
    const uint32_t w = 1u + fuzz_byte(&r) % MAX_SIDE, h = 1u + fuzz_byte(&r) % MAX_SIDE;
    const uint32_t ch = 1u + fuzz_byte(&r) % 4u;
    const uint32_t mch = fuzz_byte(&r) % (2u * DDOF_MATTE_MAX_RANKS + 2u);
    const uint32_t mw = fuzz_byte(&r) < 224 ? w : 1u + fuzz_byte(&r) % MAX_SIDE;
    const uint32_t mh = fuzz_byte(&r) < 224 ? h : 1u + fuzz_byte(&r) % MAX_SIDE;
    const uint32_t mpad = fuzz_byte(&r) < 192 ? 0u : fuzz_byte(&r) % MAX_PAD;
    const size_t mstride = (size_t)mw * (mch ? mch : 1u) + mpad;
    const size_t pixels = (size_t)w * h, mfloats = mstride * mh;
    float *color = malloc(pixels * ch * sizeof *color), *map = malloc(pixels * sizeof *map);
    float *fg = malloc(pixels * 4 * sizeof *fg), *fg_map = malloc(pixels * sizeof *fg_map);
    float *matte = malloc(mfloats * sizeof *matte), *matte0 = malloc(mfloats * sizeof *matte);
    float *out = malloc(pixels * ch * sizeof *out), *out0 = malloc(pixels * ch * sizeof *out);
    float *coc = malloc(pixels * sizeof *coc), *coc0 = malloc(pixels * sizeof *coc);
    ddof_context *ctx = NULL;
    if (!color || !map || !fg || !fg_map || !matte || !matte0 || !out || !out0 || !coc || !coc0)
        goto done;
    const int from_depth = fuzz_byte(&r) & 1;
    for (size_t i = 0; i < pixels * ch; i++)
        color[i] = fuzz_float(&r, 2.0f);
    for (size_t i = 0; i < pixels; i++) {
        map[i] = from_depth ? 0.5f + fuzz_float(&r, 20.0f) : fuzz_float(&r, 30.0f);
        fg_map[i] = from_depth ? 0.3f + fuzz_float(&r, 2.0f) : fuzz_float(&r, 30.0f);
    }
    for (size_t i = 0; i < pixels * 4; i++)
        fg[i] = (float)fuzz_byte(&r) / 255.0f;
    /* Ids: a few objects mostly (so that ranks match across pixels), any bits now and then. */
    for (size_t i = 0; i < mfloats; i++) {
        if (i % 2 == 0) {
            const uint32_t bits = fuzz_byte(&r) < 200 ? 0x3f000000u + fuzz_byte(&r) % 4u
                                                      : fuzz_u32(&r);
            memcpy(&matte[i], &bits, sizeof bits);
        } else {
            matte[i] = fuzz_byte(&r) < 230 ? (float)fuzz_byte(&r) / 255.0f : fuzz_float(&r, 2.0f);
        }
    }
    memcpy(matte0, matte, mfloats * sizeof *matte);
    for (size_t i = 0; i < pixels * ch; i++)
        out[i] = out0[i] = -7.0f;
    for (size_t i = 0; i < pixels; i++)
        coc[i] = coc0[i] = -7.0f;

    ddof_context_options co;
    ddof_context_options_init(&co);
    co.thread_count = 1u + fuzz_byte(&r) % 3u;
    if (ddof_context_create(&co, &ctx) != DDOF_OK)
        goto done;
    ddof_params p;
    ddof_params_init(&p);
    p.silhouettes = (ddof_layer_mode)(fuzz_byte(&r) % 4u); /* 3: not a value */
    p.coc_signed = fuzz_byte(&r) % 2u;
    p.near_layer = (ddof_layer_mode)(fuzz_byte(&r) % 3u);
    p.highlights = (ddof_layer_mode)(fuzz_byte(&r) % 3u);
    p.background = (ddof_layer_mode)(fuzz_byte(&r) % 3u);
    ddof_camera cam;
    ddof_camera_init(&cam);
    cam.focal_length_mm = 20.0 + fuzz_byte(&r);
    cam.fstop = 0.2 + fuzz_byte(&r) / 16.0;
    cam.focus_distance_m = 0.5 + fuzz_byte(&r) / 8.0;
    ddof_frame f;
    ddof_frame_init(&f);
    f.color = (ddof_image_in){color, w, h, ch, 0};
    if (from_depth) {
        f.depth = (ddof_image_in){map, w, h, 1, 0};
        f.camera = &cam;
    } else {
        f.coc = (ddof_image_in){map, w, h, 1, 0};
    }
    if (fuzz_byte(&r) < 48) {
        f.foreground_color = (ddof_image_in){fg, w, h, 4, 0};
        if (from_depth)
            f.foreground_depth = (ddof_image_in){fg_map, w, h, 1, 0};
        else
            f.foreground_coc = (ddof_image_in){fg_map, w, h, 1, 0};
    }
    /* coc_out: none, its own buffer, or (refused) a place inside the matte or the output */
    const int with_matte = fuzz_byte(&r) >= 8;
    const uint8_t where = fuzz_byte(&r) % 8u;
    int coc_own = 0;
    if (where == 1 || where == 2) {
        f.coc_out = (ddof_image){coc, w, h, 1, 0};
        coc_own = 1;
    } else if (where == 3 && with_matte && mfloats >= pixels) {
        /* At its first or its last row's first float: inside the matte's pixels, never in the
         * padding after its last row (which is no part of it). */
        const size_t last = (size_t)(mh - 1) * mstride;
        const size_t at = fuzz_byte(&r) % 2u && last + pixels <= mfloats ? last : 0;
        f.coc_out = (ddof_image){matte + at, w, h, 1, 0};
    } else if (where == 4) {
        f.coc_out = (ddof_image){out + (pixels * ch - pixels) * (fuzz_byte(&r) % 2u), w, h, 1, 0};
    }
    const ddof_image_in mi = {matte, mw, mh, mch, mpad ? mstride * sizeof(float) : 0u};
    const ddof_image oi = {out, w, h, ch, 0};
    const ddof_status s =
        ddof_render_frame_with_matte(ctx, &p, &f, with_matte ? &mi : NULL, &oi, NULL);
    if (!fuzz_known_status(s)) {
        fprintf(stderr, "fuzz_matte: unknown status %d\n", (int)s);
        abort();
    }
    if ((where == 3 || where == 4) && f.coc_out.pixels && s == DDOF_OK) {
        fprintf(stderr, "fuzz_matte: coc_out inside the %s was accepted\n",
                where == 3 ? "matte" : "output");
        abort();
    }
    same_or_abort("the matte", matte, matte0, mfloats, ctx, s);
    if (s != DDOF_OK) {
        same_or_abort("the output", out, out0, pixels * ch, ctx, s);
        if (coc_own)
            same_or_abort("coc_out", coc, coc0, pixels, ctx, s);
        if (!ddof_context_last_error(ctx)[0]) {
            fprintf(stderr, "fuzz_matte: status %d without a message\n", (int)s);
            abort();
        }
    } else {
        for (size_t i = 0; i < pixels * ch; i++)
            if (!isfinite(out[i])) {
                fprintf(stderr, "fuzz_matte: DDOF_OK with %g at value %zu\n", (double)out[i], i);
                abort();
            }
    }
done:
    ddof_context_free(ctx);
    free(color);
    free(map);
    free(fg);
    free(fg_map);
    free(matte);
    free(matte0);
    free(out);
    free(out0);
    free(coc);
    free(coc0);
    return 0;
}
