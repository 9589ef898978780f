/* SPDX-License-Identifier: MIT */
/* ddof-bench - speed figures measured in one run, printed one per line as `name value`.
 *
 * Every figure is a ratio of two times taken in this run on this machine, so it means the same
 * on any machine: diffusion time over one memcpy of the same image, time at CoC 200 px over
 * time at 2 px, one thread's time over two threads'. Each time is the median of --reps runs
 * after one warm-up. Absolute milliseconds are printed too (as *_ms) for the notes.
 *
 *   ddof-bench [--size WxH] [--reps N] [--solver NAME|speed|layers|disc|frame|all]
 *              [--backend cpu|auto|egl|osmesa] [--plugin PATH] [--packed-half]
 *
 * With a GL backend (docs/gl-backend.md) it prints the renderer, and per solver the time at the
 * scene's CoC, the CoC 200 / 2 px ratio and device_bytes_per_mp (the GPU memory a call's buffers
 * took, per megapixel); thread ratios are skipped (the GPU does not use the context's threads).
 * --solver disc: the disc kernels (on the backend): time vs memcpy and vs one heat step, CoC 200 / 2,
 * threads, the layered frame, and the point spread at CoC 12, 32 and 80 px (kernel SNR
 * against a uniform disc, energy, the most negative value over the disc's height), and what the
 * default preset's frame call draws of an RGB point of 100 (the highlight pass) at those sizes.
 * --solver speed: the speed issue's figures (speed_*): one heat step and the default preset's
 * kernel vs memcpy and each other, CoC 200 / 2 and 2 threads / 1 for both, and a sub-pixel
 * frame (largest CoC 0.18 px: a copy) vs memcpy, and on the CPU backend the whole default frame
 * on each GL backend that loads (EGL, OSMesa) vs the CPU; `all` prints them first.
 * --solver frame: only default_frame_ms, the default preset's whole frame on the scene (what a
 * profiler should look at).
 * --packed-half runs the Gruen solver with DDOF_PRECISION_PACKED_HALF. The plugin is
 * this build's (the benchmark links the static library) unless --plugin names another.
 */
#include "ddof.h"
#include "point_spread.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef struct bench {
    uint32_t width, height, reps;
    float *color, *coc_scene, *coc_2, *coc_200, *out;
    float *coc_sharp, *coc_half; /* all in focus; top half in focus, bottom half 2 px   */
    float *coc_sub;              /* sub-pixel everywhere (0 to 0.18 px): in focus        */
    float *coc_crowns;           /* signed: discs of 30 px before a sky of 40 px          */
    float *fg_color, *fg_coc;    /* a foreground element: a disc, alpha 1, CoC 30 px   */
    float *matte;                /* the scene's object matte: (id, coverage) x 2 ranks   */
} bench;

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The precision every call asks for, and the device memory the last call reported. */
static ddof_precision bench_precision = DDOF_PRECISION_FLOAT;
static uint64_t last_device_bytes;

static double median(double *t, uint32_t n)
{
    qsort(t, n, sizeof *t, compare_doubles);
    return n % 2 ? t[n / 2] : 0.5 * (t[n / 2 - 1] + t[n / 2]);
}

static double time_memcpy(const bench *b)
{
    const size_t bytes = (size_t)b->width * b->height * 4 * sizeof(float);
    double t[64];
    memcpy(b->out, b->color, bytes); /* warm-up: fault in the pages */
    for (uint32_t i = 0; i < b->reps; i++) {
        double t0 = now();
        memcpy(b->out, b->color, bytes);
        t[i] = now() - t0;
        b->out[i] += 1.0f; /* keep the copy observable */
    }
    return median(t, b->reps);
}

/* What a timed call runs: the single layer, or the layered call with these settings. */
typedef struct run_config {
    int layered;
    ddof_layer_mode background;
    int foreground;
    ddof_kernel kernel;
    int whole_preset; /* the default preset as it is (its kernel and sub-steps), layered */
    int far_field_off, silhouettes_off; /* a whole preset without that pass */
    int matte;                          /* with the scene's object matte (the frame call) */
    int blurred_edges_off;              /* a whole preset without the far field's slices  */
    int coc_signed;                     /* the CoC is signed (what lies behind what known)  */
} run_config;

static const run_config single_layer = {0, DDOF_LAYER_AUTO, 0, DDOF_KERNEL_HEAT, 0, 0, 0, 0, 0, 0};
static const run_config default_frame = {1, DDOF_LAYER_AUTO, 0, DDOF_KERNEL_HEAT, 1, 0, 0, 0, 0, 0};

/* One call of the configuration. */
static ddof_status run_once(const bench *b, ddof_context *context, const ddof_params *params,
                            const float *coc, run_config config, ddof_stats *stats)
{
    ddof_image_in color = {b->color, b->width, b->height, 4, 0};
    ddof_image_in coc_image = {coc, b->width, b->height, 1, 0};
    ddof_image out = {b->out, b->width, b->height, 4, 0};
    if (config.matte) {
        ddof_frame frame;
        ddof_frame_init(&frame);
        frame.color = color;
        frame.coc = coc_image;
        const ddof_image_in matte = {b->matte, b->width, b->height, 4, 0};
        return ddof_render_frame_with_matte(context, params, &frame, &matte, &out, stats);
    }
    ddof_foreground fg;
    ddof_foreground_init(&fg);
    fg.color = (ddof_image_in){b->fg_color, b->width, b->height, 4, 0};
    fg.coc = (ddof_image_in){b->fg_coc, b->width, b->height, 1, 0};
    return config.layered ? ddof_diffuse_layers(context, params, &color, &coc_image,
                                                config.foreground ? &fg : NULL, &out, stats)
                          : ddof_diffuse(context, params, &color, &coc_image, &out, stats);
}

/* Median seconds of one call; exits on error (a benchmark has nothing to hide). */
static double time_config(const bench *b, ddof_context *context, ddof_solver solver,
                          const float *coc, run_config config)
{
    ddof_params params;
    ddof_params_init(&params);
    /* One ADI step of the heat kernel, the unit every figure here is about (a preset's
     * sub-steps multiply it), so the figures stay comparable when the study changes the
     * presets; the disc figures name their kernel. */
    if (!config.whole_preset) {
        params.substeps = 1;
        params.kernel = config.kernel;
        params.background = config.background;
        /* The diffusion's figures: the passes over its result have their own below. */
        params.far_field = DDOF_LAYER_OFF;
        params.silhouettes = DDOF_LAYER_OFF;
    }
    if (config.far_field_off)
        params.far_field = DDOF_LAYER_OFF;
    if (config.silhouettes_off)
        params.silhouettes = DDOF_LAYER_OFF;
    if (config.blurred_edges_off)
        params.blurred_edges = DDOF_LAYER_OFF;
    params.coc_signed = (uint32_t)config.coc_signed;
    params.solver = solver;
    params.precision = solver == DDOF_SOLVER_GRUEN ? bench_precision : DDOF_PRECISION_FLOAT;
    double t[64];
    for (uint32_t i = 0; i <= b->reps; i++) {
        ddof_stats stats = {.struct_size = sizeof stats};
        double t0 = now();
        ddof_status status = run_once(b, context, &params, coc, config, &stats);
        double seconds = now() - t0;
        last_device_bytes = stats.device_bytes;
        if (status == DDOF_ERROR_UNSUPPORTED)
            return -1.0; /* e.g. Gruen on the CPU: the caller says so */
        if (status != DDOF_OK) {
            fprintf(stderr, "ddof-bench: %s: %s\n", ddof_status_string(status),
                    ddof_context_last_error(context));
            exit(1);
        }
        if (i > 0)
            t[i - 1] = seconds; /* run 0 is the warm-up */
    }
    return median(t, b->reps);
}

static double time_diffuse(const bench *b, ddof_context *context, ddof_solver solver,
                           const float *coc)
{
    return time_config(b, context, solver, coc, single_layer);
}

static ddof_context *make_context(uint32_t threads)
{
    ddof_context_options options;
    ddof_context_options_init(&options);
    options.thread_count = threads;
    ddof_context *context = NULL;
    if (ddof_context_create(&options, &context) != DDOF_OK) {
        fprintf(stderr, "ddof-bench: cannot create a context with %u threads\n", threads);
        exit(1);
    }
    return context;
}

/* A render-like scene: textured colour; CoC 0 on an in-focus band, growing to 40 px behind and
 * 25 px in front, with a sharp object whose edges are discontinuities. */
static void make_scene(bench *b)
{
    const size_t pixels = (size_t)b->width * b->height;
    b->color = malloc(pixels * 4 * sizeof(float));
    b->out = malloc(pixels * 4 * sizeof(float));
    b->coc_scene = malloc(pixels * sizeof(float));
    b->coc_2 = malloc(pixels * sizeof(float));
    b->coc_200 = malloc(pixels * sizeof(float));
    b->coc_sharp = calloc(pixels, sizeof(float));
    b->coc_half = malloc(pixels * sizeof(float));
    b->coc_sub = malloc(pixels * sizeof(float));
    b->coc_crowns = malloc(pixels * sizeof(float));
    b->fg_color = malloc(pixels * 4 * sizeof(float));
    b->fg_coc = malloc(pixels * sizeof(float));
    b->matte = malloc(pixels * 4 * sizeof(float));
    if (!b->color || !b->out || !b->coc_scene || !b->coc_2 || !b->coc_200 || !b->coc_sharp ||
        !b->coc_half || !b->coc_sub || !b->coc_crowns || !b->fg_color || !b->fg_coc ||
        !b->matte) {
        fprintf(stderr, "ddof-bench: out of memory\n");
        exit(1);
    }
    for (uint32_t y = 0; y < b->height; y++)
        for (uint32_t x = 0; x < b->width; x++) {
            const size_t i = (size_t)y * b->width + x;
            const float u = (float)x / b->width, v = (float)y / b->height;
            float *c = b->color + 4 * i;
            c[0] = ((x / 16 + y / 16) % 2) ? 0.8f : 0.1f;
            c[1] = u;
            c[2] = v;
            c[3] = 1.0f;
            float depth_coc = v < 0.4f ? 40.0f * (0.4f - v) / 0.4f * 1.0f
                                       : (v > 0.6f ? 25.0f * (v - 0.6f) / 0.4f : 0.0f);
            const int in_object = u > 0.45f && u < 0.55f && v > 0.2f && v < 0.8f;
            b->coc_scene[i] = in_object ? 0.0f : depth_coc;
            /* The matte: the object whole or the wall whole (ids are bit patterns). */
            const uint32_t ids[2] = {in_object ? 1u : 2u, in_object ? 2u : 1u};
            memcpy(&b->matte[4 * i], &ids[0], sizeof ids[0]);
            memcpy(&b->matte[4 * i + 2], &ids[1], sizeof ids[1]);
            b->matte[4 * i + 1] = 1.0f;
            b->matte[4 * i + 3] = 0.0f;
            b->coc_2[i] = 2.0f;
            b->coc_200[i] = 200.0f;
            b->coc_half[i] = v < 0.5f ? 0.0f : 2.0f;
            b->coc_sub[i] = 0.18f * u * v; /* the invisible frame: largest 0.18 px */
            /* Tree crowns before the sky (issue 39): discs of 1/12 of the width every 1/6. */
            const float cu = u * 6.0f - floorf(u * 6.0f) - 0.5f;
            const float cv = (v * 6.0f - floorf(v * 6.0f) - 0.5f) * b->height / b->width;
            b->coc_crowns[i] = cu * cu + cv * cv < 0.25f * 0.25f ? 30.0f : 40.0f;
            const float dx = u - 0.2f, dy = (v - 0.7f) * b->height / b->width;
            const float fg_alpha = dx * dx + dy * dy < 0.01f ? 1.0f : 0.0f;
            for (int k = 0; k < 3; k++)
                b->fg_color[4 * i + k] = 0.9f * fg_alpha;
            b->fg_color[4 * i + 3] = fg_alpha;
            b->fg_coc[i] = 30.0f;
        }
}

/* The passes over the layers' result (issues 29 and 30): the default frame with each of them
 * (the preset's AUTO) against the same frame without it, on the scene (an in-focus object, so
 * silhouettes, and smooth blur above and below it) and on a frame with nothing in focus
 * (uniform CoC 200: no silhouette to split, the far field everywhere). */
static void bench_passes(const bench *b, ddof_context *all)
{
    run_config no_far = default_frame, no_split = default_frame;
    no_far.far_field_off = 1;
    no_split.silhouettes_off = 1;
    const double frame = time_config(b, all, DDOF_SOLVER_THOMAS, b->coc_scene, default_frame);
    const double far_off = time_config(b, all, DDOF_SOLVER_THOMAS, b->coc_scene, no_far);
    const double split_off = time_config(b, all, DDOF_SOLVER_THOMAS, b->coc_scene, no_split);
    printf("default_frame_ms %.3f\n", 1e3 * frame);
    printf("default_frame_vs_far_field_off %.3f\n", frame / far_off);
    printf("default_frame_vs_silhouettes_off %.3f\n", frame / split_off);
    run_config with_matte = default_frame;
    with_matte.matte = 1;
    const double matte = time_config(b, all, DDOF_SOLVER_THOMAS, b->coc_scene, with_matte);
    printf("matte_frame_vs_silhouettes_off %.3f\n", matte / split_off);
    const double flat = time_config(b, all, DDOF_SOLVER_THOMAS, b->coc_200, default_frame);
    const double flat_split_off = time_config(b, all, DDOF_SOLVER_THOMAS, b->coc_200, no_split);
    const double flat_far_off = time_config(b, all, DDOF_SOLVER_THOMAS, b->coc_200, no_far);
    printf("no_silhouette_frame_vs_silhouettes_off %.3f\n", flat / flat_split_off);
    printf("coc200_frame_vs_far_field_off %.3f\n", flat / flat_far_off);
    /* Blurred surfaces meeting everywhere (signed CoC: crowns of 30 px before a sky of 40). */
    run_config crowns = default_frame, crowns_off = default_frame;
    crowns.coc_signed = crowns_off.coc_signed = 1;
    crowns_off.blurred_edges_off = 1;
    const double edges = time_config(b, all, DDOF_SOLVER_THOMAS, b->coc_crowns, crowns);
    const double edges_off = time_config(b, all, DDOF_SOLVER_THOMAS, b->coc_crowns, crowns_off);
    printf("crowns_frame_ms %.3f\n", 1e3 * edges);
    printf("crowns_frame_vs_blurred_edges_off %.3f\n", edges / edges_off);
    fflush(stdout);
}

/* The speed issue's figures (issue 15), all from this run: one heat step and the default
 * preset's kernel against memcpy and each other, CoC 200 / 2 and 2 threads / 1 for both, and a
 * sub-pixel frame (largest CoC 0.18 px, below the in-focus threshold: a copy) against memcpy,
 * through the planner and through the single-layer call. */
static void bench_speed(const bench *b, ddof_context *one, ddof_context *two, ddof_context *all,
                        double memcpy_s, int on_gl)
{
    ddof_params defaults;
    ddof_params_init(&defaults);
    const run_config heat = single_layer;
    const run_config disc = {0, DDOF_LAYER_AUTO, 0, defaults.kernel, 0, 0, 0, 0, 0, 0};
    const run_config kernels[2] = {heat, disc};
    const char *names[2] = {"heat", "disc_default"};
    double scene[2];
    printf("speed_disc_default_kernel %s\n", ddof_kernel_name(defaults.kernel));
    for (int k = 0; k < 2; k++) {
        scene[k] = time_config(b, all, DDOF_SOLVER_THOMAS, b->coc_scene, kernels[k]);
        const double coc2 = time_config(b, all, DDOF_SOLVER_THOMAS, b->coc_2, kernels[k]);
        const double coc200 = time_config(b, all, DDOF_SOLVER_THOMAS, b->coc_200, kernels[k]);
        printf("speed_%s_ms %.3f\n", names[k], 1e3 * scene[k]);
        printf("speed_%s_vs_memcpy %.3f\n", names[k], scene[k] / memcpy_s);
        printf("speed_%s_coc200_vs_coc2 %.3f\n", names[k], coc200 / coc2);
        if (!on_gl) {
            const double t1 = time_config(b, one, DDOF_SOLVER_THOMAS, b->coc_scene, kernels[k]);
            const double t2 = time_config(b, two, DDOF_SOLVER_THOMAS, b->coc_scene, kernels[k]);
            printf("speed_%s_threads2_vs_threads1 %.3f\n", names[k], t1 / t2);
        }
        fflush(stdout);
    }
    printf("speed_disc_default_vs_heat %.3f\n", scene[1] / scene[0]);
    const run_config planned = {1, DDOF_LAYER_AUTO, 0, defaults.kernel, 0, 0, 0, 0, 0, 0};
    const double sub_layers = time_config(b, all, DDOF_SOLVER_THOMAS, b->coc_sub, planned);
    const double sub_single = time_config(b, all, DDOF_SOLVER_THOMAS, b->coc_sub, disc);
    printf("speed_sub_pixel_layers_ms %.3f\n", 1e3 * sub_layers);
    printf("speed_sub_pixel_layers_vs_memcpy %.3f\n", sub_layers / memcpy_s);
    printf("speed_sub_pixel_single_vs_memcpy %.3f\n", sub_single / memcpy_s);
    fflush(stdout);
}

/* The whole default frame (the default preset as it is, layers planned) on each GL backend
 * that loads here against the same frame on the CPU, all threads, in this run. A backend that
 * does not load prints why and no ratio. */
static void bench_gl_frames(const bench *b, ddof_context *cpu, const char *plugin)
{
    const double on_cpu = time_config(b, cpu, DDOF_SOLVER_THOMAS, b->coc_scene, default_frame);
    printf("speed_default_frame_cpu_ms %.3f\n", 1e3 * on_cpu);
    const ddof_backend_kind kinds[] = {DDOF_BACKEND_EGL, DDOF_BACKEND_OSMESA};
    for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; k++) {
        const char *name = ddof_backend_name(kinds[k]);
        ddof_context *gl = make_context(0);
        if (ddof_context_set_backend(gl, kinds[k], plugin) != DDOF_OK) {
            printf("speed_gl_%s_unavailable %s\n", name, ddof_context_last_error(gl));
            ddof_context_free(gl);
            continue;
        }
        ddof_backend_info info = {.struct_size = sizeof info};
        ddof_context_backend_info(gl, &info);
        const double on_gl = time_config(b, gl, DDOF_SOLVER_THOMAS, b->coc_scene, default_frame);
        printf("speed_gl_%s_renderer %s\n", name, info.renderer);
        printf("speed_gl_%s_default_frame_ms %.3f\n", name, 1e3 * on_gl);
        printf("speed_gl_%s_default_frame_vs_cpu %.3f\n", name, on_gl / on_cpu);
        printf("speed_gl_%s_device_bytes_per_mp %.0f\n", name,
               (double)last_device_bytes / ((double)b->width * b->height / 1e6));
        fflush(stdout);
        ddof_context_free(gl);
    }
}

/* The disc kernels (CPU Thomas): their cost against memcpy and the heat step, CoC 200 / 2,
 * threads, the layered default frame, and the point spread against the disc a lens draws. */
static void bench_disc(const bench *b, ddof_context *one, ddof_context *two, ddof_context *all,
                       double memcpy_s, int on_gl)
{
    const double heat = time_diffuse(b, all, DDOF_SOLVER_THOMAS, b->coc_scene);
    for (int k = 1; k < DDOF_KERNEL_COUNT_; k++) {
        const run_config disc = {0, DDOF_LAYER_AUTO, 0, (ddof_kernel)k, 0, 0, 0, 0, 0, 0};
        const run_config layered = {1, DDOF_LAYER_AUTO, 0, (ddof_kernel)k, 0, 0, 0, 0, 0, 0};
        char name[32];
        snprintf(name, sizeof name, "%s", ddof_kernel_name((ddof_kernel)k));
        name[4] = '_'; /* disc_2x2: one token */
        const double scene = time_config(b, all, DDOF_SOLVER_THOMAS, b->coc_scene, disc);
        const double coc2 = time_config(b, all, DDOF_SOLVER_THOMAS, b->coc_2, disc);
        const double coc200 = time_config(b, all, DDOF_SOLVER_THOMAS, b->coc_200, disc);
        const double t1 = on_gl ? 0 : time_config(b, one, DDOF_SOLVER_THOMAS, b->coc_scene, disc);
        const double t2 = on_gl ? 0 : time_config(b, two, DDOF_SOLVER_THOMAS, b->coc_scene, disc);
        const double frame = time_config(b, all, DDOF_SOLVER_THOMAS, b->coc_scene, layered);
        printf("%s_single_layer_ms %.3f\n", name, 1e3 * scene);
        printf("%s_vs_memcpy %.3f\n", name, scene / memcpy_s);
        printf("%s_vs_heat_step %.3f\n", name, scene / heat);
        printf("%s_coc200_vs_coc2 %.3f\n", name, coc200 / coc2);
        if (!on_gl)
            printf("%s_threads2_vs_threads1 %.3f\n", name, t1 / t2);
        else
            printf("%s_device_bytes_per_mp %.0f\n", name,
                   (double)last_device_bytes / ((double)b->width * b->height / 1e6));
        printf("%s_layers_auto_ms %.3f\n", name, 1e3 * frame);
        ddof_params params;
        ddof_params_init(&params);
        params.kernel = (ddof_kernel)k;
        const float sizes[] = {12.0f, 32.0f, 80.0f};
        for (int i = 0; i < 3; i++) {
            const point_spread ps = point_spread_measure(all, &params, sizes[i]);
            printf("%s_psf_coc%.0f_snr_db %.2f\n", name, (double)sizes[i], ps.snr_db);
            printf("%s_psf_coc%.0f_energy %.6f\n", name, (double)sizes[i], ps.energy);
            printf("%s_psf_coc%.0f_most_negative %.4f\n", name, (double)sizes[i], ps.ring);
        }
        fflush(stdout);
    }
    /* An HDR highlight (a point of 100) as the default preset's frame call draws it. */
    ddof_params defaults;
    ddof_params_init(&defaults);
    const float bright_sizes[] = {12.0f, 32.0f, 80.0f};
    for (int i = 0; i < 3; i++) {
        const point_spread ps = point_spread_measure_bright(all, &defaults, bright_sizes[i], 100.0f);
        printf("default_bright_psf_coc%.0f_snr_db %.2f\n", (double)bright_sizes[i], ps.snr_db);
        printf("default_bright_psf_coc%.0f_energy %.6f\n", (double)bright_sizes[i], ps.energy);
        printf("default_bright_psf_coc%.0f_most_negative %.4f\n", (double)bright_sizes[i],
               ps.ring);
    }
    ddof_params heat_params;
    ddof_params_init(&heat_params);
    heat_params.kernel = DDOF_KERNEL_HEAT;
    for (int n = 1; n <= 8; n *= 2) {
        heat_params.substeps = (uint32_t)n;
        const point_spread ps = point_spread_measure(all, &heat_params, 32.0f);
        printf("heat_n%d_psf_coc32_snr_db %.2f\n", n, ps.snr_db);
    }
}

static int parse_size(const char *s, uint32_t *w, uint32_t *h)
{
    unsigned a, c;
    if (sscanf(s, "%ux%u", &a, &c) != 2 || a == 0 || c == 0 || a > 16384 || c > 16384)
        return 0;
    *w = a;
    *h = c;
    return 1;
}

int main(int argc, char **argv)
{
    bench b = {.width = 1920, .height = 1080, .reps = 9};
    const char *only = "all";
#ifdef DDOF_BENCH_GL_PLUGIN
    const char *plugin = DDOF_BENCH_GL_PLUGIN;
#else
    const char *plugin = NULL;
#endif
    ddof_backend_kind backend = DDOF_BACKEND_CPU;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--size") && i + 1 < argc && parse_size(argv[i + 1], &b.width, &b.height))
            i++;
        else if (!strcmp(argv[i], "--reps") && i + 1 < argc && atoi(argv[i + 1]) >= 1 &&
                 atoi(argv[i + 1]) <= 63)
            b.reps = (uint32_t)atoi(argv[++i]);
        else if (!strcmp(argv[i], "--solver") && i + 1 < argc)
            only = argv[++i];
        else if (!strcmp(argv[i], "--plugin") && i + 1 < argc)
            plugin = argv[++i];
        else if (!strcmp(argv[i], "--packed-half"))
            bench_precision = DDOF_PRECISION_PACKED_HALF;
        else if (!strcmp(argv[i], "--backend") && i + 1 < argc) {
            const char *name = argv[++i];
            int found = 0;
            for (int k = 0; k < DDOF_BACKEND_COUNT_ && !found; k++)
                if (k != DDOF_BACKEND_HOST_GL && !strcmp(name, ddof_backend_name((ddof_backend_kind)k))) {
                    backend = (ddof_backend_kind)k;
                    found = 1;
                }
            if (!found) {
                fprintf(stderr, "ddof-bench: --backend cpu|auto|egl|osmesa\n");
                return 2;
            }
        } else {
            fprintf(stderr,
                    "usage: ddof-bench [--size WxH] [--reps 1..63] [--solver NAME|speed|layers|disc|frame|all]\n"
                    "                  [--backend cpu|auto|egl|osmesa] [--plugin PATH] [--packed-half]\n"
                    "Prints `name value` lines: times as ratios measured in this run.\n");
            return 2;
        }
    }
    make_scene(&b);
    ddof_context *one = make_context(1), *two = make_context(2), *all = make_context(0);

    if (backend != DDOF_BACKEND_CPU) {
        /* One context runs on the chosen backend; the thread ratios need the CPU, so they go. */
        ddof_status status = ddof_context_set_backend(all, backend, plugin);
        if (status != DDOF_OK) {
            fprintf(stderr, "ddof-bench: backend %s: %s\n", ddof_backend_name(backend),
                    ddof_context_last_error(all));
            return 1;
        }
    }
    ddof_backend_info info = {.struct_size = sizeof info};
    ddof_context_backend_info(all, &info);
    const int on_gl = info.kind != DDOF_BACKEND_CPU;
    printf("backend %s\n", ddof_backend_name((ddof_backend_kind)info.kind));
    printf("renderer %s\n", info.renderer);
    if (info.note[0])
        printf("backend_note %s\n", info.note);
    printf("image %ux%u_rgba_f32\n", b.width, b.height);
    printf("threads_default %u\n", ddof_context_thread_count(all));
    const double memcpy_s = time_memcpy(&b);
    printf("memcpy_ms %.3f\n", 1e3 * memcpy_s);
    if (!strcmp(only, "all") || !strcmp(only, "speed")) {
        bench_speed(&b, one, two, all, memcpy_s, on_gl);
        if (!on_gl)
            bench_gl_frames(&b, all, plugin);
    }

    for (int s = 0; s < DDOF_SOLVER_COUNT_; s++) {
        const char *name = ddof_solver_name((ddof_solver)s);
        if (strcmp(only, "all") && strcmp(only, name))
            continue;
        /* The reference is single-threaded and slow: one thread, fewer figures. */
        const int reference = s == DDOF_SOLVER_REFERENCE_F64;
        if (reference && on_gl && strcmp(only, name))
            continue; /* it runs on the CPU whatever the backend: not a GL figure */
        const double scene = time_diffuse(&b, reference ? one : all, (ddof_solver)s, b.coc_scene);
        const uint64_t device_bytes = last_device_bytes;
        if (scene < 0) {
            printf("%s_unsupported_on %s\n", name, ddof_backend_name((ddof_backend_kind)info.kind));
            continue;
        }
        const double coc2 = time_diffuse(&b, reference ? one : all, (ddof_solver)s, b.coc_2);
        const double coc200 = time_diffuse(&b, reference ? one : all, (ddof_solver)s, b.coc_200);
        const char *prefix = s == DDOF_SOLVER_THOMAS ? "" : name;
        const char *sep = s == DDOF_SOLVER_THOMAS ? "" : "_";
        printf("%s%ssingle_layer_ms %.3f\n", prefix, sep, 1e3 * scene);
        printf("%s%ssingle_layer_vs_memcpy %.3f\n", prefix, sep, scene / memcpy_s);
        printf("%s%scoc200_vs_coc2 %.3f\n", prefix, sep, coc200 / coc2);
        if (on_gl && !reference)
            printf("%s%sdevice_bytes_per_mp %.0f\n", prefix, sep,
                   (double)device_bytes / ((double)b.width * b.height / 1e6));
        if (!reference && !on_gl) {
            const double t1 = time_diffuse(&b, one, (ddof_solver)s, b.coc_scene);
            const double t2 = time_diffuse(&b, two, (ddof_solver)s, b.coc_scene);
            printf("%s%sthreads2_vs_threads1 %.3f\n", prefix, sep, t1 / t2);
        }
        fflush(stdout);
    }
    if (!strcmp(only, "frame")) {
        const double frame = time_config(&b, all, DDOF_SOLVER_THOMAS, b.coc_scene, default_frame);
        printf("default_frame_ms %.3f\n", 1e3 * frame);
    }
    if (!strcmp(only, "all") || !strcmp(only, "layers")) {
        bench_passes(&b, all);
        /* Layers and the planner, Thomas, all threads. */
        const run_config background = {1, DDOF_LAYER_ON, 0, DDOF_KERNEL_HEAT, 0, 0, 0, 0, 0, 0};
        const run_config three = {1, DDOF_LAYER_ON, 1, DDOF_KERNEL_HEAT, 0, 0, 0, 0, 0, 0};
        const run_config planned = {1, DDOF_LAYER_AUTO, 0, DDOF_KERNEL_HEAT, 0, 0, 0, 0, 0, 0};
        const double single = time_diffuse(&b, all, DDOF_SOLVER_THOMAS, b.coc_scene);
        const double bg = time_config(&b, all, DDOF_SOLVER_THOMAS, b.coc_scene, background);
        const double layers3 = time_config(&b, all, DDOF_SOLVER_THOMAS, b.coc_scene, three);
        printf("background_vs_single_layer %.3f\n", bg / single);
        printf("three_layers_ms %.3f\n", 1e3 * layers3);
        printf("three_layers_vs_single_layer %.3f\n", layers3 / single);
        /* What the planner saves. The reference is the same frame blurred everywhere (2 px,
         * every line solved). An all-sharp frame is a copy; a half-sharp one solves only the
         * lines that conduct; and since its 2 px blur is below the background threshold the
         * planner also skips the background layer that a fixed pipeline would run. */
        const double blurred = time_config(&b, all, DDOF_SOLVER_THOMAS, b.coc_2, planned);
        const double sharp = time_config(&b, all, DDOF_SOLVER_THOMAS, b.coc_sharp, planned);
        const double half = time_config(&b, all, DDOF_SOLVER_THOMAS, b.coc_half, planned);
        const double half_forced = time_config(&b, all, DDOF_SOLVER_THOMAS, b.coc_half, background);
        printf("all_blurred_planned_ms %.3f\n", 1e3 * blurred);
        printf("all_sharp_planned_ms %.3f\n", 1e3 * sharp);
        printf("all_sharp_vs_all_blurred %.3f\n", sharp / blurred);
        printf("all_sharp_vs_memcpy %.3f\n", sharp / memcpy_s);
        printf("half_sharp_planned_ms %.3f\n", 1e3 * half);
        printf("half_sharp_vs_all_blurred %.3f\n", half / blurred);
        printf("half_sharp_background_forced_vs_planned %.3f\n", half_forced / half);
    }
    if (!strcmp(only, "all") || !strcmp(only, "disc"))
        bench_disc(&b, one, two, all, memcpy_s, on_gl);
    ddof_context_free(one);
    ddof_context_free(two);
    ddof_context_free(all);
    free(b.color);
    free(b.out);
    free(b.coc_scene);
    free(b.coc_2);
    free(b.coc_200);
    free(b.coc_sharp);
    free(b.coc_half);
    free(b.coc_sub);
    free(b.coc_crowns);
    free(b.fg_color);
    free(b.fg_coc);
    free(b.matte);
    return 0;
}
