/* SPDX-License-Identifier: MIT */
/* cards_run.c - --cards (cards_run.h). */
#include "cards_run.h"

#include "cards_scene.h"
#include "cli_clock.h"
#include "exrio.h"
#include "half_range.h"
#include "output_file.h"

#include <ddof.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Writes premultiplied RGBA as the output EXR (half unless --pixel-type float). */
static int write_cards_output(const cli_options *o, const float *rgba, uint32_t w, uint32_t h,
                              char *error, size_t error_size)
{
    static const char *const names[4] = {"R", "G", "B", "A"};
    exrio_write_channel channels[4];
    exrio_write_spec spec;
    output_file file;
    for (int c = 0; c < 4; c++) {
        const int type = half_range_type(o->pixel_type >= 0 ? (exrio_pixel_type)o->pixel_type
                                                            : EXRIO_HALF,
                                         o->pixel_type >= 0, rgba + c, (size_t)w * h, 4,
                                         names[c], error, error_size);
        if (type < 0)
            return -1;
        channels[c].name = names[c];
        channels[c].type = (exrio_pixel_type)type;
        channels[c].pixels = rgba + c;
        channels[c].pixel_stride = 16;
        channels[c].line_stride = (size_t)w * 16;
    }
    memset(&spec, 0, sizeof spec);
    spec.data_window.max_x = spec.display_window.max_x = (int32_t)w - 1;
    spec.data_window.max_y = spec.display_window.max_y = (int32_t)h - 1;
    spec.compression = o->compression;
    spec.dwa_level = o->dwa_level;
    spec.zip_level = o->zip_level;
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

int cards_run(const cli_options *o)
{
    char error[2048];
    cards_scene scene;
    ddof_context *context = NULL;
    float *rgba = NULL;
    const double t0 = cli_now();
    if (cards_scene_read(o->cards_json, &scene, error, sizeof error) != 0) {
        fprintf(stderr, "ddof: %s\n", error);
        return CLI_EXIT_USAGE;
    }
    int rc = CLI_EXIT_OK;
    const char *clobbered = cards_scene_input_at(&scene, o->cards_json, o->output);
    if (clobbered) {
        fprintf(stderr, "ddof: refusing to write %s: it is an input (%s); ddof never "
                "overwrites its input\n", o->output, clobbered);
        rc = CLI_EXIT_USAGE;
    } else if (!scene.width || !scene.height) {
        fprintf(stderr, "ddof: %s: the camera needs \"resolution\": [width, height], the "
                "output's size\n", o->cards_json);
        rc = CLI_EXIT_USAGE;
    } else if (scene.width > DDOF_MAX_DIMENSION || scene.height > DDOF_MAX_DIMENSION ||
               (uint64_t)scene.width * scene.height > DDOF_MAX_PIXELS) {
        fprintf(stderr, "ddof: %s: the camera's resolution %ux%u is over the limits (each side "
                "at most %u, at most %u pixels)\n", o->cards_json, scene.width, scene.height,
                DDOF_MAX_DIMENSION, DDOF_MAX_PIXELS);
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
                   1000.0 * (cli_now() - t0));
        }
    }
    ddof_context_free(context);
    free(rgba);
    cards_scene_free(&scene);
    return rc;
}
