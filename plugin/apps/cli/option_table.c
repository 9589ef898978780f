/* SPDX-License-Identifier: MIT */
/* option_table.c - the options of `ddof`, one entry each, in the order the usage prints them,
 * and the few whose value does more than land in one field (their apply functions). */
#include "option_table.h"

#include "exrio.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

const cli_curve_number cli_curve_numbers[6] = {
    {"near_blur_px", offsetof(ddof_curve, near_blur_px)},
    {"near_start", offsetof(ddof_curve, near_start)},
    {"near_end", offsetof(ddof_curve, near_end)},
    {"far_start", offsetof(ddof_curve, far_start)},
    {"far_end", offsetof(ddof_curve, far_end)},
    {"far_blur_px", offsetof(ddof_curve, far_blur_px)},
};

/* --curve "NB,NS,NE,FS,FE,FB": six numbers in the order of ddof_curve; the CoC's source. */
static int apply_curve(const cli_option *option, const char *value, cli_options *o)
{
    double v[6];
    const char *p = value;
    int i;
    for (i = 0; i < 6; i++) {
        char *end;
        errno = 0;
        v[i] = strtod(p, &end);
        if (end == p || errno != 0 || !isfinite(v[i]) || v[i] < 0.0 ||
            (i < 5 && *end != ',') || (i == 5 && *end != '\0'))
            return cli_option_bad_value(option, value,
                                        "six numbers >= 0: near_blur_px,near_start,near_end,"
                                        "far_start,far_end,far_blur_px");
        p = end + 1;
    }
    ddof_curve_init(&o->curve);
    for (i = 0; i < 6; i++)
        memcpy((char *)&o->curve + cli_curve_numbers[i].field, &v[i], sizeof v[i]);
    o->source = COC_FROM_CURVE;
    o->coc_sources_given++;
    return 0;
}

static int apply_coc_channel(const cli_option *option, const char *value, cli_options *o)
{
    o->source = COC_FROM_CHANNEL;
    o->coc_sources_given++;
    return cli_option_parse_value(option, value, o);
}

/* The older names fast and quality, kept for scripts: their settings are the library's. */
static int apply_preset(const cli_option *option, const char *value, cli_options *o)
{
    if (strcasecmp(value, "fast") == 0 || strcasecmp(value, "quality") == 0) {
        const ddof_preset now =
            value[0] == 'f' || value[0] == 'F' ? DDOF_PRESET_PREVIEW : DDOF_PRESET_FINAL;
        fprintf(stderr, "ddof: note: %s %s is now called %s %s\n", option->name, value,
                option->name, ddof_preset_name(now));
        o->preset = now;
        return 0;
    }
    return cli_option_parse_value(option, value, o);
}

/* 0.3 spelled the CoD4 preview by its enum's name; still accepted. */
static int apply_method(const cli_option *option, const char *value, cli_options *o)
{
    if (strcasecmp(value, "cod4-preview") == 0)
        value = cli_choice_name(option->choices, DDOF_METHOD_COD4_PREVIEW);
    return cli_option_parse_value(option, value, o);
}

/* NAME, or NAME:LEVEL for DWAA/DWAB (OpenEXR's dwaCompressionLevel: higher is smaller and
 * lossier; 45 when not given) and for ZIP/ZIPS (the deflate level, 1 to 9 as zlib counts; 6
 * when not given). */
static int apply_compression(const cli_option *option, const char *value, cli_options *o)
{
    const char *colon = strchr(value, ':');
    exrio_compression known;
    char name[16], *end = NULL;
    double level;
    int zip;
    if (!colon)
        return cli_option_parse_value(option, value, o);
    snprintf(name, sizeof name, "%.*s", (int)(colon - value < 15 ? colon - value : 15), value);
    zip = exrio_compression_parse(name, &known) == 0 &&
          (known == EXRIO_COMPRESSION_ZIP || known == EXRIO_COMPRESSION_ZIPS);
    if (!zip && (exrio_compression_parse(name, &known) != 0 || !exrio_compression_is_dwa(known))) {
        fprintf(stderr, "ddof: %s %s: only zip, zips, dwaa and dwab take a level (zip:1, "
                "dwaa:45)\n", option->name, value);
        return -1;
    }
    level = strtod(colon + 1, &end);
    if (end == colon + 1 || *end != '\0' ||
        (zip ? !(level >= 1.0 && level <= 9.0 && level == floor(level))
             : !(level > 0.0 && level <= 1e6))) {
        fprintf(stderr, "ddof: %s %s: %s\n", option->name, value,
                zip ? "the zip level is a whole number from 1 (fastest) to 9 (smallest)"
                    : "the level is a number above 0 (OpenEXR's default: 45)");
        return -1;
    }
    if (zip)
        o->zip_level = (int)level;
    else
        o->dwa_level = (float)level;
    return cli_option_parse_value(option, name, o);
}

static int apply_keep(const cli_option *option, const char *value, cli_options *o)
{
    (void)option;
    (void)value;
    o->keep_channels = o->keep_metadata = 1;
    return 0;
}

_Static_assert(CLI_MAX_THREADS == 1024u, "--threads' help says 1024");

#define TARGET(field) .target = offsetof(cli_options, field)
#define PARAMS .to_params = 1 /* target is params.FIELD: a ddof_params field */
#define CAMERA .to_camera = 1 /* target is camera.FIELD: a ddof_camera field */
#define INPUT .section = CLI_SECTION_INPUT
#define COC .section = CLI_SECTION_COC
#define QUALITY .section = CLI_SECTION_QUALITY
#define LAYERS .section = CLI_SECTION_LAYERS
#define OUTPUT .section = CLI_SECTION_OUTPUT
#define REPORTING .section = CLI_SECTION_REPORTING
#define FLAG(field) .kind = CLI_OPT_FLAG, TARGET(field)
#define STRING(field, placeholder) .kind = CLI_OPT_STRING, TARGET(field), .arg = placeholder
#define CHOICE(field, list) .kind = CLI_OPT_CHOICE, TARGET(field), .choices = &(list)
#define DOUBLE(field, placeholder, r) .kind = CLI_OPT_DOUBLE, TARGET(field), .arg = placeholder, \
                                      .range = r
#define FLOAT(field, placeholder, r) .kind = CLI_OPT_FLOAT, TARGET(field), .arg = placeholder, \
                                     .range = r
#define UINT(field, lo, hi) .kind = CLI_OPT_UINT, TARGET(field), .arg = "N", .min = lo, .max = hi

const cli_option cli_option_table[] = {
    /* input channels */
    {"--layer", INPUT, STRING(layer, "NAME"),
     .help = "Blender view layer (or EXR part) holding colour and depth"},
    {"--color", .alias = "--colour", INPUT, STRING(color, "NAME|R,G,B[,A]"),
     .help = "colour: a channel prefix (ViewLayer.Combined) or 3-4 names"},
    {"--depth", INPUT, STRING(depth, "NAME"),
     .help = "depth channel (planar camera Z unless --depth-kind radial)"},
    {"--matte", INPUT, STRING(matte, "auto|off|NAME"),
     .help = "object matte for the silhouettes' split: a Cryptomatte layer\n"
             "(auto: CryptoObject when the file has one, beside the colour)"},
    {"--depth-file", INPUT, STRING(depth_file, "FILE.exr"),
     .help = "read depth from another file (#### allowed)"},
    {"--cards", INPUT, STRING(cards_json, "SCENE.json"),
     .help = "render a scene of textured cards (docs/cards.md) instead of\n"
             "IN.exr: -o OUT.exr, and --pixel-type, --compression, --threads"},
    {"--list", INPUT, FLAG(list_only),
     .help = "print the parts, channels and what would be used, then exit"},

    /* circle of confusion */
    {"--camera", COC, STRING(camera_json, "FILE.json"),
     .help = "camera sidecar: focal_length_mm, sensor_width_mm, sensor_fit,\n"
             "fstop, focus_distance_m, resolution, pixel_aspect, [depth,\n"
             "unit_scale_m, aperture_blades, aperture_rotation_deg,\n"
             "aperture_ratio, aperture_catseye]; the flags below override its\n"
             "values"},
    {"--focal-length", COC, DOUBLE(camera.focal_length_mm, "MM", CLI_POSITIVE),
     CAMERA,
     .help = "the lens's focal length"},
    {"--sensor-width", COC, DOUBLE(camera.sensor_width_mm, "MM", CLI_POSITIVE),
     CAMERA,
     .help = "the sensor's width (Blender's sensor size)"},
    {"--sensor-fit", COC, CHOICE(camera.sensor_fit, cli_choices_sensor_fit),
     CAMERA,
     .help = "the image side the sensor width spans"},
    {"--fstop", COC, DOUBLE(camera.fstop, "N", CLI_POSITIVE),
     CAMERA,
     .help = "the aperture's f-number"},
    {"--focus", COC, DOUBLE(camera.focus_distance_m, "METRES", CLI_POSITIVE),
     CAMERA,
     .help = "the focus distance"},
    {"--pixel-aspect", COC, DOUBLE(camera.pixel_aspect, "A", CLI_POSITIVE),
     CAMERA,
     .help = "pixel width / height"},
    {"--aperture-blades", COC, UINT(camera.aperture_blades, 0, DDOF_MAX_APERTURE_BLADES),
     CAMERA,
     .help = "the aperture's blades: 0 round, 3..16 a polygon (Blender's\n"
             "Blades); highlights are drawn in its shape"},
    {"--aperture-rotation", COC, DOUBLE(camera.aperture_rotation_deg, "DEG", CLI_ANY_NUMBER),
     CAMERA,
     .help = "the blades' rotation, degrees (Blender's Rotation)"},
    {"--aperture-ratio", COC, DOUBLE(camera.aperture_ratio, "R", CLI_POSITIVE),
     CAMERA,
     .help = "anamorphic ratio (Blender's Ratio): 2 draws tall ovals"},
    {"--aperture-image", COC, STRING(aperture_image, "FILE.exr"),
     .help = "a custom aperture for highlights (its Y, R or first channel;\n"
             "up to 256 x 256): replaces the blades"},
    {"--aperture-catseye", COC, DOUBLE(camera.aperture_catseye, "C", CLI_NON_NEGATIVE),
     CAMERA,
     .help = "optical vignetting of highlights toward the frame's edges,\n"
             "0..1 (default 0: off)"},
    {"--depth-kind", COC, CHOICE(camera.depth_kind, cli_choices_depth_kind),
     CAMERA,
     .help = "planar: camera Z (Blender's Depth pass); radial: distance\n"
             "from the centre of projection"},
    {"--unit-scale", COC, DOUBLE(camera.depth_unit_m, "METRES", CLI_POSITIVE),
     CAMERA,
     .help = "metres per depth unit (default 1)"},
    {"--lens", COC, CHOICE(camera.lens_model, cli_choices_lens), CAMERA,
     .help = "CoC model (default cycles: matches Blender's renders)"},
    {"--curve", COC, .kind = CLI_OPT_OTHER, .arg = "NB,NS,NE,FS,FE,FB", .apply = apply_curve,
     .example = "0,0,1,2,3,4",
     .help = "artist curve: near blur px, near start, near end, far\n"
             "start, far end (depth units), far blur px"},
    {"--coc-channel", COC, STRING(coc_channel, "NAME"), .apply = apply_coc_channel,
     .help = "a channel that holds CoC diameters in pixels"},

    /* quality, method, solver, backend */
    {"--preset", QUALITY, CHOICE(preset, cli_choices_preset), .apply = apply_preset,
     .setting = "preset",
     .help = "the library's named settings (ddof_params_init_preset,\n"
             "chosen by the accuracy study); the flags below override them\n"
             "(default: default)"},
    {"--method", QUALITY, CHOICE(params.method, cli_choices_method), PARAMS,
     .apply = apply_method, .setting = "method",
     .help = "diffusion: the heat-diffusion solve; cod4: the fast,\n"
             "approximate Call of Duty 4 post-process (CPU; no --foreground)"},
    {"--kernel", QUALITY, CHOICE(params.kernel, cli_choices_kernel), PARAMS,
     .setting = "kernel",
     .help = "the blur's shape: heat, the soft real\n"
             "diffusion; disc-*, the lens's disc bokeh (thomas or reference\n"
             "on the CPU; elsewhere heat runs)"},
    {"--solver", QUALITY, CHOICE(params.solver, cli_choices_solver), PARAMS,
     .setting = "solver", .help = "the line solver (gruen: GL backends only)"},
    {"--precision", QUALITY, CHOICE(params.precision, cli_choices_precision), PARAMS,
     .setting = "precision", .help = "arithmetic of the GL solvers (packed-half: gruen only)"},
    {"--substeps", QUALITY, UINT(params.substeps, 1, 0), PARAMS, .setting = "substeps",
     .help = "ADI sub-steps (more: closer to a Gaussian, linear cost)"},
    {"--beta-scale", QUALITY, FLOAT(params.beta_scale, "K", CLI_POSITIVE), PARAMS,
     .setting = "beta_scale", .help = "k in beta = k * CoC^2"},
    {"--jacobi-iterations", QUALITY, UINT(params.jacobi_iterations, 1, 0), PARAMS,
     .setting = "jacobi_iterations", .help = "sweeps for --solver jacobi"},
    {"--threads", QUALITY, UINT(threads, 0, CLI_MAX_THREADS),
     .help = "threads per frame (0 = all cores, at most 1024)"},
    {"--backend", QUALITY, CHOICE(backend, cli_choices_backend), .setting = "backend",
     .help = "where the diffusion runs (default auto: a GPU through\n"
             "EGL when there is one, else the CPU); egl and osmesa are an\n"
             "error (exit 3) when they cannot be had"},
    {"--gl-plugin", QUALITY, STRING(gl_plugin, "FILE.so"), .setting = "gl_plugin",
     .help = "the GL backend plugin to load (default: $DDOF_GL_PLUGIN, then\n"
             "libddof_gl.so beside libddof, then the loader's search path)"},

    /* layers */
    {"--background", LAYERS, CHOICE(params.background, cli_choices_layer_mode), PARAMS,
     .setting = "background", .help = "blurring underneath sharp midground objects"},
    {"--background-threshold", LAYERS, FLOAT(params.background_threshold_px, "PX", CLI_POSITIVE),
     PARAMS, .setting = "background_threshold_px",
     .help = "CoC at which a pixel is wholly background (default 8)"},
    {"--background-ramp-start", LAYERS,
     FLOAT(params.background_ramp_start_px, "PX", CLI_NON_NEGATIVE), PARAMS,
     .setting = "background_ramp_start_px",
     .help = "CoC below which it is wholly midground (default 2)"},
    {"--background-levels", LAYERS, UINT(params.background_levels, 1, 0), PARAMS,
     .setting = "background_levels", .help = "background layers at t, 2t, 4t, ... (1..8)"},
    {"--near-spread", LAYERS, CHOICE(params.near_spread, cli_choices_layer_mode), PARAMS,
     .setting = "near_spread", .help = "soft silhouettes of blurred near objects (one image)"},
    {"--near-spread-threshold", LAYERS, FLOAT(params.near_spread_threshold_px, "PX", CLI_POSITIVE),
     PARAMS, .setting = "near_spread_threshold_px",
     .help = "near CoC from which the silhouettes spread (default 4)"},
    {"--near-layer", LAYERS, CHOICE(params.near_layer, cli_choices_layer_mode), PARAMS,
     .setting = "near_layer",
     .help = "blurred near objects turn see-through (one image: the near\n"
             "field split off, what it hid filled in)"},
    {"--near-layer-threshold", LAYERS, FLOAT(params.near_layer_threshold_px, "PX", CLI_POSITIVE),
     PARAMS, .setting = "near_layer_threshold_px",
     .help = "near CoC from which a pixel is wholly in the near layer (default 8)"},
    {"--far-field", LAYERS, CHOICE(params.far_field, cli_choices_layer_mode), PARAMS,
     .setting = "far_field",
     .help = "smooth blur away from depth edges gathered in the lens's exact\n"
             "disc (docs/design.md)"},
    {"--blurred-edges", LAYERS, CHOICE(params.blurred_edges, cli_choices_layer_mode),
     PARAMS, .setting = "blurred_edges",
     .help = "where two blurred surfaces meet, each drawn with the lens's\n"
             "shape, the nearer over the farther (the far field's depth slices)"},
    {"--silhouettes", LAYERS, CHOICE(params.silhouettes, cli_choices_layer_mode),
     PARAMS, .setting = "silhouettes",
     .help = "mixed pixels where in-focus objects meet a blurred background\n"
             "split: the object's share sharp, the background's blurred"},
    {"--highlights", LAYERS, CHOICE(params.highlights, cli_choices_layer_mode), PARAMS,
     .setting = "highlights",
     .help = "the brightest blurred pixels drawn as crisp discs (HDR bokeh)"},
    {"--highlight-threshold", LAYERS, FLOAT(params.highlight_threshold, "VALUE", CLI_POSITIVE),
     PARAMS, .setting = "highlight_threshold",
     .help = "brightness above which a pixel is a highlight (default 0.25)"},
    {"--coc-signed", LAYERS, FLAG(coc_signed),
     .help = "the --coc-channel is negative in front of the focus plane"},
    {"--foreground", LAYERS, STRING(foreground, "FILE.exr"),
     .help = "a separately rendered foreground element (RGBA + depth,\n"
             "premultiplied), blurred on top (#### allowed)"},
    {"--foreground-layer", LAYERS, STRING(foreground_layer, "NAME"),
     .help = "its layer: in FILE, or in the input when no FILE is given"},
    {"--foreground-coc-channel", LAYERS, STRING(foreground_coc, "NAME"),
     .help = "its CoC channel (with --coc-channel)"},
    {"--foreground-straight", LAYERS, FLAG(foreground_straight),
     .help = "its colour is not premultiplied by alpha"},

    /* output */
    {"--output", "-o", OUTPUT, STRING(output, "FILE.exr"),
     .help = "the result (#### for sequences); never the input file"},
    {"--pixel-type", OUTPUT, CHOICE(pixel_type, cli_choices_pixel_type),
     .help = "(default: that of the input colour)"},
    {"--compression", OUTPUT, CHOICE(compression, cli_choices_compression),
     .apply = apply_compression, .setting = "compression",
     .help = "(default zip; zip:1 is faster, dwaa and dwab take a level: dwaa:45)"},
    {"--keep-channels", OUTPUT, FLAG(keep_channels),
     .help = "also write the input's other channels, with their names"},
    {"--keep-metadata", OUTPUT, FLAG(keep_metadata), .help = "copy the input's header attributes"},
    {"--keep", OUTPUT, .kind = CLI_OPT_FLAG, .apply = apply_keep, .help = "both"},
    {"--write-coc", OUTPUT, FLAG(write_coc), .help = "add the CoC used (pixels) as channel 'coc'"},
    {"--preview", OUTPUT, STRING(preview, "FILE.png"),
     .help = "also write an sRGB preview (#### for sequences)"},
    {"--preview-input", OUTPUT, STRING(preview_input, "FILE.png"),
     .help = "the same for the input, to compare before and after"},
    {"--focus-map", OUTPUT, STRING(focus_map, "FILE.png"),
     .help = "also write the focal-plane view: in focus green, near blur\n"
             "orange, far blur blue (#### for sequences)"},
    {"--preview-exposure", OUTPUT, FLOAT(preview_exposure, "EV", CLI_ANY_NUMBER),
     .help = "exposure of the previews in stops (default 0)"},

    /* sequences and reporting */
    {"--frames", REPORTING, STRING(frames, "LIST"),
     .help = "e.g. 1-240, 1-240x2, 1,4,10-12; # runs in paths are frame numbers"},
    {"--jobs", "-j", REPORTING, UINT(jobs, 1, 0),
     .help = "frames in parallel (default: automatic, when it pays)"},
    {"--skip-existing", REPORTING, FLAG(skip_existing),
     .help = "resume a killed batch: skip frames whose outputs are complete\n"
             "and no older than their inputs"},
    {"--stats", REPORTING, STRING(stats_path, "FILE.json"),
     .help = "per-frame statistics and stage times"},
    {"--compare", REPORTING, STRING(compare, "TRUTH.exr"),
     .help = "print RMSE/PSNR of the result and of the input against TRUTH"},
    {"--progress", REPORTING, CHOICE(progress, cli_choices_progress),
     .help = "progress bar on stderr (auto: when it is a terminal)"},
    {"--quiet", "-q", REPORTING, FLAG(quiet), .help = "no per-frame summary"},
    {"--verbose", "-v", REPORTING, FLAG(verbose),
     .help = "per frame also the backend that ran, its renderer, why auto\n"
             "chose it, memory used, and the planner's decisions"},
    {"--help", "-h", REPORTING, .kind = CLI_OPT_HELP, .help = "this text"},
    {"--version", REPORTING, .kind = CLI_OPT_VERSION, .help = "the versions of ddof and libddof"},
};

const size_t cli_option_count = sizeof cli_option_table / sizeof cli_option_table[0];

const cli_option *cli_option_find(const char *name)
{
    size_t i;
    for (i = 0; i < cli_option_count; i++) {
        const cli_option *option = &cli_option_table[i];
        if (!strcmp(name, option->name) ||
            (option->short_name && !strcmp(name, option->short_name)) ||
            (option->alias && !strcmp(name, option->alias)))
            return option;
    }
    return NULL;
}
