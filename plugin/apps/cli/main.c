/* SPDX-License-Identifier: MIT */
/* main.c - `ddof`: depth of field for EXR renders and frame sequences (docs/cli.md).
 *
 * Order of work: signals first (so that every later thread inherits the blocked mask), then
 * options; everything that can be checked once (camera values, output directories, output !=
 * input) is checked before the first frame is read, so that a 240-frame job with a typo fails
 * in a second, not after frame 1 or frame 240. */
#include "aperture_image.h"
#include "camera_json.h"
#include "cards_scene.h"
#include "exrio.h"
#include "exrio_layout.h"
#include "frame_job.h"
#include "frames.h"
#include "option_table.h"
#include "options.h"
#include "output_file.h"
#include "progress.h"
#include "sequence.h"
#include "stats_json.h"

#include <ddof.h>

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The library's preset < flags. The command has no preset values of its own: they are the
 * accuracy study's, in libddof (ddof_params_init_preset). */
static void resolve_params(const cli_options *o, ddof_params *params)
{
    (void)ddof_params_init_preset(params, o->preset); /* the parser accepted only known ones */
    cli_options_override_params(o, params);
    if (o->method < 0 && params->method == DDOF_METHOD_COD4_PREVIEW &&
        (o->foreground || o->foreground_layer)) {
        /* The CoD4 preview blurs one image; a foreground element asks for the layers. */
        fprintf(stderr, "ddof: note: the %s preset's CoD4 preview takes no foreground element: "
                "using the diffusion\n", ddof_preset_name(o->preset));
        params->method = DDOF_METHOD_DIFFUSION;
    }
}

/* library defaults < camera.json < flags */
static int resolve_camera(const cli_options *o, frame_setup *setup)
{
    ddof_camera *c = &setup->camera;
    ddof_camera_init(c);
    if (o->camera_json) {
        camera_sidecar sidecar;
        char error[1024];
        if (camera_sidecar_read(o->camera_json, &sidecar, error, sizeof error) != 0) {
            fprintf(stderr, "ddof: %s\n", error);
            return -1;
        }
        *c = sidecar.camera;
        setup->sidecar_resolution[0] = sidecar.resolution[0];
        setup->sidecar_resolution[1] = sidecar.resolution[1];
        setup->camera_aspect_given = 1;
    }
    cli_options_override_camera(o, c);
    if (o->camera_set & CAM_ASPECT)
        setup->camera_aspect_given = 1;
    if (o->aperture_image) {
        char error[1024];
        setup->aperture_pixels = aperture_image_read(o->aperture_image, &c->aperture_image_width,
                                                     &c->aperture_image_height, error,
                                                     sizeof error);
        if (!setup->aperture_pixels) {
            fprintf(stderr, "ddof: --aperture-image: %s\n", error);
            return -1;
        }
        c->aperture_image = setup->aperture_pixels;
    }
    return 0;
}

/* Lets the library judge the backend, camera, curve and parameters once, so that a bad value
 * is one clear error before any frame is read (the library's messages name the value).
 * Returns 0, or the exit status. */
static int validate_with_library(const frame_setup *setup)
{
    const cli_options *o = setup->options;
    ddof_context_options co;
    ddof_context *context = NULL;
    ddof_status status = DDOF_OK;
    const char *what = "";
    int rc = 0;

    ddof_context_options_init(&co);
    co.thread_count = 1;
    if (ddof_context_create(&co, &context) != DDOF_OK) {
        fprintf(stderr, "ddof: cannot create a ddof context\n");
        return CLI_EXIT_FAILED;
    }
    /* The backend first: the solver and precision are judged by the backend that runs them. */
    status = ddof_context_set_backend(context, o->backend, o->gl_plugin);
    if (status != DDOF_OK) {
        fprintf(stderr, "ddof: --backend %s is not available: %s. Use --backend auto (a GPU "
                "when there is one, else the CPU) or --backend cpu.\n",
                ddof_backend_name(o->backend), ddof_context_last_error(context));
        ddof_context_free(context);
        return status == DDOF_ERROR_BACKEND_UNAVAILABLE ? CLI_EXIT_BACKEND : CLI_EXIT_USAGE;
    }
    if (o->source == COC_FROM_CAMERA) {
        what = "camera";
        status = ddof_camera_check(context, &setup->camera);
    } else if (o->source == COC_FROM_CURVE) {
        what = "--curve";
        status = ddof_curve_check(context, &setup->curve);
    }
    if (status == DDOF_OK) {
        what = "solver parameters";
        status = ddof_params_check(context, &setup->params);
    }
    if (status == DDOF_ERROR_UNSUPPORTED) {
        ddof_backend_info info = {.struct_size = sizeof info};
        (void)ddof_context_backend_info(context, &info);
        fprintf(stderr, "ddof: %s%s%s. --solver gruen and --precision packed-half (which needs "
                "--solver gruen) run on a GL backend only: --backend egl or osmesa.\n",
                ddof_context_last_error(context), info.note[0] ? "; " : "", info.note);
        rc = CLI_EXIT_BACKEND;
    } else if (status != DDOF_OK) {
        fprintf(stderr, "ddof: bad %s: %s\n", what, ddof_context_last_error(context));
        rc = CLI_EXIT_USAGE;
    }
    ddof_context_free(context);
    return rc;
}

static int expand(const char *pattern, int frame, char *out, const char *what)
{
    if (!pattern) {
        out[0] = '\0';
        return 0;
    }
    if (frame < 0) {
        if (strlen(pattern) >= PATH_MAX) {
            fprintf(stderr, "ddof: %s path too long\n", what);
            return -1;
        }
        strcpy(out, pattern);
        return 0;
    }
    if (frames_expand(pattern, frame, out, PATH_MAX) != 0) {
        fprintf(stderr, "ddof: %s path too long\n", what);
        return -1;
    }
    return 0;
}

/* The frame list: one file, or the frames of --frames with '#' patterns. */
static frame_paths *build_paths(const cli_options *o, int *count)
{
    int *frames = NULL;
    int n = 1, i;
    frame_paths *paths;

    if (o->frames) {
        char error[256];
        n = frames_parse(o->frames, &frames, error, sizeof error);
        if (n < 0) {
            fprintf(stderr, "ddof: %s\n", error);
            return NULL;
        }
        if (!frames_has_pattern(o->input) || !frames_has_pattern(o->output) ||
            (o->preview && !frames_has_pattern(o->preview)) ||
            (o->preview_input && !frames_has_pattern(o->preview_input)) ||
            (o->focus_map && !frames_has_pattern(o->focus_map))) {
            fprintf(stderr, "ddof: with --frames, the input, -o and preview paths need a run "
                    "of '#' for the frame number (render_####.exr)\n");
            free(frames);
            return NULL;
        }
    }
    paths = calloc((size_t)n, sizeof *paths);
    if (!paths) {
        fprintf(stderr, "ddof: out of memory\n");
        free(frames);
        return NULL;
    }
    for (i = 0; i < n; i++) {
        const int f = frames ? frames[i] : -1;
        paths[i].frame = f;
        if (expand(o->input, f, paths[i].input, "input") ||
            expand(o->output, f, paths[i].output, "output") ||
            expand(o->preview, f, paths[i].preview, "preview") ||
            expand(o->preview_input, f, paths[i].preview_input, "input preview") ||
            expand(o->focus_map, f, paths[i].focus_map, "focus map") ||
            expand(o->depth_file, f, paths[i].depth_file, "depth file") ||
            expand(o->foreground, f, paths[i].foreground, "foreground") ||
            expand(o->compare, f, paths[i].compare, "compare")) {
            free(paths);
            free(frames);
            return NULL;
        }
    }
    free(frames);
    *count = n;
    return paths;
}

/* The identity of an existing file: the same under any spelling, symbolic or hard link. */
typedef struct file_id {
    dev_t dev;
    ino_t ino;
    const char *path; /* one spelling of it, for messages */
} file_id;

static int compare_file_ids(const void *pa, const void *pb)
{
    const file_id *a = pa, *b = pb;
    if (a->dev != b->dev)
        return a->dev < b->dev ? -1 : 1;
    return a->ino < b->ino ? -1 : a->ino > b->ino;
}

/* Adds path to ids if it names an existing file (a missing one is nothing to protect). */
static void add_file_id(file_id *ids, size_t *n, const char *path)
{
    struct stat st;
    if (path && path[0] && stat(path, &st) == 0)
        ids[(*n)++] = (file_id){st.st_dev, st.st_ino, path};
}

/* The existing input that path is, or NULL. */
static const file_id *find_file_id(const file_id *ids, size_t n, const char *path)
{
    struct stat st;
    file_id key;
    if (!path || !path[0] || stat(path, &st) != 0)
        return NULL;
    key = (file_id){st.st_dev, st.st_ino, NULL};
    return bsearch(&key, ids, n, sizeof *ids, compare_file_ids);
}

/* No output of any frame, no preview and no stats file may be an input of any frame or the
 * camera sidecar: with sequences, frame 5's output may be frame 1005's input. Inputs exist,
 * so their (device, inode) identify them; each output is looked up once. */
static int check_no_input_overwritten(const cli_options *o, const frame_paths *paths, int count)
{
    file_id *ids = malloc(((size_t)count * 4 + 1) * sizeof *ids);
    size_t n = 0;
    int i, refused = 0;
    if (!ids) {
        fprintf(stderr, "ddof: out of memory\n");
        return -1;
    }
    for (i = 0; i < count; i++) {
        add_file_id(ids, &n, paths[i].input);
        add_file_id(ids, &n, paths[i].depth_file);
        add_file_id(ids, &n, paths[i].compare);
        add_file_id(ids, &n, paths[i].foreground);
    }
    add_file_id(ids, &n, o->camera_json);
    qsort(ids, n, sizeof *ids, compare_file_ids);
    for (i = 0; i <= count && !refused; i++) {
        /* Every frame's outputs, then (i == count) the stats file. */
        const char *outputs[4] = {i < count ? paths[i].output : o->stats_path,
                                  i < count ? paths[i].preview : NULL,
                                  i < count ? paths[i].preview_input : NULL,
                                  i < count ? paths[i].focus_map : NULL};
        int k;
        for (k = 0; k < 4 && !refused; k++) {
            const file_id *hit = find_file_id(ids, n, outputs[k]);
            if (hit) {
                fprintf(stderr, "ddof: refusing to write %s: it is an input (%s); ddof never "
                                "overwrites its input\n",
                        outputs[k], hit->path);
                refused = 1;
            }
        }
    }
    free(ids);
    return refused ? -1 : 0;
}

/* Every output path refused for being an input, and every output directory that cannot take
 * a file, before any work. */
static int check_outputs(const cli_options *o, const frame_paths *paths, int count)
{
    char error[2048];
    int i;
    for (i = 0; i < count; i++) { /* the common case, with the clearest message */
        if (frame_check_paths(&paths[i], error, sizeof error) != 0) {
            fprintf(stderr, "ddof: %s\n", error);
            return -1;
        }
    }
    /* A device, FIFO, socket, directory or link at any frame's output path: one lstat each,
     * before the first frame, not a failure after frame 239. */
    for (i = 0; i <= count; i++) {
        const char *outputs[4] = {i < count ? paths[i].output : o->stats_path,
                                  i < count ? paths[i].preview : NULL,
                                  i < count ? paths[i].preview_input : NULL,
                                  i < count ? paths[i].focus_map : NULL};
        int k;
        for (k = 0; k < 4; k++)
            if (outputs[k] && outputs[k][0] &&
                output_check_target(outputs[k], error, sizeof error) != 0) {
                fprintf(stderr, "ddof: %s%s\n", k == 0 && i == count ? "--stats: " : "", error);
                return -1;
            }
    }
    if (check_no_input_overwritten(o, paths, count) != 0)
        return -1;
    for (i = 0; o->stats_path && i < count; i++) { /* nor may --stats be one of the outputs */
        const char *outputs[4] = {paths[i].output, paths[i].preview, paths[i].preview_input,
                                  paths[i].focus_map};
        int k;
        for (k = 0; k < 4; k++)
            if (outputs[k][0] && (strcmp(outputs[k], o->stats_path) == 0 ||
                                  output_same_file(outputs[k], o->stats_path))) {
                if (paths[i].frame < 0)
                    fprintf(stderr, "ddof: --stats %s is also an output\n", o->stats_path);
                else
                    fprintf(stderr, "ddof: --stats %s is also an output of frame %d\n",
                            o->stats_path, paths[i].frame);
                return -1;
            }
    }
    /* Patterns keep the directory the same for every frame, so the first frame tells. */
    if (output_check_directory(paths[0].output, error, sizeof error) != 0 ||
        (paths[0].preview[0] &&
         output_check_directory(paths[0].preview, error, sizeof error) != 0) ||
        (paths[0].preview_input[0] &&
         output_check_directory(paths[0].preview_input, error, sizeof error) != 0) ||
        (paths[0].focus_map[0] &&
         output_check_directory(paths[0].focus_map, error, sizeof error) != 0)) {
        fprintf(stderr, "ddof: %s\n", error);
        return -1;
    }
    if (o->stats_path && output_check_directory(o->stats_path, error, sizeof error) != 0) {
        fprintf(stderr, "ddof: --stats: %s\n", error);
        return -1;
    }
    return 0;
}

/* What a killed run (SIGKILL, a power cut) left in the output directories. Patterns keep the
 * directory the same for every frame, so the first frame's paths name them all. */
static void remove_stale_temps(const cli_options *o, const frame_paths *first)
{
    const char *outputs[5] = {first->output, first->preview, first->preview_input,
                              first->focus_map, o->stats_path};
    int k;
    for (k = 0; k < 5; k++) {
        char note[PATH_MAX + 64];
        int removed;
        if (!outputs[k] || !outputs[k][0])
            continue;
        removed = output_remove_stale_temps(outputs[k], note, sizeof note);
        if (removed > 0)
            fprintf(stderr, "ddof: note: removed %d temporary file%s left by an earlier run "
                    "that was killed (%s%s)\n", removed, removed == 1 ? "" : "s", note,
                    removed > 1 ? ", ..." : "");
    }
}

/* --list: parts, channels, and what ddof would use. */
static int list_file(const cli_options *o, const char *path)
{
    exrio_image image;
    exrio_layout layout;
    exrio_layout_request request;
    char error[2048];
    int p, c;
    if (exrio_open(path, &image, error, sizeof error) != EXRIO_OK) {
        fprintf(stderr, "ddof: %s\n", error);
        return 1;
    }
    printf("%s: %d part%s\n", path, image.part_count, image.part_count == 1 ? "" : "s");
    for (p = 0; p < image.part_count; p++) {
        const exrio_part *part = &image.parts[p];
        printf("  part %d%s%s%s: %s, %s compression, data window (%d,%d)-(%d,%d) = %ux%u, "
               "display window (%d,%d)-(%d,%d), pixel aspect %g\n",
               p, part->name ? " '" : "", part->name ? part->name : "", part->name ? "'" : "",
               part->deep ? "deep" : part->tiled ? "tiled" : "scanline",
               exrio_compression_name(part->compression), (int)part->data_window.min_x,
               (int)part->data_window.min_y, (int)part->data_window.max_x,
               (int)part->data_window.max_y, part->width, part->height,
               (int)part->display_window.min_x, (int)part->display_window.min_y,
               (int)part->display_window.max_x, (int)part->display_window.max_y,
               (double)part->pixel_aspect);
        for (c = 0; c < image.channel_count; c++)
            if (image.channels[c].part == p)
                printf("    %-40s %s\n", image.channels[c].name,
                       exrio_pixel_type_name(image.channels[c].type));
    }
    memset(&request, 0, sizeof request);
    request.layer = o->layer;
    request.color = o->color;
    request.depth = o->depth;
    request.coc = o->source == COC_FROM_CHANNEL ? o->coc_channel : NULL;
    request.need_depth = o->source != COC_FROM_CHANNEL && !o->depth_file;
    if (exrio_find_layout(&image, &request, &layout, error, sizeof error) != EXRIO_LAYOUT_OK) {
        printf("ddof would not run on it: %s\n", error);
        exrio_close(&image);
        return 1;
    }
    printf("ddof uses: colour %s", image.channels[layout.color[0]].name);
    for (c = 1; c < layout.color_count; c++)
        printf(", %s", image.channels[layout.color[c]].name);
    if (layout.depth >= 0)
        printf("; depth %s", image.channels[layout.depth].name);
    if (layout.coc >= 0)
        printf("; CoC %s", image.channels[layout.coc].name);
    printf("\n");
    exrio_close(&image);
    return 0;
}

/* "3, 7-9, 12" */
static void print_failed_frames(const frame_paths *paths, const frame_result *results, int count)
{
    int i = 0, first = 1, failed = 0;
    for (i = 0; i < count; i++)
        failed += !results[i].ok;
    i = 0;
    fprintf(stderr, "ddof: failed frame%s: ", failed > 1 ? "s" : "");
    while (i < count) {
        int j = i;
        if (results[i].ok) {
            i++;
            continue;
        }
        while (j + 1 < count && !results[j + 1].ok && paths[j + 1].frame == paths[j].frame + 1)
            j++;
        if (paths[i].frame < 0)
            fprintf(stderr, "%s%s", first ? "" : ", ", paths[i].input);
        else if (j > i)
            fprintf(stderr, "%s%d-%d", first ? "" : ", ", paths[i].frame, paths[j].frame);
        else
            fprintf(stderr, "%s%d", first ? "" : ", ", paths[i].frame);
        first = 0;
        i = j + 1;
    }
    fprintf(stderr, "\n");
}

static void print_comparison(const frame_paths *p, const frame_result *r)
{
    char prefix[32] = "";
    if (p->frame >= 0)
        snprintf(prefix, sizeof prefix, "frame %d: ", p->frame);
    printf("%serror against %s (RGB; RMSE and PSNR of sRGB-encoded values clamped to [0, 1], "
           "linear RMSE unclamped):\n", prefix, p->compare);
    printf("  ddof result    RMSE %.5f  PSNR %6.2f dB  linear RMSE %.5f\n",
           r->error_result.rmse_srgb, r->error_result.psnr_srgb, r->error_result.rmse_linear);
    printf("  pinhole input  RMSE %.5f  PSNR %6.2f dB  linear RMSE %.5f\n",
           r->error_input.rmse_srgb, r->error_input.psnr_srgb, r->error_input.rmse_linear);
}

/* --list: the parts and channels of the first frame's file. Returns the exit status. */
static int run_list(const cli_options *o)
{
    char first[PATH_MAX], error[2048];
    int *frames = NULL;
    const int n = o->frames ? frames_parse(o->frames, &frames, error, sizeof error) : 0;
    int rc;
    if (n < 0) {
        fprintf(stderr, "ddof: %s\n", error);
        return CLI_EXIT_USAGE;
    }
    rc = expand(o->input, frames ? frames[0] : -1, first, "input");
    free(frames);
    return rc != 0 ? CLI_EXIT_USAGE : list_file(o, first);
}

/* The first readable header sizes the plan (*pixels); a missing first frame just means
 * "unknown" (its own error is reported when it runs). Returns 0 or the exit status. */
static int probe_first_frame(const cli_options *o, const frame_paths *first, uint64_t *pixels)
{
    exrio_image probe;
    char error[2048];
    int rc;
    *pixels = 0;
    if (exrio_open(first->input, &probe, error, sizeof error) != EXRIO_OK)
        return 0;
    *pixels = (uint64_t)probe.parts[0].width * probe.parts[0].height;
    rc = frame_check_input_parts(o, &probe, first->input, error, sizeof error);
    exrio_close(&probe);
    if (rc != 0) {
        fprintf(stderr, "ddof: %s\n", error);
        return CLI_EXIT_USAGE;
    }
    return 0;
}

/* Everything checked once, before the first frame is read: the params and camera, the
 * library's judgement of them, the frame list, the outputs. Returns 0 with the frames'
 * paths (free them), or the exit status. */
static int prepare(const cli_options *o, frame_setup *setup, frame_paths **paths, int *count,
                   uint64_t *pixels)
{
    int rc;
    memset(setup, 0, sizeof *setup);
    setup->options = o;
    setup->curve = o->curve;
    resolve_params(o, &setup->params);
    if (o->source == COC_FROM_CAMERA && resolve_camera(o, setup) != 0) {
        free(setup->aperture_pixels);
        return CLI_EXIT_USAGE;
    }
    rc = validate_with_library(setup);
    *paths = rc == 0 ? build_paths(o, count) : NULL;
    if (rc == 0 && !*paths)
        rc = CLI_EXIT_USAGE;
    if (rc != 0) {
        free(setup->aperture_pixels);
        return rc;
    }
    rc = check_outputs(o, *paths, *count) != 0 ? CLI_EXIT_FAILED : 0;
    if (rc == 0) {
        remove_stale_temps(o, &(*paths)[0]);
        rc = probe_first_frame(o, &(*paths)[0], pixels);
    }
    if (rc != 0) {
        free(*paths);
        *paths = NULL;
        free(setup->aperture_pixels);
    }
    return rc;
}

static void announce_plan(const cli_options *o, int count, const sequence_plan *plan)
{
    char threads[32] = "all cores";
    if (count <= 1 || o->quiet)
        return;
    if (plan->threads_per_frame > 0)
        snprintf(threads, sizeof threads, "%u thread%s", plan->threads_per_frame,
                 plan->threads_per_frame == 1 ? "" : "s");
    printf("ddof: %d frames, %u at a time, %s per frame (%s)\n", count, plan->jobs, threads,
           plan->reason);
}

/* Each frame's warning (once while it repeats) and comparison with the truth. */
static void print_frame_notes(const frame_paths *paths, const frame_result *results, int count)
{
    char last_warning[PATH_MAX + 512] = "";
    int i;
    for (i = 0; i < count; i++) {
        if (results[i].ok && results[i].warning[0] &&
            strcmp(results[i].warning, last_warning) != 0) {
            fprintf(stderr, "ddof: warning: %s\n", results[i].warning);
            snprintf(last_warning, sizeof last_warning, "%s", results[i].warning);
        }
        if (results[i].compared)
            print_comparison(&paths[i], &results[i]);
    }
}

/* The closing lines: the failed frames, or how many were written in how long. */
static void print_summary(const cli_options *o, const frame_paths *paths,
                          const frame_result *results, int count, int failed, double seconds)
{
    int i, skipped = 0;
    for (i = 0; i < count; i++)
        skipped += results[i].skipped;
    if (failed > 0) {
        if (count > 1)
            fprintf(stderr, "ddof: %d of %d frames failed\n", failed, count);
        print_failed_frames(paths, results, count);
    } else if (count > 1 && !o->quiet) {
        if (skipped > 0)
            printf("ddof: %d frame%s written, %d skipped (already complete) in %.2f s\n",
                   count - skipped, count - skipped == 1 ? "" : "s", skipped, seconds);
        else
            printf("ddof: %d frames written in %.2f s\n", count, seconds);
    }
}

/* Writes premultiplied RGBA as the output EXR (half unless --pixel-type float). */
static int write_cards_output(const cli_options *o, const float *rgba, uint32_t w, uint32_t h,
                              char *error, size_t error_size)
{
    static const char *const names[4] = {"R", "G", "B", "A"};
    exrio_write_channel channels[4];
    exrio_write_spec spec;
    output_file file;
    for (int c = 0; c < 4; c++) {
        channels[c].name = names[c];
        channels[c].type = o->pixel_type >= 0 ? (exrio_pixel_type)o->pixel_type : EXRIO_HALF;
        channels[c].pixels = rgba + c;
        channels[c].pixel_stride = 16;
        channels[c].line_stride = (size_t)w * 16;
    }
    memset(&spec, 0, sizeof spec);
    spec.data_window.max_x = spec.display_window.max_x = (int32_t)w - 1;
    spec.data_window.max_y = spec.display_window.max_y = (int32_t)h - 1;
    spec.compression = o->compression;
    spec.channel_count = 4;
    spec.channels = channels;
    if (output_file_begin(&file, o->output, error, error_size) != 0)
        return -1;
    if (exrio_write_fd(file.fd, o->output, &spec, error, error_size) != EXRIO_OK) {
        output_file_abort(&file);
        return -1;
    }
    return output_file_commit(&file, error, error_size);
}

/* --cards: one frame of a scene of textured cards (ddof_render_cards). Bad input is exit 2
 * with nothing written; a failed write exit 1. */
static int run_cards(const cli_options *o)
{
    char error[2048];
    cards_scene scene;
    ddof_context *context = NULL;
    float *rgba = NULL;
    const double t0 = now();
    if (cards_scene_read(o->cards_json, &scene, error, sizeof error) != 0) {
        fprintf(stderr, "ddof: %s\n", error);
        return CLI_EXIT_USAGE;
    }
    int rc = CLI_EXIT_OK;
    if (!scene.width || !scene.height) {
        fprintf(stderr, "ddof: %s: the camera needs \"resolution\": [width, height], the "
                "output's size\n", o->cards_json);
        rc = CLI_EXIT_USAGE;
    }
    if (rc == CLI_EXIT_OK) {
        rgba = calloc((size_t)scene.width * scene.height * 4, sizeof *rgba);
        ddof_context_options co;
        ddof_context_options_init(&co);
        co.thread_count = o->threads;
        if (!rgba || ddof_context_create(&co, &context) != DDOF_OK) {
            fprintf(stderr, "ddof: out of memory\n");
            rc = CLI_EXIT_FAILED;
        }
    }
    /* Cards go to a GL device only when one is named (--backend egl|osmesa): auto keeps them
     * on the CPU, whose image is the reference. */
    if (rc == CLI_EXIT_OK &&
        (o->backend == DDOF_BACKEND_EGL || o->backend == DDOF_BACKEND_OSMESA) &&
        ddof_context_set_backend(context, o->backend, o->gl_plugin) != DDOF_OK) {
        fprintf(stderr, "ddof: --backend %s is not available: %s. Use --backend cpu.\n",
                ddof_backend_name(o->backend), ddof_context_last_error(context));
        rc = CLI_EXIT_BACKEND;
    }
    if (rc == CLI_EXIT_OK) {
        const ddof_image out = {rgba, scene.width, scene.height, 4, 0};
        const ddof_status status =
            ddof_render_cards(context, NULL, &scene.camera, scene.cards, scene.count, &out);
        if (status != DDOF_OK) {
            fprintf(stderr, "ddof: %s: %s\n", o->cards_json, ddof_context_last_error(context));
            rc = status == DDOF_ERROR_OUT_OF_MEMORY ? CLI_EXIT_FAILED : CLI_EXIT_USAGE;
        }
    }
    if (rc == CLI_EXIT_OK) {
        if (write_cards_output(o, rgba, scene.width, scene.height, error, sizeof error) != 0) {
            fprintf(stderr, "ddof: %s\n", error);
            rc = CLI_EXIT_FAILED;
        } else if (!o->quiet) {
            printf("%s -> %s  %ux%u RGBA  %u card%s  (%.1f ms)\n", o->cards_json, o->output,
                   scene.width, scene.height, scene.count, scene.count == 1 ? "" : "s",
                   1000.0 * (now() - t0));
        }
    }
    ddof_context_free(context);
    free(rgba);
    cards_scene_free(&scene);
    return rc;
}

/* The frames, their report and the --stats file. Returns the exit status. */
static int run_frames(const cli_options *o)
{
    frame_setup setup;
    frame_paths *paths = NULL;
    frame_result *results = NULL;
    sequence_plan plan;
    progress *bar = NULL;
    char error[2048];
    uint64_t pixels = 0;
    double t0;
    int count = 0, failed, stats_failed = 0;
    const int rc = prepare(o, &setup, &paths, &count, &pixels);

    if (rc != 0)
        return rc;
    plan = sequence_plan_for(o, count, pixels);
    results = calloc((size_t)count, sizeof *results);
    bar = progress_create(count > 1 && (o->progress == PROGRESS_ALWAYS ||
                                        (o->progress == PROGRESS_AUTO && isatty(STDERR_FILENO))),
                          count, (int)plan.jobs);
    if (!results || !bar) {
        fprintf(stderr, "ddof: out of memory\n");
        free(paths);
        free(results);
        free(setup.aperture_pixels);
        progress_free(bar);
        return CLI_EXIT_FAILED;
    }
    announce_plan(o, count, &plan);

    t0 = now();
    failed = sequence_run(&setup, paths, results, count, &plan, bar, error, sizeof error);
    progress_finish(bar);
    if (failed < 0) {
        fprintf(stderr, "ddof: %s\n", error);
        failed = count;
    }
    print_frame_notes(paths, results, count);
    if (o->stats_path &&
        stats_json_write(o->stats_path, &setup, paths, results, count, plan.jobs,
                         plan.threads_per_frame, now() - t0, error, sizeof error) != 0) {
        /* The frames are not to blame: said apart from them. */
        fprintf(stderr, "ddof: --stats: %s\n", error);
        stats_failed = 1;
    }
    print_summary(o, paths, results, count, failed, now() - t0);
    errno = 0;
    if (fflush(stdout) != 0 || ferror(stdout)) {
        if (errno == EPIPE)
            output_broken_pipe("standard output");
        /* Closed (>&-), full or failing: the frames' lines are lost, so the run failed. */
        fprintf(stderr, "ddof: cannot write the standard output%s%s: the frames' report is "
                "lost\n", errno ? ": " : "", errno ? strerror(errno) : "");
        stats_failed = 1;
    }
    free(paths);
    free(results);
    free(setup.aperture_pixels);
    progress_free(bar);
    return failed > 0 || stats_failed ? CLI_EXIT_FAILED : CLI_EXIT_OK;
}

int main(int argc, char **argv)
{
    cli_options options;
    int rc;
    if (output_signals_install() != 0) {
        fprintf(stderr, "ddof: cannot set up signal handling\n");
        return CLI_EXIT_FAILED;
    }
    rc = cli_parse_options(argc, argv, &options);
    if (rc != 0)
        rc = rc > 0 ? CLI_EXIT_OK : CLI_EXIT_USAGE;
    else if (options.cards_json)
        rc = run_cards(&options);
    else if (options.list_only)
        rc = run_list(&options);
    else
        rc = run_frames(&options);
    output_signals_shutdown();
    return rc;
}
