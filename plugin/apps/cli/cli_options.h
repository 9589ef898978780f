/* SPDX-License-Identifier: MIT */
/* cli_options.h - everything the `ddof` command line can say, as one struct (each option's
 * spelling, help and field: option_table.c; the parsing: options.c), and the command's exit
 * statuses.
 *
 * The struct keeps, for each library parameter, whether the user set it, so that the sidecar
 * JSON, the preset and the flags combine in a fixed order: the library's preset
 * (ddof_params_init_preset) < camera.json < flags. */
#ifndef DDOF_CLI_CLI_OPTIONS_H
#define DDOF_CLI_CLI_OPTIONS_H

#include "exrio.h"

#include <ddof.h>

#include <stdint.h>

typedef enum coc_source {
    COC_FROM_CAMERA = 0, /* depth + camera (sidecar JSON and/or flags)            */
    COC_FROM_CURVE,      /* depth + the artist curve                               */
    COC_FROM_CHANNEL     /* a channel that already holds CoC diameters in pixels    */
} coc_source;

typedef enum progress_mode {
    PROGRESS_AUTO = 0, /* a bar when stderr is a terminal, nothing otherwise */
    PROGRESS_ALWAYS,
    PROGRESS_NEVER
} progress_mode;

typedef struct cli_options {
    /* input and output */
    const char *input;            /* path or pattern with #### */
    const char *output;           /* path or pattern with #### */
    const char *preview;          /* PNG preview path or pattern; NULL: none */
    const char *preview_input;    /* PNG preview of the input (pinhole); NULL: none */
    const char *focus_map;        /* --focus-map: PNG focal-plane view (focus_map.h); NULL */
    const char *depth_file;       /* depth from another EXR (path or pattern); NULL: same file */
    const char *compare;          /* ground truth EXR (path or pattern); NULL: none */
    const char *stats_path;       /* --stats FILE.json */
    const char *frames;           /* --frames "1-240" etc.; NULL: a single file */

    /* channels */
    const char *layer, *color, *depth, *coc_channel;
    const char *matte;            /* --matte: auto (NULL), off or a Cryptomatte layer */

    /* CoC source */
    coc_source source;
    unsigned coc_sources_given;   /* --curve and --coc-channel seen: more than one is an error */
    const char *camera_json;
    const char *cards_json;       /* --cards: a scene of textured cards instead of IN.exr    */
    const char *aperture_image;   /* --aperture-image: an EXR; NULL: the blades' shape      */
    ddof_camera camera;           /* flag values, over the sidecar's where camera_given says */
    unsigned char camera_given[sizeof(ddof_camera)]; /* the byte where each given field starts */
    ddof_curve curve;

    /* solver: every value starts from the library's preset (ddof_params_init_preset) */
    ddof_preset preset;           /* --preset; default DDOF_PRESET_DEFAULT */
    uint32_t threads;             /* 0: all cores */
    ddof_backend_kind backend;    /* --backend; default DDOF_BACKEND_AUTO */
    const char *gl_plugin;        /* --gl-plugin: the libddof_gl file; NULL: the library's search */

    /* The library's parameters the flags give (method, kernel, solver, layers...), written
     * straight into their ddof_params fields; params_given marks the byte where each given
     * field starts (cli_param_given). The rest is the preset's. */
    ddof_params params;
    unsigned char params_given[sizeof(ddof_params)];

    /* layers */
    int coc_signed;               /* --coc-signed: the CoC channel marks the near field < 0 */
    const char *foreground;       /* file (path or pattern) of a foreground element; NULL */
    const char *foreground_layer; /* its layer (in that file, or in the input); NULL */
    const char *foreground_coc;   /* its CoC channel (with --coc-channel); NULL */
    int foreground_straight;      /* its colour is not premultiplied by alpha */
    uint32_t jobs;                /* frames in parallel; 0: automatic */
    int skip_existing;            /* --skip-existing: resume a killed batch */

    /* output file */
    int pixel_type;               /* -1: as the input colour; else exrio_pixel_type */
    exrio_compression compression;
    float dwa_level;              /* --compression dwaa:LEVEL; 0: OpenEXR's default (45) */
    int zip_level;                /* --compression zip:LEVEL; 0: the default (6) */
    int keep_channels;
    int keep_metadata;
    int write_coc;                /* add the CoC used as a channel */
    float preview_exposure;       /* stops */

    /* reporting */
    progress_mode progress;
    int quiet;
    int verbose;                  /* -v: the backend, renderer and plan of every frame */
    int list_only;                /* --list: print the layout and channels, no processing */
} cli_options;

/* --threads: ddof_context_create's limit on thread_count (ddof.h). */
#define CLI_MAX_THREADS 1024u

/* Exit statuses of the command (docs/cli.md). */
#define CLI_EXIT_OK 0
#define CLI_EXIT_FAILED 1   /* some frame failed, or an output was refused              */
#define CLI_EXIT_USAGE 2    /* unknown option, bad value, bad camera                    */
#define CLI_EXIT_BACKEND 3  /* the backend asked for is unavailable, or it cannot run   */
                            /* the solver or precision asked for                        */

/* Whether a flag gave the ddof_params (ddof_camera) field at this offset (offsetof). */
static inline int cli_param_given(const cli_options *o, size_t params_field)
{
    return params_field < sizeof o->params_given && o->params_given[params_field];
}

static inline int cli_camera_given(const cli_options *o, size_t camera_field)
{
    return camera_field < sizeof o->camera_given && o->camera_given[camera_field];
}

#endif
