/* SPDX-License-Identifier: MIT */
/* frame_job.c - one frame: its inputs read (frame_input.c), the depth of field in one library
 * call, its outputs written (frame_output.c). */
#include "frame_job.h"

#include "cli_clock.h"
#include "frame_input.h"
#include "frame_output.h"
#include "path_safety.h"

#include <stdio.h>
#include <string.h>

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

/* When the data window is not the display window, the camera is the display window's: the
 * full frame's size and the data window's place in it (ddof_camera 0.5), so the sensor fit, the
 * pixel pitch and the centre that radial depth is converted about are the frame's. */
static int camera_for_window(ddof_camera *camera, const exrio_part *part, frame_result *result)
{
    const exrio_box *d = &part->display_window;
    const int64_t dw = (int64_t)d->max_x - d->min_x + 1, dh = (int64_t)d->max_y - d->min_y + 1;
    const int64_t wx = (int64_t)part->data_window.min_x - d->min_x;
    const int64_t wy = (int64_t)part->data_window.min_y - d->min_y;
    if (frame_same_window(&part->data_window, d))
        return 0;
    if (dw < 1 || dh < 1 || dw > DDOF_MAX_DIMENSION || dh > DDOF_MAX_DIMENSION ||
        wx < -(int64_t)DDOF_MAX_DIMENSION || wx > DDOF_MAX_DIMENSION ||
        wy < -(int64_t)DDOF_MAX_DIMENSION || wy > DDOF_MAX_DIMENSION)
        return frame_fail(result, "the display window (%d,%d)-(%d,%d) or the data window's place "
                          "in it is too large for the camera", (int)d->min_x, (int)d->min_y,
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
    return frame_fail(result, "%s: %s: %s", what, ddof_status_string(status),
                      ddof_context_last_error(context));
}

/* The frame's pixel aspect, decided once: a camera's given one (the sidecar's or
 * --pixel-aspect), else the EXR header's. */
static double frame_pixel_aspect(const frame_setup *setup, const frame_data *d)
{
    return setup->options->source == COC_FROM_CAMERA && setup->camera_aspect_given
               ? setup->camera.pixel_aspect
               : (double)d->part->pixel_aspect;
}

/* The camera of this frame: the setup's, with the frame's pixel aspect, for the data window.
 * Warns when the sidecar was written for another resolution. */
static int frame_camera(const frame_setup *setup, const frame_paths *paths, const frame_data *d,
                        ddof_camera *camera, frame_result *result)
{
    const exrio_box *w = &d->part->display_window;
    const uint32_t dw = (uint32_t)(w->max_x - w->min_x + 1);
    const uint32_t dh = (uint32_t)(w->max_y - w->min_y + 1);
    *camera = setup->camera;
    camera->pixel_aspect = frame_pixel_aspect(setup, d);
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

    /* The header's pixel aspect, where it is the frame's, is named as the header's when the
     * diffusion cannot take it (the library would call it params.pixel_aspect); a camera's
     * given one is the library's to judge (ddof_camera_check). */
    const double aspect = frame_pixel_aspect(setup, d);
    double lowest, highest;
    ddof_param_bounds("pixel_aspect", &lowest, &highest);
    if ((opt->source != COC_FROM_CAMERA || !setup->camera_aspect_given) &&
        !(aspect >= lowest && aspect <= highest))
        return frame_fail(result, "%s: the header's pixelAspectRatio %.9g is outside %g..%g, "
                          "the range the diffusion takes%s", paths->input, aspect, lowest,
                          highest,
                          opt->source == COC_FROM_CAMERA
                              ? " (give the camera's with --pixel-aspect or the sidecar's "
                                "pixel_aspect)"
                              : "");
    params.progress = link->bar ? on_progress : NULL;
    params.progress_user = link;
    params.pixel_aspect = (float)aspect;
    params.coc_signed = (uint32_t)opt->coc_signed;
    ddof_frame_init(&frame);
    frame.color = (ddof_image_in){d->color, w, h, channels, 0};
    if (cli_options_camera_wanted(opt)) { /* with --coc-channel: its aperture only */
        if (frame_camera(setup, paths, d, &camera, result) != 0)
            return -1;
        frame.camera = &camera;
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
    t = cli_now();
    /* The render's object matte, when it has one, gives the silhouettes' split its shares. */
    const ddof_image_in matte = {d->matte, w, h, 2 * (uint32_t)d->matte_ranks, 0};
    status = ddof_render_frame_with_matte(context, &params, &frame, d->matte ? &matte : NULL,
                                          &(ddof_image){d->out, w, h, channels, 0},
                                          &result->stats);
    result->seconds_dof = cli_now() - t;
    result->seconds_coc = result->stats.seconds_coc;
    snprintf(result->plan, sizeof result->plan, "%s", ddof_context_last_plan(context));
    if (status != DDOF_OK)
        return library_failed(result, context, "depth of field", status);
    return 0;
}

int frame_run(ddof_context *context, const frame_setup *setup, const frame_paths *paths,
              frame_result *result, progress *bar, int slot)
{
    const double t0 = cli_now();
    progress_link link = {bar, slot};
    frame_data d;
    char error[2048];
    int rc = -1;

    memset(result, 0, sizeof *result);
    memset(&d, 0, sizeof d);
    d.io_threads = ddof_context_thread_count(context);
    result->stats.struct_size = sizeof result->stats;
    result->backend.struct_size = sizeof result->backend;
    (void)ddof_context_backend_info(context, &result->backend);

    if (frame_check_paths(paths, error, sizeof error) != 0) {
        frame_fail(result, "%s", error);
    } else if (setup->options->skip_existing && frame_outputs_complete(setup->options, paths)) {
        result->ok = 1;
        result->skipped = 1;
        rc = 0;
    } else if (frame_input_open(setup, paths, &d, result) == 0 &&
               frame_input_load(setup, paths, &d, result) == 0) {
        result->seconds_read = cli_now() - t0;
        progress_update(bar, slot, 0.1f);
        if (compute(context, setup, paths, &d, result, &link) == 0) {
            progress_update(bar, slot, 0.8f);
            if (frame_output_write(context, setup, paths, &d, result, bar, slot) == 0) {
                result->ok = 1;
                rc = 0;
            }
        }
    }
    result->seconds_total = cli_now() - t0;
    frame_data_free(&d);
    return rc;
}
