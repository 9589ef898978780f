/* SPDX-License-Identifier: MIT */
/* cmd_run.c - `ddof-study run`: every configuration on every scene into results.jsonl (a
 * machine line, a line per scene, a line per measurement, a closing line). */
#include "study.h"

#include <cJSON.h>

#include <stdio.h>
#include <stdlib.h>
#include <sys/resource.h>

static cJSON *scene_json(const study_scene *s)
{
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "type", "scene");
    cJSON_AddStringToObject(j, "scene", s->name);
    cJSON_AddStringToObject(j, "dir", s->dir);
    cJSON_AddNumberToObject(j, "width", s->small.width);
    cJSON_AddNumberToObject(j, "height", s->small.height);
    cJSON_AddNumberToObject(j, "large_width", s->large.width);
    cJSON_AddNumberToObject(j, "large_height", s->large.height);
    cJSON_AddNumberToObject(j, "max_abs_coc_px", (double)s->max_abs_coc);
    cJSON_AddBoolToObject(j, "blurred", s->max_abs_coc >= 1.0f);
    cJSON_AddNumberToObject(j, "band_pixels", (double)s->band_pixels);
    cJSON_AddNumberToObject(j, "band_fraction",
                            (double)s->band_pixels / ((double)s->small.width * s->small.height));
    cJSON_AddNumberToObject(j, "smooth_pixels", (double)s->smooth_pixels);
    cJSON_AddNumberToObject(j, "smooth_fraction",
                            (double)s->smooth_pixels / ((double)s->small.width * s->small.height));
    cJSON_AddNumberToObject(j, "silhouette_pixels", (double)s->silhouette_pixels);
    cJSON_AddNumberToObject(j, "blurred_edge_pixels", (double)s->blurred_edge_pixels);
    cJSON_AddBoolToObject(j, "fg_element", s->small.fg_rgba != NULL);
    cJSON_AddBoolToObject(j, "rest_image", s->small.rest_rgba != NULL);
    cJSON_AddBoolToObject(j, "fg_resampled_large", s->large.fg_resampled);
    cJSON_AddNumberToObject(j, "coc_ms", s->seconds_coc_small * 1e3);
    cJSON_AddNumberToObject(j, "coc_ms_large", s->seconds_coc_large * 1e3);
    cJSON_AddStringToObject(j, "blender", s->blender);
    cJSON *cam = cJSON_AddObjectToObject(j, "camera");
    cJSON_AddNumberToObject(cam, "focal_length_mm", s->camera.focal_length_mm);
    cJSON_AddNumberToObject(cam, "fstop", s->camera.fstop);
    cJSON_AddNumberToObject(cam, "focus_distance_m", s->camera.focus_distance_m);
    cJSON_AddNumberToObject(cam, "sensor_width_mm", s->camera.sensor_width_mm);
    return j;
}

static int write_line(FILE *f, cJSON *j)
{
    char *text = cJSON_PrintUnformatted(j);
    cJSON_Delete(j);
    if (!text)
        return -1;
    int ok = fprintf(f, "%s\n", text) > 0 && fflush(f) == 0;
    cJSON_free(text);
    return ok ? 0 : -1;
}

int study_cmd_run(const study_options *o, const study_config_list *list)
{
    char path[4200];
    if (study_mkdirs(o->out) != 0) {
        fprintf(stderr, "ddof-study: cannot create %s\n", o->out);
        return 1;
    }
    snprintf(path, sizeof path, "%s/results.jsonl", o->out);
    FILE *f = fopen(path, o->append ? "a" : "w");
    if (!f) {
        fprintf(stderr, "ddof-study: cannot write %s\n", path);
        return 1;
    }
    const double t_start = study_now();
    if (write_line(f, study_machine_json(o)) != 0)
        goto io_error;
    ddof_context *shared;
    if (study_cpu_context(o, &shared) != DDOF_OK) {
        fclose(f);
        return 1;
    }
    const size_t total = list->count * (size_t)o->scene_count;
    size_t done = 0;
    int failures = 0;
    for (int si = 0; si < o->scene_count; si++) {
        study_scene scene;
        char error[2048] = "";
        const double t_load = study_now();
        if (study_scene_load(shared, o->scenes[si], o->large, &scene, error, sizeof error) != 0) {
            fprintf(stderr, "ddof-study: %s: %s\n", o->scenes[si], error);
            failures++;
            done += list->count;
            continue;
        }
        if (!o->quiet)
            printf("ddof-study: %s: %ux%u%s, CoC up to %.1f px, band %.1f%% of the image, "
                   "smooth far field %.1f%%%s%s (loaded in %.1f s)\n",
                   scene.name, scene.small.width, scene.small.height,
                   scene.large.width ? " + 1920x1080" : "", (double)scene.max_abs_coc,
                   100.0 * (double)scene.band_pixels /
                       ((double)scene.small.width * scene.small.height),
                   100.0 * (double)scene.smooth_pixels /
                       ((double)scene.small.width * scene.small.height),
                   scene.small.fg_rgba ? ", foreground element" : "",
                   scene.nodes[0].image || scene.nodes[1].image || scene.nodes[2].image
                       ? ", Defocus node(s)"
                       : "",
                   study_now() - t_load);
        if (write_line(f, scene_json(&scene)) != 0)
            goto io_error;
        const size_t ps = (size_t)scene.small.width * scene.small.height;
        const size_t pl = (size_t)scene.large.width * scene.large.height;
        float *out_small = malloc(ps * 4 * sizeof(float));
        float *out_large = pl ? malloc(pl * 4 * sizeof(float)) : NULL;
        float *abs_small = study_abs_of(scene.small.coc, ps);
        float *abs_large = pl ? study_abs_of(scene.large.coc, pl) : NULL;
        if (!out_small || !abs_small || (pl && (!out_large || !abs_large))) {
            fprintf(stderr, "ddof-study: out of memory\n");
            free(out_small);
            free(out_large);
            free(abs_small);
            free(abs_large);
            study_scene_free(&scene);
            fclose(f);
            ddof_context_free(shared);
            return 1;
        }
        for (size_t i = 0; i < list->count; i++) {
            char summary[1300], label[128];
            const double t0 = study_now();
            cJSON *r = study_measure(o, shared, &scene, &list->items[i], out_small, out_large,
                               abs_small, abs_large, summary, sizeof summary);
            cJSON_AddNumberToObject(r, "seconds_measuring", study_now() - t0);
            if (write_line(f, r) != 0)
                goto io_error;
            done++;
            study_config_label(&list->items[i], label, sizeof label);
            if (!o->quiet) {
                printf("[%zu/%zu] %s %s: %s\n", done, total, scene.name, label, summary);
                fflush(stdout);
            }
        }
        study_references_clear();
        free(out_small);
        free(out_large);
        free(abs_small);
        free(abs_large);
        study_scene_free(&scene);
    }
    {
        struct rusage ru;
        getrusage(RUSAGE_SELF, &ru);
        cJSON *d = cJSON_CreateObject();
        cJSON_AddStringToObject(d, "type", "done");
        cJSON_AddNumberToObject(d, "seconds", study_now() - t_start);
        cJSON_AddNumberToObject(d, "peak_rss_bytes", (double)ru.ru_maxrss * 1024.0);
        cJSON_AddNumberToObject(d, "scene_failures", failures);
        cJSON_AddNumberToObject(d, "seconds_references", study_references_seconds());
        if (write_line(f, d) != 0)
            goto io_error;
    }
    ddof_context_free(shared);
    if (fclose(f) != 0) {
        fprintf(stderr, "ddof-study: cannot write %s\n", path);
        return 1;
    }
    if (!o->quiet)
        printf("ddof-study: %zu measurements in %.1f s -> %s\n", done, study_now() - t_start,
               path);
    return failures ? 1 : 0;

io_error:
    fprintf(stderr, "ddof-study: cannot write %s\n", path);
    fclose(f);
    return 1;
}
