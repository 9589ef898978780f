/* SPDX-License-Identifier: MIT */
/* test_cli.c - the `ddof` command, run as a user runs it, on files written by the test.
 * Outputs are checked against the library called directly on the same data (bit-exact for
 * float output), messages and exit statuses against the issue's list of bad inputs.
 *
 *   test_cli DDOF_BINARY CASE SCRATCH_DIR
 * CASE: values window refuse_same unwritable bad_inputs sequence interrupt sidecar options
 *       foreground backend outputs pipe resume keep_parts */
#include "exr_test_util.h"

#include <ddof.h>

#include <cJSON.h>
#include <dlfcn.h>
#include <openexr.h>
#include <png.h>

#include "focus_map.h"

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#define W 48
#define H 32
#define N ((size_t)W * H)

static const char *ddof_bin;
static const char *dir;

/* ---- running ddof -------------------------------------------------------------------------- */

/* Runs ddof with the NULL-terminated arguments; output in dir/run.out, dir/run.err. */
static int ddof(const char *first, ...)
{
    char *argv[64];
    va_list args;
    int n = 0;
    const char *a;
    argv[n++] = (char *)ddof_bin;
    va_start(args, first);
    for (a = first; a && n < 63; a = va_arg(args, const char *))
        argv[n++] = (char *)a;
    va_end(args);
    argv[n] = NULL;
    return test_run(dir, argv);
}

static char *out_text(void)
{
    char *t = test_read_file(test_path(dir, "run.out"), NULL);
    return t ? t : calloc(1, 1);
}

static char *err_text(void)
{
    char *t = test_read_file(test_path(dir, "run.err"), NULL);
    return t ? t : calloc(1, 1);
}

static int err_contains(const char *what)
{
    char *t = err_text();
    int found = strstr(t, what) != NULL;
    if (!found)
        fprintf(stderr, "  (stderr was: %s)\n", t);
    free(t);
    return found;
}

static int out_contains(const char *what)
{
    char *t = out_text();
    int found = strstr(t, what) != NULL;
    if (!found)
        fprintf(stderr, "  (stdout was: %s)\n", t);
    free(t);
    return found;
}

/* Waits (up to 60 s, valgrind is slow) for a temporary file in `where` that stays: seen on
 * two polls 50 ms apart, since the up-front probe of an output directory
 * (output_check_directory) is a temporary file too, for microseconds. */
static void wait_for_temp(const char *where)
{
    int waited = 0, seen = 0;
    while (seen < 2 && waited < 60000) {
        struct timespec ts = {0, 50 * 1000000L};
        seen = test_count_suffix(where, ".tmp") > 0 ? seen + 1 : 0;
        nanosleep(&ts, NULL);
        waited += 50;
    }
}

/* ---- inputs ------------------------------------------------------------------------------- */

typedef struct scene {
    float rgba[4][N]; /* planes R, G, B, A */
    float z[N];
    float coc[N];
} scene;

/* A chequered, coloured pattern over depths from 1 m (left) to 20 m (right), a sharp band at
 * 3 m in the middle, and a small bright highlight: every feature the solver treats. */
static void make_scene(scene *s, int variant)
{
    size_t x, y;
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            const size_t i = y * W + x;
            const int check = (int)((x / 4 + y / 4 + (size_t)variant) % 2);
            s->rgba[0][i] = check ? 0.9f : 0.1f;
            s->rgba[1][i] = 0.2f + 0.6f * (float)x / W;
            s->rgba[2][i] = 0.3f + 0.4f * (float)y / H;
            s->rgba[3][i] = 1.0f;
            s->z[i] = (x >= 20 && x < 26) ? 3.0f : 1.0f + 19.0f * (float)x / (W - 1);
            s->coc[i] = (float)((x + y) % 9);
        }
    }
    s->rgba[0][5 * W + 40] = s->rgba[1][5 * W + 40] = s->rgba[2][5 * W + 40] = 30.0f;
}

static void write_scene(const char *path, const scene *s, int with_coc)
{
    static const char *const names[6] = {"R", "G", "B", "A", "Z", "C"};
    const exrio_pixel_type types[6] = {EXRIO_FLOAT, EXRIO_FLOAT, EXRIO_FLOAT,
                                       EXRIO_FLOAT, EXRIO_FLOAT, EXRIO_FLOAT};
    const void *planes[6] = {s->rgba[0], s->rgba[1], s->rgba[2], s->rgba[3], s->z, s->coc};
    exrio_box box = test_box(0, 0, W, H);
    CHECK(test_write_exr(path, &box, NULL, with_coc ? 6 : 5, names, types, planes,
                         EXRIO_COMPRESSION_ZIP) == 0);
}

/* ---- the library on the same data ---------------------------------------------------------- */

typedef enum { REF_CAMERA, REF_CURVE, REF_CHANNEL } ref_kind;

typedef struct reference {
    ref_kind kind;
    ddof_camera camera;
    ddof_curve curve;
    const char *preset;  /* ddof_params_init_preset by name; NULL: ddof_params_init */
    uint32_t substeps;   /* 0: the preset's */
    int heat_kernel;     /* 1: DDOF_KERNEL_HEAT (--kernel heat); 0: the preset's kernel */
} reference;

/* The library's preset of this name (ddof_preset_name); asserts it exists. */
static ddof_preset preset_named(const char *name)
{
    int p;
    for (p = 0; p < DDOF_PRESET_COUNT_; p++)
        if (ddof_preset_name((ddof_preset)p) && !strcmp(ddof_preset_name((ddof_preset)p), name))
            return (ddof_preset)p;
    CHECK_MSG(0, "the library has no preset %s", name);
    return DDOF_PRESET_DEFAULT;
}

static void camera_50mm(ddof_camera *c, double fstop, double focus)
{
    ddof_camera_init(c);
    c->focal_length_mm = 50.0;
    c->sensor_width_mm = 36.0;
    c->fstop = fstop;
    c->focus_distance_m = focus;
}

/* out: interleaved RGBA. */
static void library_result(const scene *s, const reference *ref, float *out, ddof_stats *stats)
{
    ddof_context_options co;
    ddof_context *ctx = NULL;
    ddof_params params;
    float *color = malloc(N * 4 * sizeof *color);
    float *coc = malloc(N * sizeof *coc);
    size_t i;
    int c;
    for (i = 0; i < N; i++)
        for (c = 0; c < 4; c++)
            color[i * 4 + (size_t)c] = s->rgba[c][i];
    ddof_context_options_init(&co);
    co.thread_count = 1;
    CHECK(ddof_context_create(&co, &ctx) == DDOF_OK);
    if (ref->preset)
        CHECK(ddof_params_init_preset(&params, preset_named(ref->preset)) == DDOF_OK);
    else
        ddof_params_init(&params);
    if (ref->substeps)
        params.substeps = ref->substeps;
    if (ref->heat_kernel)
        params.kernel = DDOF_KERNEL_HEAT;
    {
        const ddof_image_in color_in = {color, W, H, 4, 0};
        const ddof_image_in depth_in = {s->z, W, H, 1, 0};
        const ddof_image out_img = {out, W, H, 4, 0};
        const ddof_image coc_out = {coc, W, H, 1, 0};
        const ddof_image_in coc_in = {ref->kind == REF_CHANNEL ? s->coc : coc, W, H, 1, 0};
        if (stats) {
            memset(stats, 0, sizeof *stats);
            stats->struct_size = sizeof *stats;
        }
        if (ref->kind == REF_CAMERA) {
            CHECK(ddof_depth_of_field(ctx, &params, &ref->camera, &color_in, &depth_in, &out_img,
                                      stats) == DDOF_OK);
        } else {
            /* The command runs the layers for every source; a curve's CoC is signed so that
             * the near field is known to them. */
            if (ref->kind == REF_CURVE) {
                ddof_curve curve = ref->curve;
                curve.signed_coc = 1;
                params.coc_signed = 1;
                CHECK(ddof_coc_from_curve(ctx, &curve, &depth_in, &coc_out) == DDOF_OK);
            }
            CHECK(ddof_diffuse_layers(ctx, &params, &color_in, &coc_in, NULL, &out_img, stats) ==
                  DDOF_OK);
        }
    }
    ddof_context_free(ctx);
    free(color);
    free(coc);
}

/* Compares channels R, G, B, A of an output EXR with an interleaved RGBA reference. exact: bit
 * for bit; else within `tolerance` (relative, plus the same absolute near 0). Returns the
 * number of differing values. */
static int compare_output(const char *path, const float *ref, int exact, double tolerance,
                          int half)
{
    static const char *const names[4] = {"R", "G", "B", "A"};
    int c, bad = 0;
    for (c = 0; c < 4; c++) {
        uint32_t w = 0, h = 0;
        float *got = test_read_channel(path, names[c], &w, &h);
        size_t i;
        if (!got || w != W || h != H) {
            CHECK_MSG(0, "%s: channel %s missing or of the wrong size", path, names[c]);
            free(got);
            return -1;
        }
        for (i = 0; i < N; i++) {
            const float want = half ? test_round_half(ref[i * 4 + (size_t)c]) : ref[i * 4 + (size_t)c];
            if (exact ? memcmp(&got[i], &want, 4) != 0
                      : fabs((double)got[i] - want) > tolerance * (1.0 + fabs((double)want)))
                bad++;
        }
        free(got);
    }
    return bad;
}

/* ---- cases ---------------------------------------------------------------------------------- */

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
 * focus_map_pixels() of the camera's signed CoC, byte for byte; it is an output like the
 * others (never the input). */
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
    }
    ddof_context_free(ctx);
    focus_map_pixels(coc, rgb, 4, FW, FH, want);
    for (i = 0; i < FW * FH * 3; i++)
        bad += px[i] != want[i];
    CHECK_MSG(bad == 0, "%d bytes of the focus map differ from focus_map_pixels()", bad);
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
    /* A non-round aperture is the map's legend: the white pixels of the shapes the add-on's
     * aperture_legend (blender_addon/diffusion_dof/focus_map.py) draws, counted there too
     * (tests/blender/test_focus_map_plain.py): a hexagon at 15 degrees, a tall ellipse (ratio
     * 2), a wide pentagon (ratio 0.5); none for a round aperture or a small map. */
    {
        static uint8_t legend[320 * 240 * 3];
        const struct {
            uint32_t blades;
            double rotation, ratio;
            uint32_t w, h, white;
        } cases[] = {{6, 15.0, 1.0, 200, 120, 514}, {0, 0.0, 2.0, 200, 120, 312},
                     {5, 0.0, 0.5, 320, 240, 990}, {0, 0.0, 1.0, 200, 120, 0},
                     {6, 0.0, 1.0, 47, 200, 0}};
        for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
            ddof_camera a;
            ddof_camera_init(&a);
            a.aperture_blades = cases[k].blades;
            a.aperture_rotation_deg = cases[k].rotation;
            a.aperture_ratio = cases[k].ratio;
            memset(legend, 7, sizeof legend);
            focus_map_aperture(&a, cases[k].w, cases[k].h, legend);
            uint32_t white = 0;
            for (size_t j = 0; j < (size_t)cases[k].w * cases[k].h * 3; j += 3)
                white += legend[j] == 255;
            CHECK_MSG(white == cases[k].white, "legend %zu: %u white pixels, want %u", k, white,
                      cases[k].white);
        }
    }
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

static int case_refuse_same(void)
{
    static scene s;
    const char *in = test_path(dir, "in.exr");
    char spelled[4][4096];
    size_t size0 = 0, size1 = 0;
    char *before, *after;
    int k;

    make_scene(&s, 0);
    write_scene(in, &s, 0);
    mkdir(test_path(dir, "sub"), 0777);
    CHECK(symlink("in.exr", test_path(dir, "link.exr")) == 0);
    CHECK(link(in, test_path(dir, "hard.exr")) == 0);
    snprintf(spelled[0], 4096, "%s", in);
    snprintf(spelled[1], 4096, "%s/./in.exr", dir);
    snprintf(spelled[2], 4096, "%s/sub/../in.exr", dir);
    snprintf(spelled[3], 4096, "%s", test_path(dir, "link.exr"));
    before = test_read_file(in, &size0);
    for (k = 0; k < 4; k++) {
        CHECK_MSG(ddof(in, "-o", spelled[k], "--focal-length", "50", "--fstop", "2", "--focus",
                       "3", NULL) == 1, "%s", spelled[k]);
        CHECK(err_contains("refusing") && err_contains("never overwrites its input"));
    }
    /* A hard link is the same file under another name. */
    CHECK(ddof(test_path(dir, "hard.exr"), "-o", in, "--focal-length", "50", "--fstop", "2",
               "--focus", "3", NULL) == 1);
    CHECK(err_contains("refusing"));
    CHECK(ddof(in, "-o", test_path(dir, "ok.exr"), "--preview", in, "--focal-length", "50",
               "--fstop", "2", "--focus", "3", NULL) == 1);
    CHECK(err_contains("refusing to write preview"));
    after = test_read_file(in, &size1);
    CHECK(before && after && size0 == size1 && memcmp(before, after, size0) == 0);
    CHECK(!test_file_exists(test_path(dir, "ok.exr")));
    free(before);
    free(after);

    /* Sequences: the same pattern for input and output. */
    write_scene(test_path(dir, "f_0001.exr"), &s, 0);
    write_scene(test_path(dir, "f_0002.exr"), &s, 0);
    before = test_read_file(test_path(dir, "f_0002.exr"), &size0);
    CHECK(ddof(test_path(dir, "f_####.exr"), "-o", test_path(dir, "f_####.exr"), "--frames",
               "1-2", "--focal-length", "50", "--fstop", "2", "--focus", "3", NULL) == 1);
    CHECK(err_contains("refusing to write output") && err_contains("f_0001.exr"));
    after = test_read_file(test_path(dir, "f_0002.exr"), &size1);
    CHECK(before && after && size0 == size1 && memcmp(before, after, size0) == 0);
    free(before);
    free(after);

    /* Every input of every frame is protected from every output, the camera sidecar and the
     * --stats file included: frame 5's output must not replace frame 1005's input. */
    {
        const char *json = test_path(dir, "camera.json");
        const char *camera =
            "{\"focal_length_mm\": 50, \"sensor_width_mm\": 36, \"sensor_fit\": \"AUTO\","
            " \"fstop\": 2.0, \"focus_distance_m\": 3.0, \"resolution\": [48, 32],"
            " \"pixel_aspect\": 1.0}";
        test_write_file(json, camera, strlen(camera));
        before = test_read_file(json, &size0);
        CHECK(ddof(in, "-o", json, "--camera", json, NULL) == 1);
        CHECK(err_contains("refusing") && err_contains("never overwrites its input"));
        CHECK(ddof(in, "-o", test_path(dir, "s.exr"), "--camera", json, "--stats", json,
                   NULL) == 1);
        CHECK(err_contains("refusing"));
        CHECK(ddof(in, "-o", test_path(dir, "s.exr"), "--camera", json, "--stats", in,
                   NULL) == 1);
        CHECK(ddof(in, "-o", test_path(dir, "s.exr"), "--camera", json, "--stats",
                   test_path(dir, "s.exr"), NULL) == 1);
        CHECK(err_contains("--stats") && err_contains("also an output"));
        after = test_read_file(json, &size1);
        CHECK(before && after && size0 == size1 && memcmp(before, after, size0) == 0);
        free(before);
        free(after);

        write_scene(test_path(dir, "g_0005.exr"), &s, 0);
        write_scene(test_path(dir, "g_1005.exr"), &s, 0);
        before = test_read_file(test_path(dir, "g_1005.exr"), &size0);
        CHECK(ddof(test_path(dir, "g_####.exr"), "-o", test_path(dir, "g_1###.exr"), "--frames",
                   "5,1005", "--camera", json, NULL) == 1);
        CHECK(err_contains("refusing") && err_contains("g_1005.exr"));
        after = test_read_file(test_path(dir, "g_1005.exr"), &size1);
        CHECK(before && after && size0 == size1 && memcmp(before, after, size0) == 0);
        CHECK(!test_file_exists(test_path(dir, "s.exr")));
        free(before);
        free(after);
    }
    CHECK(test_count_suffix(dir, ".tmp") == 0);
    return test_finish("test_cli refuse_same");
}

static int case_unwritable(void)
{
    static scene s;
    const char *in = test_path(dir, "in.exr");
    const char *ro = test_path(dir, "readonly");
    char target[4096], probe[4096];
    FILE *f;

    make_scene(&s, 0);
    write_scene(in, &s, 0);
    mkdir(ro, 0777);
    chmod(ro, 0555);
    /* root writes into a 0555 directory anyway; then use a directory no one can write. */
    snprintf(probe, sizeof probe, "%s/probe", ro);
    f = fopen(probe, "w");
    if (f) {
        fclose(f);
        unlink(probe);
        snprintf(target, sizeof target, "/sys/kernel/ddof-test-out.exr");
        f = fopen(target, "w");
        if (f) {
            fclose(f);
            unlink(target);
            printf("test_cli unwritable: no unwritable directory available here; part skipped\n");
            target[0] = '\0';
        }
    } else {
        snprintf(target, sizeof target, "%s/out.exr", ro);
    }
    if (target[0]) {
        CHECK(ddof(in, "-o", target, "--focal-length", "50", "--fstop", "2", "--focus", "3",
                   NULL) == 1);
        CHECK(err_contains("is not writable"));
        CHECK(!test_file_exists(target));
    }
    chmod(ro, 0777);

    /* Missing directories are created; a directory is not a file name. */
    CHECK(ddof(in, "-o", test_path(dir, "new/deeper/out.exr"), "--focal-length", "50", "--fstop",
               "2", "--focus", "3", NULL) == 0);
    CHECK(test_file_exists(test_path(dir, "new/deeper/out.exr")));
    CHECK(ddof(in, "-o", test_path(dir, "new/"), "--focal-length", "50", "--fstop", "2",
               "--focus", "3", NULL) == 1);
    CHECK(err_contains("names a directory"));
    return test_finish("test_cli unwritable");
}

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
    /* DWAA: see test_exr_bad_input.c for why the header is patched. */
    for (i = 0; bytes && i + sizeof key < size; i++)
        if (memcmp(bytes + i, key, sizeof key - 1) == 0)
            break;
    if (bytes && i + sizeof key < size) {
        bytes[i + sizeof key - 1] = 8;
        test_write_file(test_path(dir, "dwaa.exr"), bytes, size);
        RUN_BAD(test_path(dir, "dwaa.exr"), "DWAA, which OpenEXR's C core");
    } else {
        CHECK_MSG(0, "no compression attribute found");
    }
    free(bytes);
    return test_finish("test_cli bad_inputs");
}

static int case_sequence(void)
{
    static scene s[6];
    static float ref[N * 4];
    char name[64];
    char *text;
    int f, bad;
    reference r;

    memset(&r, 0, sizeof r);
    r.kind = REF_CAMERA;
    r.substeps = 2;
    camera_50mm(&r.camera, 2.0, 3.0);
    for (f = 1; f <= 5; f++) {
        snprintf(name, sizeof name, "in_%04d.exr", f);
        make_scene(&s[f], f);
        write_scene(test_path(dir, name), &s[f], 0);
    }
    /* Frame 3 is cut short, as a render killed while writing would leave it. */
    {
        size_t size = 0;
        char *bytes = test_read_file(test_path(dir, "in_0003.exr"), &size);
        test_write_file(test_path(dir, "in_0003.exr"), bytes, size / 2);
        free(bytes);
    }
    CHECK(ddof(test_path(dir, "in_####.exr"), "-o", test_path(dir, "out/dof_####.exr"),
               "--frames", "1-5", "--focal-length", "50", "--fstop", "2", "--focus", "3",
               "--substeps", "2", "--pixel-type", "float", "--stats",
               test_path(dir, "out/stats.json"), NULL) == 1);
    CHECK(err_contains("frame 3: FAILED") && err_contains("truncated"));
    CHECK(err_contains("1 of 5 frames failed") && err_contains("failed frame: 3\n"));
    CHECK(out_contains("frame 1: ") && out_contains("frame 5: "));
    {
        char *e = err_text();
        CHECK_MSG(strchr(e, '\r') == NULL, "a progress bar was drawn into a pipe");
        free(e);
    }
    for (f = 1; f <= 5; f++) {
        snprintf(name, sizeof name, "out/dof_%04d.exr", f);
        if (f == 3) {
            CHECK(!test_file_exists(test_path(dir, name)));
            continue;
        }
        library_result(&s[f], &r, ref, NULL);
        bad = compare_output(test_path(dir, name), ref, 1, 0.0, 0);
        CHECK_MSG(bad == 0, "frame %d: %d values differ", f, bad);
    }
    CHECK(test_count_suffix(test_path(dir, "out"), ".tmp") == 0);
    text = test_read_file(test_path(dir, "out/stats.json"), NULL);
    CHECK(text != NULL);
    if (text) {
        cJSON *root = cJSON_Parse(text);
        const cJSON *frames = cJSON_GetObjectItem(root, "frames");
        CHECK(cJSON_GetArraySize(frames) == 5);
        for (f = 0; f < 5; f++) {
            const cJSON *fr = cJSON_GetArrayItem(frames, f);
            CHECK(cJSON_GetObjectItem(fr, "frame")->valuedouble == f + 1);
            CHECK(strcmp(cJSON_GetObjectItem(fr, "status")->valuestring,
                         f == 2 ? "failed" : "ok") == 0);
        }
        CHECK(cJSON_GetObjectItem(cJSON_GetObjectItem(root, "summary"), "failed")->valuedouble ==
              1.0);
        cJSON_Delete(root);
        free(text);
    }

    /* The good frames alone, one at a time, with the bar forced on. */
    CHECK(ddof(test_path(dir, "in_####.exr"), "-o", test_path(dir, "out2/dof_####.exr"),
               "--frames", "1-2,4-5", "--focal-length", "50", "--fstop", "2", "--focus", "3",
               "--jobs", "1", "--progress", "always", NULL) == 0);
    CHECK(out_contains("4 frames written") && out_contains("1 at a time"));
    CHECK(err_contains("\r") && err_contains("4/4 frames"));
    CHECK(test_file_exists(test_path(dir, "out2/dof_0005.exr")));
    return test_finish("test_cli sequence");
}

/* Issue 14: an output path that is not a regular file is refused before the first frame, and
 * never replaced: a FIFO, a symbolic link (not followed), a directory, a device (when the test
 * may make one); for -o, --stats and --preview alike. A failed --stats write is not blamed on
 * the frames. */
static int case_outputs(void)
{
    static scene s;
    const char *in = test_path(dir, "in.exr");
    const char *fifo = test_path(dir, "fifo");
    const char *link = test_path(dir, "link.exr");
    const char *target = test_path(dir, "target.exr");
    const char *folder = test_path(dir, "folder.exr");
    const char *device = test_path(dir, "null");
    struct stat st;
    int k, have_device;
#define CAMERA "--focal-length", "50", "--fstop", "2", "--focus", "3"
    make_scene(&s, 0);
    write_scene(in, &s, 0);
    CHECK(mkfifo(fifo, 0666) == 0);
    CHECK(symlink("target.exr", link) == 0);
    CHECK(mkdir(folder, 0777) == 0);
    /* A character device like /dev/null (1, 3) in the scratch folder, never the real one. */
    have_device = mknod(device, S_IFCHR | 0666, makedev(1, 3)) == 0;
    if (!have_device)
        printf("test_cli outputs: cannot make a device node here (%s); that part skipped\n",
               strerror(errno));

    for (k = 0; k < 3; k++) {
        /* -o, then --stats, then --preview at each non-file. */
        const char *paths[4] = {fifo, link, folder, device};
        const char *kinds[4] = {"it is a FIFO", "it is a symbolic link", "names a directory",
                                "it is a device"};
        int t;
        for (t = 0; t < 4; t++) {
            const char *o = k == 0 ? paths[t] : test_path(dir, "o.exr");
            int rc;
            if (t == 3 && !have_device)
                continue;
            unlink(test_path(dir, "o.exr"));
            if (k == 0)
                rc = ddof(in, "-o", o, CAMERA, NULL);
            else if (k == 1)
                rc = ddof(in, "-o", o, "--stats", paths[t], CAMERA, NULL);
            else
                rc = ddof(in, "-o", o, "--preview", paths[t], CAMERA, NULL);
            CHECK_MSG(rc == 1, "option %d, path %s: exit %d", k, paths[t], rc);
            CHECK_MSG(err_contains(kinds[t]), "option %d, path %s", k, paths[t]);
            /* Before the first frame: nothing was computed or written. */
            CHECK_MSG(!test_file_exists(test_path(dir, "o.exr")), "option %d, path %s", k,
                      paths[t]);
        }
    }
    CHECK(lstat(fifo, &st) == 0 && S_ISFIFO(st.st_mode));
    CHECK(lstat(link, &st) == 0 && S_ISLNK(st.st_mode));
    CHECK(!test_file_exists(target));
    CHECK(lstat(folder, &st) == 0 && S_ISDIR(st.st_mode));
    if (have_device)
        CHECK(lstat(device, &st) == 0 && S_ISCHR(st.st_mode));
    CHECK(test_count_suffix(dir, ".tmp") == 0);

    /* Every frame's outputs are checked up front, not only the first one's. */
    {
        char name[64];
        int f;
        for (f = 1; f <= 3; f++) {
            snprintf(name, sizeof name, "seq_%04d.exr", f);
            write_scene(test_path(dir, name), &s, 0);
        }
        mkdir(test_path(dir, "seqout"), 0777);
        CHECK(mkfifo(test_path(dir, "seqout/o_0003.exr"), 0666) == 0);
        CHECK(ddof(test_path(dir, "seq_####.exr"), "-o", test_path(dir, "seqout/o_####.exr"),
                   "--frames", "1-3", CAMERA, NULL) == 1);
        CHECK(err_contains("o_0003.exr: it is a FIFO"));
        CHECK(!test_file_exists(test_path(dir, "seqout/o_0001.exr")));
    }

    /* A --stats write that fails after the frames: its own message, exit 1, no frame blamed.
     * The directory appears while the frames run (DDOF_TEST_HOLD_TEMP_MS holds the commit). */
    {
        pid_t pid;
        int status = 0;
        const char *late = test_path(dir, "late.json");
        unlink(test_path(dir, "o.exr"));
        fflush(stdout);
        pid = fork();
        if (pid == 0) {
            char *argv[] = {(char *)ddof_bin, (char *)in, "-o", (char *)test_path(dir, "o.exr"),
                            "--stats", (char *)late, CAMERA, NULL};
            FILE *err = freopen(test_path(dir, "run.err"), "w", stderr);
            (void)err;
            setenv("DDOF_TEST_HOLD_TEMP_MS", "1500", 1);
            execv(argv[0], argv);
            _exit(127);
        }
        wait_for_temp(dir);
        CHECK(mkdir(late, 0777) == 0);
        waitpid(pid, &status, 0);
        CHECK_MSG(WIFEXITED(status) && WEXITSTATUS(status) == 1, "status %d", status);
        CHECK(err_contains("--stats: ") && err_contains("names a directory"));
        {
            char *e = err_text();
            CHECK_MSG(strstr(e, "frames failed") == NULL && strstr(e, "failed frame") == NULL,
                      "the frames were blamed: %s", e);
            free(e);
        }
        CHECK(test_file_exists(test_path(dir, "o.exr")));
    }
#undef CAMERA
    return test_finish("test_cli outputs");
}

/* Runs ddof with stdout a pipe whose reading end is already closed (`ddof ... | true`);
 * stderr goes to run.err. Returns the raw wait status. */
static int run_into_closed_pipe(char *const *argv)
{
    int fds[2], status = 0;
    pid_t pid;
    if (pipe(fds) != 0)
        return -1;
    close(fds[0]);
    fflush(stdout);
    pid = fork();
    if (pid == 0) {
        FILE *err = freopen(test_path(dir, "run.err"), "w", stderr);
        (void)err;
        dup2(fds[1], STDOUT_FILENO);
        close(fds[1]);
        execv(argv[0], argv);
        _exit(127);
    }
    close(fds[1]);
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
        ;
    return status;
}

/* Issue 14: a closed stdout ends the batch like SIGTERM: a message, the temporary files
 * removed, exit 141, not a silent death by SIGPIPE. */
static int case_pipe(void)
{
    static scene s;
    char name[64];
    int f, status, jobs;
    for (f = 1; f <= 6; f++) {
        snprintf(name, sizeof name, "r_%04d.exr", f);
        make_scene(&s, f);
        write_scene(test_path(dir, name), &s, 0);
    }
    for (jobs = 1; jobs <= 2; jobs++) {
        char *argv[] = {(char *)ddof_bin, (char *)test_path(dir, "r_####.exr"), "-o",
                        (char *)test_path(dir, "o/o_####.exr"), "--frames", "1-6",
                        "--focal-length", "50", "--fstop", "2", "--focus", "3", "--jobs",
                        jobs == 1 ? "1" : "2", NULL};
        status = run_into_closed_pipe(argv);
        CHECK_MSG(WIFEXITED(status) && WEXITSTATUS(status) == 141,
                  "--jobs %d: %s %d", jobs, WIFSIGNALED(status) ? "killed by signal" : "exit",
                  WIFSIGNALED(status) ? WTERMSIG(status) : WEXITSTATUS(status));
        CHECK(err_contains("standard output is closed"));
        CHECK(test_count_suffix(test_path(dir, "o"), ".tmp") == 0);
    }
    /* A SIGPIPE sent to the process is SIGTERM's twin. */
    {
        pid_t pid;
        mkdir(test_path(dir, "out"), 0777);
        fflush(stdout);
        pid = fork();
        if (pid == 0) {
            char *argv[] = {(char *)ddof_bin, (char *)test_path(dir, "r_0001.exr"), "-o",
                            (char *)test_path(dir, "out/out.exr"), "--focal-length", "50",
                            "--fstop", "2", "--focus", "3", NULL};
            FILE *err = freopen(test_path(dir, "run.err"), "w", stderr);
            (void)err;
            setenv("DDOF_TEST_HOLD_TEMP_MS", "30000", 1);
            execv(argv[0], argv);
            _exit(127);
        }
        wait_for_temp(test_path(dir, "out"));
        kill(pid, SIGPIPE);
        waitpid(pid, &status, 0);
        CHECK_MSG(WIFEXITED(status) && WEXITSTATUS(status) == 141, "status %d", status);
        CHECK(err_contains("interrupted by SIGPIPE") && err_contains("removed 1 temporary file"));
        CHECK(test_count_suffix(test_path(dir, "out"), ".tmp") == 0);
    }
    return test_finish("test_cli pipe");
}

/* Issue 14: a batch killed with SIGKILL leaves a temporary file; the next run removes it (its
 * process is gone) and, with --skip-existing, redoes only the frames that are missing or
 * older than their inputs. */
static int case_resume(void)
{
    static scene s;
    char name[64];
    const char *out = test_path(dir, "out");
    struct stat before, after;
    int f;
    pid_t pid;
    int status = 0;
#define SEQ test_path(dir, "in_####.exr"), "-o", test_path(dir, "out/o_####.exr"), "--frames", \
            "1-4", "--focal-length", "50", "--fstop", "2", "--focus", "3", "--jobs", "1"
    for (f = 1; f <= 4; f++) {
        snprintf(name, sizeof name, "in_%04d.exr", f);
        make_scene(&s, f);
        write_scene(test_path(dir, name), &s, 0);
    }
    mkdir(out, 0777);
    /* Frames 1 and 2 done, then SIGKILL while frame 3's file waits for its rename. */
    CHECK(ddof(test_path(dir, "in_####.exr"), "-o", test_path(dir, "out/o_####.exr"),
               "--frames", "1-2", "--focal-length", "50", "--fstop", "2", "--focus", "3",
               NULL) == 0);
    fflush(stdout);
    pid = fork();
    if (pid == 0) {
        char *argv[] = {(char *)ddof_bin, (char *)test_path(dir, "in_0003.exr"), "-o",
                        (char *)test_path(dir, "out/o_0003.exr"), "--focal-length", "50",
                        "--fstop", "2", "--focus", "3", NULL};
        FILE *err = freopen(test_path(dir, "run.err"), "w", stderr);
        (void)err;
        setenv("DDOF_TEST_HOLD_TEMP_MS", "30000", 1);
        execv(argv[0], argv);
        _exit(127);
    }
    wait_for_temp(out);
    kill(pid, SIGKILL);
    waitpid(pid, &status, 0);
    CHECK(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
    CHECK_MSG(test_count_suffix(out, ".tmp") == 1, "SIGKILL should leave the temporary file");
    CHECK(!test_file_exists(test_path(dir, "out/o_0003.exr")));

    /* Frame 2's input changes after its output was written: redone; frame 1: skipped. */
    CHECK(stat(test_path(dir, "out/o_0001.exr"), &before) == 0);
    {
        struct timespec ts = {0, 20 * 1000000L};
        nanosleep(&ts, NULL);
        make_scene(&s, 7);
        write_scene(test_path(dir, "in_0002.exr"), &s, 0);
    }
    CHECK(ddof(SEQ, "--skip-existing", "--stats", test_path(dir, "stats.json"), NULL) == 0);
    CHECK(err_contains("removed 1 temporary file left by an earlier run"));
    CHECK(test_count_suffix(out, ".tmp") == 0);
    CHECK(out_contains("frame 1: ") && out_contains("skipped: complete and newer"));
    CHECK(out_contains("3 frames written, 1 skipped"));
    CHECK(stat(test_path(dir, "out/o_0001.exr"), &after) == 0);
    CHECK_MSG(before.st_mtim.tv_sec == after.st_mtim.tv_sec &&
                  before.st_mtim.tv_nsec == after.st_mtim.tv_nsec && before.st_ino == after.st_ino,
              "frame 1 was rewritten");
    for (f = 2; f <= 4; f++) {
        snprintf(name, sizeof name, "out/o_%04d.exr", f);
        CHECK_MSG(test_file_exists(test_path(dir, name)), "%s", name);
    }
    {
        char *status_text = NULL;
        char *text = test_read_file(test_path(dir, "stats.json"), NULL);
        cJSON *root = text ? cJSON_Parse(text) : NULL;
        const cJSON *frames = cJSON_GetObjectItem(root, "frames");
        status_text = cJSON_GetStringValue(cJSON_GetObjectItem(cJSON_GetArrayItem(frames, 0),
                                                               "status"));
        CHECK(status_text && !strcmp(status_text, "skipped"));
        status_text = cJSON_GetStringValue(cJSON_GetObjectItem(cJSON_GetArrayItem(frames, 1),
                                                               "status"));
        CHECK(status_text && !strcmp(status_text, "ok"));
        cJSON_Delete(root);
        free(text);
    }
    /* A not-EXR at an output path is not "complete": redone. */
    test_write_file(test_path(dir, "out/o_0004.exr"), "junk", 4);
    CHECK(ddof(SEQ, "--skip-existing", NULL) == 0);
    CHECK(out_contains("1 frame written, 3 skipped"));
    /* A live process's temporary file is left alone (PID 1 always exists). */
    test_write_file(test_path(dir, "out/.o_0001.exr.ddof-1-1.tmp"), "", 0);
    CHECK(ddof(SEQ, "--skip-existing", NULL) == 0);
    CHECK(test_file_exists(test_path(dir, "out/.o_0001.exr.ddof-1-1.tmp")));
    unlink(test_path(dir, "out/.o_0001.exr.ddof-1-1.tmp"));
#undef SEQ
    return test_finish("test_cli resume");
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

/* SIGINT and SIGTERM while a finished temporary file waits for its rename (held there by the
 * DDOF_TEST_HOLD_TEMP_MS hook): the file is removed and the exit status says so. */
static int case_interrupt(void)
{
    static scene s;
    const int sigs[2] = {SIGINT, SIGTERM};
    int k;
    make_scene(&s, 0);
    write_scene(test_path(dir, "in.exr"), &s, 0);
    mkdir(test_path(dir, "out"), 0777);
    for (k = 0; k < 2; k++) {
        pid_t pid;
        int status = 0;
        fflush(stdout);
        pid = fork();
        if (pid == 0) {
            char *argv[] = {(char *)ddof_bin, (char *)test_path(dir, "in.exr"), "-o",
                            (char *)test_path(dir, "out/out.exr"), "--focal-length", "50",
                            "--fstop", "2", "--focus", "3", NULL};
            FILE *err = freopen(test_path(dir, "run.err"), "w", stderr);
            (void)err;
            setenv("DDOF_TEST_HOLD_TEMP_MS", "30000", 1);
            execv(argv[0], argv);
            _exit(127);
        }
        wait_for_temp(test_path(dir, "out"));
        CHECK_MSG(test_count_suffix(test_path(dir, "out"), ".tmp") == 1,
                  "no temporary file appeared");
        kill(pid, sigs[k]);
        waitpid(pid, &status, 0);
        CHECK_MSG(WIFEXITED(status) && WEXITSTATUS(status) == 128 + sigs[k], "status %d",
                  status);
        CHECK(test_count_suffix(test_path(dir, "out"), ".tmp") == 0);
        CHECK(!test_file_exists(test_path(dir, "out/out.exr")));
        CHECK(err_contains("interrupted") && err_contains("removed 1 temporary file"));
    }
    return test_finish("test_cli interrupt");
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
    CHECK(ddof(in, "-o", test_path(dir, "o.exr"), "--compression", "dwaa", NULL) == 2 &&
          err_contains("cannot write DWAA"));
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
    return test_finish("test_cli options");
}

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
    const char *which;
    if (argc != 4) {
        fprintf(stderr, "usage: test_cli DDOF_BINARY CASE SCRATCH_DIR\n");
        return 2;
    }
    ddof_bin = argv[1];
    which = argv[2];
    dir = argv[3];
    test_fresh_dir(dir);
    if (!strcmp(which, "values")) return case_values();
    if (!strcmp(which, "window")) return case_window();
    if (!strcmp(which, "focus_map")) return case_focus_map();
    if (!strcmp(which, "refuse_same")) return case_refuse_same();
    if (!strcmp(which, "unwritable")) return case_unwritable();
    if (!strcmp(which, "bad_inputs")) return case_bad_inputs();
    if (!strcmp(which, "sequence")) return case_sequence();
    if (!strcmp(which, "interrupt")) return case_interrupt();
    if (!strcmp(which, "sidecar")) return case_sidecar();
    if (!strcmp(which, "options")) return case_options();
    if (!strcmp(which, "foreground")) return case_foreground();
    if (!strcmp(which, "backend")) return case_backend();
    if (!strcmp(which, "outputs")) return case_outputs();
    if (!strcmp(which, "pipe")) return case_pipe();
    if (!strcmp(which, "resume")) return case_resume();
    if (!strcmp(which, "keep_parts")) return case_keep_parts();
    if (!strcmp(which, "cards")) return case_cards();
    if (!strcmp(which, "messages")) return case_messages();
    fprintf(stderr, "test_cli: unknown case %s\n", which);
    return 2;
}
