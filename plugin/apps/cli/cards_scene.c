/* SPDX-License-Identifier: MIT */
/* cards_scene.c - reading `ddof --cards scene.json` (cards_scene.h). */
#include "cards_scene.h"

#include "camera_json.h"
#include "exrio.h"
#include "input_file.h"
#include "json_strict.h"

#include <cJSON.h>
#include <png.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

/* A scene of a card a few hundred bytes long: this is tens of thousands of cards, far past what
 * one frame draws; a larger file is not a scene (and would be read whole into memory). */
#define MAX_SCENE_BYTES (64u << 20)

/* A path relative to the scene file's folder. */
static void resolve_path(const char *scene_path, const char *name, char *out, size_t size)
{
    const char *slash = strrchr(scene_path, '/');
    if (name[0] == '/' || !slash)
        snprintf(out, size, "%s", name);
    else
        snprintf(out, size, "%.*s/%s", (int)(slash - scene_path), scene_path, name);
}

static int ends_with(const char *s, const char *suffix)
{
    const size_t n = strlen(s), m = strlen(suffix);
    return n >= m && strcasecmp(s + n - m, suffix) == 0;
}

static float srgb_to_linear(float v)
{
    return v <= 0.04045f ? v / 12.92f : powf((v + 0.055f) / 1.055f, 2.4f);
}

/* A PNG as premultiplied linear RGBA floats. */
static float *read_png(const char *path, uint32_t *w, uint32_t *h, char *error, size_t size)
{
    png_image image;
    FILE *f = input_file_open(path, "card texture", error, size);
    if (!f)
        return NULL;
    memset(&image, 0, sizeof image);
    image.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_stdio(&image, f)) {
        snprintf(error, size, "%s: not a readable PNG (%s)", path, image.message);
        fclose(f);
        return NULL;
    }
    image.format = PNG_FORMAT_RGBA;
    uint8_t *bytes = malloc(PNG_IMAGE_SIZE(image));
    float *rgba = bytes ? malloc((size_t)image.width * image.height * 4 * sizeof *rgba) : NULL;
    if (!rgba || !png_image_finish_read(&image, NULL, bytes, 0, NULL)) {
        snprintf(error, size, "%s: %s", path, rgba ? image.message : "out of memory");
        png_image_free(&image);
        fclose(f);
        free(bytes);
        free(rgba);
        return NULL;
    }
    fclose(f);
    for (size_t i = 0; i < (size_t)image.width * image.height; i++) {
        const float a = bytes[i * 4 + 3] / 255.0f;
        for (int c = 0; c < 3; c++)
            rgba[i * 4 + c] = srgb_to_linear(bytes[i * 4 + c] / 255.0f) * a;
        rgba[i * 4 + 3] = a;
    }
    *w = image.width;
    *h = image.height;
    free(bytes);
    return rgba;
}

/* Which of R, G, B, A (index: their channels, -1 absent) is stored as UINT, or -1. */
static int uint_texture_channel(const exrio_image *image, const int index[4])
{
    for (int c = 0; c < 4; c++)
        if (index[c] >= 0 && image->channels[index[c]].type == EXRIO_UINT)
            return c;
    return -1;
}

/* An EXR's R, G, B (and A, else 1) as interleaved floats. */
static float *read_exr(const char *path, uint32_t *w, uint32_t *h, char *error, size_t size)
{
    static const char *const names[4] = {"R", "G", "B", "A"};
    exrio_image image;
    float *rgba = NULL;
    int index[4], c;
    if (input_file_open_exr(path, "card texture", &image, error, size) != EXRIO_OK)
        return NULL;
    unsigned char *wanted = calloc((size_t)image.channel_count + 1, 1);
    for (c = 0; c < 4; c++) {
        index[c] = exrio_find_channel(&image, names[c], 0);
        if (index[c] >= 0 && wanted)
            wanted[index[c]] = 1;
    }
    const int uint_channel = uint_texture_channel(&image, index);
    if (index[0] < 0 || index[1] < 0 || index[2] < 0) {
        snprintf(error, size, "%s: a card image needs channels R, G and B", path);
    } else if (uint_channel >= 0) {
        snprintf(error, size, "%s: channel %s is UINT (whole numbers such as ids, not a "
                 "colour); a card image's R, G, B and A are half or float", path,
                 names[uint_channel]);
    } else if (!wanted) {
        snprintf(error, size, "out of memory");
    } else if (exrio_load(&image, wanted, error, size) == EXRIO_OK) {
        const exrio_part *part = &image.parts[0];
        const size_t n = (size_t)part->width * part->height;
        rgba = malloc(n * 4 * sizeof *rgba);
        if (!rgba)
            snprintf(error, size, "out of memory");
        for (size_t i = 0; rgba && i < n; i++)
            for (c = 0; c < 4; c++)
                rgba[i * 4 + (size_t)c] =
                    index[c] >= 0 ? ((const float *)image.channels[index[c]].pixels)[i] : 1.0f;
        *w = part->width;
        *h = part->height;
    }
    free(wanted);
    exrio_close(&image);
    return rgba;
}

/* n numbers of an array item into out; 0, or -1 when it is not an array of n numbers. */
static int numbers(const cJSON *item, int n, float *out)
{
    if (!cJSON_IsArray(item) || cJSON_GetArraySize(item) != n)
        return -1;
    for (int i = 0; i < n; i++) {
        const cJSON *v = cJSON_GetArrayItem(item, i);
        if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble))
            return -1;
        out[i] = (float)v->valuedouble;
    }
    return 0;
}

/* The texture of file `file` from the scene's list, decoded and added when no card showed that
 * file (by identity: "a.png" and "./a.png" are one) before. */
static const cards_texture *texture_for(cards_scene *scene, const char *file, char *error,
                                        size_t size)
{
    cards_texture *t = &scene->textures[scene->texture_count];
    struct stat st;
    const int known = stat(file, &st) == 0;
    for (uint32_t i = 0; known && i < scene->texture_count; i++)
        if (scene->textures[i].device == st.st_dev && scene->textures[i].inode == st.st_ino)
            return &scene->textures[i];
    memset(t, 0, sizeof *t);
    t->pixels = ends_with(file, ".png") ? read_png(file, &t->width, &t->height, error, size)
                                        : read_exr(file, &t->width, &t->height, error, size);
    if (!t->pixels)
        return NULL;
    t->path = strdup(file);
    if (!t->path) {
        free(t->pixels);
        snprintf(error, size, "out of memory");
        return NULL;
    }
    /* The identity of the file read: stat again, since the reader may have seen another one. */
    if (stat(file, &st) == 0) {
        t->device = st.st_dev;
        t->inode = st.st_ino;
    }
    scene->texture_count++;
    return t;
}

static int read_card(const char *path, const cJSON *item, int k, ddof_card *card,
                     cards_scene *scene, char *error, size_t size)
{
    static const float corner_uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const cJSON *image = cJSON_GetObjectItemCaseSensitive(item, "image");
    const cJSON *corners = cJSON_GetObjectItemCaseSensitive(item, "corners");
    const cJSON *uv = cJSON_GetObjectItemCaseSensitive(item, "uv");
    const int n = cJSON_IsArray(corners) ? cJSON_GetArraySize(corners) : 0;
    char file[4096];
    const cards_texture *texture;
    if (!cJSON_IsObject(item) || !cJSON_IsString(image)) {
        snprintf(error, size, "%s: card %d needs \"image\" (a file name)", path, k);
        return -1;
    }
    if (n < 3 || n > (int)DDOF_CARD_MAX_VERTICES || (n != 4 && !uv)) {
        snprintf(error, size, "%s: card %d needs \"corners\": 4 [x, y, z] (the image's "
                 "corners), or 3..%d with \"uv\"", path, k, (int)DDOF_CARD_MAX_VERTICES);
        return -1;
    }
    if (uv && (!cJSON_IsArray(uv) || cJSON_GetArraySize(uv) != n)) {
        snprintf(error, size, "%s: card %d: \"uv\" must hold one [u, v] per corner", path, k);
        return -1;
    }
    memset(card, 0, sizeof *card);
    card->vertex_count = (uint32_t)n;
    for (int i = 0; i < n; i++) {
        if (numbers(cJSON_GetArrayItem(corners, i), 3, card->position[i]) != 0 ||
            (uv ? numbers(cJSON_GetArrayItem(uv, i), 2, card->uv[i]) != 0
                : (memcpy(card->uv[i], corner_uv[i], sizeof card->uv[i]), 0))) {
            snprintf(error, size, "%s: card %d, corner %d: not [x, y, z] (and [u, v]) of finite "
                     "numbers", path, k, i);
            return -1;
        }
    }
    resolve_path(path, image->valuestring, file, sizeof file);
    texture = texture_for(scene, file, error, size);
    if (!texture)
        return -1;
    card->texture = (ddof_image_in){texture->pixels, texture->width, texture->height, 4, 0};
    return 0;
}

int cards_scene_read(const char *path, cards_scene *scene, char *error, size_t error_size)
{
    size_t size = 0;
    char *text =
        input_file_read_text(path, "cards scene", MAX_SCENE_BYTES, &size, error, error_size);
    cJSON *root = text ? json_strict_parse(text, size, path, "a cards scene is {\"camera\": "
                                           "{...}, \"cards\": [...]}", error, error_size)
                       : NULL;
    int rc = -1;
    memset(scene, 0, sizeof *scene);
    const cJSON *camera = root ? cJSON_GetObjectItemCaseSensitive(root, "camera") : NULL;
    const cJSON *cards = root ? cJSON_GetObjectItemCaseSensitive(root, "cards") : NULL;
    if (root && (!cJSON_IsObject(camera) || !cJSON_IsArray(cards) ||
                 cJSON_GetArraySize(cards) < 1)) {
        snprintf(error, error_size, "%s: a cards scene is {\"camera\": {...}, \"cards\": [...]} "
                 "with at least one card", path);
    } else if (root) {
        /* The camera object is a sidecar of its own: printed and read by the sidecar's rules. */
        char *camera_text = cJSON_PrintUnformatted(camera);
        camera_sidecar sidecar;
        if (camera_text && camera_sidecar_parse(camera_text, strlen(camera_text), path,
                                                &sidecar, error, error_size) == 0) {
            scene->camera = sidecar.camera;
            scene->width = sidecar.resolution[0];
            scene->height = sidecar.resolution[1];
            scene->count = (uint32_t)cJSON_GetArraySize(cards);
            scene->cards = calloc(scene->count, sizeof *scene->cards);
            scene->textures = calloc(scene->count, sizeof *scene->textures);
            rc = scene->cards && scene->textures ? 0 : -1;
            if (rc != 0)
                snprintf(error, error_size, "out of memory");
            for (uint32_t k = 0; rc == 0 && k < scene->count; k++)
                rc = read_card(path, cJSON_GetArrayItem(cards, (int)k), (int)k,
                               &scene->cards[k], scene, error, error_size);
        }
        free(camera_text);
    }
    cJSON_Delete(root);
    free(text);
    if (rc != 0)
        cards_scene_free(scene);
    return rc;
}

const char *cards_scene_input_at(const cards_scene *scene, const char *path,
                                 const char *candidate)
{
    struct stat st, in;
    if (stat(candidate, &st) != 0)
        return NULL;
    if (stat(path, &in) == 0 && in.st_dev == st.st_dev && in.st_ino == st.st_ino)
        return path;
    for (uint32_t i = 0; i < scene->texture_count; i++)
        if (scene->textures[i].device == st.st_dev && scene->textures[i].inode == st.st_ino)
            return scene->textures[i].path;
    return NULL;
}

void cards_scene_free(cards_scene *scene)
{
    for (uint32_t k = 0; scene->textures && k < scene->texture_count; k++) {
        free(scene->textures[k].path);
        free(scene->textures[k].pixels);
    }
    free(scene->textures);
    free(scene->cards);
    memset(scene, 0, sizeof *scene);
}
