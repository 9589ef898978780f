/* SPDX-License-Identifier: MIT */
/* frame_output.c - the frame's EXR, previews and focal-plane view (frame_output.h). */
#include "frame_output.h"

#include "cli_clock.h"
#include "focus_map.h"
#include "frame_compare.h"
#include "half_range.h"
#include "output_file.h"
#include "preview.h"

#include <stdlib.h>
#include <string.h>

/* Builds the output channel list and writes the EXR atomically. */
static int write_output(const frame_setup *setup, const frame_paths *paths,
                        const exrio_image *image, const exrio_layout *layout, const float *out,
                        int channels, const float *coc, unsigned threads, frame_result *result)
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
        return frame_fail(result, "out of memory");
    for (c = 0; c < channels; c++) {
        /* --keep-channels keeps the input's layout, so the colour keeps its names too. */
        const int kept = half_range_type(type, opt->pixel_type >= 0, out + c,
                                         (size_t)part->width * part->height, (size_t)channels,
                                         plain[c], error, sizeof error);
        if (kept < 0) {
            free(list);
            return frame_fail(result, "%s", error);
        }
        list[count].name = opt->keep_channels ? image->channels[layout->color[c]].name : plain[c];
        list[count].type = (exrio_pixel_type)kept;
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
    spec.dwa_level = opt->dwa_level;
    spec.zip_level = opt->zip_level;
    spec.threads = threads;
    spec.channel_count = count;
    spec.channels = list;
    spec.metadata_from = opt->keep_metadata ? image : NULL;
    spec.metadata_part = layout->part;

    if (output_file_begin(&file, paths->output, error, sizeof error) != 0) {
        free(list);
        return frame_fail(result, "%s", error);
    }
    if (exrio_write_fd(file.fd, paths->output, &spec, error, sizeof error) != EXRIO_OK) {
        output_file_abort(&file);
        free(list);
        return frame_fail(result, "%s", error);
    }
    free(list);
    if (output_file_commit(&file, error, sizeof error) != 0)
        return frame_fail(result, "%s", error);
    return 0;
}

int frame_output_write(ddof_context *context, const frame_setup *setup,
                       const frame_paths *paths, const frame_data *d, frame_result *result,
                       progress *bar, int slot)
{
    const cli_options *opt = setup->options;
    const uint32_t channels = (uint32_t)d->layout.color_count;
    const float *coc = opt->write_coc ? d->coc : NULL;
    char error[2048];
    double t = cli_now();

    if (write_output(setup, paths, &d->image, &d->layout, d->out, (int)channels, coc,
                     d->io_threads, result) != 0)
        return -1;
    result->seconds_write = cli_now() - t;
    if (paths->preview[0]) {
        t = cli_now();
        if (preview_write(paths->preview, d->out, channels, d->part->width, d->part->height,
                          opt->preview_exposure, error, sizeof error) != 0)
            return frame_fail(result, "preview: %s", error);
        result->seconds_preview = cli_now() - t;
    }
    if (paths->preview_input[0]) {
        t = cli_now();
        if (preview_write(paths->preview_input, d->color, channels, d->part->width,
                          d->part->height, opt->preview_exposure, error, sizeof error) != 0)
            return frame_fail(result, "input preview: %s", error);
        result->seconds_preview += cli_now() - t;
    }
    if (paths->focus_map[0]) {
        t = cli_now();
        if (focus_map_write(context, paths->focus_map, d->coc, d->color, channels,
                            d->part->width, d->part->height,
                            cli_options_camera_wanted(opt) ? &setup->camera : NULL, error,
                            sizeof error) != 0)
            return frame_fail(result, "focus map: %s", error);
        result->seconds_preview += cli_now() - t;
    }
    progress_update(bar, slot, 0.95f);
    if (paths->compare[0]) {
        t = cli_now();
        if (frame_compare_with_truth(paths, d->color, d->out, (int)channels, d->part, result) != 0)
            return -1;
        result->seconds_compare = cli_now() - t;
    }
    return 0;
}
