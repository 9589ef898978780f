/* SPDX-License-Identifier: MIT */
/* main.c - ddof-study: runs the configurations of the accuracy-vs-cost study on scene folders.
 *
 *   ddof-study run --out DIR [options] SCENE_DIR...     measure; writes DIR/results.jsonl
 *   ddof-study images --out DIR --configs LIST SCENE_DIR...
 *                                                        the images of some configurations
 *   ddof-study list [--configs LIST]                     print the configuration ids
 *
 * study/README.md says what is measured and how; report.py reads the results. This file reads
 * the command line; cmd_run.c and cmd_images.c run the commands. */
#include "study.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void usage(FILE *f)
{
    fprintf(f,
            "usage: ddof-study run --out DIR [options] SCENE_DIR...\n"
            "       ddof-study images --out DIR --configs LIST SCENE_DIR...\n"
            "       ddof-study list [--configs LIST]\n"
            "\n"
            "A scene folder holds pinhole.exr, truth.exr, camera.json and optionally fg.exr,\n"
            "pinhole_1080.exr, defocus[-4.2|-5.3].exr + .json (study/scenes/README.md).\n"
            "\n"
            "  --configs LIST     comma-separated ids and lists: full (default), smoke,\n"
            "                     baselines, cpu/thomas/f32/n4/k0.03125/auto, cod4, gather,\n"
            "                     pinhole, defocus, defocus-4.2, defocus-5.3\n"
            "  --out DIR          run: DIR/results.jsonl; images: DIR/<scene>/<id>.npy\n"
            "  --append           add to an existing results.jsonl instead of replacing it\n"
            "  --reps N           timed calls after the warm-up at the scene's size (5)\n"
            "  --large-reps N     the same at 1920x1080 (3)\n"
            "  --no-large         do not time at 1920x1080 (pinhole_1080.exr)\n"
            "  --large-limit S    skip a 1080p timing that the scene-size time predicts to\n"
            "                     take over S seconds per call (5); an estimate is recorded\n"
            "  --egl-software     measure EGL also when it finds no GPU (by default its\n"
            "                     software renderer is the one OSMesa measures already)\n"
            "  --threads N        threads of the CPU contexts (0 = all cores, the default)\n"
            "  --gl-plugin PATH   the libddof_gl to load (default: DDOF_GL_PLUGIN, beside\n"
            "                     libddof, the build tree's)\n"
            "  --no-gl            never load the GL plugin (GL configurations: not available)\n"
            "  -q                 no progress lines\n");
}

static int parse_int(const char *s, int lo, int hi, int *out)
{
    char *end;
    long v = strtol(s, &end, 10);
    if (!*s || *end || v < lo || v > hi)
        return -1;
    *out = (int)v;
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 2 || !strcmp(argv[1], "--help") || !strcmp(argv[1], "-h")) {
        usage(argc < 2 ? stderr : stdout);
        return argc < 2 ? 2 : 0;
    }
    const char *command = argv[1];
    study_options o = {.configs = NULL, .reps_small = 5, .reps_large = 3, .budget_small = 1.0,
                 .budget_large = 2.0, .large = 1, .large_limit = 5.0};
    o.scenes = calloc((size_t)argc, sizeof *o.scenes);
    if (!o.scenes)
        return 1;
    for (int i = 2; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        int n;
        if (!strcmp(a, "--out") && v) {
            o.out = v;
            i++;
        } else if (!strcmp(a, "--configs") && v) {
            o.configs = v;
            i++;
        } else if (!strcmp(a, "--gl-plugin") && v) {
            o.gl_plugin = v;
            i++;
        } else if (!strcmp(a, "--reps") && v && parse_int(v, 1, 15, &o.reps_small) == 0) {
            i++;
        } else if (!strcmp(a, "--large-reps") && v && parse_int(v, 1, 15, &o.reps_large) == 0) {
            i++;
        } else if (!strcmp(a, "--threads") && v && parse_int(v, 0, 1024, &n) == 0) {
            o.threads = (uint32_t)n;
            i++;
        } else if (!strcmp(a, "--large-limit") && v && atof(v) > 0) {
            o.large_limit = atof(v);
            i++;
        } else if (!strcmp(a, "--no-gl")) {
            o.no_gl = 1;
        } else if (!strcmp(a, "--egl-software")) {
            o.egl_software = 1;
        } else if (!strcmp(a, "--no-large")) {
            o.large = 0;
        } else if (!strcmp(a, "--append")) {
            o.append = 1;
        } else if (!strcmp(a, "-q")) {
            o.quiet = 1;
        } else if (a[0] == '-') {
            fprintf(stderr, "ddof-study: unknown or incomplete option %s\n", a);
            usage(stderr);
            return 2;
        } else {
            o.scenes[o.scene_count++] = a;
        }
    }
    study_config_list list = {0};
    char error[1024];
    if (study_config_from_spec(&list, o.configs ? o.configs : "full", error, sizeof error) != 0) {
        fprintf(stderr, "ddof-study: %s\n", error);
        return 2;
    }
    int rc;
    if (!strcmp(command, "list")) {
        for (size_t i = 0; i < list.count; i++)
            printf("%s\t%s\n", list.items[i].id, list.items[i].sweeps);
        rc = 0;
    } else if (!strcmp(command, "run") || !strcmp(command, "images")) {
        if (!o.out || o.scene_count == 0) {
            fprintf(stderr, "ddof-study %s: --out DIR and at least one scene folder are "
                    "needed\n", command);
            rc = 2;
        } else {
            rc = !strcmp(command, "run") ? study_cmd_run(&o, &list) : study_cmd_images(&o, &list);
        }
    } else {
        fprintf(stderr, "ddof-study: unknown command %s\n", command);
        usage(stderr);
        rc = 2;
    }
    study_gl_free();
    study_config_list_free(&list);
    free(o.scenes);
    return rc;
}
