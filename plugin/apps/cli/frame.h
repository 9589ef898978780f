/* SPDX-License-Identifier: MIT */
/* frame.h - what one frame is, for every part of its run (frame_input.c, frame_output.c,
 * frame_compare.c, frame_job.c) and for those that set it up and report it: its shared setup,
 * its paths, its result, and how it fails (frame.c). */
#ifndef DDOF_CLI_FRAME_H
#define DDOF_CLI_FRAME_H

#include "compare.h"
#include "options.h"

#include <ddof.h>

#include <limits.h>
#include <stdint.h>

#ifndef PATH_MAX
#define PATH_MAX 4096
#endif

/* What every frame shares, resolved once in main: the options, and the camera, curve and
 * solver parameters after combining defaults, preset, sidecar and flags. */
typedef struct frame_setup {
    const cli_options *options;
    ddof_camera camera;
    int camera_aspect_given;      /* pixel aspect from the sidecar or a flag (else: the EXR's) */
    uint32_t sidecar_resolution[2]; /* 0, 0 when none */
    ddof_curve curve;
    ddof_params params;           /* progress fields are set per frame */
    float *aperture_pixels;       /* --aperture-image's, owned (camera.aperture_image) */
} frame_setup;

typedef struct frame_paths {
    int frame;                    /* the frame number; -1 for a single file */
    char input[PATH_MAX];
    char output[PATH_MAX];
    char preview[PATH_MAX];       /* "" when none */
    char preview_input[PATH_MAX]; /* "" when none */
    char focus_map[PATH_MAX];     /* "" when none */
    char depth_file[PATH_MAX];    /* "" when none */
    char foreground[PATH_MAX];    /* a foreground element file; "" when none */
    char compare[PATH_MAX];       /* "" when none */
} frame_paths;

typedef struct frame_result {
    int ok;
    int skipped;                  /* --skip-existing found the outputs complete: not run */
    char error[2048];
    char warning[PATH_MAX + 512]; /* worth saying once, e.g. a resolution mismatch */
    uint32_t width, height;       /* data window */
    int channels;                 /* colour channels diffused: 3 or 4 */
    char color_name[320];         /* e.g. "ViewLayer.Combined.RGBA" or "R,G,B,A" */
    char depth_name[256];         /* the depth or CoC channel used */
    char matte_name[256];         /* the object matte used ("" none), e.g. ViewLayer.CryptoObject */
    int matte_ranks;              /* its (id, coverage) ranks per pixel */
    ddof_stats stats;             /* from the library */
    char plan[DDOF_PLAN_MAX_BYTES]; /* its plan, whole (ddof_context_last_plan; stats.plan is
                                     * cut at 512 bytes)                                       */
    ddof_backend_info backend;    /* the context's backend: what runs, its renderer, AUTO's note */
    double seconds_read;          /* open + decode (+ depth file) */
    double seconds_coc;           /* our CoC stage when separate (curve, --write-coc) */
    double seconds_dof;           /* the library call(s) */
    double seconds_write;         /* EXR encode + write + rename */
    double seconds_preview;
    double seconds_compare;
    double seconds_total;
    int compared;
    image_error error_result;     /* result vs truth */
    image_error error_input;      /* pinhole input vs truth */
} frame_result;

/* The frame's failure: result->error gets the message, result->ok 0. Returns -1. */
int frame_fail(frame_result *result, const char *format, ...);

#endif
