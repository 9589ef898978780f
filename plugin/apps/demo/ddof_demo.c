/* SPDX-License-Identifier: MIT */
/* ddof_demo.c - `ddof-demo`: depth of field on a synthetic render, written out as PNGs.
 *
 * Renders the scene of synthetic_scene.h (640x360, linear RGB + planar depth) and makes one
 * ddof_render_frame call with an 85 mm lens on a 36 mm sensor (Cycles lens model) focused on
 * the subject, which also hands back the circle of confusion it used; writes, into the output
 * directory:
 *   pinhole.png       the input render
 *   depth.png         nearest depth / depth: near is bright, far dark, the sky black
 *   coc.png           CoC / largest CoC; orange in front of the focus plane, blue behind
 *   dof.png           the result
 *   before_after.png  pinhole | result, side by side
 * Colour images are linear -> sRGB (clamped); depth and CoC are written as display values. */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L
#endif

#include "png_write.h"
#include "synthetic_scene.h"

#include <ddof.h>

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#define WIDTH 640
#define HEIGHT 360
#define FOCAL_LENGTH_MM 85.0
#define SENSOR_WIDTH_MM 36.0
#define SEPARATOR_PX 4

typedef struct options {
    const char *out_dir;
    double fstop;
    double focus_m;
    int solver;        /* a ddof_solver, or -1 for the library default */
    uint32_t substeps; /* 0 for the library default */
    uint32_t threads;
} options;

static void usage(FILE *to)
{
    fprintf(to,
            "usage: ddof-demo [options]\n"
            "Renders a synthetic %dx%d scene with depth, applies diffusion depth of field\n"
            "(%.0f mm lens, %.0f mm sensor, Cycles lens model) and writes pinhole.png, depth.png,\n"
            "coc.png, dof.png and before_after.png.\n"
            "\n"
            "  -o, --output DIR   output directory, created if missing (default ddof-demo-out)\n"
            "  --fstop N          f-number (default 1.4)\n"
            "  --focus M          focus distance in metres (default %.1f, the subject)\n"
            "  --solver NAME      thomas | cr | pcr | jacobi | reference (default: the\n"
            "                     library's, thomas)\n"
            "  --substeps N       ADI sub-steps, >= 1; more gives rounder bokeh at linear cost\n"
            "                     (default: the library's, 1)\n"
            "  --threads N        worker threads, 0 = one per core (default 0)\n"
            "  -h, --help         this text\n",
            WIDTH, HEIGHT, FOCAL_LENGTH_MM, SENSOR_WIDTH_MM, DEMO_SCENE_SUBJECT_DISTANCE_M);
}

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int parse_double(const char *name, const char *text, double *out)
{
    char *end;
    double v;
    errno = 0;
    v = strtod(text, &end);
    if (end == text || *end != '\0' || errno != 0 || !isfinite(v)) {
        fprintf(stderr, "ddof-demo: %s wants a number, not '%s'\n", name, text);
        return -1;
    }
    *out = v;
    return 0;
}

static int parse_uint(const char *name, const char *text, uint32_t *out)
{
    char *end;
    unsigned long v;
    errno = 0;
    v = strtoul(text, &end, 10);
    if (end == text || *end != '\0' || errno != 0 || text[0] == '-' || v > 0xffffffffUL) {
        fprintf(stderr, "ddof-demo: %s wants a whole number >= 0, not '%s'\n", name, text);
        return -1;
    }
    *out = (uint32_t)v;
    return 0;
}

static int parse_solver(const char *text, int *out)
{
    int s;
    for (s = 0; s < DDOF_SOLVER_COUNT_; s++) {
        const char *name = ddof_solver_name((ddof_solver)s);
        if (name && strcmp(name, text) == 0) {
            *out = s;
            return 0;
        }
    }
    fprintf(stderr, "ddof-demo: unknown solver '%s' (thomas, cr, pcr, jacobi, reference)\n", text);
    return -1;
}

/* Returns 0 to run, 1 to exit successfully (--help), -1 on a usage error. */
static int parse_options(int argc, char **argv, options *o)
{
    int i;
    o->out_dir = "ddof-demo-out";
    o->fstop = 1.4;
    o->focus_m = DEMO_SCENE_SUBJECT_DISTANCE_M;
    o->solver = -1;
    o->substeps = 0;
    o->threads = 0;

    for (i = 1; i < argc; i++) {
        const char *arg = argv[i];
        const char *value = NULL;
        const char *eq = NULL;
        char name[32];
        int rc = 0;

        if (strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0) {
            usage(stdout);
            return 1;
        }
        /* --name=value or --name value */
        if (strncmp(arg, "--", 2) == 0)
            eq = strchr(arg, '=');
        if (eq) {
            size_t n = (size_t)(eq - arg);
            if (n >= sizeof name)
                n = sizeof name - 1;
            memcpy(name, arg, n);
            name[n] = '\0';
            value = eq + 1;
        } else {
            snprintf(name, sizeof name, "%s", arg);
        }
        if (strcmp(name, "-o") != 0 && strcmp(name, "--output") != 0 &&
            strcmp(name, "--fstop") != 0 && strcmp(name, "--focus") != 0 &&
            strcmp(name, "--solver") != 0 && strcmp(name, "--substeps") != 0 &&
            strcmp(name, "--threads") != 0) {
            fprintf(stderr, "ddof-demo: unknown argument '%s' (try --help)\n", arg);
            return -1;
        }
        if (!value) {
            if (i + 1 >= argc) {
                fprintf(stderr, "ddof-demo: %s needs a value (try --help)\n", name);
                return -1;
            }
            value = argv[++i];
        }
        if (strcmp(name, "-o") == 0 || strcmp(name, "--output") == 0) {
            if (value[0] == '\0') {
                fprintf(stderr, "ddof-demo: %s needs a directory name\n", name);
                return -1;
            }
            o->out_dir = value;
        } else if (strcmp(name, "--fstop") == 0) {
            rc = parse_double(name, value, &o->fstop);
        } else if (strcmp(name, "--focus") == 0) {
            rc = parse_double(name, value, &o->focus_m);
        } else if (strcmp(name, "--solver") == 0) {
            rc = parse_solver(value, &o->solver);
        } else if (strcmp(name, "--substeps") == 0) {
            rc = parse_uint(name, value, &o->substeps);
            if (rc == 0 && o->substeps == 0) {
                fprintf(stderr, "ddof-demo: --substeps must be at least 1\n");
                rc = -1;
            }
        } else {
            rc = parse_uint(name, value, &o->threads);
        }
        if (rc != 0)
            return -1;
    }
    return 0;
}

/* mkdir -p: creates `path` and its missing parents; fails if it exists as something else. */
static int make_directories(const char *path)
{
    struct stat st;
    char *copy = strdup(path);
    char *p;
    int ok = 1;
    if (!copy) {
        fprintf(stderr, "ddof-demo: out of memory\n");
        return -1;
    }
    for (p = copy + 1; ok && *p; p++) {
        if (*p == '/' && p[-1] != '/') {
            *p = '\0';
            if (mkdir(copy, 0777) != 0 && errno != EEXIST) {
                fprintf(stderr, "ddof-demo: cannot create directory '%s': %s\n", copy,
                        strerror(errno));
                ok = 0;
            }
            *p = '/';
        }
    }
    if (ok && mkdir(copy, 0777) != 0) {
        if (errno != EEXIST) {
            fprintf(stderr, "ddof-demo: cannot create directory '%s': %s\n", path,
                    strerror(errno));
            ok = 0;
        } else if (stat(copy, &st) != 0 || !S_ISDIR(st.st_mode)) {
            fprintf(stderr, "ddof-demo: '%s' exists and is not a directory\n", path);
            ok = 0;
        }
    }
    free(copy);
    return ok ? 0 : -1;
}

static uint8_t to_byte(double v)
{
    if (!(v > 0.0))
        return 0;
    if (v >= 1.0)
        return 255;
    return (uint8_t)(v * 255.0 + 0.5);
}

/* Linear light to an 8-bit sRGB code value (IEC 61966-2-1), clamped to [0, 1]. */
static uint8_t srgb_encode(float linear)
{
    double v = linear;
    if (!(v > 0.0))
        return 0;
    if (v >= 1.0)
        return 255;
    v = v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055;
    return to_byte(v);
}

static void encode_color(const float *linear, size_t pixels, uint8_t *out)
{
    size_t i;
    for (i = 0; i < pixels * 3; i++)
        out[i] = srgb_encode(linear[i]);
}

/* Inverse depth over that of the nearest pixel (nearest/depth): the nearest point is white, the
 * sky (+inf) black, and equal steps in the image are equal steps in defocus. */
static void encode_depth(const float *depth, size_t pixels, uint8_t *out)
{
    double nearest = INFINITY;
    size_t i;
    for (i = 0; i < pixels; i++)
        if (depth[i] > 0.0f && depth[i] < nearest)
            nearest = depth[i];
    for (i = 0; i < pixels; i++)
        out[i] = depth[i] > 0.0f && isfinite(nearest) ? to_byte(nearest / depth[i]) : 0;
}

/* CoC relative to the largest; orange for the near field, blue for the far field. */
static void encode_coc(const float *coc, const float *depth, double focus_m, size_t pixels,
                       uint8_t *out)
{
    double max = 0.0;
    size_t i;
    for (i = 0; i < pixels; i++)
        max = coc[i] > max ? coc[i] : max;
    for (i = 0; i < pixels; i++) {
        double k = max > 0.0 ? coc[i] / max : 0.0;
        int near = depth[i] < focus_m;
        out[i * 3 + 0] = to_byte(k * (near ? 1.00 : 0.30));
        out[i * 3 + 1] = to_byte(k * (near ? 0.60 : 0.60));
        out[i * 3 + 2] = to_byte(k * (near ? 0.15 : 1.00));
    }
}

/* Writes one PNG into the output directory and says so. */
static int write_png(const char *dir, const char *name, const uint8_t *pixels, uint32_t width,
                     uint32_t height, uint32_t channels)
{
    char path[4096];
    char error[4096 + 256];
    int n = snprintf(path, sizeof path, "%s/%s", dir, name);
    if (n < 0 || (size_t)n >= sizeof path) {
        fprintf(stderr, "ddof-demo: output path too long: %s/%s\n", dir, name);
        return -1;
    }
    if (png_write_file(path, pixels, width, height, channels, error, sizeof error) != 0) {
        fprintf(stderr, "ddof-demo: %s\n", error);
        return -1;
    }
    printf("wrote %s (%ux%u)\n", path, width, height);
    return 0;
}

/* Depth of field of the scene in one library call, which hands back the CoC it used. */
static int run_library(const options *opt, const demo_scene *scene, float *coc, float *result,
                       ddof_stats *stats)
{
    ddof_context_options context_options;
    ddof_context *context = NULL;
    ddof_camera camera;
    ddof_params params;
    ddof_frame frame;
    ddof_status status;

    ddof_context_options_init(&context_options);
    context_options.thread_count = opt->threads;
    status = ddof_context_create(&context_options, &context);
    if (status != DDOF_OK) {
        fprintf(stderr, "ddof-demo: cannot create a ddof context: %s\n", ddof_status_string(status));
        return -1;
    }
    ddof_camera_init(&camera);
    camera.lens_model = DDOF_LENS_CYCLES;
    camera.depth_kind = DDOF_DEPTH_PLANAR;
    camera.focal_length_mm = FOCAL_LENGTH_MM;
    camera.sensor_width_mm = SENSOR_WIDTH_MM;
    camera.fstop = opt->fstop;
    camera.focus_distance_m = opt->focus_m;
    ddof_params_init(&params);
    if (opt->solver >= 0)
        params.solver = (ddof_solver)opt->solver;
    if (opt->substeps > 0)
        params.substeps = opt->substeps;
    ddof_frame_init(&frame);
    frame.color = (ddof_image_in){scene->color, WIDTH, HEIGHT, 3, 0};
    frame.depth = (ddof_image_in){scene->depth, WIDTH, HEIGHT, 1, 0};
    frame.camera = &camera;
    frame.coc_out = (ddof_image){coc, WIDTH, HEIGHT, 1, 0};
    memset(stats, 0, sizeof *stats);
    stats->struct_size = sizeof *stats;
    status = ddof_render_frame(context, &params, &frame,
                               &(ddof_image){result, WIDTH, HEIGHT, 3, 0}, stats);
    if (status != DDOF_OK)
        fprintf(stderr, "ddof-demo: depth of field: %s: %s\n", ddof_status_string(status),
                ddof_context_last_error(context));
    ddof_context_free(context);
    return status == DDOF_OK ? 0 : -1;
}

/* pinhole.png, depth.png, coc.png, dof.png and before_after.png (pinhole | result). */
static int write_pictures(const options *opt, const demo_scene *scene, const float *coc,
                          const float *result)
{
    const size_t pixels = (size_t)WIDTH * HEIGHT;
    const uint32_t pair_width = 2 * WIDTH + SEPARATOR_PX;
    uint8_t *rgb8 = malloc(pixels * 3), *gray8 = malloc(pixels);
    uint8_t *pair8 = malloc((size_t)pair_width * HEIGHT * 3);
    int rc = -1;
    uint32_t y;

    if (!rgb8 || !gray8 || !pair8) {
        fprintf(stderr, "ddof-demo: out of memory\n");
        goto done;
    }
    encode_color(scene->color, pixels, rgb8);
    if (write_png(opt->out_dir, "pinhole.png", rgb8, WIDTH, HEIGHT, 3) != 0)
        goto done;
    for (y = 0; y < HEIGHT; y++) { /* left half of the pair, while rgb8 holds the input */
        uint8_t *row = pair8 + (size_t)y * pair_width * 3;
        memcpy(row, rgb8 + (size_t)y * WIDTH * 3, (size_t)WIDTH * 3);
        memset(row + (size_t)WIDTH * 3, 255, (size_t)SEPARATOR_PX * 3);
    }
    encode_depth(scene->depth, pixels, gray8);
    if (write_png(opt->out_dir, "depth.png", gray8, WIDTH, HEIGHT, 1) != 0)
        goto done;
    encode_coc(coc, scene->depth, opt->focus_m, pixels, rgb8);
    if (write_png(opt->out_dir, "coc.png", rgb8, WIDTH, HEIGHT, 3) != 0)
        goto done;
    encode_color(result, pixels, rgb8);
    if (write_png(opt->out_dir, "dof.png", rgb8, WIDTH, HEIGHT, 3) != 0)
        goto done;
    for (y = 0; y < HEIGHT; y++)
        memcpy(pair8 + ((size_t)y * pair_width + WIDTH + SEPARATOR_PX) * 3,
               rgb8 + (size_t)y * WIDTH * 3, (size_t)WIDTH * 3);
    if (write_png(opt->out_dir, "before_after.png", pair8, pair_width, HEIGHT, 3) != 0)
        goto done;
    rc = 0;
done:
    free(rgb8);
    free(gray8);
    free(pair8);
    return rc;
}

int main(int argc, char **argv)
{
    const size_t pixels = (size_t)WIDTH * HEIGHT;
    options opt;
    demo_scene scene = {0, 0, NULL, NULL};
    ddof_stats stats;
    float *coc = NULL, *result = NULL;
    double t0, scene_seconds;
    int exit_code = 1;
    int rc;

    rc = parse_options(argc, argv, &opt);
    if (rc != 0)
        return rc > 0 ? 0 : 2;
    if (make_directories(opt.out_dir) != 0)
        return 1;

    t0 = now_seconds();
    if (demo_scene_render(&scene, WIDTH, HEIGHT, FOCAL_LENGTH_MM, SENSOR_WIDTH_MM) != 0) {
        fprintf(stderr, "ddof-demo: out of memory\n");
        return 1;
    }
    scene_seconds = now_seconds() - t0;

    coc = malloc(pixels * sizeof *coc);
    result = malloc(pixels * 3 * sizeof *result);
    if (!coc || !result) {
        fprintf(stderr, "ddof-demo: out of memory\n");
        goto done;
    }
    if (run_library(&opt, &scene, coc, result, &stats) != 0 ||
        write_pictures(&opt, &scene, coc, result) != 0)
        goto done;

    printf("scene: %dx%d rendered in %.1f ms; lens %.0f mm f/%g focused at %g m\n", WIDTH, HEIGHT,
           scene_seconds * 1e3, FOCAL_LENGTH_MM, opt.fstop, opt.focus_m);
    printf("ddof %s: solver %s, %u substep(s), %u thread(s): %.2f ms total (CoC %.2f ms, rows "
           "%.2f ms, columns %.2f ms); %llu lines solved, %llu skipped; max CoC %.1f px%s\n",
           ddof_version_string(), ddof_solver_name((ddof_solver)stats.solver), stats.substeps,
           stats.threads, stats.seconds_total * 1e3, stats.seconds_coc * 1e3,
           stats.seconds_rows * 1e3, stats.seconds_columns * 1e3,
           (unsigned long long)stats.lines_solved, (unsigned long long)stats.lines_skipped,
           (double)stats.max_coc_px, stats.copied_only ? " (nothing out of focus: copied)" : "");
    exit_code = 0;

done:
    demo_scene_free(&scene);
    free(coc);
    free(result);
    return exit_code;
}
