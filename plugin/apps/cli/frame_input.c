/* SPDX-License-Identifier: MIT */
/* frame_input.c - a frame's inputs read into float planes and interleaved colour
 * (frame_input.h). */
#include "frame_input.h"

#include "input_file.h"
#include "matte_input.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
float *frame_interleave(const exrio_image *image, const int *index, int count, size_t pixels)
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

int frame_same_window(const exrio_box *a, const exrio_box *b)
{
    return a->min_x == b->min_x && a->min_y == b->min_y && a->max_x == b->max_x &&
           a->max_y == b->max_y;
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

/* Reads depth from a separate file; it must cover the same data window as the colour. */
static int read_depth_file(const frame_setup *setup, const frame_paths *paths,
                           const exrio_layout *layout, const exrio_part *color_part,
                           exrio_image *depth_image, int *depth_index, frame_result *result)
{
    char error[1024];
    unsigned char *wanted;
    const exrio_part *dp;
    int idx;
    if (input_file_open_exr(paths->depth_file, "depth file", depth_image, error, sizeof error) != EXRIO_OK)
        return frame_fail(result, "%s", error);
    idx = exrio_find_depth(depth_image, layout->color_prefix, setup->options->depth);
    if (idx < 0) {
        char list[1024];
        exrio_list_channels(depth_image, 40, list, sizeof list);
        return frame_fail(result, "%s: no depth channel%s%s%s found; channels in the file: %s",
                          paths->depth_file, setup->options->depth ? " '" : "",
                          setup->options->depth ? setup->options->depth : "",
                          setup->options->depth ? "'" : "", list);
    }
    dp = &depth_image->parts[depth_image->channels[idx].part];
    if (!frame_same_window(&dp->data_window, &color_part->data_window))
        return frame_fail(result, "mismatched layer sizes: depth %s in %s is %ux%u at (%d,%d) "
                          "but the colour in %s is %ux%u at (%d,%d)",
                          depth_image->channels[idx].name, paths->depth_file, dp->width,
                          dp->height, (int)dp->data_window.min_x, (int)dp->data_window.min_y,
                          paths->input, color_part->width, color_part->height,
                          (int)color_part->data_window.min_x, (int)color_part->data_window.min_y);
    wanted = calloc((size_t)depth_image->channel_count, 1);
    if (!wanted)
        return frame_fail(result, "out of memory");
    wanted[idx] = 1;
    if (exrio_load(depth_image, wanted, error, sizeof error) != EXRIO_OK) {
        free(wanted);
        return frame_fail(result, "%s", error);
    }
    free(wanted);
    *depth_index = idx;
    return 0;
}

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
        if (input_file_open_exr(paths->foreground, "foreground element", file, error, sizeof error) != EXRIO_OK)
            return frame_fail(result, "foreground element: %s", error);
        source = file;
    }
    memset(&request, 0, sizeof request);
    request.layer = opt->foreground_layer;
    request.coc = opt->source == COC_FROM_CHANNEL ? opt->foreground_coc : NULL;
    request.need_depth = opt->source != COC_FROM_CHANNEL;
    if (exrio_find_layout(source, &request, &layout, error, sizeof error) != EXRIO_LAYOUT_OK)
        return frame_fail(result, "foreground element: %s", error);
    if (source == input && layout.part == main_layout->part &&
        layout.color[0] == main_layout->color[0])
        return frame_fail(result, "foreground element: layer '%s' is the main colour layer",
                          opt->foreground_layer);
    if (layout.color_count != 4)
        return frame_fail(result, "foreground element in %s has no alpha channel (%s.A): it is "
                          "needed to composite the element", name,
                          layout.color_prefix[0] ? layout.color_prefix : "R,G,B");
    part = &source->parts[layout.part];
    if (part->data_window.min_x != main_part->data_window.min_x ||
        part->data_window.min_y != main_part->data_window.min_y ||
        part->width != main_part->width || part->height != main_part->height)
        return frame_fail(result, "mismatched layer sizes: the foreground element in %s is %ux%u "
                          "at (%d,%d) but the image is %ux%u at (%d,%d)", name, part->width,
                          part->height, (int)part->data_window.min_x,
                          (int)part->data_window.min_y, main_part->width, main_part->height,
                          (int)main_part->data_window.min_x, (int)main_part->data_window.min_y);
    wanted = calloc((size_t)source->channel_count, 1);
    if (!wanted)
        return frame_fail(result, "out of memory");
    for (i = 0; i < 4; i++)
        wanted[layout.color[i]] = 1;
    plane = layout.coc >= 0 ? layout.coc : layout.depth;
    wanted[plane] = 1;
    if (exrio_load(source, wanted, error, sizeof error) != EXRIO_OK) {
        free(wanted);
        return frame_fail(result, "foreground element: %s", error);
    }
    free(wanted);
    fg->color = frame_interleave(source, layout.color, 4, pixels);
    if (layout.coc >= 0)
        fg->coc = float_plane(source, plane, pixels, &fg->owned);
    else
        fg->depth = float_plane(source, plane, pixels, &fg->owned);
    if (!fg->color || (!fg->coc && !fg->depth))
        return frame_fail(result, "out of memory");
    return 0;
}

void frame_data_free(frame_data *d)
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
    free(d->matte);
}

/* Opens the input and finds its channels (colour, depth or CoC); names them in result. */
int frame_input_open(const frame_setup *setup, const frame_paths *paths, frame_data *d,
                     frame_result *result)
{
    const cli_options *opt = setup->options;
    exrio_layout_request request;
    char error[2048];
    exrio_image *image = &d->image;
    const exrio_layout *layout = &d->layout;

    if (input_file_open_exr(paths->input, "input", image, error, sizeof error) != EXRIO_OK)
        return frame_fail(result, "%s", error);
    /* The ground truth is read after the output is written: a truth that cannot be opened
     * fails the frame here, before its output appears. */
    if (paths->compare[0] &&
        input_file_check(paths->compare, "ground truth", error, sizeof error) != 0)
        return frame_fail(result, "ground truth: %s", error);
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
        return frame_fail(result, "%s", error);
    d->matte_ranks = matte_find(image, layout, opt->matte, d->matte_index, result->matte_name,
                                sizeof result->matte_name, error, sizeof error);
    if (d->matte_ranks < 0)
        return frame_fail(result, "%s: %s", paths->input, error);
    result->matte_ranks = d->matte_ranks;
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
int frame_input_load(const frame_setup *setup, const frame_paths *paths, frame_data *d,
                     frame_result *result)
{
    const cli_options *opt = setup->options;
    const exrio_layout *layout = &d->layout;
    unsigned char *wanted = calloc((size_t)d->image.channel_count, 1);
    char error[2048];
    int i;

    if (!wanted)
        return frame_fail(result, "out of memory");
    for (i = 0; i < layout->color_count; i++)
        wanted[layout->color[i]] = 1;
    if (layout->depth >= 0)
        wanted[layout->depth] = 1;
    if (layout->coc >= 0)
        wanted[layout->coc] = 1;
    for (i = 0; i < 2 * d->matte_ranks; i++)
        wanted[d->matte_index[i]] = 1;
    if (opt->keep_channels)
        for (i = 0; i < d->image.channel_count; i++)
            if (d->image.channels[i].part == layout->part)
                wanted[i] = 1;
    i = exrio_load_threads(&d->image, wanted, d->io_threads, error, sizeof error);
    free(wanted);
    if (i != EXRIO_OK)
        return frame_fail(result, "%s", error);

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
    d->color = frame_interleave(&d->image, layout->color, layout->color_count, d->pixels);
    if (d->matte_ranks &&
        !(d->matte = frame_interleave(&d->image, d->matte_index, 2 * d->matte_ranks, d->pixels)))
        return frame_fail(result, "out of memory for the matte of a %ux%u frame",
                          d->part->width, d->part->height);
    d->out = malloc(d->pixels * (size_t)layout->color_count * sizeof *d->out);
    /* The CoC the call used: written out (--write-coc) or drawn (--focus-map). */
    const int want_coc = opt->write_coc || paths->focus_map[0];
    if (want_coc)
        d->coc = malloc(d->pixels * sizeof *d->coc);
    if (!d->color || !d->out || (!d->depth && !d->coc_in) || (want_coc && !d->coc))
        return frame_fail(result, "out of memory for a %ux%u frame", d->part->width,
                          d->part->height);
    /* The foreground element, when there is one: same size, RGBA, its own depth or CoC. */
    if (opt->foreground || opt->foreground_layer)
        return read_foreground(setup, paths, &d->image, layout, d->part, &d->fg_image, &d->fg,
                               result);
    return 0;
}
