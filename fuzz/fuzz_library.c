/* SPDX-License-Identifier: MIT */
/* fuzz_library.c - libddof's entry points on fuzzed sizes, channel counts, row strides, CoC,
 * depth, camera, curve and params: ddof_diffuse, ddof_diffuse_layers (with and without a
 * foreground element), ddof_depth_of_field, ddof_coc_from_camera, ddof_coc_from_curve and
 * ddof_focus_map;
 * params of every size the struct rules allow (ddof_params_init_sized, older and newer).
 *
 * The buffers are always as large as the description handed over says (a caller that lies
 * about its buffers is outside any C API's contract). Checked: a call returns a known status;
 * on DDOF_OK every output value is finite; on an error the output is untouched and there is a
 * message. Colour, CoC, depth and every parameter take raw float and double bit patterns (NaN,
 * infinities, denormals, values near FLT_MAX) as well as plausible values. */
#ifndef DDOF_EXPERIMENTAL /* ddof_focus_map (the build may define it already) */
#define DDOF_EXPERIMENTAL
#endif
#include <ddof.h>

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_SIDE 48u
#define MAX_STRIDE_PAD 5u

typedef struct reader {
    const uint8_t *data;
    size_t size, at;
} reader;

static uint8_t byte(reader *r)
{
    return r->at < r->size ? r->data[r->at++] : 0;
}

static uint32_t u32(reader *r)
{
    uint32_t v = 0;
    int i;
    for (i = 0; i < 4; i++)
        v = v << 8 | byte(r);
    return v;
}

/* A float: often a plausible value, sometimes a raw bit pattern (NaN, inf, denormal, huge). */
static float any_float(reader *r, float scale)
{
    const uint8_t kind = byte(r);
    if (kind < 200)
        return scale * (float)byte(r) / 255.0f;
    if (kind < 230)
        return -scale * (float)byte(r) / 255.0f;
    {
        const uint32_t bits = u32(r);
        float f;
        memcpy(&f, &bits, sizeof f);
        return f;
    }
}

static double any_double(reader *r, double scale)
{
    const uint8_t kind = byte(r);
    if (kind < 220)
        return scale * (0.01 + (double)byte(r)) / 64.0;
    {
        uint64_t bits = (uint64_t)u32(r) << 32 | u32(r);
        double d;
        memcpy(&d, &bits, sizeof d);
        return d;
    }
}

static int known_status(ddof_status s)
{
    return s == DDOF_OK || ddof_status_string(s) != NULL;
}

/* The checks every call gets. `out` holds `floats` values of which `written` describe the
 * image (the rest is padding, which must not change either). */
static void check_call(ddof_context *ctx, const char *what, ddof_status s, const float *out,
                       const float *before, size_t floats, const ddof_image *image)
{
    size_t x, y, c;
    if (!known_status(s)) {
        fprintf(stderr, "fuzz_library: %s: unknown status %d\n", what, (int)s);
        abort();
    }
    if (s != DDOF_OK) {
        if (memcmp(out, before, floats * sizeof *out) != 0) {
            fprintf(stderr, "fuzz_library: %s failed (%s) but wrote its output\n", what,
                    ddof_context_last_error(ctx));
            abort();
        }
        if (!ddof_context_last_error(ctx)[0]) {
            fprintf(stderr, "fuzz_library: %s failed without a message\n", what);
            abort();
        }
        return;
    }
    for (y = 0; y < image->height; y++) {
        const size_t stride = image->row_stride ? image->row_stride
                                                : (size_t)image->width * image->channels;
        for (x = 0; x < image->width; x++)
            for (c = 0; c < image->channels; c++) {
                const float v = out[y * stride + x * image->channels + c];
                if (!isfinite(v)) {
                    fprintf(stderr, "fuzz_library: %s returned DDOF_OK with %g at (%zu, %zu) "
                            "channel %zu\n", what, (double)v, x, y, c);
                    abort();
                }
            }
    }
}

/* The focal-plane view of the colour by the depth read as a CoC (any values), with the
 * camera's legend: a known status; on DDOF_OK every pixel in one band, on an error the map
 * untouched with a message. */
static void check_focus_map(ddof_context *ctx, const ddof_image_in *color,
                            const ddof_image_in *coc, const ddof_camera *camera, size_t pixels)
{
    uint8_t *map = malloc(pixels * 3);
    uint64_t counts[3] = {0, 0, 0};
    if (!map)
        return;
    memset(map, 0xA5, pixels * 3);
    const ddof_status s = ddof_focus_map(ctx, color, coc, camera, map, pixels * 3, counts);
    size_t i = 0;
    if (s != DDOF_OK)
        while (i < pixels * 3 && map[i] == 0xA5)
            i++;
    if (!known_status(s) || (s == DDOF_OK && counts[0] + counts[1] + counts[2] != pixels) ||
        (s != DDOF_OK && (i != pixels * 3 || !ddof_context_last_error(ctx)[0]))) {
        fprintf(stderr, "fuzz_library: ddof_focus_map: status %d, counts %llu %llu %llu of "
                "%zu, map %s (%s)\n", (int)s, (unsigned long long)counts[0],
                (unsigned long long)counts[1], (unsigned long long)counts[2], pixels,
                i == pixels * 3 ? "untouched" : "written", ddof_context_last_error(ctx));
        abort();
    }
    free(map);
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
    reader r = {data, size, 0};
    ddof_context_options co;
    ddof_context *ctx = NULL;
    ddof_params params;
    ddof_camera camera;
    static float aperture[64];
    ddof_curve curve;
    ddof_foreground fg;
    const uint32_t w = 1u + byte(&r) % MAX_SIDE, h = 1u + byte(&r) % MAX_SIDE;
    const uint32_t cch = 1u + byte(&r) % 4u, zch = 1u + byte(&r) % 4u;
    const uint32_t cpad = byte(&r) % MAX_STRIDE_PAD, zpad = byte(&r) % MAX_STRIDE_PAD;
    const uint32_t opad = byte(&r) % MAX_STRIDE_PAD;
    const size_t cstride = (size_t)w * cch + cpad, zstride = (size_t)w * zch + zpad;
    const size_t ostride = (size_t)w * cch + opad;
    const size_t cfloats = cstride * h, zfloats = zstride * h, ofloats = ostride * h;
    float *color = malloc(cfloats * sizeof *color), *coc = malloc(zfloats * sizeof *coc);
    float *out = malloc(ofloats * sizeof *out), *before = malloc(ofloats * sizeof *out);
    float *fg_color = malloc((size_t)w * h * 4 * sizeof *fg_color);
    float *fg_coc = malloc((size_t)w * h * 2 * sizeof *fg_coc); /* 1 or 2 channels */
    float *coc_out = malloc((size_t)w * h * sizeof *coc_out);
    float *coc_before = malloc((size_t)w * h * sizeof *coc_before);
    const uint8_t which = byte(&r);
    size_t i;
    ddof_status s;

    if (!color || !coc || !out || !before || !fg_color || !fg_coc || !coc_out || !coc_before)
        goto done;
    for (i = 0; i < cfloats; i++)
        color[i] = any_float(&r, 1e3f);
    for (i = 0; i < zfloats; i++)
        coc[i] = any_float(&r, byte(&r) < 250 ? 40.0f : DDOF_MAX_COC_PX);
    for (i = 0; i < (size_t)w * h * 4; i++)
        fg_color[i] = (float)byte(&r) / 255.0f;
    for (i = 0; i < (size_t)w * h * 2; i++)
        fg_coc[i] = any_float(&r, 30.0f);
    for (i = 0; i < ofloats; i++)
        out[i] = before[i] = -7.0f;
    for (i = 0; i < (size_t)w * h; i++)
        coc_out[i] = coc_before[i] = -7.0f;

    ddof_context_options_init(&co);
    co.thread_count = 1u + byte(&r) % 3u;
    if (ddof_context_create(&co, &ctx) != DDOF_OK)
        goto done;

    ddof_params_init(&params);
    params.solver = (ddof_solver)(byte(&r) % (DDOF_SOLVER_COUNT_ + 1));
    params.substeps = byte(&r) % 6u;
    if (byte(&r) < 200)
        params.beta_scale = any_float(&r, 1.0f);
    if (byte(&r) < 128)
        params.pixel_aspect = any_float(&r, 4.0f);
    params.jacobi_iterations = byte(&r) % 12u;
    params.coc_signed = byte(&r) % 3u;
    params.background = (ddof_layer_mode)(byte(&r) % 4u);
    if (byte(&r) < 128) {
        params.background_threshold_px = any_float(&r, 20.0f);
        params.background_ramp_start_px = any_float(&r, 10.0f);
    }
    params.background_levels = byte(&r) % 10u;
    params.near_spread = (ddof_layer_mode)(byte(&r) % 4u);
    if (byte(&r) < 128)
        params.near_spread_threshold_px = any_float(&r, 20.0f);
    params.method = (ddof_method)(byte(&r) % 3u);
    params.precision = (ddof_precision)(byte(&r) % 3u);

    /* The params as callers of other versions hand them in (ddof.h's struct rules): today's
     * size, an older one (from the first version's up), or a newer caller's larger struct
     * whose unknown tail is zero (read) or set (refused). */
    struct {
        ddof_params p;
        uint8_t tail[16];
    } sized;
    memset(&sized, 0, sizeof sized);
    {
        const uint8_t how = byte(&r);
        size_t size = sizeof params;
        if (how < 32)
            size = offsetof(ddof_params, coc_signed) +
                   byte(&r) % (sizeof params - offsetof(ddof_params, coc_signed));
        else if (how < 64)
            size = sizeof params + 1u + byte(&r) % sizeof sized.tail;
        ddof_params_init_sized(&sized.p, size);
        memcpy(&sized.p, &params, size < sizeof params ? size : sizeof params);
        sized.p.struct_size = (uint32_t)size;
        if (how < 64 && size > sizeof params && byte(&r) < 64)
            sized.tail[byte(&r) % (size - sizeof params)] = 1u + byte(&r) % 255u;
    }
    const ddof_params *pp = &sized.p;

    {
        const ddof_image_in ci = {color, w, h, cch, byte(&r) < 128 ? 0u : (uint32_t)cstride};
        const ddof_image_in zi = {coc, w, h, zch, byte(&r) < 128 ? 0u : (uint32_t)zstride};
        const ddof_image oi = {out, w, h, cch, byte(&r) < 128 ? 0u : (uint32_t)ostride};
        const ddof_image co_img = {coc_out, w, h, 1, 0};
        const ddof_image_in ci_tight = {color, w, h, cch, 0};
        const ddof_image_in zi_tight = {coc, w, h, 1, 0};
        (void)ci_tight;
        switch (which % 6u) {
        case 0:
            s = ddof_diffuse(ctx, pp, &ci, &zi, &oi, NULL);
            check_call(ctx, "ddof_diffuse", s, out, before, ofloats, &oi);
            break;
        case 1: {
            ddof_stats stats = {.struct_size = sizeof stats};
            const int with_fg = byte(&r) & 1;
            ddof_foreground_init(&fg);
            fg.color = (ddof_image_in){fg_color, w, h, 4, 0};
            fg.coc = (ddof_image_in){fg_coc, w, h, 1, 0};
            fg.premultiplied = byte(&r) % 3u;
            s = ddof_diffuse_layers(ctx, pp, &ci, &zi, with_fg ? &fg : NULL, &oi, &stats);
            check_call(ctx, "ddof_diffuse_layers", s, out, before, ofloats, &oi);
            break;
        }
        case 2:
            ddof_camera_init(&camera);
            camera.focal_length_mm = any_double(&r, 50.0);
            camera.sensor_width_mm = any_double(&r, 36.0);
            camera.sensor_fit = (ddof_sensor_fit)(byte(&r) % 4u);
            camera.fstop = any_double(&r, 2.0);
            camera.focus_distance_m = any_double(&r, 3.0);
            if (byte(&r) < 128)
                camera.pixel_aspect = any_double(&r, 1.0);
            camera.depth_kind = (ddof_depth_kind)(byte(&r) % 3u);
            camera.depth_unit_m = byte(&r) < 200 ? 1.0 : any_double(&r, 1.0);
            camera.lens_model = (ddof_lens_model)(byte(&r) % 3u);
            if (byte(&r) < 96) { /* an aperture: polygons, ellipses, and out-of-range values */
                camera.aperture_blades = byte(&r) % 20u;
                camera.aperture_rotation_deg = any_double(&r, 90.0);
                camera.aperture_ratio = byte(&r) < 128 ? 1.0 : any_double(&r, 1.0);
                camera.aperture_catseye = byte(&r) < 160 ? 0.0 : any_double(&r, 0.5);
                if (byte(&r) < 64) { /* an aperture image, 0..8 per side (0: refused) */
                    camera.aperture_image_width = byte(&r) % 9u;
                    camera.aperture_image_height = byte(&r) % 9u;
                    for (uint32_t i = 0; i < 64; i++)
                        aperture[i] = (float)any_double(&r, 1.0);
                    camera.aperture_image = aperture;
                }
            }
            switch (byte(&r) % 3u) {
            case 0:
                s = ddof_depth_of_field(ctx, pp, &camera, &ci, &zi, &oi, NULL);
                check_call(ctx, "ddof_depth_of_field", s, out, before, ofloats, &oi);
                break;
            case 1:
                s = ddof_coc_from_camera(ctx, &camera, &zi_tight, &co_img);
                check_call(ctx, "ddof_coc_from_camera", s, coc_out, coc_before,
                           (size_t)w * h, &co_img);
                break;
            default:
                check_focus_map(ctx, &ci, &zi_tight, &camera, (size_t)w * h);
                break;
            }
            break;
        case 3:
            ddof_curve_init(&curve);
            curve.near_blur_px = any_double(&r, 20.0);
            curve.near_start = any_double(&r, 1.0);
            curve.near_end = any_double(&r, 2.0);
            curve.far_start = any_double(&r, 3.0);
            curve.far_end = any_double(&r, 6.0);
            curve.far_blur_px = any_double(&r, 20.0);
            curve.signed_coc = byte(&r) % 3u;
            s = ddof_coc_from_curve(ctx, &curve, &zi_tight, &co_img);
            check_call(ctx, "ddof_coc_from_curve", s, coc_out, coc_before, (size_t)w * h,
                       &co_img);
            break;
        case 4: {
            /* An object matte: 0..4 ranks (odd channel counts too), ids of any bits, coverage
             * of any value, its own width now and then. */
            const uint32_t channels = byte(&r) % 9u;
            const uint32_t mw = byte(&r) < 240 ? w : 1u + byte(&r) % MAX_SIDE;
            float *matte = malloc((size_t)mw * h * (channels ? channels : 1u) * sizeof *matte);
            if (!matte)
                break;
            for (i = 0; i < (size_t)mw * h * channels; i++) {
                const uint32_t bits = byte(&r) < 128 ? 0x3f000000u + byte(&r) % 4u : u32(&r);
                if (i % 2 == 0)
                    memcpy(&matte[i], &bits, sizeof bits);
                else
                    matte[i] = byte(&r) < 240 ? (float)byte(&r) / 255.0f : any_float(&r, 2.0f);
            }
            ddof_frame frame;
            ddof_frame_init(&frame);
            frame.color = ci;
            frame.coc = zi;
            const ddof_image_in mi = {matte, mw, h, channels, 0};
            s = ddof_render_frame_with_matte(ctx, pp, &frame, byte(&r) < 16 ? NULL : &mi, &oi,
                                             NULL);
            check_call(ctx, "ddof_render_frame_with_matte", s, out, before, ofloats, &oi);
            free(matte);
            break;
        }
        default: {
            /* A foreground element of its own size and strides, to reach the mismatch checks. */
            const uint32_t fw = byte(&r) & 1 ? w : 1u + byte(&r) % MAX_SIDE;
            ddof_foreground_init(&fg);
            fg.color = (ddof_image_in){fg_color, fw <= w ? fw : w, h, 4, 0};
            fg.coc = (ddof_image_in){fg_coc, fw <= w ? fw : w, h, byte(&r) & 1 ? 1u : 2u, 0};
            if (fg.coc.channels == 2)
                fg.coc.width = fg.coc.width / 2 ? fg.coc.width / 2 : 1;
            s = ddof_diffuse_layers(ctx, pp, &ci, &zi, &fg, &oi, NULL);
            check_call(ctx, "ddof_diffuse_layers (foreground)", s, out, before, ofloats, &oi);
            break;
        }
        }
    }

done:
    ddof_context_free(ctx);
    free(color);
    free(coc);
    free(out);
    free(before);
    free(fg_color);
    free(fg_coc);
    free(coc_out);
    free(coc_before);
    return 0;
}
