/* SPDX-License-Identifier: MIT */
/* test_cli_backends.c - one frame with a foreground element through the `ddof` command, bit
 * for bit with the library (and left for the add-on's one-pipeline test), and the backends
 * the command can run on.
 *
 *   test_cli_backends DDOF_BINARY CASE SCRATCH_DIR
 * CASE: foreground backend */
#include "cli_test.h"

#include <cJSON.h>
#include <dlfcn.h>

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Raw floats into the scratch folder, for a test in another language to read. */
static int dump_floats(const char *name, const float *values, size_t count)
{
    FILE *f = fopen(test_path(dir, name), "wb");
    int ok = f && fwrite(values, sizeof *values, count, f) == count;
    if (f && fclose(f) != 0)
        ok = 0;
    return ok ? 0 : -1;
}

/* A foreground element: as a second layer of the input (Blender view layer "Foreground") and
 * as a separate file; the result equals ddof_diffuse_layers with the element, both CoCs from
 * the camera, signed. Without alpha, or of another size, it is refused. */
static int case_foreground(void)
{
    static const char *const names[10] = {
        "Foreground.Combined.A", "Foreground.Combined.B", "Foreground.Combined.G",
        "Foreground.Combined.R", "Foreground.Depth.Z",    "ViewLayer.Combined.A",
        "ViewLayer.Combined.B",  "ViewLayer.Combined.G",  "ViewLayer.Combined.R",
        "ViewLayer.Depth.Z"};
    static const char *const flat[5] = {"A", "B", "G", "R", "Z"};
    exrio_pixel_type types[10];
    static scene s;
    static float fg[5][N], color[N * 4], fgc[N * 4], coc[N], fgcoc[N], ref[N * 4];
    const void *planes[10];
    exrio_box box = test_box(0, 0, W, H), small = test_box(0, 0, W / 2, H);
    const char *in = test_path(dir, "layers.exr");
    ddof_camera camera;
    ddof_params params;
    ddof_foreground element;
    ddof_context_options co;
    ddof_context *ctx = NULL;
    size_t i;
    int c, bad;

    make_scene(&s, 0);
    /* The element: a bar 1.2 m away over columns 10..17, alpha 1 inside, 0.5 on its edges,
     * premultiplied colour. */
    for (i = 0; i < N; i++) {
        const size_t x = i % W;
        const float a = (x >= 10 && x <= 17) ? (x == 10 || x == 17 ? 0.5f : 1.0f) : 0.0f;
        fg[0][i] = a;
        fg[1][i] = 0.2f * a;
        fg[2][i] = 0.7f * a;
        fg[3][i] = 0.9f * a;
        fg[4][i] = a > 0.0f ? 1.2f : 1e10f;
    }
    for (c = 0; c < 10; c++)
        types[c] = EXRIO_FLOAT;
    for (c = 0; c < 5; c++)
        planes[c] = fg[c];
    planes[5] = s.rgba[3];
    planes[6] = s.rgba[2];
    planes[7] = s.rgba[1];
    planes[8] = s.rgba[0];
    planes[9] = s.z;
    CHECK(test_write_exr(in, &box, NULL, 10, names, types, planes, EXRIO_COMPRESSION_ZIP) == 0);
    CHECK(test_write_exr(test_path(dir, "fg.exr"), &box, NULL, 5, flat, types, planes,
                         EXRIO_COMPRESSION_ZIP) == 0);
    CHECK(test_write_exr(test_path(dir, "fg_small.exr"), &small, NULL, 5, flat, types, planes,
                         EXRIO_COMPRESSION_ZIP) == 0);
    /* B, G, R, Z: no A. */
    CHECK(test_write_exr(test_path(dir, "fg_noalpha.exr"), &box, NULL, 4, flat + 1, types,
                         planes + 1, EXRIO_COMPRESSION_ZIP) == 0);

    /* The library with the element. */
    for (i = 0; i < N; i++) {
        for (c = 0; c < 4; c++)
            color[i * 4 + (size_t)c] = s.rgba[c][i];
        fgc[i * 4 + 0] = fg[3][i];
        fgc[i * 4 + 1] = fg[2][i];
        fgc[i * 4 + 2] = fg[1][i];
        fgc[i * 4 + 3] = fg[0][i];
    }
    ddof_context_options_init(&co);
    co.thread_count = 1;
    ddof_context_create(&co, &ctx);
    camera_50mm(&camera, 2.0, 3.0);
    camera.signed_coc = 1;
    ddof_params_init(&params);
    params.substeps = 2;
    params.coc_signed = 1;
    {
        const ddof_image_in depth_in = {s.z, W, H, 1, 0}, fg_depth_in = {fg[4], W, H, 1, 0};
        const ddof_image coc_out = {coc, W, H, 1, 0}, fgcoc_out = {fgcoc, W, H, 1, 0};
        const ddof_image_in color_in = {color, W, H, 4, 0}, coc_in = {coc, W, H, 1, 0};
        const ddof_image out_img = {ref, W, H, 4, 0};
        CHECK(ddof_coc_from_camera(ctx, &camera, &depth_in, &coc_out) == DDOF_OK);
        CHECK(ddof_coc_from_camera(ctx, &camera, &fg_depth_in, &fgcoc_out) == DDOF_OK);
        ddof_foreground_init(&element);
        element.color.pixels = fgc;
        element.color.width = W;
        element.color.height = H;
        element.color.channels = 4;
        element.coc.pixels = fgcoc;
        element.coc.width = W;
        element.coc.height = H;
        element.coc.channels = 1;
        CHECK(ddof_diffuse_layers(ctx, &params, &color_in, &coc_in, &element, &out_img, NULL) ==
              DDOF_OK);
    }
    /* The one call gives the same, bit for bit; its inputs and result are left for the
     * add-on's test (tests/blender/check_one_pipeline.py), which runs the same frame through
     * the binding. */
    {
        static float one[N * 4];
        ddof_frame frame;
        ddof_params p = params;
        p.coc_signed = 0; /* the camera's CoC is signed by the call itself */
        camera.signed_coc = 0;
        ddof_frame_init(&frame);
        frame.color = (ddof_image_in){color, W, H, 4, 0};
        frame.depth = (ddof_image_in){s.z, W, H, 1, 0};
        frame.camera = &camera;
        frame.foreground_color = (ddof_image_in){fgc, W, H, 4, 0};
        frame.foreground_depth = (ddof_image_in){fg[4], W, H, 1, 0};
        CHECK(ddof_render_frame(ctx, &p, &frame, &(ddof_image){one, W, H, 4, 0}, NULL) ==
              DDOF_OK);
        CHECK_MSG(memcmp(one, ref, sizeof one) == 0,
                  "ddof_render_frame differs from the composed calls");
        CHECK(dump_floats("one_pipeline_color.f32", color, N * 4) == 0 &&
              dump_floats("one_pipeline_depth.f32", s.z, N) == 0 &&
              dump_floats("one_pipeline_fg_color.f32", fgc, N * 4) == 0 &&
              dump_floats("one_pipeline_fg_depth.f32", fg[4], N) == 0 &&
              dump_floats("one_pipeline_out.f32", ref, N * 4) == 0);
    }
    ddof_context_free(ctx);

    /* Same file, second layer: the main layer is found despite two layers with depth. */
    CHECK(ddof(in, "-o", test_path(dir, "out1.exr"), "--foreground-layer", "Foreground",
               "--focal-length", "50", "--fstop", "2", "--focus", "3", "--substeps", "2",
               "--pixel-type", "float", "--threads", "1", "--stats", test_path(dir, "s.json"),
               NULL) == 0);
    bad = compare_output(test_path(dir, "out1.exr"), ref, 1, 0.0, 0);
    CHECK_MSG(bad == 0, "foreground layer: %d values differ", bad);
    CHECK(out_contains("foreground"));
    /* A separate file. */
    CHECK(ddof(in, "-o", test_path(dir, "out2.exr"), "--layer", "ViewLayer", "--foreground",
               test_path(dir, "fg.exr"), "--focal-length", "50", "--fstop", "2", "--focus", "3",
               "--substeps", "2", "--pixel-type", "float", "--threads", "1", NULL) == 0);
    bad = compare_output(test_path(dir, "out2.exr"), ref, 1, 0.0, 0);
    CHECK_MSG(bad == 0, "foreground file: %d values differ", bad);
    /* Refusals. */
    CHECK(ddof(in, "-o", test_path(dir, "out3.exr"), "--layer", "ViewLayer", "--foreground",
               test_path(dir, "fg_small.exr"), "--focal-length", "50", "--fstop", "2",
               "--focus", "3", NULL) == 1);
    CHECK(err_contains("mismatched layer sizes") && err_contains("24x32"));
    CHECK(ddof(in, "-o", test_path(dir, "out3.exr"), "--layer", "ViewLayer", "--foreground",
               test_path(dir, "fg_noalpha.exr"), "--focal-length", "50", "--fstop", "2",
               "--focus", "3", NULL) == 1);
    CHECK(err_contains("no alpha channel"));
    CHECK(ddof(in, "-o", test_path(dir, "out3.exr"), "--focal-length", "50", "--fstop", "2",
               "--focus", "3", NULL) == 1);
    CHECK(err_contains("several colour layers") && err_contains("'ViewLayer.Combined'"));
    CHECK(!test_file_exists(test_path(dir, "out3.exr")));
    return test_finish("test_cli foreground");
}

/* The file libddof was loaded from; the GL plugin is looked for beside it. */
static int gl_plugin_beside_library(void)
{
    Dl_info info;
    char path[4096];
    const char *slash;
    if (!dladdr((void *)(uintptr_t)ddof_version_number, &info) || !info.dli_fname)
        return 0;
    slash = strrchr(info.dli_fname, '/');
    if (!slash)
        return 0;
    snprintf(path, sizeof path, "%.*slibddof_gl.so", (int)(slash - info.dli_fname + 1),
             info.dli_fname);
    return test_file_exists(path);
}

/* A string of frame 0 of a --stats file's "simulated" (allocated; "" when missing). */
static char *stats_string(const char *path, const char *key)
{
    char *text = test_read_file(path, NULL), *value = NULL;
    cJSON *root = text ? cJSON_Parse(text) : NULL;
    const cJSON *sim = cJSON_GetObjectItem(
        cJSON_GetArrayItem(cJSON_GetObjectItem(root, "frames"), 0), "simulated");
    const cJSON *item = cJSON_GetObjectItem(sim, key);
    if (cJSON_IsString(item)) {
        value = malloc(strlen(item->valuestring) + 1);
        if (value)
            strcpy(value, item->valuestring);
    }
    cJSON_Delete(root);
    free(text);
    if (!value)
        value = calloc(1, 1);
    return value;
}

/* Backends (libddof 0.3): an explicit GL backend that cannot be had is exit status 3 and a
 * sentence, never a crash and never a silent CPU run; auto uses the CPU when there is no GPU and
 * gives the CPU's pixels then; -v and --stats say what ran. Gruen and packed-half precision
 * need a GL backend. The CoD4 preview runs through --method. */
static int case_backend(void)
{
    static scene s;
    static float ref[N * 4];
    const char *in = test_path(dir, "in.exr");
    const char *camera[] = {"--focal-length", "50", "--fstop", "2", "--focus", "3"};
    reference r;
    char *ran, *renderer, *note, *method;
    int bad;

    make_scene(&s, 0);
    write_scene(in, &s, 0);
    memset(&r, 0, sizeof r);
    r.kind = REF_CAMERA;
    camera_50mm(&r.camera, 2.0, 3.0);

#define CAMERA camera[0], camera[1], camera[2], camera[3], camera[4], camera[5]
    /* A plugin that is not there: the explicit path wins over every other place. */
    CHECK(ddof(in, "-o", test_path(dir, "osmesa.exr"), CAMERA, "--backend", "osmesa",
               "--gl-plugin", "/nonexistent/libddof_gl.so", NULL) == 3);
    CHECK(err_contains("--backend osmesa is not available") &&
          err_contains("/nonexistent/libddof_gl.so") && err_contains("--backend cpu"));
    CHECK(!test_file_exists(test_path(dir, "osmesa.exr")));
    CHECK(ddof(in, "-o", test_path(dir, "egl.exr"), CAMERA, "--backend", "egl", "--gl-plugin",
               "/nonexistent/libddof_gl.so", NULL) == 3 &&
          err_contains("--backend egl is not available"));
    /* The same through DDOF_GL_PLUGIN, when no plugin sits beside libddof (the library then
     * goes on to that one: see the report on the search order). */
    if (!gl_plugin_beside_library()) {
        setenv("DDOF_GL_PLUGIN", "/nonexistent/libddof_gl.so", 1);
        CHECK(ddof(in, "-o", test_path(dir, "osmesa.exr"), CAMERA, "--backend", "osmesa",
                   NULL) == 3 && err_contains("--backend osmesa is not available"));
        /* auto does not fail for it: it falls back to the CPU and says why. */
        CHECK(ddof(in, "-o", test_path(dir, "auto_env.exr"), CAMERA, "--backend", "auto",
                   "--stats", test_path(dir, "auto_env.json"), NULL) == 0);
        ran = stats_string(test_path(dir, "auto_env.json"), "backend");
        note = stats_string(test_path(dir, "auto_env.json"), "backend_note");
        CHECK_MSG(!strcmp(ran, "cpu") && strstr(note, "auto: the CPU"), "ran %s, note %s", ran,
                  note);
        free(ran);
        free(note);
        unsetenv("DDOF_GL_PLUGIN");
    }

    /* cpu: the library's pixels. */
    r.substeps = 2;
    library_result(&s, &r, ref, NULL);
    CHECK(ddof(in, "-o", test_path(dir, "cpu.exr"), CAMERA, "--backend", "cpu", "--substeps",
               "2", "--pixel-type", "float", "--stats", test_path(dir, "cpu.json"), "-v",
               NULL) == 0);
    bad = compare_output(test_path(dir, "cpu.exr"), ref, 1, 0.0, 0);
    CHECK_MSG(bad == 0, "--backend cpu: %d values differ from the library", bad);
    CHECK(out_contains("backend cpu (CPU, ") && out_contains("method diffusion") &&
          out_contains("plan: midground: "));
    ran = stats_string(test_path(dir, "cpu.json"), "backend");
    renderer = stats_string(test_path(dir, "cpu.json"), "renderer");
    note = stats_string(test_path(dir, "cpu.json"), "backend_note");
    CHECK_MSG(!strcmp(ran, "cpu") && !strncmp(renderer, "CPU, ", 5) && !note[0],
              "cpu: ran %s on %s, note %s", ran, renderer, note);
    free(ran);
    free(renderer);
    free(note);

    /* auto (the default): on a machine without a GPU (or without the plugin) the CPU, the same
     * pixels, and -v / --stats say so and why. With a GPU the pixels are the GL solver's: they
     * agree within float rounding. */
    CHECK(ddof(in, "-o", test_path(dir, "auto.exr"), CAMERA, "--substeps", "2", "--pixel-type",
               "float", "--stats", test_path(dir, "auto.json"), "--verbose", NULL) == 0);
    ran = stats_string(test_path(dir, "auto.json"), "backend");
    renderer = stats_string(test_path(dir, "auto.json"), "renderer");
    note = stats_string(test_path(dir, "auto.json"), "backend_note");
    CHECK_MSG(strstr(note, "auto: ") == note, "auto's note: %s", note);
    {
        char line[512];
        snprintf(line, sizeof line, "backend %s (%s)", ran, renderer);
        CHECK(out_contains(line) && out_contains(note));
    }
    if (!strcmp(ran, "cpu")) {
        bad = compare_output(test_path(dir, "auto.exr"), ref, 1, 0.0, 0);
        CHECK_MSG(bad == 0, "--backend auto on the CPU: %d values differ from cpu", bad);
        CHECK(strstr(note, "auto: the CPU, because") != NULL);
    } else {
        printf("auto ran on %s (%s)\n", ran, renderer);
        CHECK(compare_output(test_path(dir, "auto.exr"), ref, 0, 1e-4, 0) == 0);
    }
    free(ran);
    free(renderer);
    free(note);

    /* With the GL plugin built beside libddof: osmesa runs the same diffusion in software GL,
     * within float rounding of the CPU's, and says so. (A machine without libOSMesa gives the
     * backend error, exit 3.) */
    if (gl_plugin_beside_library()) {
        int rc;
        setenv("MESA_SHADER_CACHE_DIR", test_path(dir, "mesa-cache"), 1);
        rc = ddof(in, "-o", test_path(dir, "osmesa_gl.exr"), CAMERA, "--backend", "osmesa",
                  "--substeps", "2", "--pixel-type", "float", "--stats",
                  test_path(dir, "osmesa.json"), NULL);
        CHECK_MSG(rc == 0 || (rc == 3 && err_contains("--backend osmesa is not available")),
                  "osmesa with the plugin: exit %d", rc);
        if (rc == 0) {
            ran = stats_string(test_path(dir, "osmesa.json"), "backend");
            renderer = stats_string(test_path(dir, "osmesa.json"), "renderer");
            printf("osmesa ran on %s (%s)\n", ran, renderer);
            CHECK_MSG(!strcmp(ran, "osmesa") && renderer[0], "osmesa: ran %s on %s", ran,
                      renderer);
            bad = compare_output(test_path(dir, "osmesa_gl.exr"), ref, 0, 1e-4, 0);
            CHECK_MSG(bad == 0, "--backend osmesa: %d values differ from the CPU's by > 1e-4",
                      bad);
            free(ran);
            /* The default preset's kernel runs on GL too (Thomas has the discs' complex form
             * there). */
            ddof_params preset;
            ddof_params_init(&preset);
            ran = stats_string(test_path(dir, "osmesa.json"), "kernel");
            CHECK_MSG(!strcmp(ran, ddof_kernel_name(preset.kernel)), "osmesa: the %s kernel ran",
                      ran);
            free(ran);
            free(renderer);
        }
    }

    /* Gruen and packed half need GL: on the CPU, exit 3 and what to do. */
    CHECK(ddof(in, "-o", test_path(dir, "gruen.exr"), CAMERA, "--backend", "cpu", "--solver",
               "gruen", NULL) == 3);
    CHECK(err_contains("cannot run solver gruen") && err_contains("--backend egl or osmesa"));
    CHECK(ddof(in, "-o", test_path(dir, "half.exr"), CAMERA, "--backend", "cpu", "--precision",
               "packed-half", NULL) == 3 && err_contains("packed half"));
    CHECK(!test_file_exists(test_path(dir, "gruen.exr")) &&
          !test_file_exists(test_path(dir, "half.exr")));

    /* The CoD4 preview: --method cod4, reported as such. */
    CHECK(ddof(in, "-o", test_path(dir, "cod4.exr"), CAMERA, "--method", "cod4", "--stats",
               test_path(dir, "cod4.json"), NULL) == 0 && out_contains("CoD4 preview"));
    method = stats_string(test_path(dir, "cod4.json"), "method");
    CHECK_MSG(!strcmp(method, "cod4"), "method %s", method);
    free(method);
#undef CAMERA
    return test_finish("test_cli backend");
}

int main(int argc, char **argv)
{
    static const cli_case cases[] = {
        {"foreground", case_foreground},
        {"backend", case_backend},
    };
    return cli_test_main(argc, argv, "test_cli_backends", cases, sizeof cases / sizeof cases[0]);
}
