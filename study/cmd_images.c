/* SPDX-License-Identifier: MIT */
/* cmd_images.c - `ddof-study images`: the inputs, the band and the outputs of some
 * configurations as .npy files, for the report's crop grid. */
#include "study.h"

#include <stdio.h>
#include <stdlib.h>

static void safe_name(const char *id, char *out, size_t size)
{
    snprintf(out, size, "%s", id);
    for (char *p = out; *p; p++)
        if (*p == '/')
            *p = '_';
}

int study_cmd_images(const study_options *o, const study_config_list *list)
{
    ddof_context *shared;
    if (study_cpu_context(o, &shared) != DDOF_OK)
        return 1;
    int rc = 0;
    for (int si = 0; si < o->scene_count && !rc; si++) {
        study_scene scene;
        char error[2048] = "", dir[4200], path[4400];
        if (study_scene_load(shared, o->scenes[si], 0, &scene, error, sizeof error) != 0) {
            fprintf(stderr, "ddof-study: %s: %s\n", o->scenes[si], error);
            rc = 1;
            break;
        }
        snprintf(dir, sizeof dir, "%s/%s", o->out, scene.name);
        const uint32_t w = scene.small.width, h = scene.small.height;
        const size_t pixels = (size_t)w * h;
        float *out = malloc(pixels * 4 * sizeof(float));
        float *band = malloc(pixels * sizeof(float));
        float *smooth = malloc(pixels * sizeof(float));
        float *abs_coc = study_abs_of(scene.small.coc, pixels);
        if (!out || !band || !smooth || !abs_coc || study_mkdirs(dir) != 0) {
            fprintf(stderr, "ddof-study: cannot prepare %s\n", dir);
            rc = 1;
        }
        for (size_t i = 0; !rc && i < pixels; i++) {
            band[i] = scene.band[i];
            smooth[i] = scene.smooth[i];
        }
#define WRITE(name, data, ch)                                                                \
    do {                                                                                     \
        snprintf(path, sizeof path, "%s/%s.npy", dir, name);                                 \
        if (!rc && study_write_npy(path, data, w, h, ch) != 0) {                             \
            fprintf(stderr, "ddof-study: cannot write %s\n", path);                          \
            rc = 1;                                                                          \
        }                                                                                    \
    } while (0)
        WRITE("input_pinhole", scene.small.rgba, 4);
        WRITE("input_truth", scene.truth, 4);
        WRITE("input_coc", scene.small.coc, 1);
        WRITE("input_depth", scene.small.depth, 1);
        WRITE("input_band", band, 1);
        WRITE("input_smooth", smooth, 1);
        for (size_t i = 0; !rc && i < list->count; i++) {
            const study_config *cfg = &list->items[i];
            char name[128];
            safe_name(cfg->id, name, sizeof name);
            if (cfg->kind == STUDY_DEFOCUS) {
                if (scene.nodes[cfg->node].image)
                    WRITE(name, scene.nodes[cfg->node].image, 4);
                continue;
            }
            int owned;
            const char *why, *renderer;
            ddof_context *ctx = study_context_for(o, cfg, &owned, &why, &renderer);
            if (!ctx)
                continue;
            study_call c = {.cfg = cfg, .scene = &scene, .frame = &scene.small, .ctx = ctx,
                            .abs_coc = abs_coc, .out = out};
            ddof_status st = study_run_call(&c);
            if (st == DDOF_OK)
                WRITE(name, out, 4);
            else if (!o->quiet || (st != DDOF_ERROR_UNSUPPORTED &&
                                   st != DDOF_ERROR_BACKEND_UNAVAILABLE))
                fprintf(stderr, "ddof-study: %s %s: %s\n", scene.name, cfg->id, c.error);
            if (owned)
                ddof_context_free(ctx);
        }
#undef WRITE
        if (!o->quiet && !rc)
            printf("ddof-study: images of %s -> %s\n", scene.name, dir);
        free(out);
        free(band);
        free(smooth);
        free(abs_coc);
        study_scene_free(&scene);
    }
    ddof_context_free(shared);
    return rc;
}
