/* SPDX-License-Identifier: MIT */
/* scene.c - loading a study scene folder (study/scenes/README.md; samples/ has the same layout):
 *   pinhole.exr        Blender multilayer: ViewLayer.Combined.R/G/B/A + ViewLayer.Depth.Z
 *   truth.exr          the Cycles lens-DOF render, RGBA
 *   camera.json        the camera sidecar
 *   fg.exr             optional: the near objects alone (premultiplied RGBA + Depth.Z)
 *   rest.exr           optional (with fg.exr): everything but the near objects, as pinhole.exr
 *   matte.exr          optional: the pinhole render with its object matte (Cryptomatte)
 *   pinhole_1080.exr   optional: the pinhole render at 1920x1080, for timings
 *   defocus.exr/.json  optional: Blender's Defocus node on pinhole.exr, and its timing
 *   defocus_1080.json  optional: its timing at 1920x1080
 *   render.json        optional: what Blender rendered (its version is read from here)
 * and computing the signed CoC of each frame and the band around depth edges. */
#include "study.h"

#include "camera_json.h"
#include "exrio.h"
#include "exrio_layout.h"

#include <cJSON.h>

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static int fail(char *error, size_t size, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(error, size, fmt, ap);
    va_end(ap);
    return -1;
}

static int exists(const char *path)
{
    return access(path, R_OK) == 0;
}

/* Reads colour (RGBA; alpha 1 when the file has none) and, when depth_out is given, depth. */
static int read_exr(const char *path, float **rgba_out, float **depth_out, uint32_t *width,
                    uint32_t *height, char *error, size_t size)
{
    exrio_image image;
    char message[2048];
    if (exrio_open(path, &image, message, sizeof message) != EXRIO_OK)
        return fail(error, size, "%s", message);
    exrio_layout_request request;
    memset(&request, 0, sizeof request);
    request.need_depth = depth_out != NULL;
    exrio_layout layout;
    if (exrio_find_layout(&image, &request, &layout, message, sizeof message) !=
        EXRIO_LAYOUT_OK) {
        exrio_close(&image);
        return fail(error, size, "%s: %s", path, message);
    }
    unsigned char *wanted = calloc((size_t)image.channel_count, 1);
    if (!wanted) {
        exrio_close(&image);
        return fail(error, size, "out of memory");
    }
    for (int c = 0; c < layout.color_count; c++)
        wanted[layout.color[c]] = 1;
    if (depth_out)
        wanted[layout.depth] = 1;
    exrio_status st = exrio_load(&image, wanted, message, sizeof message);
    free(wanted);
    if (st != EXRIO_OK) {
        exrio_close(&image);
        return fail(error, size, "%s", message);
    }
    const exrio_part *part = &image.parts[layout.part];
    const size_t pixels = (size_t)part->width * part->height;
    float *rgba = malloc(pixels * 4 * sizeof *rgba);
    float *depth = depth_out ? malloc(pixels * sizeof *depth) : NULL;
    if (!rgba || (depth_out && !depth)) {
        free(rgba);
        free(depth);
        exrio_close(&image);
        return fail(error, size, "out of memory");
    }
    for (int c = 0; c < 4; c++) {
        if (c >= layout.color_count) {
            for (size_t i = 0; i < pixels; i++)
                rgba[i * 4 + (size_t)c] = 1.0f;
            continue;
        }
        const exrio_channel *ch = &image.channels[layout.color[c]];
        for (size_t i = 0; i < pixels; i++)
            rgba[i * 4 + (size_t)c] = ch->type == EXRIO_UINT
                                          ? (float)((const uint32_t *)ch->pixels)[i]
                                          : ((const float *)ch->pixels)[i];
    }
    if (depth_out) {
        const exrio_channel *ch = &image.channels[layout.depth];
        for (size_t i = 0; i < pixels; i++)
            depth[i] = ch->type == EXRIO_UINT ? (float)((const uint32_t *)ch->pixels)[i]
                                              : ((const float *)ch->pixels)[i];
        *depth_out = depth;
    }
    *rgba_out = rgba;
    *width = part->width;
    *height = part->height;
    exrio_close(&image);
    return 0;
}

/* The signed CoC of a frame (median time of a few runs into *seconds). */
static int compute_coc(ddof_context *ctx, const ddof_camera *camera, const float *depth,
                       uint32_t width, uint32_t height, float **coc_out, double *seconds,
                       char *error, size_t size)
{
    float *coc = malloc((size_t)width * height * sizeof *coc);
    if (!coc)
        return fail(error, size, "out of memory");
    ddof_camera cam = *camera;
    cam.signed_coc = 1;
    ddof_image_in d = {depth, width, height, 1, 0};
    ddof_image c = {coc, width, height, 1, 0};
    double t[3];
    for (int i = 0; i < 3; i++) {
        const double t0 = study_now();
        ddof_status st = ddof_coc_from_camera(ctx, &cam, &d, &c);
        t[i] = study_now() - t0;
        if (st != DDOF_OK) {
            free(coc);
            return fail(error, size, "CoC from the camera: %s: %s", ddof_status_string(st),
                        ddof_context_last_error(ctx));
        }
    }
    if (seconds)
        *seconds = study_median(t, 3);
    *coc_out = coc;
    return 0;
}

/* Nearest-neighbour resampling (the foreground element at 1080p, for timing only). */
static float *resample(const float *in, uint32_t w, uint32_t h, uint32_t channels, uint32_t W,
                       uint32_t H)
{
    float *out = malloc((size_t)W * H * channels * sizeof *out);
    if (!out)
        return NULL;
    for (uint32_t y = 0; y < H; y++) {
        const uint32_t sy = (uint32_t)((uint64_t)y * h / H);
        for (uint32_t x = 0; x < W; x++) {
            const uint32_t sx = (uint32_t)((uint64_t)x * w / W);
            memcpy(out + ((size_t)y * W + x) * channels, in + ((size_t)sy * w + sx) * channels,
                   channels * sizeof *out);
        }
    }
    return out;
}

/* A number from a JSON file; NAN when absent. */
static double json_number(const char *path, const char *key)
{
    char *text = study_read_text(path);
    if (!text)
        return NAN;
    cJSON *root = cJSON_Parse(text);
    free(text);
    double v = NAN;
    const cJSON *item = root ? cJSON_GetObjectItemCaseSensitive(root, key) : NULL;
    if (cJSON_IsNumber(item))
        v = item->valuedouble;
    cJSON_Delete(root);
    return v;
}

/* The Blender version that made the scene: render.json's files.*.blender, else defocus.json. */
static void blender_version(const char *dir, char *out, size_t size)
{
    static const char *const names[] = {"render.json", "defocus.json"};
    out[0] = '\0';
    for (size_t n = 0; n < 2 && !out[0]; n++) {
        char path[4352];
        snprintf(path, sizeof path, "%s/%s", dir, names[n]);
        char *text = study_read_text(path);
        cJSON *root = text ? cJSON_Parse(text) : NULL;
        free(text);
        const cJSON *v = cJSON_GetObjectItemCaseSensitive(root, "blender");
        const cJSON *files = cJSON_GetObjectItemCaseSensitive(root, "files");
        if (!cJSON_IsString(v) && cJSON_IsObject(files)) {
            const cJSON *f;
            cJSON_ArrayForEach(f, files)
            {
                v = cJSON_GetObjectItemCaseSensitive(f, "blender");
                if (cJSON_IsString(v))
                    break;
            }
        }
        if (cJSON_IsString(v))
            snprintf(out, size, "%s", v->valuestring);
        cJSON_Delete(root);
    }
}

/* A JSON file's top-level string `key` into out ("" when absent). */
static void json_string(const char *path, const char *key, char *out, size_t size)
{
    out[0] = '\0';
    char *text = study_read_text(path);
    cJSON *root = text ? cJSON_Parse(text) : NULL;
    free(text);
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(root, key);
    if (cJSON_IsString(v))
        snprintf(out, size, "%s", v->valuestring);
    cJSON_Delete(root);
}

/* The median of a node's timed composites in its JSON (as ddof's times are medians; "seconds"
 * is their minimum), "seconds" when there is no median; -1 when absent. */
static double node_seconds(const char *path)
{
    double t = json_number(path, "seconds_median");
    if (!isfinite(t))
        t = json_number(path, "seconds");
    return isfinite(t) ? t : -1.0;
}

/* One Blender's Defocus node: <name>.exr (absent: no node result, not an error), its times in
 * <name>.json and <name>_1080.json. 0, or -1 with a message. */
static int load_node(const char *dir, const char *name, const study_scene *s, study_node *node,
                     char *error, size_t size)
{
    char path[4352];
    uint32_t w, h;
    snprintf(path, sizeof path, "%s/%s.exr", dir, name);
    if (!exists(path))
        return 0;
    if (read_exr(path, &node->image, NULL, &w, &h, error, size) != 0)
        return -1;
    if (w != s->small.width || h != s->small.height)
        return fail(error, size, "%s is %ux%u, pinhole.exr %ux%u", path, w, h, s->small.width,
                    s->small.height);
    snprintf(path, sizeof path, "%s/%s.json", dir, name);
    node->seconds = node_seconds(path);
    json_string(path, "blender", node->blender, sizeof node->blender);
    snprintf(path, sizeof path, "%s/%s_1080.json", dir, name);
    node->seconds_large = node_seconds(path);
    return 0;
}

static void frame_free(study_frame *f)
{
    free(f->rgba);
    free(f->depth);
    free(f->coc);
    free(f->fg_rgba);
    free(f->fg_coc);
    free(f->rest_rgba);
    free(f->rest_coc);
    free(f->matte);
    memset(f, 0, sizeof *f);
}

void study_scene_free(study_scene *s)
{
    frame_free(&s->small);
    frame_free(&s->large);
    free(s->truth);
    free(s->band);
    free(s->smooth);
    free(s->silhouette);
    free(s->blurred_edges);
    for (int n = 0; n < STUDY_NODE_COUNT; n++)
        free(s->nodes[n].image);
    memset(s, 0, sizeof *s);
}

/* A layer of the small frame (RGBA and its depth) upscaled to the large frame (nearest), and
 * its CoC there; 0, or -1 with a message. */
static int upscale_layer(ddof_context *ctx, study_scene *s, const float *rgba, const float *depth,
                         float **out_rgba, float **out_coc, char *error, size_t size)
{
    const study_frame *small = &s->small, *L = &s->large;
    float *big_depth = resample(depth, small->width, small->height, 1, L->width, L->height);
    *out_rgba = resample(rgba, small->width, small->height, 4, L->width, L->height);
    const int rc = big_depth && *out_rgba
                       ? compute_coc(ctx, &s->camera, big_depth, L->width, L->height, out_coc,
                                     NULL, error, size)
                       : fail(error, size, "out of memory");
    free(big_depth);
    return rc ? -1 : 0;
}

int study_scene_load(ddof_context *ctx, const char *dir, int want_large, study_scene *s,
                     char *error, size_t size)
{
    memset(s, 0, sizeof *s);
    if (size)
        error[0] = '\0';
    for (int n = 0; n < STUDY_NODE_COUNT; n++)
        s->nodes[n].seconds = s->nodes[n].seconds_large = -1.0;
    snprintf(s->dir, sizeof s->dir, "%s", dir);
    {
        size_t n = strlen(dir);
        while (n > 1 && dir[n - 1] == '/')
            n--;
        const char *end = dir + n, *start = end;
        while (start > dir && start[-1] != '/')
            start--;
        snprintf(s->name, sizeof s->name, "%.*s", (int)(end - start), start);
    }
    char path[4352];
    uint32_t w, h;
    float *fg_depth = NULL, *rest_depth = NULL; /* the small frame's, freed on every way out */

    snprintf(path, sizeof path, "%s/camera.json", dir);
    camera_sidecar sidecar;
    if (camera_sidecar_read(path, &sidecar, error, size) != 0)
        goto failed;
    s->camera = sidecar.camera;

    snprintf(path, sizeof path, "%s/pinhole.exr", dir);
    if (read_exr(path, &s->small.rgba, &s->small.depth, &s->small.width, &s->small.height,
                 error, size) != 0)
        goto failed;
    const size_t pixels = (size_t)s->small.width * s->small.height;
    if (compute_coc(ctx, &s->camera, s->small.depth, s->small.width, s->small.height,
                    &s->small.coc, &s->seconds_coc_small, error, size) != 0)
        goto failed;

    snprintf(path, sizeof path, "%s/truth.exr", dir);
    if (read_exr(path, &s->truth, NULL, &w, &h, error, size) != 0)
        goto failed;
    if (w != s->small.width || h != s->small.height) {
        fail(error, size, "%s is %ux%u, pinhole.exr %ux%u", path, w, h, s->small.width,
             s->small.height);
        goto failed;
    }

    snprintf(path, sizeof path, "%s/fg.exr", dir);
    if (exists(path)) {
        if (read_exr(path, &s->small.fg_rgba, &fg_depth, &w, &h, error, size) != 0)
            goto failed;
        if (w != s->small.width || h != s->small.height) {
            fail(error, size, "%s is %ux%u, pinhole.exr %ux%u", path, w, h, s->small.width,
                 s->small.height);
            goto failed;
        }
        /* Transparent pixels may hold any depth (Blender writes its far value): the element's
         * CoC only counts where its alpha is > 0, so they get +inf (the sky, always valid). */
        for (size_t i = 0; i < (size_t)w * h; i++)
            if (!(s->small.fg_rgba[i * 4 + 3] > 0.0f))
                fg_depth[i] = INFINITY;
        if (compute_coc(ctx, &s->camera, fg_depth, w, h, &s->small.fg_coc, NULL, error, size))
            goto failed;
    }

    snprintf(path, sizeof path, "%s/rest.exr", dir);
    if (s->small.fg_rgba && exists(path)) {
        if (read_exr(path, &s->small.rest_rgba, &rest_depth, &w, &h, error, size) != 0 ||
            w != s->small.width || h != s->small.height ||
            compute_coc(ctx, &s->camera, rest_depth, w, h, &s->small.rest_coc, NULL, error,
                        size) != 0) {
            if (!error[0])
                fail(error, size, "%s is %ux%u, pinhole.exr %ux%u", path, w, h,
                     s->small.width, s->small.height);
            goto failed;
        }
    }

    snprintf(path, sizeof path, "%s/matte.exr", dir);
    if (exists(path) && study_read_matte(path, s->small.width, s->small.height, &s->small.matte,
                                         &s->small.matte_ranks, error, size) != 0)
        goto failed;

    s->band = malloc(pixels);
    if (!s->band) {
        fail(error, size, "out of memory");
        goto failed;
    }
    s->band_pixels = study_band(s->small.coc, s->small.width, s->small.height, s->band);
    s->smooth = malloc(pixels);
    if (!s->smooth) {
        fail(error, size, "out of memory");
        goto failed;
    }
    s->smooth_pixels = study_smooth(s->small.coc, s->small.rgba, s->truth, s->small.width,
                                    s->small.height, s->smooth);
    s->silhouette = malloc(pixels);
    if (!s->silhouette) {
        fail(error, size, "out of memory");
        goto failed;
    }
    s->silhouette_pixels =
        study_silhouettes(s->small.coc, s->small.width, s->small.height, s->silhouette);
    s->blurred_edges = malloc(pixels);
    if (!s->blurred_edges) {
        fail(error, size, "out of memory");
        goto failed;
    }
    s->blurred_edge_pixels =
        study_blurred_edges(s->small.coc, s->small.width, s->small.height, s->blurred_edges);
    for (size_t i = 0; i < pixels; i++)
        s->max_abs_coc = fmaxf(s->max_abs_coc, fabsf(s->small.coc[i]));

    snprintf(path, sizeof path, "%s/pinhole_1080.exr", dir);
    if (want_large && exists(path)) {
        study_frame *L = &s->large;
        if (read_exr(path, &L->rgba, &L->depth, &L->width, &L->height, error, size) != 0 ||
            compute_coc(ctx, &s->camera, L->depth, L->width, L->height, &L->coc,
                        &s->seconds_coc_large, error, size) != 0)
            goto failed;
        /* No 1080p renders of the element and the rest: the small ones upscaled, for timing. */
        if (s->small.fg_rgba) {
            L->fg_resampled = 1;
            if (upscale_layer(ctx, s, s->small.fg_rgba, fg_depth, &L->fg_rgba, &L->fg_coc,
                              error, size) != 0)
                goto failed;
        }
        if (s->small.rest_rgba && upscale_layer(ctx, s, s->small.rest_rgba, rest_depth,
                                                &L->rest_rgba, &L->rest_coc, error, size) != 0)
            goto failed;
        /* The matte likewise: ids are copied, never blended. */
        if (s->small.matte) {
            L->matte_ranks = s->small.matte_ranks;
            if (!(L->matte = resample(s->small.matte, s->small.width, s->small.height,
                                      2 * L->matte_ranks, L->width, L->height))) {
                fail(error, size, "out of memory");
                goto failed;
            }
        }
    }

    for (int n = 0; n < STUDY_NODE_COUNT; n++)
        if (load_node(dir, study_node_names[n], s, &s->nodes[n], error, size) != 0)
            goto failed;
    blender_version(dir, s->blender, sizeof s->blender);
    free(fg_depth);
    free(rest_depth);
    return 0;

failed:
    free(fg_depth);
    free(rest_depth);
    study_scene_free(s);
    return -1;
}
