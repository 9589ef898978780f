/* SPDX-License-Identifier: MIT */
/* test_cli_inputs.c - what the `ddof` command is given: bad input files (messages and exit
 * statuses against the issue's list), the camera sidecar, the options, a multipart input with
 * --keep, and the messages that name what the user set.
 *
 *   test_cli_inputs DDOF_BINARY CASE SCRATCH_DIR
 * CASE: bad_inputs sidecar options messages keep_parts */
#include "cli_test.h"

#include <cJSON.h>
#include <openexr.h>

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

static int case_bad_inputs(void)
{
    static scene s;
    const char *good = test_path(dir, "good.exr");
    const char *out = test_path(dir, "out.exr");
    static const char key[] = "compression\0compression\0\1\0\0\0";
    size_t size = 0, i;
    char *bytes;

    make_scene(&s, 0);
    write_scene(good, &s, 0);
    bytes = test_read_file(good, &size);

#define RUN_BAD(input, message)                                                              \
    do {                                                                                     \
        CHECK_MSG(ddof(input, "-o", out, "--focal-length", "50", "--fstop", "2", "--focus",  \
                       "3", NULL) == 1, "%s", input);                                        \
        CHECK(err_contains(message));                                                        \
        CHECK(err_contains("failed frame"));                                                 \
        CHECK(!test_file_exists(out));                                                       \
        CHECK(test_count_suffix(dir, ".tmp") == 0);                                          \
    } while (0)

    RUN_BAD(test_path(dir, "missing.exr"), "No such file");
    test_write_file(test_path(dir, "notexr.exr"), "P3\n1 1\n255\n0 0 0\n", 17);
    RUN_BAD(test_path(dir, "notexr.exr"), "not an OpenEXR file");
    test_write_file(test_path(dir, "trunc.exr"), bytes, size * 2 / 3);
    RUN_BAD(test_path(dir, "trunc.exr"), "truncated");
    {
        static const char *const names[3] = {"beauty.R", "beauty.G", "Y"};
        const exrio_pixel_type types[3] = {EXRIO_HALF, EXRIO_HALF, EXRIO_HALF};
        const void *planes[3] = {s.z, s.z, s.z};
        exrio_box box = test_box(0, 0, W, H);
        test_write_exr(test_path(dir, "channels.exr"), &box, NULL, 3, names, types, planes,
                       EXRIO_COMPRESSION_ZIP);
        RUN_BAD(test_path(dir, "channels.exr"), "channels in the file: Y, beauty.G, beauty.R");
    }
    {
        static const char *const names[4] = {"R", "G", "B", "A"};
        const exrio_pixel_type types[4] = {EXRIO_HALF, EXRIO_HALF, EXRIO_HALF, EXRIO_HALF};
        const void *planes[4] = {s.rgba[0], s.rgba[1], s.rgba[2], s.rgba[3]};
        exrio_box box = test_box(0, 0, W, H);
        test_write_exr(test_path(dir, "nodepth.exr"), &box, NULL, 4, names, types, planes,
                       EXRIO_COMPRESSION_ZIP);
        RUN_BAD(test_path(dir, "nodepth.exr"), "no depth channel");
    }
    /* A DWAA header over ZIP data (see test_exr_bad_input.c): read as DWA, found damaged. */
    for (i = 0; bytes && i + sizeof key < size; i++)
        if (memcmp(bytes + i, key, sizeof key - 1) == 0)
            break;
    if (bytes && i + sizeof key < size) {
        bytes[i + sizeof key - 1] = 8;
        test_write_file(test_path(dir, "dwaa.exr"), bytes, size);
        RUN_BAD(test_path(dir, "dwaa.exr"), "damaged or truncated pixel data (DWA");
    } else {
        CHECK_MSG(0, "no compression attribute found");
    }
    free(bytes);
    return test_finish("test_cli bad_inputs");
}

/* Two parts of W x H: "beauty" (R, G, B, A, Z of the scene) and "extra" (one channel Y). */
static void write_two_parts(const char *path, const scene *sc)
{
    static const char *const beauty[5] = {"A", "B", "G", "R", "Z"}; /* sorted, as EXR stores */
    const float *planes[5] = {sc->rgba[3], sc->rgba[2], sc->rgba[1], sc->rgba[0], sc->z};
    exr_context_t ctxt = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    int a = 0, b = 0, c, p;
    CHECK(exr_start_write(&ctxt, path, EXR_WRITE_FILE_DIRECTLY, &init) == 0);
    exr_add_part(ctxt, "beauty", EXR_STORAGE_SCANLINE, &a);
    exr_initialize_required_attr_simple(ctxt, a, W, H, EXR_COMPRESSION_NONE);
    for (c = 0; c < 5; c++)
        exr_add_channel(ctxt, a, beauty[c], EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR, 1, 1);
    exr_add_part(ctxt, "extra", EXR_STORAGE_SCANLINE, &b);
    exr_initialize_required_attr_simple(ctxt, b, W, H, EXR_COMPRESSION_NONE);
    exr_add_channel(ctxt, b, "Y", EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR, 1, 1);
    CHECK(exr_write_header(ctxt) == 0);
    for (p = 0; p < 2; p++) {
        exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
        exr_chunk_info_t cinfo;
        int y;
        for (y = 0; y < H; y++) {
            exr_write_scanline_chunk_info(ctxt, p, y, &cinfo);
            if (y == 0)
                exr_encoding_initialize(ctxt, p, &cinfo, &enc);
            else
                exr_encoding_update(ctxt, p, &cinfo, &enc);
            for (c = 0; c < enc.channel_count; c++) {
                const float *plane = p ? sc->coc : planes[c];
                enc.channels[c].encode_from_ptr = (const uint8_t *)(plane + (size_t)y * W);
                enc.channels[c].user_pixel_stride = 4;
                enc.channels[c].user_line_stride = W * 4;
                enc.channels[c].user_bytes_per_element = 4;
                enc.channels[c].user_data_type = EXR_PIXEL_FLOAT;
            }
            if (y == 0)
                exr_encoding_choose_default_routines(ctxt, p, &enc);
            CHECK(exr_encoding_run(ctxt, p, &enc) == 0);
        }
        exr_encoding_destroy(ctxt, &enc);
    }
    CHECK(exr_finish(&ctxt) == 0);
}

/* Issue 14: --keep on a multipart input would drop the other parts: refused up front, with the
 * reason; without --keep-channels the part is diffused as before. */
static int case_keep_parts(void)
{
    static scene s;
    const char *in = test_path(dir, "two.exr");
    make_scene(&s, 0);
    write_two_parts(in, &s);
#define CAMERA "--focal-length", "50", "--fstop", "2", "--focus", "3"
    CHECK(ddof(in, "-o", test_path(dir, "k.exr"), "--keep", CAMERA, NULL) == 2);
    CHECK(err_contains("has 2 parts") && err_contains("drop the other parts"));
    CHECK(!test_file_exists(test_path(dir, "k.exr")));
    CHECK(ddof(in, "-o", test_path(dir, "k.exr"), "--keep-channels", CAMERA, NULL) == 2);
    CHECK(ddof(in, "-o", test_path(dir, "m.exr"), "--keep-metadata", CAMERA, NULL) == 0);
    CHECK(ddof(in, "-o", test_path(dir, "p.exr"), CAMERA, NULL) == 0);
    CHECK(test_file_exists(test_path(dir, "p.exr")));
#undef CAMERA
    return test_finish("test_cli keep_parts");
}

static int case_sidecar(void)
{
    static scene s;
    const char *in = test_path(dir, "in.exr");
    const char *json = test_path(dir, "camera.json");
    const char *good =
        "{\"focal_length_mm\": 50, \"sensor_width_mm\": 36, \"sensor_fit\": \"AUTO\","
        " \"fstop\": 2.0, \"focus_distance_m\": 3.0, \"resolution\": [48, 32],"
        " \"pixel_aspect\": 1.0, \"depth\": \"planar\", \"unit_scale_m\": 1.0,"
        " \"blender_version\": \"3.4.1\"}";
    static float ref[N * 4];
    reference r;
    make_scene(&s, 0);
    write_scene(in, &s, 0);
    memset(&r, 0, sizeof r);
    r.kind = REF_CAMERA;
    r.substeps = 3;

    test_write_file(json, good, strlen(good));
    camera_50mm(&r.camera, 2.0, 3.0);
    library_result(&s, &r, ref, NULL);
    CHECK(ddof(in, "-o", test_path(dir, "a.exr"), "--camera", json, "--substeps", "3",
               "--pixel-type", "float", NULL) == 0);
    CHECK(compare_output(test_path(dir, "a.exr"), ref, 1, 0.0, 0) == 0);
    /* A flag overrides the sidecar. */
    camera_50mm(&r.camera, 4.0, 3.0);
    library_result(&s, &r, ref, NULL);
    CHECK(ddof(in, "-o", test_path(dir, "b.exr"), "--camera", json, "--fstop", "4",
               "--substeps", "3", "--pixel-type", "float", NULL) == 0);
    CHECK(compare_output(test_path(dir, "b.exr"), ref, 1, 0.0, 0) == 0);

    /* The aperture's keys reach the library's camera; the flags override them. */
    {
        const char *aperture =
            "{\"focal_length_mm\": 50, \"sensor_width_mm\": 36, \"sensor_fit\": \"AUTO\","
            " \"fstop\": 2.0, \"focus_distance_m\": 3.0, \"resolution\": [48, 32],"
            " \"pixel_aspect\": 1.0, \"aperture_blades\": 6, \"aperture_rotation_deg\": -15,"
            " \"aperture_ratio\": 2}";
        test_write_file(json, aperture, strlen(aperture));
        camera_50mm(&r.camera, 2.0, 3.0);
        r.camera.aperture_blades = 6;
        r.camera.aperture_rotation_deg = -15.0;
        r.camera.aperture_ratio = 2.0;
        library_result(&s, &r, ref, NULL);
        CHECK(ddof(in, "-o", test_path(dir, "ap.exr"), "--camera", json, "--substeps", "3",
                   "--pixel-type", "float", NULL) == 0);
        CHECK(compare_output(test_path(dir, "ap.exr"), ref, 1, 0.0, 0) == 0);
        r.camera.aperture_blades = 5;
        r.camera.aperture_ratio = 1.5;
        library_result(&s, &r, ref, NULL);
        CHECK(ddof(in, "-o", test_path(dir, "ap2.exr"), "--camera", json, "--substeps", "3",
                   "--aperture-blades", "5", "--aperture-ratio", "1.5", "--pixel-type", "float",
                   NULL) == 0);
        CHECK(compare_output(test_path(dir, "ap2.exr"), ref, 1, 0.0, 0) == 0);
        CHECK(ddof(in, "-o", test_path(dir, "bad.exr"), "--camera", json, "--aperture-blades",
                   "17", NULL) == 2);
        CHECK(!test_file_exists(test_path(dir, "bad.exr")));
        /* --aperture-image: an EXR's Y channel is the camera's aperture image. */
        {
            static float cross[8 * 8], zeros[8 * 8];
            const char *names[1] = {"Y"};
            const exrio_pixel_type types[1] = {EXRIO_FLOAT};
            const exrio_box box = test_box(0, 0, 8, 8);
            const void *planes[1] = {cross};
            for (int i = 0; i < 64; i++)
                cross[i] = (i % 8 == 3 || i % 8 == 4 || i / 8 == 3 || i / 8 == 4) ? 1.0f : 0.0f;
            CHECK(test_write_exr(test_path(dir, "cross.exr"), &box, &box, 1, names, types,
                                 planes, EXRIO_COMPRESSION_ZIP) == 0);
            static float without[N * 4];
            /* f/0.1: the scene's highlight (30 at 17 m) gets a CoC of 9 px, so it is drawn. */
            r.camera.fstop = 0.1;
            library_result(&s, &r, without, NULL);
            r.camera.aperture_image = cross;
            r.camera.aperture_image_width = r.camera.aperture_image_height = 8;
            library_result(&s, &r, ref, NULL);
            CHECK(memcmp(without, ref, sizeof without) != 0); /* the image is drawn */
            CHECK(ddof(in, "-o", test_path(dir, "ap3.exr"), "--camera", json, "--substeps", "3",
                       "--fstop", "0.1", "--aperture-blades", "5", "--aperture-ratio", "1.5",
                       "--aperture-image", test_path(dir, "cross.exr"), "--pixel-type",
                       "float", NULL) == 0);
            CHECK(compare_output(test_path(dir, "ap3.exr"), ref, 1, 0.0, 0) == 0);
            r.camera.aperture_image = NULL;
            r.camera.aperture_image_width = r.camera.aperture_image_height = 0;
            r.camera.fstop = 2.0;
            planes[0] = zeros;
            CHECK(test_write_exr(test_path(dir, "zeros.exr"), &box, &box, 1, names, types,
                                 planes, EXRIO_COMPRESSION_ZIP) == 0);
            CHECK(ddof(in, "-o", test_path(dir, "bad.exr"), "--camera", json,
                       "--aperture-image", test_path(dir, "zeros.exr"), NULL) == 2);
            CHECK(err_contains("all 0"));
            CHECK(ddof(in, "-o", test_path(dir, "bad.exr"), "--camera", json,
                       "--aperture-image", test_path(dir, "none.exr"), NULL) == 2);
            CHECK(err_contains("--aperture-image"));
            CHECK(!test_file_exists(test_path(dir, "bad.exr")));
        }
        r.camera.aperture_blades = 0;
        r.camera.aperture_rotation_deg = 0.0;
        r.camera.aperture_ratio = 1.0;
    }

    /* A sidecar of another resolution: a warning, and the file's pixels rule. */
    {
        const char *other = "{\"focal_length_mm\": 50, \"sensor_width_mm\": 36, \"sensor_fit\":"
                            " \"AUTO\", \"fstop\": 2, \"focus_distance_m\": 3, \"resolution\":"
                            " [96, 64], \"pixel_aspect\": 1}";
        test_write_file(json, other, strlen(other));
        CHECK(ddof(in, "-o", test_path(dir, "c.exr"), "--camera", json, NULL) == 0);
        CHECK(err_contains("warning") && err_contains("96x64"));
    }

#define BAD_JSON(text, message)                                                              \
    do {                                                                                     \
        test_write_file(json, text, strlen(text));                                           \
        CHECK(ddof(in, "-o", test_path(dir, "bad.exr"), "--camera", json, NULL) == 2);       \
        CHECK(err_contains(message));                                                        \
        CHECK(!test_file_exists(test_path(dir, "bad.exr")));                                 \
    } while (0)

    BAD_JSON("{\"focal_length_mm\": 50", "not valid JSON");
    BAD_JSON("[1, 2]", "must be a JSON object");
    BAD_JSON("{\"focal_length_mm\": 50, \"sensor_width_mm\": 36, \"sensor_fit\": \"AUTO\","
             " \"focus_distance_m\": 3, \"resolution\": [48, 32], \"pixel_aspect\": 1}",
             "missing \"fstop\"");
    BAD_JSON("{\"focal_length_mm\": 50, \"sensor_width_mm\": 36, \"sensor_fit\": \"DIAGONAL\","
             " \"fstop\": 2, \"focus_distance_m\": 3, \"resolution\": [48, 32],"
             " \"pixel_aspect\": 1}", "\"sensor_fit\" must be one of");
    BAD_JSON("{\"focal_length_mm\": \"50\", \"sensor_width_mm\": 36, \"sensor_fit\": \"AUTO\","
             " \"fstop\": 2, \"focus_distance_m\": 3, \"resolution\": [48, 32],"
             " \"pixel_aspect\": 1}", "\"focal_length_mm\" must be a number > 0");
    BAD_JSON("{\"focal_length_mm\": 50, \"sensor_width_mm\": 36, \"sensor_fit\": \"AUTO\","
             " \"fstop\": 2, \"focus_distance_m\": 3, \"resolution\": [48.5, 32],"
             " \"pixel_aspect\": 1}", "\"resolution\" must be [width, height]");
    BAD_JSON("{\"focal_length_mm\": 50, \"sensor_width_mm\": 36, \"sensor_fit\": \"AUTO\","
             " \"fstop\": 2, \"focus_distance_m\": 3, \"resolution\": [48, 32],"
             " \"pixel_aspect\": 1, \"aperture_blades\": 2.5}",
             "\"aperture_blades\" must be a whole number within 0..16");
    BAD_JSON("{\"focal_length_mm\": 50, \"sensor_width_mm\": 36, \"sensor_fit\": \"AUTO\","
             " \"fstop\": 2, \"focus_distance_m\": 3, \"resolution\": [48, 32],"
             " \"pixel_aspect\": 1, \"aperture_ratio\": 0}", "\"aperture_ratio\" is 0");
    BAD_JSON("{\"focal_length_mm\": 50, \"sensor_width_mm\": 36, \"sensor_fit\": \"AUTO\","
             " \"fstop\": 2, \"focus_distance_m\": 3, \"resolution\": [48, 32],"
             " \"pixel_aspect\": 1, \"aperture_rotation_deg\": 400}",
             "aperture_rotation_deg 400 must be within -360..360");
    /* Valid JSON, impossible camera: the library's check, once, before any frame. */
    BAD_JSON("{\"focal_length_mm\": 50, \"sensor_width_mm\": 36, \"sensor_fit\": \"AUTO\","
             " \"fstop\": 2, \"focus_distance_m\": 0.01, \"resolution\": [48, 32],"
             " \"pixel_aspect\": 1}", "bad camera");
    CHECK(ddof(in, "-o", test_path(dir, "bad.exr"), "--camera", test_path(dir, "none.json"),
               NULL) == 2);
    CHECK(err_contains("cannot open camera file"));
    { /* a sidecar is read in one bounded piece: a file over 1 MiB is no sidecar */
        const char *big = test_path(dir, "big.json");
        FILE *f = fopen(big, "wb");
        CHECK(f != NULL);
        for (int k = 0; f && k < (1 << 20) + 1; k++)
            fputc(' ', f);
        if (f)
            fclose(f);
        CHECK(ddof(in, "-o", test_path(dir, "bad.exr"), "--camera", big, NULL) == 2);
        CHECK(err_contains("too large for a camera file (over 1048576 bytes)"));
    }

    /* Issue 14: a pixel aspect the diffusion cannot take is exit 2 before the first frame,
     * with the sidecar's own value (not the float each frame would convert it to). */
#define SIDECAR_ASPECT(value)                                                                    "{\"focal_length_mm\": 50, \"sensor_width_mm\": 36, \"sensor_fit\": \"AUTO\","      \
    " \"fstop\": 2, \"focus_distance_m\": 3, \"resolution\": [48, 32], \"pixel_aspect\": " \
    value "}"
    BAD_JSON(SIDECAR_ASPECT("1e-300"), "pixel_aspect 1e-300 must be within 0.01..100");
    BAD_JSON(SIDECAR_ASPECT("5e-324"), "pixel_aspect 4.94065646e-324 must be within 0.01..100");
    BAD_JSON(SIDECAR_ASPECT("1e300"), "pixel_aspect 1e+300 must be within 0.01..100");
    BAD_JSON(SIDECAR_ASPECT("1e20"), "pixel_aspect 1e+20 must be within 0.01..100");
    {
        const char *edge = SIDECAR_ASPECT("100");
        test_write_file(json, edge, strlen(edge));
        CHECK(ddof(in, "-o", test_path(dir, "edge.exr"), "--camera", json, NULL) == 0);
    }
    /* Issue 14: trailing data, a duplicate key, deep nesting: refused with the byte offset. */
    BAD_JSON("{\"focal_length_mm\": 50, \"sensor_width_mm\": 36, \"sensor_fit\": \"AUTO\","
             " \"fstop\": 2, \"focus_distance_m\": 3, \"resolution\": [48, 32],"
             " \"pixel_aspect\": 1} trailing", "data after the end of the JSON value at byte 147");
    BAD_JSON("{\"focal_length_mm\": 50, \"sensor_width_mm\": 36, \"sensor_fit\": \"AUTO\","
             " \"fstop\": 2, \"focus_distance_m\": 3, \"resolution\": [48, 32],"
             " \"pixel_aspect\": 1, \"fstop\": 8}", "duplicate key \"fstop\" at byte 147 (first at "
             "byte 69)");
    /* Issue 22: the same key through an escape is the same key (cJSON reads both as
     * "fstop"; the first used to win silently). */
    BAD_JSON("{\"focal_length_mm\": 50, \"sensor_width_mm\": 36, \"sensor_fit\": \"AUTO\","
             " \"fstop\": 2, \"focus_distance_m\": 3, \"resolution\": [48, 32],"
             " \"pixel_aspect\": 1, \"fs\\u0074op\": 8}", "duplicate key \"fstop\" at byte 147 "
             "(first at byte 69)");
    BAD_JSON("{\"focal_length_mm\": 50, \"sensor_width_mm\": 36, \"sensor_fit\": \"AUTO\","
             " \"fstop\": 2, \"focus_distance_m\": 3, \"resolution\": [48, 32],"
             " \"pixel_aspect\": 1, \"\\u00e9\\ud83d\\ude00\": 1, \"\xc3\xa9\xf0\x9f\x98\x80\": 2}",
             "duplicate key");
    {
        /* 1e5 brackets: said to be too deep where they become so, not "invalid at 1000". */
        const size_t n = 100000;
        char *deep = malloc(2 * n + 1);
        memset(deep, '[', n);
        memset(deep + n, ']', n);
        deep[2 * n] = '\0';
        test_write_file(json, deep, 2 * n);
        CHECK(ddof(in, "-o", test_path(dir, "bad.exr"), "--camera", json, NULL) == 2);
        CHECK(err_contains("nested deeper than 32 levels at byte 32"));
        free(deep);
    }
    /* Brackets and repeated names inside strings are text, not structure. */
    {
        const char *ok = "{\"focal_length_mm\": 50, \"sensor_width_mm\": 36, \"note\": "
                         "\"[[{ \\\"fstop\\\": 1, \", \"sensor_fit\": \"AUTO\", \"fstop\": 2,"
                         " \"focus_distance_m\": 3, \"resolution\": [48, 32], \"pixel_aspect\": 1,"
                         " \"extra\": {\"fstop\": 4}}";
        test_write_file(json, ok, strlen(ok));
        CHECK(ddof(in, "-o", test_path(dir, "ok.exr"), "--camera", json, NULL) == 0);
    }
#undef SIDECAR_ASPECT
    return test_finish("test_cli sidecar");
}

static int case_options(void)
{
    static scene s;
    const char *in = test_path(dir, "in.exr");
    make_scene(&s, 0);
    write_scene(in, &s, 0);

    CHECK(ddof("--help", NULL) == 0 && out_contains("usage: ddof"));
    {
        /* --help lists the presets with the library's values, not values of its own. */
        ddof_params final;
        char line[128];
        CHECK(ddof_params_init_preset(&final, DDOF_PRESET_FINAL) == DDOF_OK);
        snprintf(line, sizeof line, "final    %s",
                 final.method == DDOF_METHOD_COD4_PREVIEW ? "cod4" : "diffusion");
        CHECK(out_contains(line));
        if (final.method == DDOF_METHOD_DIFFUSION && final.kernel != DDOF_KERNEL_HEAT) {
            snprintf(line, sizeof line, "%s, %s kernel", ddof_solver_name(final.solver),
                     ddof_kernel_name(final.kernel));
            CHECK(out_contains(line));
        } else if (final.method == DDOF_METHOD_DIFFUSION) {
            snprintf(line, sizeof line, "%s, %u sub-step", ddof_solver_name(final.solver),
                     final.substeps);
            CHECK(out_contains(line));
        }
    }
    {
        /* The choices are the library's names in its enum's order (all but the host's GL,
         * which a command has not), not a copy of them. */
        char line[128] = "--backend ";
        int k;
        for (k = 0; k < DDOF_BACKEND_COUNT_; k++)
            if (k != DDOF_BACKEND_HOST_GL)
                snprintf(line + strlen(line), sizeof line - strlen(line), "%s%s",
                         k ? "|" : "", ddof_backend_name((ddof_backend_kind)k));
        CHECK_MSG(out_contains(line), "%s", line);
    }
    CHECK(ddof("--version", NULL) == 0 && out_contains("libddof"));
    CHECK(ddof(in, NULL) == 2 && err_contains("no output file"));
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), NULL) == 2 && err_contains("no camera"));
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--bogus", NULL) == 2 &&
          err_contains("unknown option '--bogus'"));
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--fstop", "fast", NULL) == 2 &&
          err_contains("--fstop wants a number > 0"));
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--solver", "magic", NULL) == 2 &&
          err_contains("thomas | cr | pcr | jacobi | reference | gruen"));
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--preset", "best", NULL) == 2 &&
          err_contains("one of preview | default | final"));
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--method", "gauss", NULL) == 2 &&
          err_contains("diffusion | cod4"));
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--precision", "double", NULL) == 2 &&
          err_contains("float | packed-half"));
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--method", "cod4", "--foreground", "fg.exr",
               "--focal-length", "50", "--fstop", "2", "--focus", "3", NULL) == 2 &&
          err_contains("--method cod4 takes no foreground element"));
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--backend", "cpu", "--gl-plugin", "x.so",
               NULL) == 2 && err_contains("--backend cpu uses none"));
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--coc-channel", "Z", "--foreground", "fg.exr",
               NULL) == 2 && err_contains("--foreground-coc-channel"));
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--background", "sometimes", NULL) == 2 &&
          err_contains("auto | off | on"));
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--backend", "gl", NULL) == 2 &&
          err_contains("one of cpu | auto | egl | osmesa"));
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--compression", "zip:45", NULL) == 2 &&
          err_contains("whole number from 1 (fastest) to 9"));
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--compression", "piz:2", NULL) == 2 &&
          err_contains("only zip, zips, dwaa and dwab take a level"));
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--compression", "dwab:fine", NULL) == 2 &&
          err_contains("the level is a number"));
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--curve", "1,2,3", NULL) == 2 &&
          err_contains("six numbers"));
    CHECK(ddof(in, "-o", test_path(dir, "o_####.exr"), "--frames", "1-3", "--focus", "3",
               "--fstop", "2", "--focal-length", "50", NULL) == 2 &&
          err_contains("need a run of '#'"));
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--frames", "3-1", NULL) == 2);
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--curve", "0,0,1,2,3,4", "--fstop", "2",
               NULL) == 2 && err_contains("camera options do not apply"));
    /* Every solver runs (the accuracy study drives them through the command). */
    {
        static const char *const solvers[] = {"thomas", "cr", "pcr", "jacobi", "reference"};
        size_t k;
        for (k = 0; k < 5; k++)
            CHECK_MSG(ddof(in, "-o", test_path(dir, "o.exr"), "--focal-length", "50", "--fstop",
                           "2", "--focus", "3", "--solver", solvers[k], "--jacobi-iterations",
                           "5", "--beta-scale", "0.05", "--threads", "2", NULL) == 0 &&
                          out_contains(solvers[k]),
                      "%s", solvers[k]);
    }
    CHECK(ddof("--list", in, NULL) == 0 && out_contains("ddof uses: colour R, G, B, A; depth Z"));
    /* Issue 14: out-of-range values are usage errors that name the option and the limit. */
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--focal-length", "50", "--fstop", "2",
               "--focus", "3", "--threads", "100000", NULL) == 2 &&
          err_contains("--threads wants a whole number within 0..1024"));
    CHECK(ddof(in, "-o", test_path(dir, "o_####.exr"), "--frames", "2147483647",
               "--focal-length", "50", "--fstop", "2", "--focus", "3", NULL) == 2 &&
          err_contains("at most 99999999"));
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--focal-length", "50", "--fstop", "2",
               "--focus", "3", "--pixel-aspect", "1e20", NULL) == 2 &&
          err_contains("pixel_aspect 1e+20 must be within 0.01..100"));
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--focal-length", "50", "--fstop", "2",
               "--focus", "3", "--pixel-aspect", "100.001", NULL) == 2);
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--focal-length", "50", "--fstop", "2",
               "--focus", "3", "--pixel-aspect", "0.01", NULL) == 0);
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--focal-length", "50", "--fstop", "2",
               "--focus", "3", "--beta-scale", "2", NULL) == 2 &&
          err_contains("params.beta_scale 2 must be > 0 and at most 1"));
    {
        /* A CoC just above the limit is printed as itself, not rounded to the limit. */
        static scene big;
        make_scene(&big, 0);
        big.coc[7] = 100000.01f;
        write_scene(test_path(dir, "bigcoc.exr"), &big, 1);
        CHECK(ddof(test_path(dir, "bigcoc.exr"), "-o", test_path(dir, "o.exr"), "--coc-channel",
                   "C", NULL) == 1 && err_contains("is 100000.008; it must be finite, within "
                                                   "0..100000 px"));
    }
    /* A forced near spread: fine with the camera's signed CoC; refused with a foreground
     * element, which is the near field. */
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--focal-length", "50", "--fstop", "2",
               "--focus", "3", "--near-spread", "on", NULL) == 0);
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--focal-length", "50", "--fstop", "2",
               "--focus", "3", "--near-spread", "on", "--foreground-layer", "F", NULL) == 2 &&
          err_contains("--near-spread on works on one image"));
    /* The near layer likewise; forced on beside a forced near spread, refused up front. */
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--focal-length", "50", "--fstop", "2",
               "--focus", "3", "--near-layer", "on", "--near-layer-threshold", "6", NULL) == 0);
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--focal-length", "50", "--fstop", "2",
               "--focus", "3", "--near-layer", "on", "--foreground-layer", "F", NULL) == 2 &&
          err_contains("--near-layer on works on one image"));
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--focal-length", "50", "--fstop", "2",
               "--focus", "3", "--near-layer", "on", "--near-spread", "on", NULL) == 2 &&
          err_contains("near_layer and near_spread are both forced on"));
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--near-layer-threshold", "0", NULL) == 2);
    CHECK(!test_file_exists(test_path(dir, "o_0001.exr")));
    {
        /* Issue 42: DWAA and DWAB written (with a level), and ZIP at the fastest level. */
        static const char *const ways[3] = {"dwaa", "dwab:60", "zip:1"};
        static const exrio_compression stored[3] = {
            EXRIO_COMPRESSION_DWAA, EXRIO_COMPRESSION_DWAB, EXRIO_COMPRESSION_ZIP};
        int k;
        for (k = 0; k < 3; k++) {
            exrio_image out;
            char error[1024];
            CHECK_MSG(ddof(in, "-o", test_path(dir, "o.exr"), "--focal-length", "50", "--fstop",
                           "2", "--focus", "3", "--compression", ways[k], NULL) == 0,
                      "--compression %s", ways[k]);
            CHECK(exrio_open(test_path(dir, "o.exr"), &out, error, sizeof error) == EXRIO_OK &&
                  out.parts[0].compression == stored[k] &&
                  exrio_load(&out, NULL, error, sizeof error) == EXRIO_OK);
            exrio_close(&out);
        }
    }
    return test_finish("test_cli options");
}

/* Issue 22: messages that name what the user set. */
static int case_messages(void)
{
    static scene s;
    const char *in = test_path(dir, "in.exr"), *json = test_path(dir, "cam.json");
    make_scene(&s, 0);
    write_scene(in, &s, 0);

    /* A subnormal pixel aspect is a number, judged against the range it is outside; a value
     * beyond a double is said to be so. */
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--focal-length", "50", "--fstop", "2",
               "--focus", "3", "--pixel-aspect", "5e-324", NULL) == 2);
    CHECK(err_contains("4.94065646e-324") && err_contains("0.01..100"));
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--focal-length", "50", "--fstop", "2",
               "--focus", "3", "--pixel-aspect", "1e-400", NULL) == 2);
    CHECK(err_contains("--pixel-aspect '1e-400' is closer to 0 than a double can hold"));
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--focal-length", "50", "--fstop", "1e999",
               "--focus", "3", NULL) == 2);
    CHECK(err_contains("--fstop '1e999' is larger than a double can hold"));
    {
        const char *big = "{\"focal_length_mm\": 50, \"sensor_width_mm\": 36, \"sensor_fit\": "
                          "\"AUTO\", \"fstop\": 2, \"focus_distance_m\": 3, \"resolution\": [48, "
                          "32], \"pixel_aspect\": 1e999}";
        test_write_file(json, big, strlen(big));
        CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--camera", json, NULL) == 2);
        CHECK(err_contains("\"pixel_aspect\" is larger than a double can hold"));
    }
    /* The EXR header's pixelAspectRatio is named as such, not as params.pixel_aspect. */
    {
        size_t size = 0;
        char *bytes = test_read_file(in, &size);
        static const char attr[] = "pixelAspectRatio\0float\0\4\0\0\0";
        const float wide = 1e5f;
        size_t at = 0;
        while (bytes && at + sizeof attr + 4 <= size &&
               memcmp(bytes + at, attr, sizeof attr - 1) != 0)
            at++;
        CHECK(bytes && at + sizeof attr + 4 <= size);
        if (bytes && at + sizeof attr + 4 <= size) {
            memcpy(bytes + at + sizeof attr - 1, &wide, 4);
            test_write_file(test_path(dir, "wide.exr"), bytes, size);
            CHECK(ddof(test_path(dir, "wide.exr"), "-o", test_path(dir, "o.exr"), "--curve",
                       "8,0,2,4,12,10", NULL) == 1);
            CHECK(err_contains("the header's pixelAspectRatio 100000 is outside 0.01..100"));
            CHECK(ddof(test_path(dir, "wide.exr"), "-o", test_path(dir, "o.exr"),
                       "--focal-length", "50", "--fstop", "2", "--focus", "3", NULL) == 1);
            CHECK(err_contains("the header's pixelAspectRatio 100000") &&
                  err_contains("--pixel-aspect"));
            CHECK(ddof(test_path(dir, "wide.exr"), "-o", test_path(dir, "o.exr"),
                       "--focal-length", "50", "--fstop", "2", "--focus", "3", "--pixel-aspect",
                       "1", NULL) == 0);
        }
        free(bytes);
    }
    /* --stats whose directory cannot take it: said with its option, before any frame. */
    CHECK(ddof(in, "-o", test_path(dir, "o2.exr"), "--focal-length", "50", "--fstop", "2",
               "--focus", "3", "--stats", test_path(dir, "in.exr/s.json"), NULL) != 0);
    CHECK(err_contains("ddof: --stats: "));
    CHECK(!test_file_exists(test_path(dir, "o2.exr")));
    /* Standard output closed: the report is lost, so the run is a failure, said on stderr. */
    {
        char command[8192];
        snprintf(command, sizeof command,
                 "'%s' '%s' -o '%s' --focal-length 50 --fstop 2 --focus 3 >&- 2>'%s'",
                 ddof_bin, in, test_path(dir, "o3.exr"), test_path(dir, "closed.err"));
        const int rc = system(command);
        CHECK_MSG(WIFEXITED(rc) && WEXITSTATUS(rc) == 1, "exit %d", rc);
        char *e = test_read_file(test_path(dir, "closed.err"), NULL);
        CHECK_MSG(e && strstr(e, "cannot write the standard output"), "stderr: %s",
                  e ? e : "");
        free(e);
    }
    return test_finish("test_cli messages");
}

int main(int argc, char **argv)
{
    static const cli_case cases[] = {
        {"bad_inputs", case_bad_inputs},
        {"sidecar", case_sidecar},
        {"options", case_options},
        {"messages", case_messages},
        {"keep_parts", case_keep_parts},
    };
    return cli_test_main(argc, argv, "test_cli_inputs", cases, sizeof cases / sizeof cases[0]);
}
