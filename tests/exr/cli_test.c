/* SPDX-License-Identifier: MIT */
/* cli_test.c - running the `ddof` command for its tests, the test scene, and the library on
 * the same data (cli_test.h). */
#include "cli_test.h"

#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

const char *ddof_bin;
const char *dir;

/* Runs ddof with the NULL-terminated arguments; output in dir/run.out, dir/run.err. */
int ddof(const char *first, ...)
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

char *out_text(void)
{
    char *t = test_read_file(test_path(dir, "run.out"), NULL);
    return t ? t : calloc(1, 1);
}

char *err_text(void)
{
    char *t = test_read_file(test_path(dir, "run.err"), NULL);
    return t ? t : calloc(1, 1);
}

int err_contains(const char *what)
{
    char *t = err_text();
    int found = strstr(t, what) != NULL;
    if (!found)
        fprintf(stderr, "  (stderr was: %s)\n", t);
    free(t);
    return found;
}

int out_contains(const char *what)
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
void wait_for_temp(const char *where)
{
    int waited = 0, seen = 0;
    while (seen < 2 && waited < 60000) {
        struct timespec ts = {0, 50 * 1000000L};
        seen = test_count_suffix(where, ".tmp") > 0 ? seen + 1 : 0;
        nanosleep(&ts, NULL);
        waited += 50;
    }
}

/* A chequered, coloured pattern over depths from 1 m (left) to 20 m (right), a sharp band at
 * 3 m in the middle, and a small bright highlight: every feature the solver treats. */
void make_scene(scene *s, int variant)
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

void write_scene(const char *path, const scene *s, int with_coc)
{
    static const char *const names[6] = {"R", "G", "B", "A", "Z", "C"};
    const exrio_pixel_type types[6] = {EXRIO_FLOAT, EXRIO_FLOAT, EXRIO_FLOAT,
                                       EXRIO_FLOAT, EXRIO_FLOAT, EXRIO_FLOAT};
    const void *planes[6] = {s->rgba[0], s->rgba[1], s->rgba[2], s->rgba[3], s->z, s->coc};
    exrio_box box = test_box(0, 0, W, H);
    CHECK(test_write_exr(path, &box, NULL, with_coc ? 6 : 5, names, types, planes,
                         EXRIO_COMPRESSION_ZIP) == 0);
}

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

void camera_50mm(ddof_camera *c, double fstop, double focus)
{
    ddof_camera_init(c);
    c->focal_length_mm = 50.0;
    c->sensor_width_mm = 36.0;
    c->fstop = fstop;
    c->focus_distance_m = focus;
}

/* out: interleaved RGBA. */
void library_result(const scene *s, const reference *ref, float *out, ddof_stats *stats)
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
            if (ref->aperture_blades) {
                ddof_camera camera;
                ddof_camera_init(&camera);
                camera.aperture_blades = ref->aperture_blades;
                ddof_frame frame;
                ddof_frame_init(&frame);
                frame.color = color_in;
                frame.coc = coc_in;
                frame.camera = &camera;
                CHECK(ddof_render_frame(ctx, &params, &frame, &out_img, stats) == DDOF_OK);
            } else {
                CHECK(ddof_diffuse_layers(ctx, &params, &color_in, &coc_in, NULL, &out_img,
                                          stats) == DDOF_OK);
            }
        }
    }
    ddof_context_free(ctx);
    free(color);
    free(coc);
}

/* Compares channels R, G, B, A of an output EXR with an interleaved RGBA reference. exact: bit
 * for bit; else within `tolerance` (relative, plus the same absolute near 0). Returns the
 * number of differing values. */
int compare_output(const char *path, const float *ref, int exact, double tolerance,
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

int cli_test_main(int argc, char **argv, const char *program, const cli_case *cases,
                  size_t count)
{
    const char *which;
    size_t i;
    if (argc != 4) {
        fprintf(stderr, "usage: %s DDOF_BINARY CASE SCRATCH_DIR\n", program);
        return 2;
    }
    ddof_bin = argv[1];
    which = argv[2];
    dir = argv[3];
    test_fresh_dir(dir);
    for (i = 0; i < count; i++)
        if (!strcmp(which, cases[i].name))
            return cases[i].run();
    fprintf(stderr, "%s: unknown case %s\n", program, which);
    return 2;
}
