/* SPDX-License-Identifier: MIT */
/* test_cli_results.c - the `ddof` command's outputs against the library called directly on the
 * same data (bit for bit for float output): the values, the data and display windows, the
 * focal-plane view, the cards. Run as a user runs it, on files written by the test.
 *
 *   test_cli_results DDOF_BINARY CASE SCRATCH_DIR
 * CASE: cards values window focus_map */
#include "cli_test.h"

#include <cJSON.h>
#include <png.h>

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* --cards: a scene of textured cards (plugin/apps/cli/cards_scene.h). Two cards, an EXR and a
 * PNG, out of focus at 1 m and 6 m before a 3 m focus: the output is ddof_render_cards on the
 * same cards, bit for bit (the PNG decoded here from its bytes, sRGB to linear, premultiplied);
 * bad scenes are exit 2 with nothing written. */
static int case_cards(void)
{
    enum { TW = 8, TH = 6 };
    static float tex[TW * TH * 4], png_tex[TW * TH * 4], ref[N * 4];
    static uint8_t png_bytes[TW * TH * 4];
    static const char *const names[4] = {"R", "G", "B", "A"};
    const exrio_pixel_type types[4] = {EXRIO_FLOAT, EXRIO_FLOAT, EXRIO_FLOAT, EXRIO_FLOAT};
    static float planes[4][TW * TH];
    const void *cplanes[4] = {planes[0], planes[1], planes[2], planes[3]};
    const exrio_box box = test_box(0, 0, TW, TH);
    const char *json = test_path(dir, "cards.json"), *out = test_path(dir, "cards.exr");
    png_image png;
    for (int i = 0; i < TW * TH; i++) {
        for (int c = 0; c < 3; c++)
            planes[c][i] = tex[i * 4 + c] = (float)((i * (c + 3)) % 7) / 6.0f;
        planes[3][i] = tex[i * 4 + 3] = 1.0f;
        for (int c = 0; c < 4; c++)
            png_bytes[i * 4 + c] = (uint8_t)(c == 3 ? 128 + (i % 2) * 127 : (i * 37 + c * 50) % 256);
        const float a = png_bytes[i * 4 + 3] / 255.0f;
        for (int c = 0; c < 3; c++) {
            const float v = png_bytes[i * 4 + c] / 255.0f;
            png_tex[i * 4 + c] = (v <= 0.04045f ? v / 12.92f : powf((v + 0.055f) / 1.055f, 2.4f)) * a;
        }
        png_tex[i * 4 + 3] = a;
    }
    CHECK(test_write_exr(test_path(dir, "far.exr"), &box, &box, 4, names, types, cplanes,
                         EXRIO_COMPRESSION_ZIP) == 0);
    memset(&png, 0, sizeof png);
    png.version = PNG_IMAGE_VERSION;
    png.width = TW;
    png.height = TH;
    png.format = PNG_FORMAT_RGBA;
    CHECK(png_image_write_to_file(&png, test_path(dir, "near.png"), 0, png_bytes, 0, NULL) != 0);
    const char *scene =
        "{\"camera\": {\"focal_length_mm\": 50, \"sensor_width_mm\": 36, \"sensor_fit\": \"AUTO\","
        " \"fstop\": 1.4, \"focus_distance_m\": 3, \"resolution\": [48, 32], \"pixel_aspect\": 1},"
        " \"cards\": [{\"image\": \"far.exr\", \"corners\": [[-3, -2, -6], [3, -2, -6], [3, 2, -6],"
        " [-3, 2, -6]]}, {\"image\": \"near.png\", \"corners\": [[-0.2, -0.1, -1], [0.1, -0.1, -1],"
        " [0.1, 0.15, -1]], \"uv\": [[0, 0], [1, 0], [1, 1]]}]}";
    test_write_file(json, scene, strlen(scene));
    CHECK(ddof("--cards", json, "-o", out, "--pixel-type", "float", NULL) == 0);
    {
        ddof_context *ctx = NULL;
        ddof_camera cam;
        ddof_card cards[2];
        static const float quad[4][3] = {{-3, -2, -6}, {3, -2, -6}, {3, 2, -6}, {-3, 2, -6}};
        static const float tri[3][3] = {{-0.2f, -0.1f, -1}, {0.1f, -0.1f, -1}, {0.1f, 0.15f, -1}};
        static const float uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        memset(cards, 0, sizeof cards);
        cards[0].vertex_count = 4;
        cards[1].vertex_count = 3;
        memcpy(cards[0].position, quad, sizeof quad);
        memcpy(cards[0].uv, uv, sizeof uv);
        memcpy(cards[1].position, tri, sizeof tri);
        memcpy(cards[1].uv, uv, 3 * sizeof uv[0]);
        cards[0].texture = (ddof_image_in){tex, TW, TH, 4, 0};
        cards[1].texture = (ddof_image_in){png_tex, TW, TH, 4, 0};
        camera_50mm(&cam, 1.4, 3.0);
        memset(ref, 0, sizeof ref);
        CHECK(ddof_context_create(NULL, &ctx) == DDOF_OK);
        CHECK(ddof_render_cards(ctx, NULL, &cam, cards, 2, &(ddof_image){ref, W, H, 4, 0}) ==
              DDOF_OK);
        ddof_context_free(ctx);
    }
    CHECK(compare_output(out, ref, 1, 0.0, 0) == 0);
    /* On a named GL backend the device draws them: within the GL tests' 1e-4 of the CPU (exit
     * 3 where OSMesa is missing: nothing to compare). */
    {
        const char *gl_out = test_path(dir, "cards_gl.exr");
        const int rc = ddof("--cards", json, "-o", gl_out, "--pixel-type", "float", "--backend",
                            "osmesa", NULL);
        CHECK(rc == 0 || (rc == 3 && err_contains("--backend osmesa is not available")));
        if (rc == 0) { /* close, and not the CPU's bits: the device drew */
            CHECK(compare_output(gl_out, ref, 0, 1e-4, 0) == 0);
            CHECK(compare_output(gl_out, ref, 1, 0.0, 0) > 0);
        }
    }

#define BAD_SCENE(text, message)                                                              \
    do {                                                                                      \
        test_write_file(json, text, strlen(text));                                            \
        CHECK(ddof("--cards", json, "-o", test_path(dir, "bad.exr"), NULL) == 2);             \
        CHECK_MSG(err_contains(message), "wanted '%s'", message);                             \
        CHECK(!test_file_exists(test_path(dir, "bad.exr")));                                  \
    } while (0)
#define CAMERA "{\"camera\": {\"focal_length_mm\": 50, \"sensor_width_mm\": 36, \"sensor_fit\": " \
               "\"AUTO\", \"fstop\": 1.4, \"focus_distance_m\": 3, \"resolution\": [48, 32], "     \
               "\"pixel_aspect\": 1}, "
    BAD_SCENE(CAMERA "\"cards\": []}", "at least one card");
    BAD_SCENE(CAMERA "\"cards\": [{\"image\": \"missing.exr\", \"corners\": [[0, 0, -1], "
              "[1, 0, -1], [1, 1, -1], [0, 1, -1]]}]}", "missing.exr");
    BAD_SCENE(CAMERA "\"cards\": [{\"image\": \"far.exr\", \"corners\": [[0, 0, -1], [1, 0, -1]]}]}",
              "needs \"corners\"");
    BAD_SCENE(CAMERA "\"cards\": [{\"image\": \"far.exr\", \"corners\": [[0, 0, 1], [1, 0, 1], "
              "[1, 1, 1], [0, 1, 1]]}]}", "behind");
    BAD_SCENE("{\"camera\": {\"focal_length_mm\": 50}, \"cards\": [{}]}", "missing");
#undef CAMERA
#undef BAD_SCENE
    CHECK(ddof("--cards", json, test_path(dir, "in.exr"), "-o", out, NULL) == 2);
    CHECK(err_contains("no input file"));
    CHECK(ddof("--cards", json, "-o", out, "--frames", "1-3", NULL) == 2);
    CHECK(err_contains("no --frames"));
    return test_finish("test_cli cards");
}

static int case_values(void)
{
    static scene s;
    static float ref[N * 4], ref2[N * 4];
    const char *in = test_path(dir, "in.exr");
    reference r;
    ddof_stats stats;
    char *text;
    int bad;

    make_scene(&s, 0);
    write_scene(in, &s, 1);
    memset(&r, 0, sizeof r);
    r.kind = REF_CAMERA;
    camera_50mm(&r.camera, 2.0, 3.0);

    /* Camera flags, float output: bit-exact with ddof_depth_of_field. */
    r.substeps = 3;
    r.heat_kernel = 1;
    library_result(&s, &r, ref, &stats);
    CHECK(ddof(in, "-o", test_path(dir, "out.exr"), "--focal-length", "50", "--sensor-width",
               "36", "--fstop", "2", "--focus", "3", "--pixel-type", "float", "--substeps", "3",
               "--solver", "thomas", "--kernel", "heat", "--threads", "1", "--stats",
               test_path(dir, "stats.json"), NULL) == 0);
    bad = compare_output(test_path(dir, "out.exr"), ref, 1, 0.0, 0);
    CHECK_MSG(bad == 0, "%d values differ from ddof_depth_of_field", bad);
    CHECK(out_contains("in.exr -> ") && out_contains("thomas x3"));
    text = test_read_file(test_path(dir, "stats.json"), NULL);
    CHECK(text != NULL);
    if (text) {
        cJSON *root = cJSON_Parse(text);
        const cJSON *frame = cJSON_GetArrayItem(cJSON_GetObjectItem(root, "frames"), 0);
        const cJSON *sim = cJSON_GetObjectItem(frame, "simulated");
        const cJSON *sec = cJSON_GetObjectItem(frame, "seconds");
        CHECK(root && frame && sim && sec);
        CHECK(cJSON_GetObjectItem(sim, "lines_solved") &&
              cJSON_GetObjectItem(sim, "lines_solved")->valuedouble ==
                  (double)stats.lines_solved);
        CHECK(cJSON_GetObjectItem(sim, "substeps")->valuedouble == 3.0);
        /* Where it ran and what it took (libddof 0.3). */
        CHECK(cJSON_IsString(cJSON_GetObjectItem(sim, "backend")) &&
              strcmp(cJSON_GetObjectItem(sim, "backend")->valuestring,
                     ddof_backend_name((ddof_backend_kind)stats.backend)) == 0);
        CHECK(cJSON_IsString(cJSON_GetObjectItem(sim, "renderer")) &&
              cJSON_GetObjectItem(sim, "renderer")->valuestring[0]);
        CHECK(cJSON_IsString(cJSON_GetObjectItem(sim, "backend_note")));
        CHECK(cJSON_IsString(cJSON_GetObjectItem(sim, "method")) &&
              strcmp(cJSON_GetObjectItem(sim, "method")->valuestring, "diffusion") == 0);
        CHECK(cJSON_IsNumber(cJSON_GetObjectItem(sim, "device_bytes")));
        CHECK(cJSON_IsNumber(cJSON_GetObjectItem(sim, "host_bytes")) &&
              cJSON_GetObjectItem(sim, "host_bytes")->valuedouble > 0.0);
        CHECK(strcmp(cJSON_GetObjectItem(cJSON_GetObjectItem(root, "settings"),
                                         "backend")->valuestring, "auto") == 0);
        CHECK(strcmp(cJSON_GetObjectItem(cJSON_GetObjectItem(root, "settings"),
                                         "preset")->valuestring, "default") == 0);
        CHECK(cJSON_IsString(cJSON_GetObjectItem(sim, "why")));
        CHECK(cJSON_GetObjectItem(sec, "frame")->valuedouble > 0.0);
        CHECK(strcmp(cJSON_GetObjectItem(frame, "status")->valuestring, "ok") == 0);
        cJSON_Delete(root);
        free(text);
    }

    /* Presets come from the library: --preset NAME gives the pixels of the library called with
     * ddof_params_init_preset(NAME), bit for bit; no --preset is ddof_params_init (the default
     * preset); a flag overrides the preset's value. Half output rounds the same result. */
    {
        static const char *const names[] = {"preview", "default", "final"};
        size_t k;
        CHECK(DDOF_PRESET_COUNT_ == 3);
        r.substeps = 0;
        r.heat_kernel = 0;
        for (k = 0; k < 3; k++) {
            char out[64];
            r.preset = names[k];
            library_result(&s, &r, ref2, NULL);
            snprintf(out, sizeof out, "preset_%s.exr", names[k]);
            CHECK(ddof(in, "-o", test_path(dir, out), "--focal-length", "50", "--fstop", "2",
                       "--focus", "3", "--preset", names[k], "--pixel-type", "float",
                       NULL) == 0);
            bad = compare_output(test_path(dir, out), ref2, 1, 0.0, 0);
            CHECK_MSG(bad == 0, "--preset %s: %d values differ from ddof_params_init_preset",
                      names[k], bad);
        }
        r.preset = NULL;
        library_result(&s, &r, ref2, NULL);
        CHECK(ddof(in, "-o", test_path(dir, "no_preset.exr"), "--focal-length", "50", "--fstop",
                   "2", "--focus", "3", "--pixel-type", "half", NULL) == 0);
        bad = compare_output(test_path(dir, "no_preset.exr"), ref2, 1, 0.0, 1);
        CHECK_MSG(bad == 0, "no --preset: %d half values differ from ddof_params_init", bad);
        r.preset = "final";
        r.substeps = 2;
        library_result(&s, &r, ref2, NULL);
        CHECK(ddof(in, "-o", test_path(dir, "final2.exr"), "--focal-length", "50", "--fstop",
                   "2", "--focus", "3", "--preset", "final", "--substeps", "2", "--pixel-type",
                   "float", NULL) == 0);
        bad = compare_output(test_path(dir, "final2.exr"), ref2, 1, 0.0, 0);
        CHECK_MSG(bad == 0, "--preset final --substeps 2: %d values differ", bad);
        /* 0.2's names still run, as the presets they became. */
        CHECK(ddof(in, "-o", test_path(dir, "quality.exr"), "--focal-length", "50", "--fstop",
                   "2", "--focus", "3", "--preset", "quality", "--substeps", "2", "--pixel-type",
                   "float", NULL) == 0 && err_contains("now called --preset final"));
        CHECK(compare_output(test_path(dir, "quality.exr"), ref2, 1, 0.0, 0) == 0);
        r.preset = NULL;
    }

    /* The thin-lens model differs from the default Cycles one, and matches the library's. */
    r.substeps = 3;
    r.camera.lens_model = DDOF_LENS_THIN_LENS;
    library_result(&s, &r, ref2, NULL);
    CHECK(ddof(in, "-o", test_path(dir, "thin.exr"), "--focal-length", "50", "--fstop", "2",
               "--focus", "3", "--lens", "thin-lens", "--substeps", "3", "--pixel-type", "float",
               NULL) == 0);
    CHECK(compare_output(test_path(dir, "thin.exr"), ref2, 1, 0.0, 0) == 0);
    CHECK(compare_output(test_path(dir, "thin.exr"), ref, 1, 0.0, 0) > 0);

    /* The artist curve. */
    r.kind = REF_CURVE;
    ddof_curve_init(&r.curve);
    r.curve.near_blur_px = 8;
    r.curve.near_start = 0;
    r.curve.near_end = 2;
    r.curve.far_start = 4;
    r.curve.far_end = 12;
    r.curve.far_blur_px = 10;
    library_result(&s, &r, ref2, NULL);
    CHECK(ddof(in, "-o", test_path(dir, "curve.exr"), "--curve", "8,0,2,4,12,10", "--substeps",
               "3", "--pixel-type", "float", NULL) == 0);
    bad = compare_output(test_path(dir, "curve.exr"), ref2, 1, 0.0, 0);
    CHECK_MSG(bad == 0, "curve: %d values differ", bad);

    /* CoC from a channel. */
    r.kind = REF_CHANNEL;
    library_result(&s, &r, ref2, NULL);
    CHECK(ddof(in, "-o", test_path(dir, "chan.exr"), "--coc-channel", "C", "--substeps", "3",
               "--pixel-type", "float", NULL) == 0);
    bad = compare_output(test_path(dir, "chan.exr"), ref2, 1, 0.0, 0);
    CHECK_MSG(bad == 0, "coc channel: %d values differ", bad);
    /* A renderer's CoC pass has a lens shape too: the aperture's flags apply to it (the
     * library's ddof_frame.camera beside the CoC image), the CoC's do not. */
    r.aperture_blades = 5;
    library_result(&s, &r, ref2, NULL);
    CHECK(ddof(in, "-o", test_path(dir, "chan5.exr"), "--coc-channel", "C", "--substeps", "3",
               "--pixel-type", "float", "--aperture-blades", "5", NULL) == 0);
    bad = compare_output(test_path(dir, "chan5.exr"), ref2, 1, 0.0, 0);
    CHECK_MSG(bad == 0, "coc channel with 5 blades: %d values differ", bad);
    r.aperture_blades = 0;
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--coc-channel", "C", "--fstop", "2", NULL) ==
              2 && err_contains("only --camera and the aperture's flags"));

    /* --keep keeps the other channels bit for bit; --write-coc adds the CoC used. */
    CHECK(ddof(in, "-o", test_path(dir, "keep.exr"), "--focal-length", "50", "--fstop", "2",
               "--focus", "3", "--substeps", "3", "--keep", "--write-coc", NULL) == 0);
    {
        uint32_t w, h;
        float *z = test_read_channel(test_path(dir, "keep.exr"), "Z", &w, &h);
        float *c = test_read_channel(test_path(dir, "keep.exr"), "C", &w, &h);
        float *coc = test_read_channel(test_path(dir, "keep.exr"), "coc", &w, &h);
        float expect_coc[N];
        ddof_context *ctx = NULL;
        const ddof_image_in depth_in = {s.z, W, H, 1, 0};
        const ddof_image coc_out = {expect_coc, W, H, 1, 0};
        ddof_context_create(NULL, &ctx);
        camera_50mm(&r.camera, 2.0, 3.0);
        r.camera.signed_coc = 1; /* --write-coc writes the signed CoC the layers use */
        ddof_coc_from_camera(ctx, &r.camera, &depth_in, &coc_out);
        ddof_context_free(ctx);
        CHECK(z && c && coc);
        if (z && c && coc) {
            CHECK(memcmp(z, s.z, sizeof s.z) == 0);
            CHECK(memcmp(c, s.coc, sizeof s.coc) == 0);
            CHECK(memcmp(coc, expect_coc, sizeof expect_coc) == 0);
        }
        free(z);
        free(c);
        free(coc);
    }

    /* The preview is the result, sRGB-encoded. */
    CHECK(ddof(in, "-o", test_path(dir, "p.exr"), "--focal-length", "50", "--fstop", "2",
               "--focus", "3", "--substeps", "3", "--preview", test_path(dir, "p.png"), NULL) == 0);
    {
        png_image img;
        uint8_t *px;
        memset(&img, 0, sizeof img);
        img.version = PNG_IMAGE_VERSION;
        CHECK(png_image_begin_read_from_file(&img, test_path(dir, "p.png")) != 0);
        CHECK(img.width == W && img.height == H);
        img.format = PNG_FORMAT_RGB;
        px = malloc(PNG_IMAGE_SIZE(img));
        CHECK(png_image_finish_read(&img, NULL, px, 0, NULL) != 0);
        {
            /* Pixel (10, 7) of the result, red: linear -> sRGB -> 8 bits. */
            const double v = ref[(7 * W + 10) * 4];
            const double e = v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1 / 2.4) - 0.055;
            const int want = (int)(fmin(fmax(e, 0.0), 1.0) * 255.0 + 0.5);
            CHECK_MSG(abs((int)px[(7 * W + 10) * 3] - want) <= 1, "preview %d, want %d",
                      px[(7 * W + 10) * 3], want);
        }
        free(px);
    }

    /* --compare with the input itself as "truth": the input's error is 0. */
    CHECK(ddof(in, "-o", test_path(dir, "cmp.exr"), "--focal-length", "50", "--fstop", "2",
               "--focus", "3", "--compare", in, NULL) == 0);
    CHECK(out_contains("pinhole input  RMSE 0.00000") && out_contains("ddof result"));
    return test_finish("test_cli values");
}

/* Data window (4,2)-(43,29) of a 64x40 frame, constant depth: the CoC in pixels must follow
 * the frame's 64 px width, not the data window's 40. */
static int case_window(void)
{
    static const char *const names[5] = {"R", "G", "B", "A", "Z"};
    const exrio_pixel_type types[5] = {EXRIO_FLOAT, EXRIO_FLOAT, EXRIO_FLOAT, EXRIO_FLOAT,
                                       EXRIO_FLOAT};
    enum { DW = 40, DH = 28 };
    static float planes[5][DW * DH], color[DW * DH * 4], out[DW * DH * 4], coc[DW * DH];
    const void *cplanes[5] = {planes[0], planes[1], planes[2], planes[3], planes[4]};
    exrio_box data = test_box(4, 2, DW, DH), display = test_box(0, 0, 64, 40);
    const char *in = test_path(dir, "window.exr");
    /* 50 mm f/1.4 focused at 1 m, everything at 6 m: c = f^2 / (N S1) * |Z - S1| / Z. */
    const double c_mm = 50.0 * 50.0 / (1.4 * 1000.0) * 5.0 / 6.0;
    const float coc_px = (float)(c_mm * 64.0 / 36.0);
    ddof_context *ctx = NULL;
    ddof_params params;
    exrio_image image;
    char error[1024];
    int i, c, bad = 0;

    for (i = 0; i < DW * DH; i++) {
        for (c = 0; c < 4; c++)
            planes[c][i] = c == 3 ? 1.0f : (float)(((i % DW) / 3 + (i / DW) / 3 + c) % 2);
        planes[4][i] = 6.0f;
    }
    CHECK(test_write_exr(in, &data, &display, 5, names, types, cplanes,
                         EXRIO_COMPRESSION_NONE) == 0);
    CHECK(ddof(in, "-o", test_path(dir, "out.exr"), "--focal-length", "50", "--fstop", "1.4",
               "--focus", "1", "--substeps", "2", "--pixel-type", "float", "--write-coc",
               "--far-field", "off",
               NULL) == 0);

    for (i = 0; i < DW * DH; i++) {
        for (c = 0; c < 4; c++)
            color[i * 4 + c] = planes[c][i];
        coc[i] = coc_px;
    }
    ddof_context_create(NULL, &ctx);
    ddof_params_init(&params);
    params.substeps = 2;
    {
        const ddof_image_in color_in = {color, DW, DH, 4, 0};
        const ddof_image_in coc_in = {coc, DW, DH, 1, 0};
        const ddof_image out_img = {out, DW, DH, 4, 0};
        CHECK(ddof_diffuse(ctx, &params, &color_in, &coc_in, &out_img, NULL) == DDOF_OK);
    }
    ddof_context_free(ctx);

    CHECK(exrio_open(test_path(dir, "out.exr"), &image, error, sizeof error) == EXRIO_OK);
    CHECK(image.parts[0].data_window.min_x == 4 && image.parts[0].data_window.min_y == 2 &&
          image.parts[0].data_window.max_x == 43 && image.parts[0].data_window.max_y == 29);
    CHECK(image.parts[0].display_window.max_x == 63 && image.parts[0].display_window.max_y == 39);
    CHECK(exrio_load(&image, NULL, error, sizeof error) == EXRIO_OK);
    {
        const float *coc_got = image.channels[exrio_find_channel(&image, "coc", 0)].pixels;
        const float *r = image.channels[exrio_find_channel(&image, "R", 0)].pixels;
        CHECK_MSG(fabsf(coc_got[0] - coc_px) < 1e-4f * coc_px, "CoC %g px, want %g px",
                  (double)coc_got[0], (double)coc_px);
        for (i = 0; i < DW * DH; i++)
            bad += fabsf(r[i] - out[i * 4]) > 1e-4f;
        CHECK_MSG(bad == 0, "%d values differ from a diffusion with CoC %g px", bad,
                  (double)coc_px);
    }
    exrio_close(&image);

    /* Radial depth in a cropped frame: converted about the full frame's centre (ddof_camera's
     * frame and window), so every pixel's CoC is the full frame's at that place. */
    CHECK(ddof(in, "-o", test_path(dir, "radial.exr"), "--focal-length", "50", "--fstop", "1.4",
               "--focus", "1", "--depth-kind", "radial", "--substeps", "2", "--write-coc",
               NULL) == 0);
    CHECK(exrio_open(test_path(dir, "radial.exr"), &image, error, sizeof error) == EXRIO_OK);
    CHECK(exrio_load(&image, NULL, error, sizeof error) == EXRIO_OK);
    {
        const float *coc_got = image.channels[exrio_find_channel(&image, "coc", 0)].pixels;
        const double pw = 36.0 / 64.0;
        double worst = 0.0;
        for (i = 0; i < DW * DH; i++) {
            const double xs = ((i % DW) + 4 + 0.5 - 32.0) * pw, ys = ((i / DW) + 2 + 0.5 - 20.0) * pw;
            const double z = 6000.0 / sqrt(1.0 + (xs * xs + ys * ys) / 2500.0);
            const double want = 50.0 * 50.0 / (1.4 * 1000.0) * (z - 1000.0) / z / pw;
            worst = fmax(worst, fabs(coc_got[i] - want) / want);
        }
        CHECK_MSG(worst < 1e-5, "radial CoC of the crop off the full frame's by %g (relative)",
                  worst);
    }
    exrio_close(&image);

    /* Depth from a second file: same window works, another window is a size mismatch. */
    {
        static const char *const zname[1] = {"Z"};
        const void *zplane[1] = {planes[4]};
        exrio_box other = test_box(0, 0, DW, DH);
        CHECK(test_write_exr(test_path(dir, "depth_same.exr"), &data, &display, 1, zname,
                             types, zplane, EXRIO_COMPRESSION_ZIP) == 0);
        CHECK(test_write_exr(test_path(dir, "depth_other.exr"), &other, NULL, 1, zname, types,
                             zplane, EXRIO_COMPRESSION_ZIP) == 0);
        CHECK(ddof(in, "-o", test_path(dir, "df.exr"), "--depth-file",
                   test_path(dir, "depth_same.exr"), "--focal-length", "50", "--fstop", "1.4",
                   "--focus", "1", "--substeps", "2", "--pixel-type", "float",
                   "--far-field", "off", NULL) == 0);
        CHECK(ddof(in, "-o", test_path(dir, "df2.exr"), "--depth-file",
                   test_path(dir, "depth_other.exr"), "--focal-length", "50", "--fstop", "1.4",
                   "--focus", "1", NULL) == 1);
        CHECK(err_contains("mismatched layer sizes"));
        CHECK(!test_file_exists(test_path(dir, "df2.exr")));
        /* A Blender multilayer depth file beside a plain RGB colour (a lens truth or a
         * composite): its one <layer>.Depth.Z is the depth, whatever the layer's name. */
        static const char *const blender_z[1] = {"RenderLayer.Depth.Z"};
        CHECK(test_write_exr(test_path(dir, "depth_blender.exr"), &data, &display, 1, blender_z,
                             types, zplane, EXRIO_COMPRESSION_ZIP) == 0);
        CHECK(ddof(in, "-o", test_path(dir, "df3.exr"), "--depth-file",
                   test_path(dir, "depth_blender.exr"), "--focal-length", "50", "--fstop", "1.4",
                   "--focus", "1", "--substeps", "2", "--pixel-type", "float",
                   "--far-field", "off", NULL) == 0);
    }
    {
        uint32_t w, h;
        float *a = test_read_channel(test_path(dir, "df.exr"), "G", &w, &h);
        float *b = test_read_channel(test_path(dir, "out.exr"), "G", &w, &h);
        float *c = test_read_channel(test_path(dir, "df3.exr"), "G", &w, &h);
        CHECK(a && b && memcmp(a, b, DW * DH * sizeof(float)) == 0);
        CHECK(a && c && memcmp(a, c, DW * DH * sizeof(float)) == 0);
        free(a);
        free(b);
        free(c);
    }
    return test_finish("test_cli window");
}

/* --focus-map: the focal-plane view. Depth in three bands (near 0.6 m, focus 1 m, far 6 m) of
 * a mid-grey frame: green where in focus, orange where near, blue where far; the PNG is
 * the library's ddof_focus_map() of the camera's signed CoC, byte for byte (its arithmetic and
 * the aperture's legend: tests/test_focus_map.c); it is an output like the others (never the
 * input). */
static int case_focus_map(void)
{
    static const char *const names[5] = {"R", "G", "B", "A", "Z"};
    const exrio_pixel_type types[5] = {EXRIO_FLOAT, EXRIO_FLOAT, EXRIO_FLOAT, EXRIO_FLOAT,
                                       EXRIO_FLOAT};
    enum { FW = 48, FH = 16 };
    static float planes[5][FW * FH], rgb[FW * FH * 4], coc[FW * FH];
    static uint8_t want[FW * FH * 3];
    const void *cplanes[5] = {planes[0], planes[1], planes[2], planes[3], planes[4]};
    exrio_box box = test_box(0, 0, FW, FH);
    const char *in = test_path(dir, "fm.exr"), *map = test_path(dir, "fm.png");
    ddof_context *ctx = NULL;
    ddof_camera cam;
    png_image img;
    uint8_t *px = NULL;
    int i, c, bad = 0;

    for (i = 0; i < FW * FH; i++) {
        const int x = i % FW;
        for (c = 0; c < 4; c++)
            planes[c][i] = c == 3 ? 1.0f : 0.2f;
        planes[4][i] = x < FW / 3 ? 0.6f : x < 2 * FW / 3 ? 1.0f : 6.0f;
        for (c = 0; c < 4; c++)
            rgb[i * 4 + c] = planes[c][i];
    }
    CHECK(test_write_exr(in, &box, NULL, 5, names, types, cplanes, EXRIO_COMPRESSION_NONE) == 0);
    CHECK(ddof(in, "-o", test_path(dir, "fm_out.exr"), "--focal-length", "50", "--fstop", "1.4",
               "--focus", "1", "--focus-map", map, NULL) == 0);
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    CHECK(png_image_begin_read_from_file(&img, map) != 0);
    CHECK(img.width == FW && img.height == FH);
    img.format = PNG_FORMAT_RGB;
    px = malloc(PNG_IMAGE_SIZE(img));
    CHECK(px && png_image_finish_read(&img, NULL, px, 0, NULL) != 0);

    ddof_context_create(NULL, &ctx);
    ddof_camera_init(&cam);
    cam.focal_length_mm = 50;
    cam.fstop = 1.4;
    cam.focus_distance_m = 1;
    cam.signed_coc = 1;
    {
        const ddof_image_in depth_in = {planes[4], FW, FH, 1, 0};
        const ddof_image coc_out = {coc, FW, FH, 1, 0};
        CHECK(ddof_coc_from_camera(ctx, &cam, &depth_in, &coc_out) == DDOF_OK);
        const ddof_image_in color_in = {rgb, FW, FH, 4, 0}, coc_in = {coc, FW, FH, 1, 0};
        CHECK(ddof_focus_map(ctx, &color_in, &coc_in, &cam, want, sizeof want, NULL) ==
              DDOF_OK);
    }
    ddof_context_free(ctx);
    for (i = 0; i < FW * FH * 3; i++)
        bad += px[i] != want[i];
    CHECK_MSG(bad == 0, "%d bytes of the focus map differ from ddof_focus_map()", bad);
    {
        const uint8_t *near = px + (size_t)(8 * FW + 2) * 3, *focus = px + (size_t)(8 * FW + 24) * 3,
                      *far = px + (size_t)(8 * FW + 45) * 3;
        CHECK_MSG(near[0] > near[1] && near[0] > near[2], "near %d %d %d", near[0], near[1],
                  near[2]);
        CHECK_MSG(focus[1] > focus[0] && focus[1] > focus[2], "focus %d %d %d", focus[0],
                  focus[1], focus[2]);
        CHECK_MSG(far[2] > far[0] && far[2] > far[1], "far %d %d %d", far[0], far[1], far[2]);
    }
    free(px);
    /* Never another output: refused before the first frame, so the EXR result (or the
     * preview) is not replaced by the PNG, in one frame or a batch. */
    {
        const char *out = test_path(dir, "fm_twice.exr"), *pv = test_path(dir, "fm_pv.png");
        CHECK(ddof(in, "-o", out, "--focal-length", "50", "--fstop", "2", "--focus", "1",
                   "--focus-map", out, NULL) == 1);
        CHECK(err_contains("the focus map and the output are the same file"));
        CHECK(!test_file_exists(out));
        CHECK(ddof(in, "-o", test_path(dir, "fm_pv.exr"), "--focal-length", "50", "--fstop",
                   "2", "--focus", "1", "--preview", pv, "--focus-map", pv, NULL) == 1);
        CHECK(err_contains("the focus map and the preview are the same file"));
        CHECK(!test_file_exists(pv) && !test_file_exists(test_path(dir, "fm_pv.exr")));
    }
    /* Never the input. */
    CHECK(ddof(in, "-o", test_path(dir, "fm_out2.exr"), "--focal-length", "50", "--fstop", "2",
               "--focus", "1", "--focus-map", in, NULL) == 1);
    CHECK(err_contains("refusing to write") && err_contains("focus map"));
    return test_finish("test_cli focus_map");
}

/* A frame with every pass on says more than ddof_stats.plan's 512 bytes: the command prints
 * and writes the whole plan (ddof_context_last_plan), the passes' lines said last included. */
static int case_whole_plan(void)
{
    enum { PW = 64, PH = 48 };
    static const char *const names[4] = {"R", "G", "B", "coc"};
    const exrio_pixel_type types[4] = {EXRIO_FLOAT, EXRIO_FLOAT, EXRIO_FLOAT, EXRIO_FLOAT};
    static float planes[4][PW * PH];
    const void *cplanes[4] = {planes[0], planes[1], planes[2], planes[3]};
    const exrio_box box = test_box(0, 0, PW, PH);
    const char *in = test_path(dir, "plan.exr"), *json = test_path(dir, "plan.json");
    /* Two blurred backgrounds with bright points, an in-focus bar, a near disc over its end
     * (tests/test_last_plan.c's frame). */
    for (int y = 0; y < PH; y++)
        for (int x = 0; x < PW; x++) {
            const int i = y * PW + x;
            const float dx = (float)x - 26.0f, dy = (float)y - 36.0f;
            for (int c = 0; c < 3; c++)
                planes[c][i] = 0.2f + 0.3f * (float)((i * (c + 5)) % 11) / 10.0f;
            if ((x * 7 + y * 3) % 23 == 0)
                planes[0][i] = 30.0f;
            planes[3][i] = dx * dx + dy * dy < 64.0f          ? -20.0f
                           : x >= 20 && x < 28 && y >= 6 && y < 42 ? 0.0f
                           : y < PH / 2                          ? 20.0f
                                                                 : 9.0f;
        }
    CHECK(test_write_exr(in, &box, NULL, 4, names, types, cplanes, EXRIO_COMPRESSION_NONE) == 0);
    CHECK(ddof(in, "-o", test_path(dir, "plan_out.exr"), "--coc-channel", "coc", "--coc-signed",
               "--aperture-blades", "5", "--highlights", "on", "--far-field", "on",
               "--blurred-edges", "on", "--silhouettes", "on", "--backend", "cpu", "-v",
               "--stats", json, NULL) == 0);
    CHECK(out_contains("plan: highlights: on: ") && out_contains("plan: far field: on: ") &&
          out_contains("plan: silhouettes: on: "));
    CHECK(!out_contains("the plan goes on"));
    char *text = test_read_file(json, NULL);
    cJSON *root = text ? cJSON_Parse(text) : NULL;
    const cJSON *frame = cJSON_GetArrayItem(cJSON_GetObjectItem(root, "frames"), 0);
    const cJSON *plan = cJSON_GetObjectItem(cJSON_GetObjectItem(frame, "simulated"), "plan");
    size_t bytes = 0;
    int silhouettes = 0;
    const cJSON *line;
    cJSON_ArrayForEach(line, plan)
    {
        bytes += strlen(line->valuestring) + 1;
        silhouettes |= strncmp(line->valuestring, "silhouettes: on: ", 17) == 0;
    }
    CHECK_MSG(bytes >= sizeof ((ddof_stats *)0)->plan && silhouettes,
              "the stats file's plan: %zu bytes, silhouettes' line %s", bytes,
              silhouettes ? "there" : "missing");
    cJSON_Delete(root);
    free(text);
    return test_finish("test_cli whole_plan");
}

int main(int argc, char **argv)
{
    static const cli_case cases[] = {
        {"cards", case_cards},
        {"values", case_values},
        {"window", case_window},
        {"focus_map", case_focus_map},
        {"whole_plan", case_whole_plan},
    };
    return cli_test_main(argc, argv, "test_cli_results", cases, sizeof cases / sizeof cases[0]);
}
