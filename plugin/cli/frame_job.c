/* frame_job.c - one frame: read, CoC, diffuse, write, preview, compare. */
#include "frame_job.h"

#include "exrio.h"
#include "exrio_layout.h"
#include "output_file.h"
#include "focus_map.h"
#include "preview.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int fail(frame_result *result, const char *format, ...)
{
    va_list args;
    va_start(args, format);
    vsnprintf(result->error, sizeof result->error, format, args);
    va_end(args);
    result->ok = 0;
    return -1;
}

typedef struct progress_link {
    progress *bar;
    int slot;
} progress_link;

/* The library reports [0, 1] of its call; the call is the middle 70 % of a frame's work. */
static int on_progress(void *user, float fraction)
{
    progress_link *link = user;
    progress_update(link->bar, link->slot, 0.1f + 0.7f * fraction);
    return 0;
}

static int same_box(const exrio_box *a, const exrio_box *b)
{
    return a->min_x == b->min_x && a->min_y == b->min_y && a->max_x == b->max_x &&
           a->max_y == b->max_y;
}

int frame_check_paths(const frame_paths *paths, char *error, size_t error_size)
{
    const char *inputs[4];
    const char *input_kind[4] = {"input", "depth file", "ground truth", "foreground element"};
    const char *outputs[4];
    const char *output_kind[4] = {"output", "preview", "input preview", "focus map"};
    int i, o;
    inputs[0] = paths->input;
    inputs[1] = paths->depth_file;
    inputs[2] = paths->compare;
    inputs[3] = paths->foreground;
    outputs[0] = paths->output;
    outputs[1] = paths->preview;
    outputs[2] = paths->preview_input;
    outputs[3] = paths->focus_map;
    for (o = 0; o < 4; o++) {
        if (!outputs[o][0])
            continue;
        for (i = 0; i < 4; i++) {
            if (!inputs[i][0])
                continue;
            /* Same spelling, or the same file under another spelling or link. */
            if (strcmp(outputs[o], inputs[i]) == 0 || output_same_file(outputs[o], inputs[i])) {
                snprintf(error, error_size, "refusing to write %s %s: it is the %s (%s); ddof "
                         "never overwrites its input", output_kind[o], outputs[o],
                         input_kind[i], inputs[i]);
                return -1;
            }
        }
    }
    for (o = 1; o < 3; o++) {
        int p;
        for (p = 0; p < o; p++) {
            if (outputs[o][0] && (strcmp(outputs[o], outputs[p]) == 0 ||
                                  output_same_file(outputs[o], outputs[p]))) {
                snprintf(error, error_size, "the %s and the %s are the same file (%s)",
                         output_kind[o], output_kind[p], outputs[o]);
                return -1;
            }
        }
    }
    return 0;
}

int frame_check_input_parts(const cli_options *options, const exrio_image *image,
                            const char *path, char *error, size_t error_size)
{
    if (!options->keep_channels || image->part_count <= 1)
        return 0;
    /* The path is cut to half the buffer so that the reason always fits. */
    snprintf(error, error_size, "%.*s has %d parts, and ddof writes a single-part EXR: "
             "--keep-channels (or --keep) would keep the channels of the part it diffuses only "
             "and silently drop the other parts; split the parts first, or leave out "
             "--keep-channels", (int)(error_size / 2), path, image->part_count);
    return -1;
}

/* 1 when `output` was modified no earlier than `input` (both exist). */
static int newer_than(const struct stat *output, const char *input)
{
    struct stat in;
    if (!input || !input[0])
        return 1;
    if (stat(input, &in) != 0)
        return 0; /* a missing input: let the frame run and say so */
    if (output->st_mtim.tv_sec != in.st_mtim.tv_sec)
        return output->st_mtim.tv_sec > in.st_mtim.tv_sec;
    return output->st_mtim.tv_nsec >= in.st_mtim.tv_nsec;
}

int frame_outputs_complete(const cli_options *options, const frame_paths *paths)
{
    const char *outputs[4] = {paths->output, paths->preview, paths->preview_input,
                              paths->focus_map};
    const char *inputs[5] = {paths->input, paths->depth_file, paths->foreground,
                             options->camera_json, options->compare ? paths->compare : NULL};
    exrio_image image;
    char error[1024];
    int o, i;
    for (o = 0; o < 4; o++) {
        struct stat st;
        if (!outputs[o][0])
            continue;
        if (lstat(outputs[o], &st) != 0 || !S_ISREG(st.st_mode))
            return 0;
        for (i = 0; i < 5; i++)
            if (!newer_than(&st, inputs[i]))
                return 0;
    }
    /* Outputs appear only by renaming a complete temporary file, so an output that opens as
     * an EXR is one ddof finished (or one a user put there deliberately). */
    if (exrio_open(paths->output, &image, error, sizeof error) != EXRIO_OK)
        return 0;
    exrio_close(&image);
    return 1;
}

/* A float plane for channel `index`: its own pixels, or a converted copy for UINT channels
 * (then *owned is set and the caller frees it). */
static const float *float_plane(const exrio_image *image, int index, size_t pixels,
                                float **owned)
{
    const exrio_channel *ch = &image->channels[index];
    float *copy;
    size_t i;
    *owned = NULL;
    if (ch->type != EXRIO_UINT)
        return ch->pixels;
    copy = malloc(pixels * sizeof *copy);
    if (!copy)
        return NULL;
    for (i = 0; i < pixels; i++)
        copy[i] = (float)((const uint32_t *)ch->pixels)[i];
    *owned = copy;
    return copy;
}

/* Interleaves channels `index[0..count)` into a new buffer of count floats per pixel. */
static float *interleave(const exrio_image *image, const int *index, int count, size_t pixels)
{
    float *out = malloc(pixels * (size_t)count * sizeof *out);
    size_t i;
    int c;
    if (!out)
        return NULL;
    for (c = 0; c < count; c++) {
        const exrio_channel *ch = &image->channels[index[c]];
        if (ch->type == EXRIO_UINT) {
            const uint32_t *in = ch->pixels;
            for (i = 0; i < pixels; i++)
                out[i * (size_t)count + (size_t)c] = (float)in[i];
        } else {
            const float *in = ch->pixels;
            for (i = 0; i < pixels; i++)
                out[i * (size_t)count + (size_t)c] = in[i];
        }
    }
    return out;
}

/* When the data window is not the display window, the camera is the display window's: the
 * full frame's size and the data window's place in it (ddof_camera 0.5), so the sensor fit, the
 * pixel pitch and the centre that radial depth is converted about are the frame's. */
static int camera_for_window(ddof_camera *camera, const exrio_part *part, frame_result *result)
{
    const exrio_box *d = &part->display_window;
    const int64_t dw = (int64_t)d->max_x - d->min_x + 1, dh = (int64_t)d->max_y - d->min_y + 1;
    const int64_t wx = (int64_t)part->data_window.min_x - d->min_x;
    const int64_t wy = (int64_t)part->data_window.min_y - d->min_y;
    if (same_box(&part->data_window, d))
        return 0;
    if (dw < 1 || dh < 1 || dw > DDOF_MAX_DIMENSION || dh > DDOF_MAX_DIMENSION ||
        wx < -(int64_t)DDOF_MAX_DIMENSION || wx > DDOF_MAX_DIMENSION ||
        wy < -(int64_t)DDOF_MAX_DIMENSION || wy > DDOF_MAX_DIMENSION)
        return fail(result, "the display window (%d,%d)-(%d,%d) or the data window's place in "
                    "it is too large for the camera", (int)d->min_x, (int)d->min_y,
                    (int)d->max_x, (int)d->max_y);
    camera->frame_width = (uint32_t)dw;
    camera->frame_height = (uint32_t)dh;
    camera->window_x = (int32_t)wx;
    camera->window_y = (int32_t)wy;
    return 0;
}

ddof_context *frame_context_create(const cli_options *options, uint32_t thread_count,
                                   char *error, size_t error_size)
{
    ddof_context_options co;
    ddof_context *context = NULL;
    ddof_status status;
    ddof_context_options_init(&co);
    co.thread_count = thread_count;
    status = ddof_context_create(&co, &context);
    if (status != DDOF_OK) {
        snprintf(error, error_size, "cannot create a ddof context: %s",
                 ddof_status_string(status));
        return NULL;
    }
    /* AUTO never fails for want of a GPU; an explicit GL backend that cannot be had does (main
     * checked it once already; this is a GPU that went away in between). */
    status = ddof_context_set_backend(context, options->backend, options->gl_plugin);
    if (status != DDOF_OK) {
        snprintf(error, error_size, "--backend %s is not available: %s",
                 ddof_backend_name(options->backend), ddof_context_last_error(context));
        ddof_context_free(context);
        return NULL;
    }
    return context;
}

static int library_failed(frame_result *result, ddof_context *context, const char *what,
                          ddof_status status)
{
    return fail(result, "%s: %s: %s", what, ddof_status_string(status),
                ddof_context_last_error(context));
}

/* Measures the result and the input against the ground truth. */
static int compare_with_truth(const frame_paths *paths, const float *color, const float *out,
                              int channels, const exrio_part *part, frame_result *result)
{
    exrio_image truth;
    exrio_layout layout;
    exrio_layout_request request;
    char error[1024];
    unsigned char *wanted;
    float *rgb;
    const size_t pixels = (size_t)part->width * part->height;
    int i;

    if (exrio_open(paths->compare, &truth, error, sizeof error) != EXRIO_OK)
        return fail(result, "ground truth: %s", error);
    memset(&request, 0, sizeof request);
    if (exrio_find_layout(&truth, &request, &layout, error, sizeof error) != EXRIO_LAYOUT_OK) {
        exrio_close(&truth);
        return fail(result, "ground truth: %s", error);
    }
    if (!same_box(&truth.parts[layout.part].data_window, &part->data_window)) {
        fail(result, "ground truth %s is %ux%u, the input is %ux%u: mismatched sizes",
             paths->compare, truth.parts[layout.part].width, truth.parts[layout.part].height,
             part->width, part->height);
        exrio_close(&truth);
        return -1;
    }
    wanted = calloc((size_t)truth.channel_count, 1);
    if (!wanted) {
        exrio_close(&truth);
        return fail(result, "out of memory");
    }
    for (i = 0; i < 3; i++)
        wanted[layout.color[i]] = 1;
    if (exrio_load(&truth, wanted, error, sizeof error) != EXRIO_OK) {
        free(wanted);
        exrio_close(&truth);
        return fail(result, "ground truth: %s", error);
    }
    free(wanted);
    rgb = interleave(&truth, layout.color, 3, pixels);
    exrio_close(&truth);
    if (!rgb)
        return fail(result, "out of memory");
    compare_rgb(out, channels, rgb, 3, pixels, &result->error_result);
    compare_rgb(color, channels, rgb, 3, pixels, &result->error_input);
    result->compared = 1;
    free(rgb);
    return 0;
}

/* Reads depth from a separate file; it must cover the same data window as the colour. */
static int read_depth_file(const frame_setup *setup, const frame_paths *paths,
                           const exrio_layout *layout, const exrio_part *color_part,
                           exrio_image *depth_image, int *depth_index, frame_result *result)
{
    char error[1024];
    unsigned char *wanted;
    const exrio_part *dp;
    int idx;
    if (exrio_open(paths->depth_file, depth_image, error, sizeof error) != EXRIO_OK)
        return fail(result, "%s", error);
    idx = exrio_find_depth(depth_image, layout->color_prefix, setup->options->depth);
    if (idx < 0) {
        char list[1024];
        exrio_list_channels(depth_image, 40, list, sizeof list);
        return fail(result, "%s: no depth channel%s%s%s found; channels in the file: %s",
                    paths->depth_file, setup->options->depth ? " '" : "",
                    setup->options->depth ? setup->options->depth : "",
                    setup->options->depth ? "'" : "", list);
    }
    dp = &depth_image->parts[depth_image->channels[idx].part];
    if (!same_box(&dp->data_window, &color_part->data_window))
        return fail(result, "mismatched layer sizes: depth %s in %s is %ux%u at (%d,%d) but the "
                    "colour in %s is %ux%u at (%d,%d)", depth_image->channels[idx].name,
                    paths->depth_file, dp->width, dp->height, (int)dp->data_window.min_x,
                    (int)dp->data_window.min_y, paths->input, color_part->width,
                    color_part->height, (int)color_part->data_window.min_x,
                    (int)color_part->data_window.min_y);
    wanted = calloc((size_t)depth_image->channel_count, 1);
    if (!wanted)
        return fail(result, "out of memory");
    wanted[idx] = 1;
    if (exrio_load(depth_image, wanted, error, sizeof error) != EXRIO_OK) {
        free(wanted);
        return fail(result, "%s", error);
    }
    free(wanted);
    *depth_index = idx;
    return 0;
}

/* The foreground element's buffers: interleaved premultiplied RGBA, and its depth or CoC. */
typedef struct foreground_data {
    float *color;         /* 4 channels, owned                                              */
    const float *depth;   /* its depth plane (camera/curve CoC); may point into the image  */
    const float *coc;     /* its CoC plane (--coc-channel)                                  */
    float *owned;         /* a converted uint plane, when one was needed                    */
} foreground_data;

/* Reads the foreground element: from --foreground FILE (its --foreground-layer, or found
 * automatically), or from --foreground-layer of the input itself. */
static int read_foreground(const frame_setup *setup, const frame_paths *paths,
                           exrio_image *input, const exrio_layout *main_layout,
                           const exrio_part *main_part, exrio_image *file,
                           foreground_data *fg, frame_result *result)
{
    const cli_options *opt = setup->options;
    exrio_image *source = input;
    exrio_layout layout;
    exrio_layout_request request;
    const exrio_part *part;
    unsigned char *wanted;
    char error[2048];
    const size_t pixels = (size_t)main_part->width * main_part->height;
    const char *name = paths->foreground[0] ? paths->foreground : paths->input;
    int i, plane;

    if (paths->foreground[0]) {
        if (exrio_open(paths->foreground, file, error, sizeof error) != EXRIO_OK)
            return fail(result, "foreground element: %s", error);
        source = file;
    }
    memset(&request, 0, sizeof request);
    request.layer = opt->foreground_layer;
    request.coc = opt->source == COC_FROM_CHANNEL ? opt->foreground_coc : NULL;
    request.need_depth = opt->source != COC_FROM_CHANNEL;
    if (exrio_find_layout(source, &request, &layout, error, sizeof error) != EXRIO_LAYOUT_OK)
        return fail(result, "foreground element: %s", error);
    if (source == input && layout.part == main_layout->part &&
        layout.color[0] == main_layout->color[0])
        return fail(result, "foreground element: layer '%s' is the main colour layer",
                    opt->foreground_layer);
    if (layout.color_count != 4)
        return fail(result, "foreground element in %s has no alpha channel (%s.A): it is needed "
                    "to composite the element", name,
                    layout.color_prefix[0] ? layout.color_prefix : "R,G,B");
    part = &source->parts[layout.part];
    if (part->data_window.min_x != main_part->data_window.min_x ||
        part->data_window.min_y != main_part->data_window.min_y ||
        part->width != main_part->width || part->height != main_part->height)
        return fail(result, "mismatched layer sizes: the foreground element in %s is %ux%u at "
                    "(%d,%d) but the image is %ux%u at (%d,%d)", name, part->width,
                    part->height, (int)part->data_window.min_x, (int)part->data_window.min_y,
                    main_part->width, main_part->height, (int)main_part->data_window.min_x,
                    (int)main_part->data_window.min_y);
    wanted = calloc((size_t)source->channel_count, 1);
    if (!wanted)
        return fail(result, "out of memory");
    for (i = 0; i < 4; i++)
        wanted[layout.color[i]] = 1;
    plane = layout.coc >= 0 ? layout.coc : layout.depth;
    wanted[plane] = 1;
    if (exrio_load(source, wanted, error, sizeof error) != EXRIO_OK) {
        free(wanted);
        return fail(result, "foreground element: %s", error);
    }
    free(wanted);
    fg->color = interleave(source, layout.color, 4, pixels);
    if (layout.coc >= 0)
        fg->coc = float_plane(source, plane, pixels, &fg->owned);
    else
        fg->depth = float_plane(source, plane, pixels, &fg->owned);
    if (!fg->color || (!fg->coc && !fg->depth))
        return fail(result, "out of memory");
    return 0;
}

/* Builds the output channel list and writes the EXR atomically. */
static int write_output(const frame_setup *setup, const frame_paths *paths,
                        const exrio_image *image, const exrio_layout *layout, const float *out,
                        int channels, const float *coc, frame_result *result)
{
    static const char *const plain[4] = {"R", "G", "B", "A"};
    const cli_options *opt = setup->options;
    const exrio_part *part = &image->parts[layout->part];
    const size_t line = (size_t)part->width * 4;
    exrio_write_channel *list;
    exrio_write_spec spec;
    output_file file;
    exrio_pixel_type type;
    char error[1024];
    int count = 0, i, c;

    type = opt->pixel_type >= 0 ? (exrio_pixel_type)opt->pixel_type
                                : image->channels[layout->color[0]].type;
    if (type == EXRIO_UINT)
        type = EXRIO_FLOAT;
    list = calloc((size_t)image->channel_count + 5, sizeof *list);
    if (!list)
        return fail(result, "out of memory");
    for (c = 0; c < channels; c++) {
        /* --keep-channels keeps the input's layout, so the colour keeps its names too. */
        list[count].name = opt->keep_channels ? image->channels[layout->color[c]].name : plain[c];
        list[count].type = type;
        list[count].pixels = out + c;
        list[count].pixel_stride = (size_t)channels * sizeof(float);
        list[count].line_stride = (size_t)part->width * (size_t)channels * sizeof(float);
        count++;
    }
    if (opt->keep_channels) {
        for (i = 0; i < image->channel_count; i++) {
            const exrio_channel *ch = &image->channels[i];
            int is_color = 0;
            for (c = 0; c < channels; c++)
                is_color |= layout->color[c] == i;
            if (is_color || ch->part != layout->part || !ch->pixels)
                continue;
            list[count].name = ch->name;
            list[count].type = ch->type;
            list[count].pixels = ch->pixels;
            list[count].pixel_stride = 4;
            list[count].line_stride = line;
            count++;
        }
    }
    if (coc) {
        const char *name = "coc";
        if (opt->keep_channels && exrio_find_channel(image, name, layout->part) >= 0)
            name = "ddof.coc";
        list[count].name = name;
        list[count].type = EXRIO_FLOAT;
        list[count].pixels = coc;
        list[count].pixel_stride = 4;
        list[count].line_stride = line;
        count++;
    }

    memset(&spec, 0, sizeof spec);
    spec.data_window = part->data_window;
    spec.display_window = part->display_window;
    spec.pixel_aspect = part->pixel_aspect;
    spec.compression = opt->compression;
    spec.channel_count = count;
    spec.channels = list;
    spec.metadata_from = opt->keep_metadata ? image : NULL;
    spec.metadata_part = layout->part;

    if (output_file_begin(&file, paths->output, error, sizeof error) != 0) {
        free(list);
        return fail(result, "%s", error);
    }
    if (exrio_write_fd(file.fd, paths->output, &spec, error, sizeof error) != EXRIO_OK) {
        output_file_abort(&file);
        free(list);
        return fail(result, "%s", error);
    }
    free(list);
    if (output_file_commit(&file, error, sizeof error) != 0)
        return fail(result, "%s", error);
    return 0;
}

int frame_run(ddof_context *context, const frame_setup *setup, const frame_paths *paths,
              frame_result *result, progress *bar, int slot)
{
    const cli_options *opt = setup->options;
    const double t0 = now();
    double t;
    exrio_image image, depth_image;
    exrio_layout layout;
    exrio_layout_request request;
    const exrio_part *part;
    unsigned char *wanted = NULL;
    float *color = NULL, *out = NULL, *coc = NULL, *depth_owned = NULL, *coc_owned = NULL;
    float *fg_coc = NULL;
    exrio_image fg_image;
    foreground_data fg;
    ddof_camera camera;
    const float *depth = NULL, *coc_in = NULL;
    progress_link link;
    ddof_params params;
    ddof_status status;
    char error[2048];
    size_t pixels;
    int depth_index = -1, i, rc = -1;

    memset(result, 0, sizeof *result);
    memset(&image, 0, sizeof image);
    memset(&depth_image, 0, sizeof depth_image);
    memset(&fg_image, 0, sizeof fg_image);
    memset(&fg, 0, sizeof fg);
    ddof_camera_init(&camera);
    result->stats.struct_size = sizeof result->stats;
    result->backend.struct_size = sizeof result->backend;
    (void)ddof_context_backend_info(context, &result->backend);
    link.bar = bar;
    link.slot = slot;

    if (frame_check_paths(paths, error, sizeof error) != 0) {
        fail(result, "%s", error);
        goto done;
    }
    if (opt->skip_existing && frame_outputs_complete(opt, paths)) {
        result->ok = 1;
        result->skipped = 1;
        rc = 0;
        goto done;
    }

    /* Read: header, channel layout, then only the channels needed. */
    if (exrio_open(paths->input, &image, error, sizeof error) != EXRIO_OK) {
        fail(result, "%s", error);
        goto done;
    }
    memset(&request, 0, sizeof request);
    request.layer = opt->layer;
    request.color = opt->color;
    request.depth = paths->depth_file[0] ? NULL : opt->depth;
    request.coc = opt->source == COC_FROM_CHANNEL ? opt->coc_channel : NULL;
    request.need_depth = opt->source != COC_FROM_CHANNEL && !paths->depth_file[0];
    /* A foreground layer in the same file is never the main colour. */
    request.exclude_layer = !paths->foreground[0] ? opt->foreground_layer : NULL;
    if (exrio_find_layout(&image, &request, &layout, error, sizeof error) != EXRIO_LAYOUT_OK ||
        frame_check_input_parts(opt, &image, paths->input, error, sizeof error) != 0) {
        fail(result, "%s", error);
        goto done;
    }
    part = &image.parts[layout.part];
    pixels = (size_t)part->width * part->height;
    result->width = part->width;
    result->height = part->height;
    result->channels = layout.color_count;
    if (layout.color_prefix[0])
        snprintf(result->color_name, sizeof result->color_name, "%s.%s", layout.color_prefix,
                 layout.color_count == 4 ? "RGBA" : "RGB");
    else
        snprintf(result->color_name, sizeof result->color_name, "%s,%s,%s%s%s",
                 image.channels[layout.color[0]].name, image.channels[layout.color[1]].name,
                 image.channels[layout.color[2]].name, layout.color_count == 4 ? "," : "",
                 layout.color_count == 4 ? image.channels[layout.color[3]].name : "");

    wanted = calloc((size_t)image.channel_count, 1);
    if (!wanted) {
        fail(result, "out of memory");
        goto done;
    }
    for (i = 0; i < layout.color_count; i++)
        wanted[layout.color[i]] = 1;
    if (layout.depth >= 0)
        wanted[layout.depth] = 1;
    if (layout.coc >= 0)
        wanted[layout.coc] = 1;
    if (opt->keep_channels)
        for (i = 0; i < image.channel_count; i++)
            if (image.channels[i].part == layout.part)
                wanted[i] = 1;
    if (exrio_load(&image, wanted, error, sizeof error) != EXRIO_OK) {
        fail(result, "%s", error);
        goto done;
    }

    if (opt->source != COC_FROM_CHANNEL) {
        const exrio_image *from = &image;
        depth_index = layout.depth;
        if (paths->depth_file[0]) {
            if (read_depth_file(setup, paths, &layout, part, &depth_image, &depth_index,
                                result) != 0)
                goto done;
            from = &depth_image;
        }
        snprintf(result->depth_name, sizeof result->depth_name, "%s",
                 from->channels[depth_index].name);
        depth = float_plane(from, depth_index, pixels, &depth_owned);
    } else {
        snprintf(result->depth_name, sizeof result->depth_name, "%s",
                 image.channels[layout.coc].name);
        coc_in = float_plane(&image, layout.coc, pixels, &coc_owned);
    }
    color = interleave(&image, layout.color, layout.color_count, pixels);
    out = malloc(pixels * (size_t)layout.color_count * sizeof *out);
    if (!color || !out || (!depth && !coc_in)) {
        fail(result, "out of memory for a %ux%u frame", part->width, part->height);
        goto done;
    }
    result->seconds_read = now() - t0;
    progress_update(bar, slot, 0.1f);

    /* The foreground element, when there is one: same size, RGBA, its own depth or CoC. */
    if (opt->foreground || opt->foreground_layer) {
        if (read_foreground(setup, paths, &image, &layout, part, &fg_image, &fg, result) != 0)
            goto done;
    }

    /* Depth of field. */
    params = setup->params;
    params.progress = bar ? on_progress : NULL;
    params.progress_user = &link;
    {
        const ddof_image_in color_in = {color, part->width, part->height,
                                        (uint32_t)layout.color_count, 0};
        const ddof_image out_image = {out, part->width, part->height,
                                      (uint32_t)layout.color_count, 0};
        const ddof_image_in depth_in = {depth, part->width, part->height, 1, 0};
        const ddof_image_in fg_depth_in = {fg.depth, part->width, part->height, 1, 0};
        const int need_coc = opt->write_coc || fg.color != NULL || paths->focus_map[0];
        ddof_image coc_image = {NULL, part->width, part->height, 1, 0};
        ddof_image fg_coc_image = {NULL, part->width, part->height, 1, 0};
        ddof_foreground element;

        /* A buffer for the CoC the camera or the curve computes; a CoC channel is its own. */
        if ((need_coc && opt->source != COC_FROM_CHANNEL) || opt->source == COC_FROM_CURVE) {
            coc = malloc(pixels * sizeof *coc);
            if (!coc) {
                fail(result, "out of memory");
                goto done;
            }
            coc_image.pixels = coc;
        }
        if (fg.color && !fg.coc) {
            fg_coc = malloc(pixels * sizeof *fg_coc);
            if (!fg_coc) {
                fail(result, "out of memory");
                goto done;
            }
            fg_coc_image.pixels = fg_coc;
        }
        t = now();
        if (opt->source == COC_FROM_CAMERA) {
            const exrio_box *d = &part->display_window;
            const uint32_t dw = (uint32_t)(d->max_x - d->min_x + 1);
            const uint32_t dh = (uint32_t)(d->max_y - d->min_y + 1);
            camera = setup->camera;
            if (!setup->camera_aspect_given)
                camera.pixel_aspect = part->pixel_aspect;
            if (setup->sidecar_resolution[0] &&
                (setup->sidecar_resolution[0] != dw || setup->sidecar_resolution[1] != dh))
                snprintf(result->warning, sizeof result->warning,
                         "the camera sidecar says %ux%u but %s is a %ux%u frame: the CoC "
                         "follows the file's pixels (a render at another resolution scale)",
                         setup->sidecar_resolution[0], setup->sidecar_resolution[1],
                         paths->input, dw, dh);
            if (camera_for_window(&camera, part, result) != 0)
                goto done;
            /* Signed, as ddof_depth_of_field computes it: negative in front of the focus. */
            camera.signed_coc = 1;
            if (need_coc &&
                (status = ddof_coc_from_camera(context, &camera, &depth_in, &coc_image)) !=
                    DDOF_OK) {
                library_failed(result, context, "CoC", status);
                goto done;
            }
            if (fg_coc_image.pixels &&
                (status = ddof_coc_from_camera(context, &camera, &fg_depth_in, &fg_coc_image)) !=
                    DDOF_OK) {
                library_failed(result, context, "CoC of the foreground element", status);
                goto done;
            }
            params.coc_signed = 1;
            params.pixel_aspect = (float)camera.pixel_aspect;
        } else if (opt->source == COC_FROM_CURVE) {
            ddof_curve curve = setup->curve;
            curve.signed_coc = 1; /* so that the near field is known to the layers */
            if ((status = ddof_coc_from_curve(context, &curve, &depth_in, &coc_image)) !=
                DDOF_OK) {
                library_failed(result, context, "CoC from the curve", status);
                goto done;
            }
            if (fg_coc_image.pixels &&
                (status = ddof_coc_from_curve(context, &curve, &fg_depth_in, &fg_coc_image)) !=
                    DDOF_OK) {
                library_failed(result, context, "CoC of the foreground element", status);
                goto done;
            }
            coc_in = coc;
            params.coc_signed = 1;
            params.pixel_aspect = part->pixel_aspect;
        } else {
            params.coc_signed = (uint32_t)opt->coc_signed;
            params.pixel_aspect = part->pixel_aspect;
        }
        result->seconds_coc = need_coc || opt->source == COC_FROM_CURVE ? now() - t : 0.0;

        t = now();
        if (opt->source == COC_FROM_CAMERA && !fg.color) {
            /* The main job in one call, exactly as a program using the library would. */
            status = ddof_depth_of_field(context, &params, &camera, &color_in, &depth_in,
                                         &out_image, &result->stats);
        } else {
            const ddof_image_in coc_read = {opt->source == COC_FROM_CAMERA ? coc : coc_in,
                                            part->width, part->height, 1, 0};
            if (fg.color) {
                ddof_foreground_init(&element);
                element.color.pixels = fg.color;
                element.color.width = part->width;
                element.color.height = part->height;
                element.color.channels = 4;
                element.color.row_stride = 0;
                element.coc.pixels = fg.coc ? fg.coc : fg_coc;
                element.coc.width = part->width;
                element.coc.height = part->height;
                element.coc.channels = 1;
                element.coc.row_stride = 0;
                element.premultiplied = opt->foreground_straight ? 0u : 1u;
            }
            status = ddof_diffuse_layers(context, &params, &color_in, &coc_read,
                                         fg.color ? &element : NULL, &out_image, &result->stats);
        }
        result->seconds_dof = now() - t;
        if (status != DDOF_OK) {
            library_failed(result, context, "depth of field", status);
            goto done;
        }
    }
    progress_update(bar, slot, 0.8f);

    /* Output. */
    t = now();
    if (write_output(setup, paths, &image, &layout, out, layout.color_count,
                     opt->write_coc ? (coc ? coc : coc_in) : NULL, result) != 0)
        goto done;
    result->seconds_write = now() - t;
    if (paths->preview[0]) {
        t = now();
        if (preview_write(paths->preview, out, (uint32_t)layout.color_count, part->width,
                          part->height, opt->preview_exposure, error, sizeof error) != 0) {
            fail(result, "preview: %s", error);
            goto done;
        }
        result->seconds_preview = now() - t;
    }
    if (paths->preview_input[0]) {
        t = now();
        if (preview_write(paths->preview_input, color, (uint32_t)layout.color_count, part->width,
                          part->height, opt->preview_exposure, error, sizeof error) != 0) {
            fail(result, "input preview: %s", error);
            goto done;
        }
        result->seconds_preview += now() - t;
    }
    if (paths->focus_map[0]) {
        t = now();
        if (focus_map_write(paths->focus_map, coc ? coc : coc_in, color,
                            (uint32_t)layout.color_count, part->width, part->height, error,
                            sizeof error) != 0) {
            fail(result, "focus map: %s", error);
            goto done;
        }
        result->seconds_preview += now() - t;
    }
    progress_update(bar, slot, 0.95f);
    if (paths->compare[0]) {
        t = now();
        if (compare_with_truth(paths, color, out, layout.color_count, part, result) != 0)
            goto done;
        result->seconds_compare = now() - t;
    }
    result->ok = 1;
    rc = 0;

done:
    result->seconds_total = now() - t0;
    exrio_close(&image);
    exrio_close(&depth_image);
    exrio_close(&fg_image);
    free(fg.color);
    free(fg.owned);
    free(fg_coc);
    free(wanted);
    free(color);
    free(out);
    free(coc);
    free(depth_owned);
    free(coc_owned);
    return rc;
}
