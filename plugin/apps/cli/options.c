/* SPDX-License-Identifier: MIT */
/* options.c - the `ddof` command line: argv walked against the table of options
 * (option_table.c), then the rules that tie options together. */
#include "options.h"

#include "option_table.h"

#include <stddef.h>
#include <string.h>

static void defaults(cli_options *o)
{
    memset(o, 0, sizeof *o);
    o->source = COC_FROM_CAMERA;
    ddof_camera_init(&o->camera);
    ddof_curve_init(&o->curve);
    o->preset = DDOF_PRESET_DEFAULT;
    o->backend = DDOF_BACKEND_AUTO;
    o->pixel_type = -1;
    o->compression = EXRIO_COMPRESSION_ZIP;
    o->progress = PROGRESS_AUTO;
}

/* A word that is no option: the input, given once. */
static int take_input(cli_options *o, const char *arg)
{
    if (o->input) {
        fprintf(stderr, "ddof: more than one input ('%s' and '%s'); use --frames for "
                "sequences (try --help)\n", o->input, arg);
        return -1;
    }
    o->input = arg;
    return 0;
}

/* argv[*i] is an option, "--name value" or "--name=value": applies it, consuming its value.
 * Returns 0, 1 after the help or the version, -1 after an error. */
static int take_option(int argc, char **argv, int *i, cli_options *o)
{
    const char *arg = argv[*i];
    const char *equals = strncmp(arg, "--", 2) == 0 ? strchr(arg, '=') : NULL;
    const char *value = equals ? equals + 1 : NULL;
    const cli_option *option;
    char name[64];

    snprintf(name, sizeof name, "%s", arg);
    if (equals && (size_t)(equals - arg) < sizeof name)
        name[equals - arg] = '\0';
    option = cli_option_find(name);
    if (!option) {
        fprintf(stderr, "ddof: unknown option '%s' (try --help)\n", arg);
        return -1;
    }
    if (option->kind == CLI_OPT_HELP) {
        cli_usage(stdout);
        return 1;
    }
    if (option->kind == CLI_OPT_VERSION) {
        printf("ddof %s (libddof %s)\n", DDOF_CLI_VERSION, ddof_version_string());
        return 1;
    }
    if (option->kind == CLI_OPT_FLAG) {
        if (value) {
            fprintf(stderr, "ddof: %s takes no value\n", option->name);
            return -1;
        }
    } else {
        if (!value) {
            if (*i + 1 >= argc) {
                fprintf(stderr, "ddof: %s needs a value (try --help)\n", option->name);
                return -1;
            }
            value = argv[++*i];
        }
        if (value[0] == '\0') {
            fprintf(stderr, "ddof: %s needs a non-empty value\n", option->name);
            return -1;
        }
    }
    return option->apply ? option->apply(option, value, o)
                         : cli_option_parse_value(option, value, o);
}

/* Whether the camera field at this offset describes the aperture alone. */
static int aperture_field(size_t field)
{
    return field == offsetof(ddof_camera, aperture_blades) ||
           field == offsetof(ddof_camera, aperture_rotation_deg) ||
           field == offsetof(ddof_camera, aperture_ratio) ||
           field == offsetof(ddof_camera, aperture_catseye);
}

/* Whether a camera flag was given among the aperture's (aperture 1) or the others (0). */
static int camera_flags_given(const cli_options *o, int aperture)
{
    for (size_t field = 0; field < sizeof o->camera_given; field++)
        if (cli_camera_given(o, field) && aperture_field(field) == aperture)
            return 1;
    return 0;
}

int cli_options_camera_wanted(const cli_options *o)
{
    return o->source == COC_FROM_CAMERA ||
           (o->source == COC_FROM_CHANNEL &&
            (o->camera_json || camera_flags_given(o, 1) || o->aperture_image));
}

/* Options that do not go together, or need another. */
static int check_combination(const cli_options *o)
{
    const int has_foreground = o->foreground || o->foreground_layer;
    if (o->coc_sources_given > 1) {
        fprintf(stderr, "ddof: --curve and --coc-channel are two CoC sources: give one\n");
        return -1;
    }
    if (o->source == COC_FROM_CURVE &&
        (o->camera_json || camera_flags_given(o, 0) || camera_flags_given(o, 1))) {
        fprintf(stderr, "ddof: camera options do not apply with --curve\n");
        return -1;
    }
    if (o->source == COC_FROM_CHANNEL && camera_flags_given(o, 0)) {
        fprintf(stderr, "ddof: with --coc-channel the CoC is given: of the camera, only "
                "--camera and the aperture's flags (--aperture-*) apply\n");
        return -1;
    }
    if (o->coc_signed && o->source != COC_FROM_CHANNEL) {
        fprintf(stderr, "ddof: --coc-signed describes a --coc-channel\n");
        return -1;
    }
    if (o->source == COC_FROM_CHANNEL && has_foreground && !o->foreground_coc) {
        fprintf(stderr, "ddof: with --coc-channel, a foreground element needs its own CoC: give "
                "--foreground-coc-channel\n");
        return -1;
    }
    if (cli_param_given(o, offsetof(ddof_params, method)) &&
        o->params.method == DDOF_METHOD_COD4_PREVIEW && has_foreground) {
        fprintf(stderr, "ddof: --method cod4 takes no foreground element: the CoD4 preview "
                "blurs one image (use --method diffusion with --foreground)\n");
        return -1;
    }
    const int spread_on = cli_param_given(o, offsetof(ddof_params, near_spread)) &&
                          o->params.near_spread == DDOF_LAYER_ON;
    const int near_on = cli_param_given(o, offsetof(ddof_params, near_layer)) &&
                        o->params.near_layer == DDOF_LAYER_ON;
    if ((spread_on || near_on) && has_foreground) {
        const char *flag = spread_on ? "--near-spread" : "--near-layer";
        fprintf(stderr, "ddof: %s on works on one image: with a foreground element the element "
                "is the near field (leave out %s on)\n", flag, flag);
        return -1;
    }
    if (o->gl_plugin && o->backend == DDOF_BACKEND_CPU) {
        fprintf(stderr, "ddof: --gl-plugin names the GL backend, but --backend cpu uses none\n");
        return -1;
    }
    return 0;
}

/* What a run (not --list) needs besides the input: an output and a CoC source. */
static int check_run_needs(const cli_options *o)
{
    if (!o->output) {
        fprintf(stderr, "ddof: no output file: give -o OUT.exr (try --help)\n");
        return -1;
    }
    if (o->source == COC_FROM_CAMERA && !o->camera_json &&
        !(cli_camera_given(o, offsetof(ddof_camera, fstop)) &&
          cli_camera_given(o, offsetof(ddof_camera, focus_distance_m)) &&
          cli_camera_given(o, offsetof(ddof_camera, focal_length_mm)))) {
        fprintf(stderr, "ddof: no camera: give --camera CAMERA.json, or at least --focal-length, "
                "--fstop and --focus (or --curve, or --coc-channel)\n");
        return -1;
    }
    return 0;
}

int cli_parse_options(int argc, char **argv, cli_options *o)
{
    int i;
    defaults(o);
    for (i = 1; i < argc; i++) {
        const char *arg = argv[i];
        int rc;
        if (arg[0] != '-' || arg[1] == '\0') {
            rc = take_input(o, arg);
        } else if (!strcmp(arg, "--")) {
            /* "--" ends the options: what follows is the input, even if it starts with '-'. */
            if (i + 1 >= argc || o->input) {
                fprintf(stderr, "ddof: unexpected '--' (try --help)\n");
                return -1;
            }
            rc = take_input(o, argv[++i]);
        } else {
            rc = take_option(argc, argv, &i, o);
        }
        if (rc != 0)
            return rc;
    }
    if (o->cards_json) {
        /* A scene of cards is its own input: its camera and images come from the JSON. */
        if (o->input) {
            fprintf(stderr, "ddof: --cards renders its own scene: no input file ('%s')\n",
                    o->input);
            return -1;
        }
        if (o->frames || o->list_only) {
            fprintf(stderr, "ddof: --cards renders one frame of its scene: no %s\n",
                    o->frames ? "--frames" : "--list");
            return -1;
        }
        if (!o->output) {
            fprintf(stderr, "ddof: no output file: give -o OUT.exr (try --help)\n");
            return -1;
        }
        return 0;
    }
    if (!o->input) {
        fprintf(stderr, "ddof: no input file (try --help)\n");
        return -1;
    }
    if (check_combination(o) != 0)
        return -1;
    return o->list_only ? 0 : check_run_needs(o);
}
