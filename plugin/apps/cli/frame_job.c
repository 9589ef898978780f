/* SPDX-License-Identifier: MIT */
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
    for (o = 1; o < 4; o++) { /* every pair of outputs, the focus map included */
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

/* One frame's images between reading, computing and writing. */
typedef struct frame_data {
    exrio_image image, depth_image, fg_image;
    exrio_layout layout;
    const exrio_part *part;       /* the colour's part of image                             */
    size_t pixels;
    float *color;                 /* interleaved colour channels, owned                     */
    const float *depth, *coc_in;  /* the depth plane (camera, curve) or the CoC channel       */
    float *depth_owned, *coc_owned; /* converted planes, when the channel was not float     */
    foreground_data fg;
    float *out;                   /* the result, owned                                      */
    float *coc;                   /* the CoC the library used (--write-coc), owned          */
} frame_data;

static void frame_data_free(frame_data *d)
{
    exrio_close(&d->image);
    exrio_close(&d->depth_image);
    exrio_close(&d->fg_image);
    free(d->fg.color);
    free(d->fg.owned);
    free(d->color);
    free(d->out);
    free(d->coc);
    free(d->depth_owned);
    free(d->coc_owned);
}

/* Opens the input and finds its channels (colour, depth or CoC); names them in result. */
static int open_input(const frame_setup *setup, const frame_paths *paths, frame_data *d,
                      frame_result *result)
{
    const cli_options *opt = setup->options;
    exrio_layout_request request;
    char error[2048];
    exrio_image *image = &d->image;
    const exrio_layout *layout = &d->layout;

    if (exrio_open(paths->input, image, error, sizeof error) != EXRIO_OK)
        return fail(result, "%s", error);
    memset(&request, 0, sizeof request);
    request.layer = opt->layer;
    request.color = opt->color;
    request.depth = paths->depth_file[0] ? NULL : opt->depth;
    request.coc = opt->source == COC_FROM_CHANNEL ? opt->coc_channel : NULL;
    request.need_depth = opt->source != COC_FROM_CHANNEL && !paths->depth_file[0];
    /* A foreground layer in the same file is never the main colour. */
    request.exclude_layer = !paths->foreground[0] ? opt->foreground_layer : NULL;
    if (exrio_find_layout(image, &request, &d->layout, error, sizeof error) != EXRIO_LAYOUT_OK ||
        frame_check_input_parts(opt, image, paths->input, error, sizeof error) != 0)
        return fail(result, "%s", error);
    d->part = &image->parts[layout->part];
    d->pixels = (size_t)d->part->width * d->part->height;
    result->width = d->part->width;
    result->height = d->part->height;
    result->channels = layout->color_count;
    if (layout->color_prefix[0])
        snprintf(result->color_name, sizeof result->color_name, "%s.%s", layout->color_prefix,
                 layout->color_count == 4 ? "RGBA" : "RGB");
    else
        snprintf(result->color_name, sizeof result->color_name, "%s,%s,%s%s%s",
                 image->channels[layout->color[0]].name, image->channels[layout->color[1]].name,
                 image->channels[layout->color[2]].name, layout->color_count == 4 ? "," : "",
                 layout->color_count == 4 ? image->channels[layout->color[3]].name : "");
    return 0;
}

/* Loads the channels the frame needs (and those --keep-channels carries over), the depth file
 * and the foreground element, as float planes and interleaved colour. */
static int load_input(const frame_setup *setup, const frame_paths *paths, frame_data *d,
                      frame_result *result)
{
    const cli_options *opt = setup->options;
    const exrio_layout *layout = &d->layout;
    unsigned char *wanted = calloc((size_t)d->image.channel_count, 1);
    char error[2048];
    int i;

    if (!wanted)
        return fail(result, "out of memory");
    for (i = 0; i < layout->color_count; i++)
        wanted[layout->color[i]] = 1;
    if (layout->depth >= 0)
        wanted[layout->depth] = 1;
    if (layout->coc >= 0)
        wanted[layout->coc] = 1;
    if (opt->keep_channels)
        for (i = 0; i < d->image.channel_count; i++)
            if (d->image.channels[i].part == layout->part)
                wanted[i] = 1;
    i = exrio_load(&d->image, wanted, error, sizeof error);
    free(wanted);
    if (i != EXRIO_OK)
        return fail(result, "%s", error);

    if (opt->source != COC_FROM_CHANNEL) {
        const exrio_image *from = &d->image;
        int depth_index = layout->depth;
        if (paths->depth_file[0]) {
            if (read_depth_file(setup, paths, layout, d->part, &d->depth_image, &depth_index,
                                result) != 0)
                return -1;
            from = &d->depth_image;
        }
        snprintf(result->depth_name, sizeof result->depth_name, "%s",
                 from->channels[depth_index].name);
        d->depth = float_plane(from, depth_index, d->pixels, &d->depth_owned);
    } else {
        snprintf(result->depth_name, sizeof result->depth_name, "%s",
                 d->image.channels[layout->coc].name);
        d->coc_in = float_plane(&d->image, layout->coc, d->pixels, &d->coc_owned);
    }
    d->color = interleave(&d->image, layout->color, layout->color_count, d->pixels);
    d->out = malloc(d->pixels * (size_t)layout->color_count * sizeof *d->out);
    /* The CoC the call used: written out (--write-coc) or drawn (--focus-map). */
    const int want_coc = opt->write_coc || paths->focus_map[0];
    if (want_coc)
        d->coc = malloc(d->pixels * sizeof *d->coc);
    if (!d->color || !d->out || (!d->depth && !d->coc_in) || (want_coc && !d->coc))
        return fail(result, "out of memory for a %ux%u frame", d->part->width, d->part->height);
    /* The foreground element, when there is one: same size, RGBA, its own depth or CoC. */
    if (opt->foreground || opt->foreground_layer)
        return read_foreground(setup, paths, &d->image, layout, d->part, &d->fg_image, &d->fg,
                               result);
    return 0;
}

/* The camera of this frame: the setup's, with the EXR's pixel aspect unless one was given, for
 * the data window. Warns when the sidecar was written for another resolution. */
static int frame_camera(const frame_setup *setup, const frame_paths *paths, const frame_data *d,
                        ddof_camera *camera, frame_result *result)
{
    const exrio_box *w = &d->part->display_window;
    const uint32_t dw = (uint32_t)(w->max_x - w->min_x + 1);
    const uint32_t dh = (uint32_t)(w->max_y - w->min_y + 1);
    *camera = setup->camera;
    if (!setup->camera_aspect_given)
        camera->pixel_aspect = d->part->pixel_aspect;
    if (setup->sidecar_resolution[0] &&
        (setup->sidecar_resolution[0] != dw || setup->sidecar_resolution[1] != dh))
        snprintf(result->warning, sizeof result->warning,
                 "the camera sidecar says %ux%u but %s is a %ux%u frame: the CoC follows the "
                 "file's pixels (a render at another resolution scale)",
                 setup->sidecar_resolution[0], setup->sidecar_resolution[1], paths->input, dw,
                 dh);
    return camera_for_window(camera, d->part, result);
}

/* Depth of field of the frame in one library call, whatever the CoC's source and with the
 * foreground element when there is one. */
static int compute(ddof_context *context, const frame_setup *setup, const frame_paths *paths,
                   frame_data *d, frame_result *result, progress_link *link)
{
    const cli_options *opt = setup->options;
    const uint32_t w = d->part->width, h = d->part->height;
    const uint32_t channels = (uint32_t)d->layout.color_count;
    ddof_params params = setup->params;
    ddof_camera camera;
    ddof_frame frame;
    ddof_status status;
    double t;

    /* The file's pixel aspect, unless a camera brings one: named as the header's when the
     * diffusion cannot take it (the library would call it params.pixel_aspect). */
    if ((opt->source != COC_FROM_CAMERA || !setup->camera_aspect_given) &&
        !(d->part->pixel_aspect >= 0.01f && d->part->pixel_aspect <= 100.0f))
        return fail(result, "%s: the header's pixelAspectRatio %.9g is outside 0.01..100, the "
                    "range the diffusion takes%s", paths->input, (double)d->part->pixel_aspect,
                    opt->source == COC_FROM_CAMERA
                        ? " (give the camera's with --pixel-aspect or the sidecar's "
                          "pixel_aspect)"
                        : "");
    params.progress = link->bar ? on_progress : NULL;
    params.progress_user = link;
    /* The image's own pixel aspect; a camera brings its own (frame_camera). */
    params.pixel_aspect = d->part->pixel_aspect;
    params.coc_signed = (uint32_t)opt->coc_signed;
    ddof_frame_init(&frame);
    frame.color = (ddof_image_in){d->color, w, h, channels, 0};
    if (opt->source == COC_FROM_CAMERA) {
        if (frame_camera(setup, paths, d, &camera, result) != 0)
            return -1;
        frame.camera = &camera;
        /* The camera's aspect is the call's (ddof_render_frame); the file's, which a given
         * one replaces, must not be judged in its place. */
        params.pixel_aspect = (float)camera.pixel_aspect;
    } else if (opt->source == COC_FROM_CURVE) {
        frame.curve = &setup->curve;
    }
    if (opt->source == COC_FROM_CHANNEL)
        frame.coc = (ddof_image_in){d->coc_in, w, h, 1, 0};
    else
        frame.depth = (ddof_image_in){d->depth, w, h, 1, 0};
    if (d->fg.color) {
        frame.foreground_color = (ddof_image_in){d->fg.color, w, h, 4, 0};
        if (d->fg.coc)
            frame.foreground_coc = (ddof_image_in){d->fg.coc, w, h, 1, 0};
        else
            frame.foreground_depth = (ddof_image_in){d->fg.depth, w, h, 1, 0};
        frame.foreground_premultiplied = opt->foreground_straight ? 0u : 1u;
    }
    if (d->coc)
        frame.coc_out = (ddof_image){d->coc, w, h, 1, 0};
    t = now();
    status = ddof_render_frame(context, &params, &frame,
                               &(ddof_image){d->out, w, h, channels, 0}, &result->stats);
    result->seconds_dof = now() - t;
    result->seconds_coc = result->stats.seconds_coc;
    if (status != DDOF_OK)
        return library_failed(result, context, "depth of field", status);
    return 0;
}

/* The EXR, the previews and the comparison with the truth. */
static int write_results(const frame_setup *setup, const frame_paths *paths,
                         const frame_data *d, frame_result *result, progress *bar, int slot)
{
    const cli_options *opt = setup->options;
    const uint32_t channels = (uint32_t)d->layout.color_count;
    const float *coc = opt->write_coc ? d->coc : NULL;
    char error[2048];
    double t = now();

    if (write_output(setup, paths, &d->image, &d->layout, d->out, (int)channels, coc, result) !=
        0)
        return -1;
    result->seconds_write = now() - t;
    if (paths->preview[0]) {
        t = now();
        if (preview_write(paths->preview, d->out, channels, d->part->width, d->part->height,
                          opt->preview_exposure, error, sizeof error) != 0)
            return fail(result, "preview: %s", error);
        result->seconds_preview = now() - t;
    }
    if (paths->preview_input[0]) {
        t = now();
        if (preview_write(paths->preview_input, d->color, channels, d->part->width,
                          d->part->height, opt->preview_exposure, error, sizeof error) != 0)
            return fail(result, "input preview: %s", error);
        result->seconds_preview += now() - t;
    }
    if (paths->focus_map[0]) {
        t = now();
        if (focus_map_write(paths->focus_map, d->coc, d->color, channels, d->part->width,
                            d->part->height,
                            opt->source == COC_FROM_CAMERA ? &setup->camera : NULL, error,
                            sizeof error) != 0)
            return fail(result, "focus map: %s", error);
        result->seconds_preview += now() - t;
    }
    progress_update(bar, slot, 0.95f);
    if (paths->compare[0]) {
        t = now();
        if (compare_with_truth(paths, d->color, d->out, (int)channels, d->part, result) != 0)
            return -1;
        result->seconds_compare = now() - t;
    }
    return 0;
}

int frame_run(ddof_context *context, const frame_setup *setup, const frame_paths *paths,
              frame_result *result, progress *bar, int slot)
{
    const double t0 = now();
    progress_link link = {bar, slot};
    frame_data d;
    char error[2048];
    int rc = -1;

    memset(result, 0, sizeof *result);
    memset(&d, 0, sizeof d);
    result->stats.struct_size = sizeof result->stats;
    result->backend.struct_size = sizeof result->backend;
    (void)ddof_context_backend_info(context, &result->backend);

    if (frame_check_paths(paths, error, sizeof error) != 0) {
        fail(result, "%s", error);
    } else if (setup->options->skip_existing && frame_outputs_complete(setup->options, paths)) {
        result->ok = 1;
        result->skipped = 1;
        rc = 0;
    } else if (open_input(setup, paths, &d, result) == 0 &&
               load_input(setup, paths, &d, result) == 0) {
        result->seconds_read = now() - t0;
        progress_update(bar, slot, 0.1f);
        if (compute(context, setup, paths, &d, result, &link) == 0) {
            progress_update(bar, slot, 0.8f);
            if (write_results(setup, paths, &d, result, bar, slot) == 0) {
                result->ok = 1;
                rc = 0;
            }
        }
    }
    result->seconds_total = now() - t0;
    frame_data_free(&d);
    return rc;
}
