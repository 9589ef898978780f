/* options.c - the `ddof` command line: a table of options, each parsed into cli_options. */
#include "options.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* Printed in sections: ISO C only promises string literals of 4095 characters. */
void cli_usage(FILE *to)
{
    static const char *const sections[] = {
        "usage: ddof IN.exr -o OUT.exr [--camera CAMERA.json | camera flags | --curve ... |\n"
        "                               --coc-channel NAME] [options]\n"
        "       ddof render_####.exr -o dof_####.exr --frames 1-240 [options]\n"
        "       ddof --list IN.exr\n"
        "\n",
        "Depth of field for a pinhole render (linear colour + depth) by simulated heat diffusion.\n"
        "Reads Blender's multilayer EXR (ViewLayer.Combined.RGBA + ViewLayer.Depth.Z) or a single\n"
        "layer (R, G, B, A, Z). With no quality options it uses the default preset.\n"
        "\n",
        "Input channels (found automatically; name them when a file is ambiguous):\n"
        "  --layer NAME            Blender view layer (or EXR part) holding colour and depth\n"
        "  --color NAME|R,G,B[,A]  colour: a channel prefix (ViewLayer.Combined) or 3-4 names\n"
        "  --depth NAME            depth channel (planar camera Z unless --depth-kind radial)\n"
        "  --depth-file FILE.exr   read depth from another file (#### allowed)\n"
        "  --list                  print the parts, channels and what would be used, then exit\n"
        "\n",
        "Circle of confusion (one source; default: camera):\n"
        "  --camera FILE.json      camera sidecar: focal_length_mm, sensor_width_mm, sensor_fit,\n"
        "                          fstop, focus_distance_m, resolution, pixel_aspect, [depth,\n"
        "                          unit_scale_m]; the flags below override its values\n"
        "  --focal-length MM  --sensor-width MM  --sensor-fit auto|horizontal|vertical\n"
        "  --fstop N  --focus METRES  --pixel-aspect A  --depth-kind planar|radial\n"
        "  --unit-scale METRES     metres per depth unit (default 1)\n"
        "  --lens cycles|thin-lens CoC model (default cycles: matches Blender's renders)\n"
        "  --curve NB,NS,NE,FS,FE,FB   artist curve: near blur px, near start, near end, far\n"
        "                          start, far end (depth units), far blur px\n"
        "  --coc-channel NAME      a channel that holds CoC diameters in pixels\n"
        "\n",
        "Quality, method, solver, backend:\n"
        "  --preset preview|default|final  the library's named settings (ddof_params_init_preset,\n"
        "                          chosen by the accuracy study); the flags below override them\n"
        "                          (default: default)\n"
        "  --method diffusion|cod4 diffusion: the heat-diffusion solve; cod4: the fast,\n"
        "                          approximate Call of Duty 4 post-process (CPU; no --foreground)\n"
        "  --kernel heat|disc-2x2|disc-2x3|disc-3x3   the blur's shape: heat, the soft real\n"
        "                          diffusion; disc-*, the lens's disc bokeh (thomas or reference\n"
        "                          on the CPU; elsewhere heat runs)\n"
        "  --solver thomas|cr|pcr|jacobi|reference|gruen   (gruen: GL backends only)\n"
        "  --precision float|packed-half   arithmetic of the GL solvers (packed-half: gruen only)\n"
        "  --substeps N            ADI sub-steps (more: closer to a Gaussian, linear cost)\n"
        "  --beta-scale K          k in beta = k * CoC^2\n"
        "  --jacobi-iterations N   sweeps for --solver jacobi\n"
        "  --threads N             threads per frame (0 = all cores, at most 1024)\n"
        "  --backend auto|cpu|egl|osmesa   where the diffusion runs (default auto: a GPU through\n"
        "                          EGL when there is one, else the CPU); egl and osmesa are an\n"
        "                          error (exit 3) when they cannot be had\n"
        "  --gl-plugin FILE.so     the GL backend plugin to load (default: $DDOF_GL_PLUGIN, then\n"
        "                          libddof_gl.so beside libddof, then the loader's search path)\n"
        "\n",
        "Layers (Kass et al. 3.1, 3.2; the planner runs them when the scene calls for them;\n"
        "modes and levels default to the preset's):\n"
        "  --background auto|on|off        blurring underneath sharp midground objects\n"
        "  --background-threshold PX       CoC at which a pixel is wholly background (default 8)\n"
        "  --background-ramp-start PX      CoC below which it is wholly midground (default 2)\n"
        "  --background-levels N           background layers at t, 2t, 4t, ... (1..8)\n"
        "  --near-spread auto|on|off       soft silhouettes of blurred near objects (one image)\n"
        "  --near-spread-threshold PX      (default 4)\n"
        "  --coc-signed            the --coc-channel is negative in front of the focus plane\n"
        "  --foreground FILE.exr   a separately rendered foreground element (RGBA + depth,\n"
        "                          premultiplied), blurred on top (#### allowed)\n"
        "  --foreground-layer NAME its layer: in FILE, or in the input when no FILE is given\n"
        "  --foreground-coc-channel NAME   its CoC channel (with --coc-channel)\n"
        "  --foreground-straight   its colour is not premultiplied by alpha\n"
        "\n",
        "Output:\n"
        "  -o, --output FILE.exr   the result (#### for sequences); never the input file\n"
        "  --pixel-type half|float (default: that of the input colour)\n"
        "  --compression zip|piz|zips|rle|pxr24|b44|b44a|none   (default zip)\n"
        "  --keep-channels         also write the input's other channels, with their names\n"
        "  --keep-metadata         copy the input's header attributes\n"
        "  --keep                  both\n"
        "  --write-coc             add the CoC used (pixels) as channel 'coc'\n"
        "  --preview FILE.png      also write an sRGB preview (#### for sequences)\n"
        "  --preview-input FILE.png  the same for the input, to compare before and after\n"
        "  --preview-exposure EV   exposure of the previews in stops (default 0)\n"
        "  --focus-map FILE.png    also write the focal-plane view: in focus green, near blur\n"
        "                          orange, far blur blue (#### for sequences)\n"
        "\n",
        "Sequences and reporting:\n"
        "  --frames LIST           e.g. 1-240, 1-240x2, 1,4,10-12; # runs in paths are frame numbers\n"
        "  --jobs N                frames in parallel (default: automatic, when it pays)\n"
        "  --skip-existing         resume a killed batch: skip frames whose outputs are complete\n"
        "                          and no older than their inputs\n"
        "  --stats FILE.json       per-frame statistics and stage times\n"
        "  --compare TRUTH.exr     print RMSE/PSNR of the result and of the input against TRUTH\n"
        "  --progress auto|always|never   progress bar on stderr (auto: when it is a terminal)\n"
        "  -q, --quiet             no per-frame summary\n"
        "  -v, --verbose           per frame also the backend that ran, its renderer, why auto\n"
        "                          chose it, memory used, and the planner's decisions\n"
        "  -h, --help  --version\n"
        "\n",
        "Exit status: 0 all frames written; 1 some frame failed (listed at the end); 2 usage error;\n"
        "3 the backend is unavailable or cannot run the solver or precision asked for;\n"
        "129/130/141/143 interrupted by SIGHUP/SIGINT/SIGPIPE (or a closed stdout)/SIGTERM\n"
        "(temporary files removed).\n"};
    static const char *const modes[] = {"auto", "off", "on"};
    size_t i;
    int p;
    for (i = 0; i < sizeof sections / sizeof sections[0]; i++)
        fputs(sections[i], to);
    /* The values are the library's (the accuracy study writes them): asked, never copied. */
    fprintf(to, "\nPresets of this libddof (%s):\n", ddof_version_string());
    for (p = 0; p < DDOF_PRESET_COUNT_; p++) {
        ddof_params params;
        if (ddof_params_init_preset(&params, (ddof_preset)p) != DDOF_OK)
            continue;
        fprintf(to, "  %-8s %s", ddof_preset_name((ddof_preset)p),
                params.method == DDOF_METHOD_COD4_PREVIEW ? "cod4" : "diffusion");
        if (params.method == DDOF_METHOD_DIFFUSION && params.kernel != DDOF_KERNEL_HEAT)
            fprintf(to, ", %s, %s kernel, background %s (%u level%s), near spread %s",
                    ddof_solver_name(params.solver), ddof_kernel_name(params.kernel),
                    modes[(unsigned)params.background % 3u], params.background_levels,
                    params.background_levels == 1 ? "" : "s",
                    modes[(unsigned)params.near_spread % 3u]);
        else if (params.method == DDOF_METHOD_DIFFUSION)
            fprintf(to, ", %s, %u sub-step%s, k %g, background %s (%u level%s), near spread %s",
                    ddof_solver_name(params.solver), params.substeps,
                    params.substeps == 1 ? "" : "s", (double)params.beta_scale,
                    modes[(unsigned)params.background % 3u], params.background_levels,
                    params.background_levels == 1 ? "" : "s",
                    modes[(unsigned)params.near_spread % 3u]);
        fputc('\n', to);
    }
}

typedef enum arg_kind { ARG_FLAG, ARG_VALUE } arg_kind;

typedef struct option_spec {
    const char *name;
    const char *alias;
    arg_kind kind;
} option_spec;

static const option_spec specs[] = {
    {"--output", "-o", ARG_VALUE},      {"--layer", NULL, ARG_VALUE},
    {"--color", "--colour", ARG_VALUE}, {"--depth", NULL, ARG_VALUE},
    {"--depth-file", NULL, ARG_VALUE},  {"--list", NULL, ARG_FLAG},
    {"--camera", NULL, ARG_VALUE},      {"--focal-length", NULL, ARG_VALUE},
    {"--sensor-width", NULL, ARG_VALUE},{"--sensor-fit", NULL, ARG_VALUE},
    {"--fstop", NULL, ARG_VALUE},       {"--focus", NULL, ARG_VALUE},
    {"--pixel-aspect", NULL, ARG_VALUE},{"--depth-kind", NULL, ARG_VALUE},
    {"--unit-scale", NULL, ARG_VALUE},  {"--lens", NULL, ARG_VALUE},
    {"--curve", NULL, ARG_VALUE},       {"--coc-channel", NULL, ARG_VALUE},
    {"--preset", NULL, ARG_VALUE},      {"--solver", NULL, ARG_VALUE},
    {"--substeps", NULL, ARG_VALUE},    {"--beta-scale", NULL, ARG_VALUE},
    {"--jacobi-iterations", NULL, ARG_VALUE}, {"--threads", NULL, ARG_VALUE},
    {"--backend", NULL, ARG_VALUE},     {"--gl-plugin", NULL, ARG_VALUE},
    {"--method", NULL, ARG_VALUE},      {"--precision", NULL, ARG_VALUE},
    {"--kernel", NULL, ARG_VALUE},
    {"--verbose", "-v", ARG_FLAG},      {"--foreground", NULL, ARG_VALUE},
    {"--foreground-layer", NULL, ARG_VALUE},
    {"--foreground-coc-channel", NULL, ARG_VALUE},
    {"--foreground-straight", NULL, ARG_FLAG},
    {"--background", NULL, ARG_VALUE},  {"--background-threshold", NULL, ARG_VALUE},
    {"--background-ramp-start", NULL, ARG_VALUE},
    {"--background-levels", NULL, ARG_VALUE},
    {"--near-spread", NULL, ARG_VALUE}, {"--near-spread-threshold", NULL, ARG_VALUE},
    {"--coc-signed", NULL, ARG_FLAG},
    {"--pixel-type", NULL, ARG_VALUE},  {"--compression", NULL, ARG_VALUE},
    {"--keep-channels", NULL, ARG_FLAG},{"--keep-metadata", NULL, ARG_FLAG},
    {"--keep", NULL, ARG_FLAG},         {"--write-coc", NULL, ARG_FLAG},
    {"--preview", NULL, ARG_VALUE},     {"--preview-exposure", NULL, ARG_VALUE},
    {"--preview-input", NULL, ARG_VALUE}, {"--focus-map", NULL, ARG_VALUE},
    {"--frames", NULL, ARG_VALUE},      {"--jobs", "-j", ARG_VALUE},
    {"--stats", NULL, ARG_VALUE},       {"--compare", NULL, ARG_VALUE},
    {"--skip-existing", NULL, ARG_FLAG},
    {"--progress", NULL, ARG_VALUE},    {"--quiet", "-q", ARG_FLAG},
    {"--help", "-h", ARG_FLAG},         {"--version", NULL, ARG_FLAG},
};

static int bad(const char *name, const char *value, const char *want)
{
    fprintf(stderr, "ddof: %s wants %s, not '%s' (try --help)\n", name, want, value);
    return -1;
}

static int parse_double(const char *name, const char *text, double *out, int positive)
{
    char *end;
    double v;
    errno = 0;
    v = strtod(text, &end);
    if (end == text || *end != '\0' || errno != 0 || !isfinite(v) || (positive && !(v > 0.0)))
        return bad(name, text, positive ? "a number > 0" : "a number");
    *out = v;
    return 0;
}

static int parse_uint_max(const char *name, const char *text, uint32_t *out, uint32_t min,
                          uint32_t max)
{
    char *end;
    unsigned long v;
    errno = 0;
    v = strtoul(text, &end, 10);
    if (end == text || *end != '\0' || errno != 0 || text[0] == '-' || v > 0xffffffffUL ||
        v < min || v > max) {
        char want[64];
        if (max < 0xffffffffu)
            snprintf(want, sizeof want, "a whole number within %u..%u", min, max);
        else
            snprintf(want, sizeof want, "a whole number >= %u", min);
        return bad(name, text, want);
    }
    *out = (uint32_t)v;
    return 0;
}

static int parse_uint(const char *name, const char *text, uint32_t *out, uint32_t min)
{
    return parse_uint_max(name, text, out, min, 0xffffffffu);
}

static int parse_choice(const char *name, const char *text, const char *const *choices,
                        int count, int *out)
{
    int i;
    char want[256];
    size_t used = 0;
    for (i = 0; i < count; i++) {
        if (strcasecmp(text, choices[i]) == 0) {
            *out = i;
            return 0;
        }
    }
    want[0] = '\0';
    for (i = 0; i < count && used < sizeof want; i++) {
        int n = snprintf(want + used, sizeof want - used, "%s%s", i ? " | " : "one of ",
                         choices[i]);
        if (n < 0)
            break;
        used += (size_t)n;
    }
    return bad(name, text, want);
}

/* The choices a library enum has by name, "one of a | b | c" for messages. */
static void name_list(const char *(*name_of)(int), int count, char *out, size_t size)
{
    size_t used = 0;
    int i;
    out[0] = '\0';
    for (i = 0; i < count && used < size; i++) {
        const char *n = name_of(i);
        int k = n ? snprintf(out + used, size - used, "%s%s", used ? " | " : "one of ", n) : 0;
        if (k < 0)
            break;
        used += (size_t)k;
    }
}

static const char *solver_name_of(int i) { return ddof_solver_name((ddof_solver)i); }
static const char *kernel_name_of(int i) { return ddof_kernel_name((ddof_kernel)i); }
static const char *preset_name_of(int i) { return ddof_preset_name((ddof_preset)i); }

/* Backends the command can use: the host-GL one needs a host application's context. */
static const char *backend_name_of(int i)
{
    return i == DDOF_BACKEND_HOST_GL ? NULL : ddof_backend_name((ddof_backend_kind)i);
}

/* Looks text up among the names name_of(0 .. count-1) gives. */
static int parse_named(const char *option, const char *text, const char *(*name_of)(int),
                       int count, int *out)
{
    char want[256];
    int i;
    for (i = 0; i < count; i++) {
        const char *n = name_of(i);
        if (n && strcasecmp(n, text) == 0) {
            *out = i;
            return 0;
        }
    }
    name_list(name_of, count, want, sizeof want);
    return bad(option, text, want);
}

/* "NB,NS,NE,FS,FE,FB": six numbers in the order of ddof_curve. */
static int parse_curve(const char *text, ddof_curve *curve)
{
    double v[6];
    const char *p = text;
    int i;
    for (i = 0; i < 6; i++) {
        char *end;
        errno = 0;
        v[i] = strtod(p, &end);
        if (end == p || errno != 0 || !isfinite(v[i]) || v[i] < 0.0 ||
            (i < 5 && *end != ',') || (i == 5 && *end != '\0'))
            return bad("--curve", text,
                       "six numbers >= 0: near_blur_px,near_start,near_end,far_start,far_end,"
                       "far_blur_px");
        p = end + 1;
    }
    ddof_curve_init(curve);
    curve->near_blur_px = v[0];
    curve->near_start = v[1];
    curve->near_end = v[2];
    curve->far_start = v[3];
    curve->far_end = v[4];
    curve->far_blur_px = v[5];
    return 0;
}

static void defaults(cli_options *o)
{
    memset(o, 0, sizeof *o);
    o->source = COC_FROM_CAMERA;
    ddof_camera_init(&o->camera);
    ddof_curve_init(&o->curve);
    o->preset = DDOF_PRESET_DEFAULT;
    o->method = -1;
    o->precision = -1;
    o->kernel = -1;
    o->solver = -1;
    o->backend = DDOF_BACKEND_AUTO;
    o->pixel_type = -1;
    o->background = -1;
    o->near_spread = -1;
    o->background_ramp_start = -1.0f;
    o->compression = EXRIO_COMPRESSION_ZIP;
    o->progress = PROGRESS_AUTO;
}

/* Applies one recognised option. */
static int apply(cli_options *o, const char *name, const char *value, int *sources)
{
    static const char *const fits[] = {"auto", "horizontal", "vertical"};
    static const char *const kinds[] = {"planar", "radial"};
    static const char *const lenses[] = {"cycles", "thin-lens"};
    static const char *const types[] = {"uint", "half", "float"};
    static const char *const progress[] = {"auto", "always", "never"};
    static const char *const methods[] = {"diffusion", "cod4"};
    static const char *const precisions[] = {"float", "packed-half"};
    int choice = 0;

    if (!strcmp(name, "--output")) o->output = value;
    else if (!strcmp(name, "--layer")) o->layer = value;
    else if (!strcmp(name, "--color")) o->color = value;
    else if (!strcmp(name, "--depth")) o->depth = value;
    else if (!strcmp(name, "--depth-file")) o->depth_file = value;
    else if (!strcmp(name, "--list")) o->list_only = 1;
    else if (!strcmp(name, "--camera")) o->camera_json = value;
    else if (!strcmp(name, "--focal-length")) {
        o->camera_set |= CAM_FOCAL;
        return parse_double(name, value, &o->camera.focal_length_mm, 1);
    } else if (!strcmp(name, "--sensor-width")) {
        o->camera_set |= CAM_SENSOR;
        return parse_double(name, value, &o->camera.sensor_width_mm, 1);
    } else if (!strcmp(name, "--sensor-fit")) {
        o->camera_set |= CAM_FIT;
        if (parse_choice(name, value, fits, 3, &choice) != 0) return -1;
        o->camera.sensor_fit = (ddof_sensor_fit)choice;
    } else if (!strcmp(name, "--fstop")) {
        o->camera_set |= CAM_FSTOP;
        return parse_double(name, value, &o->camera.fstop, 1);
    } else if (!strcmp(name, "--focus")) {
        o->camera_set |= CAM_FOCUS;
        return parse_double(name, value, &o->camera.focus_distance_m, 1);
    } else if (!strcmp(name, "--pixel-aspect")) {
        o->camera_set |= CAM_ASPECT;
        return parse_double(name, value, &o->camera.pixel_aspect, 1);
    } else if (!strcmp(name, "--depth-kind")) {
        o->camera_set |= CAM_DEPTH_KIND;
        if (parse_choice(name, value, kinds, 2, &choice) != 0) return -1;
        o->camera.depth_kind = (ddof_depth_kind)choice;
    } else if (!strcmp(name, "--unit-scale")) {
        o->camera_set |= CAM_UNIT;
        return parse_double(name, value, &o->camera.depth_unit_m, 1);
    } else if (!strcmp(name, "--lens")) {
        o->camera_set |= CAM_LENS;
        if (parse_choice(name, value, lenses, 2, &choice) != 0) return -1;
        o->camera.lens_model = choice ? DDOF_LENS_THIN_LENS : DDOF_LENS_CYCLES;
    } else if (!strcmp(name, "--curve")) {
        o->source = COC_FROM_CURVE;
        (*sources)++;
        return parse_curve(value, &o->curve);
    } else if (!strcmp(name, "--coc-channel")) {
        o->source = COC_FROM_CHANNEL;
        o->coc_channel = value;
        (*sources)++;
    } else if (!strcmp(name, "--preset")) {
        /* The names of 0.2's command, kept for scripts: their settings are the library's. */
        if (strcasecmp(value, "fast") == 0 || strcasecmp(value, "quality") == 0) {
            const ddof_preset now = value[0] == 'f' || value[0] == 'F' ? DDOF_PRESET_PREVIEW
                                                                      : DDOF_PRESET_FINAL;
            fprintf(stderr, "ddof: note: --preset %s is now called --preset %s\n", value,
                    ddof_preset_name(now));
            o->preset = now;
            return 0;
        }
        if (parse_named(name, value, preset_name_of, DDOF_PRESET_COUNT_, &choice) != 0)
            return -1;
        o->preset = (ddof_preset)choice;
    } else if (!strcmp(name, "--method")) {
        if (strcasecmp(value, "cod4-preview") == 0)
            value = "cod4";
        if (parse_choice(name, value, methods, 2, &choice) != 0) return -1;
        o->method = choice ? DDOF_METHOD_COD4_PREVIEW : DDOF_METHOD_DIFFUSION;
    } else if (!strcmp(name, "--precision")) {
        if (parse_choice(name, value, precisions, 2, &choice) != 0) return -1;
        o->precision = choice ? DDOF_PRECISION_PACKED_HALF : DDOF_PRECISION_FLOAT;
    } else if (!strcmp(name, "--solver")) {
        return parse_named(name, value, solver_name_of, DDOF_SOLVER_COUNT_, &o->solver);
    } else if (!strcmp(name, "--kernel")) {
        return parse_named(name, value, kernel_name_of, DDOF_KERNEL_COUNT_, &o->kernel);
    } else if (!strcmp(name, "--substeps")) {
        return parse_uint(name, value, &o->substeps, 1);
    } else if (!strcmp(name, "--beta-scale")) {
        double k;
        if (parse_double(name, value, &k, 1) != 0) return -1;
        o->beta_scale = (float)k;
    } else if (!strcmp(name, "--jacobi-iterations")) {
        return parse_uint(name, value, &o->jacobi_iterations, 1);
    } else if (!strcmp(name, "--threads")) {
        return parse_uint_max(name, value, &o->threads, 0, CLI_MAX_THREADS);
    } else if (!strcmp(name, "--jobs")) {
        return parse_uint(name, value, &o->jobs, 1);
    } else if (!strcmp(name, "--backend")) {
        if (parse_named(name, value, backend_name_of, DDOF_BACKEND_COUNT_, &choice) != 0)
            return -1;
        o->backend = (ddof_backend_kind)choice;
    } else if (!strcmp(name, "--gl-plugin")) {
        o->gl_plugin = value;
    } else if (!strcmp(name, "--foreground")) {
        o->foreground = value;
    } else if (!strcmp(name, "--foreground-layer")) {
        o->foreground_layer = value;
    } else if (!strcmp(name, "--foreground-coc-channel")) {
        o->foreground_coc = value;
    } else if (!strcmp(name, "--foreground-straight")) {
        o->foreground_straight = 1;
    } else if (!strcmp(name, "--background") || !strcmp(name, "--near-spread")) {
        static const char *const modes[] = {"auto", "off", "on"};
        if (parse_choice(name, value, modes, 3, &choice) != 0) return -1;
        /* the order of ddof_layer_mode: AUTO, OFF, ON */
        if (!strcmp(name, "--background"))
            o->background = choice;
        else
            o->near_spread = choice;
    } else if (!strcmp(name, "--background-threshold")) {
        double v;
        if (parse_double(name, value, &v, 1) != 0) return -1;
        o->background_threshold = (float)v;
    } else if (!strcmp(name, "--background-ramp-start")) {
        double v;
        if (parse_double(name, value, &v, 0) != 0) return -1;
        if (v < 0.0) return bad(name, value, "a number >= 0");
        o->background_ramp_start = (float)v;
    } else if (!strcmp(name, "--background-levels")) {
        return parse_uint(name, value, &o->background_levels, 1);
    } else if (!strcmp(name, "--near-spread-threshold")) {
        double v;
        if (parse_double(name, value, &v, 1) != 0) return -1;
        o->near_spread_threshold = (float)v;
    } else if (!strcmp(name, "--coc-signed")) {
        o->coc_signed = 1;
    } else if (!strcmp(name, "--pixel-type")) {
        if (parse_choice(name, value, types, 3, &choice) != 0) return -1;
        if (choice == EXRIO_UINT)
            return bad(name, value, "half | float");
        o->pixel_type = choice;
    } else if (!strcmp(name, "--compression")) {
        if (exrio_compression_parse(value, &o->compression) != 0)
            return bad(name, value, "zip | piz | zips | rle | pxr24 | b44 | b44a | none");
        if (!exrio_compression_can_encode(o->compression)) {
            fprintf(stderr, "ddof: --compression %s: OpenEXR's C core cannot write DWAA/DWAB; "
                    "use zip or piz\n", value);
            return -1;
        }
    } else if (!strcmp(name, "--keep-channels")) o->keep_channels = 1;
    else if (!strcmp(name, "--keep-metadata")) o->keep_metadata = 1;
    else if (!strcmp(name, "--keep")) o->keep_channels = o->keep_metadata = 1;
    else if (!strcmp(name, "--write-coc")) o->write_coc = 1;
    else if (!strcmp(name, "--preview")) o->preview = value;
    else if (!strcmp(name, "--preview-input")) o->preview_input = value;
    else if (!strcmp(name, "--focus-map")) o->focus_map = value;
    else if (!strcmp(name, "--preview-exposure")) {
        double ev;
        if (parse_double(name, value, &ev, 0) != 0) return -1;
        o->preview_exposure = (float)ev;
    } else if (!strcmp(name, "--frames")) o->frames = value;
    else if (!strcmp(name, "--stats")) o->stats_path = value;
    else if (!strcmp(name, "--skip-existing")) o->skip_existing = 1;
    else if (!strcmp(name, "--compare")) o->compare = value;
    else if (!strcmp(name, "--progress")) {
        if (parse_choice(name, value, progress, 3, &choice) != 0) return -1;
        o->progress = (progress_mode)choice;
    } else if (!strcmp(name, "--quiet")) o->quiet = 1;
    else if (!strcmp(name, "--verbose")) o->verbose = 1;
    return 0;
}

int cli_parse_options(int argc, char **argv, cli_options *o)
{
    int i, sources = 0;
    defaults(o);

    for (i = 1; i < argc; i++) {
        const char *arg = argv[i];
        const char *value = NULL;
        const option_spec *spec = NULL;
        char name[64];
        size_t k;

        if (arg[0] != '-' || arg[1] == '\0') {
            if (o->input) {
                fprintf(stderr, "ddof: more than one input ('%s' and '%s'); use --frames for "
                        "sequences (try --help)\n", o->input, arg);
                return -1;
            }
            o->input = arg;
            continue;
        }
        if (!strcmp(arg, "--")) {
            if (i + 1 < argc && !o->input) {
                o->input = argv[++i];
                continue;
            }
            fprintf(stderr, "ddof: unexpected '--' (try --help)\n");
            return -1;
        }
        /* --name=value or --name value */
        snprintf(name, sizeof name, "%s", arg);
        if (strncmp(arg, "--", 2) == 0 && strchr(arg, '=')) {
            size_t n = (size_t)(strchr(arg, '=') - arg);
            if (n < sizeof name)
                name[n] = '\0';
            value = strchr(arg, '=') + 1;
        }
        for (k = 0; k < sizeof specs / sizeof specs[0]; k++) {
            if (!strcmp(name, specs[k].name) || (specs[k].alias && !strcmp(name, specs[k].alias))) {
                spec = &specs[k];
                break;
            }
        }
        if (!spec) {
            fprintf(stderr, "ddof: unknown option '%s' (try --help)\n", arg);
            return -1;
        }
        if (!strcmp(spec->name, "--help")) {
            cli_usage(stdout);
            return 1;
        }
        if (!strcmp(spec->name, "--version")) {
            printf("ddof %s (libddof %s)\n", DDOF_CLI_VERSION, ddof_version_string());
            return 1;
        }
        if (spec->kind == ARG_FLAG && value) {
            fprintf(stderr, "ddof: %s takes no value\n", spec->name);
            return -1;
        }
        if (spec->kind == ARG_VALUE && !value) {
            if (i + 1 >= argc) {
                fprintf(stderr, "ddof: %s needs a value (try --help)\n", spec->name);
                return -1;
            }
            value = argv[++i];
        }
        if (spec->kind == ARG_VALUE && value[0] == '\0') {
            fprintf(stderr, "ddof: %s needs a non-empty value\n", spec->name);
            return -1;
        }
        if (apply(o, spec->name, value, &sources) != 0)
            return -1;
    }

    if (!o->input) {
        fprintf(stderr, "ddof: no input file (try --help)\n");
        return -1;
    }
    if (sources > 1) {
        fprintf(stderr, "ddof: --curve and --coc-channel are two CoC sources: give one\n");
        return -1;
    }
    if (o->source != COC_FROM_CAMERA && (o->camera_json || o->camera_set)) {
        fprintf(stderr, "ddof: camera options do not apply with %s\n",
                o->source == COC_FROM_CURVE ? "--curve" : "--coc-channel");
        return -1;
    }
    if (o->coc_signed && o->source != COC_FROM_CHANNEL) {
        fprintf(stderr, "ddof: --coc-signed describes a --coc-channel\n");
        return -1;
    }
    if (o->source == COC_FROM_CHANNEL && (o->foreground || o->foreground_layer) &&
        !o->foreground_coc) {
        fprintf(stderr, "ddof: with --coc-channel, a foreground element needs its own CoC: give "
                "--foreground-coc-channel\n");
        return -1;
    }
    if (o->method == DDOF_METHOD_COD4_PREVIEW && (o->foreground || o->foreground_layer)) {
        fprintf(stderr, "ddof: --method cod4 takes no foreground element: the CoD4 preview "
                "blurs one image (use --method diffusion with --foreground)\n");
        return -1;
    }
    if (o->near_spread == DDOF_LAYER_ON && (o->foreground || o->foreground_layer)) {
        fprintf(stderr, "ddof: --near-spread on works on one image: with a foreground element "
                "the element is the near field (leave out --near-spread on)\n");
        return -1;
    }
    if (o->gl_plugin && o->backend == DDOF_BACKEND_CPU) {
        fprintf(stderr, "ddof: --gl-plugin names the GL backend, but --backend cpu uses none\n");
        return -1;
    }
    if (o->list_only)
        return 0;
    if (!o->output) {
        fprintf(stderr, "ddof: no output file: give -o OUT.exr (try --help)\n");
        return -1;
    }
    if (o->source == COC_FROM_CAMERA && !o->camera_json &&
        (o->camera_set & (CAM_FSTOP | CAM_FOCUS | CAM_FOCAL)) != (CAM_FSTOP | CAM_FOCUS | CAM_FOCAL)) {
        fprintf(stderr, "ddof: no camera: give --camera CAMERA.json, or at least --focal-length, "
                "--fstop and --focus (or --curve, or --coc-channel)\n");
        return -1;
    }
    return 0;
}
