/* SPDX-License-Identifier: MIT */
/* run_setup.c - the run's checks before the first frame (run_setup.h). */
#include "run_setup.h"

#include "aperture_image.h"
#include "camera_json.h"
#include "exrio.h"
#include "frame_input.h"
#include "frame_paths.h"
#include "input_file.h"
#include "option_table.h"
#include "path_safety.h"

#include <stdio.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

/* The library's preset < flags. The command has no preset values of its own: they are the
 * accuracy study's, in libddof (ddof_params_init_preset). */
static void resolve_params(const cli_options *o, ddof_params *params)
{
    (void)ddof_params_init_preset(params, o->preset); /* the parser accepted only known ones */
    cli_options_override_params(o, params);
    if (!cli_param_given(o, offsetof(ddof_params, method)) &&
        params->method == DDOF_METHOD_COD4_PREVIEW &&
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
    if (cli_camera_given(o, offsetof(ddof_camera, pixel_aspect)))
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
    if (cli_options_camera_wanted(o)) {
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

/* The first readable header sizes the plan (*pixels); a missing first frame just means
 * "unknown" (its own error is reported when it runs). Returns 0 or the exit status. */
static int probe_first_frame(const cli_options *o, const frame_paths *first, uint64_t *pixels)
{
    exrio_image probe;
    char error[2048];
    int rc;
    *pixels = 0;
    if (input_file_open_exr(first->input, "input", &probe, error, sizeof error) != EXRIO_OK)
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

int run_setup_prepare(const cli_options *o, frame_setup *setup, frame_paths **paths, int *count,
                      uint64_t *pixels)
{
    int rc;
    memset(setup, 0, sizeof *setup);
    setup->options = o;
    setup->curve = o->curve;
    resolve_params(o, &setup->params);
    if (cli_options_camera_wanted(o) && resolve_camera(o, setup) != 0) {
        free(setup->aperture_pixels);
        return CLI_EXIT_USAGE;
    }
    rc = validate_with_library(setup);
    *paths = rc == 0 ? frame_paths_build(o, count) : NULL;
    if (rc == 0 && !*paths)
        rc = CLI_EXIT_USAGE;
    if (rc != 0) {
        free(setup->aperture_pixels);
        return rc;
    }
    rc = path_safety_check_outputs(o, *paths, *count) != 0 ? CLI_EXIT_FAILED : 0;
    if (rc == 0) {
        path_safety_remove_stale_temps(o, &(*paths)[0]);
        rc = probe_first_frame(o, &(*paths)[0], pixels);
    }
    if (rc != 0) {
        free(*paths);
        *paths = NULL;
        free(setup->aperture_pixels);
    }
    return rc;
}
