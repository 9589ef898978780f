/* camera_json.c - reading the camera sidecar JSON with cJSON. */
#include "camera_json.h"

#include <cJSON.h>

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* A sidecar is a few hundred bytes; anything past this is not one. */
#define MAX_SIDECAR_BYTES (1u << 20)

static char *read_text(const char *path, char *error, size_t error_size)
{
    FILE *f = fopen(path, "rb");
    char *text;
    size_t n;
    if (!f) {
        snprintf(error, error_size, "%s: cannot open camera file: %s", path, strerror(errno));
        return NULL;
    }
    text = malloc(MAX_SIDECAR_BYTES + 1);
    if (!text) {
        fclose(f);
        snprintf(error, error_size, "%s: out of memory", path);
        return NULL;
    }
    n = fread(text, 1, MAX_SIDECAR_BYTES + 1, f);
    if (ferror(f) || n > MAX_SIDECAR_BYTES) {
        snprintf(error, error_size, "%s: %s", path,
                 ferror(f) ? "cannot read camera file" : "too large for a camera sidecar");
        fclose(f);
        free(text);
        return NULL;
    }
    fclose(f);
    text[n] = '\0';
    return text;
}

static int number(const cJSON *root, const char *key, int required, double *out,
                  const char *path, char *error, size_t error_size)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(root, key);
    if (!item) {
        if (!required)
            return 0;
        snprintf(error, error_size, "%s: missing \"%s\"", path, key);
        return -1;
    }
    if (!cJSON_IsNumber(item) || !isfinite(item->valuedouble) || !(item->valuedouble > 0.0)) {
        snprintf(error, error_size, "%s: \"%s\" must be a number > 0", path, key);
        return -1;
    }
    *out = item->valuedouble;
    return 0;
}

static int choice(const cJSON *root, const char *key, int required, const char *const *names,
                  int count, int *out, const char *path, char *error, size_t error_size)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(root, key);
    int i;
    if (!item) {
        if (!required)
            return 0;
        snprintf(error, error_size, "%s: missing \"%s\"", path, key);
        return -1;
    }
    if (cJSON_IsString(item)) {
        for (i = 0; i < count; i++) {
            if (strcasecmp(item->valuestring, names[i]) == 0) {
                *out = i;
                return 0;
            }
        }
    }
    snprintf(error, error_size, "%s: \"%s\" must be one of \"%s\", \"%s\"%s%s%s", path, key,
             names[0], names[1], count > 2 ? ", \"" : "", count > 2 ? names[2] : "",
             count > 2 ? "\"" : "");
    return -1;
}

static int resolution(const cJSON *root, uint32_t out[2], const char *path, char *error,
                      size_t error_size)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(root, "resolution");
    int i;
    if (!item) {
        snprintf(error, error_size, "%s: missing \"resolution\"", path);
        return -1;
    }
    if (!cJSON_IsArray(item) || cJSON_GetArraySize(item) != 2)
        goto bad;
    for (i = 0; i < 2; i++) {
        const cJSON *v = cJSON_GetArrayItem(item, i);
        if (!cJSON_IsNumber(v) || !(v->valuedouble >= 1.0) || v->valuedouble > 1e6 ||
            v->valuedouble != floor(v->valuedouble))
            goto bad;
        out[i] = (uint32_t)v->valuedouble;
    }
    return 0;
bad:
    snprintf(error, error_size, "%s: \"resolution\" must be [width, height] in whole pixels",
             path);
    return -1;
}

int camera_sidecar_read(const char *path, camera_sidecar *out, char *error, size_t error_size)
{
    static const char *const fits[] = {"AUTO", "HORIZONTAL", "VERTICAL"};
    static const char *const depths[] = {"planar", "radial"};
    char *text;
    cJSON *root;
    int fit = 0, depth = 0, rc = -1;

    memset(out, 0, sizeof *out);
    ddof_camera_init(&out->camera);
    text = read_text(path, error, error_size);
    if (!text)
        return -1;
    root = cJSON_Parse(text);
    if (!root) {
        const char *at = cJSON_GetErrorPtr();
        long offset = at && at >= text ? (long)(at - text) : -1;
        snprintf(error, error_size, "%s: not valid JSON (near byte %ld)", path, offset);
        free(text);
        return -1;
    }
    if (!cJSON_IsObject(root)) {
        snprintf(error, error_size, "%s: the camera sidecar must be a JSON object", path);
        goto done;
    }
    if (number(root, "focal_length_mm", 1, &out->camera.focal_length_mm, path, error,
               error_size) ||
        number(root, "sensor_width_mm", 1, &out->camera.sensor_width_mm, path, error,
               error_size) ||
        choice(root, "sensor_fit", 1, fits, 3, &fit, path, error, error_size) ||
        number(root, "fstop", 1, &out->camera.fstop, path, error, error_size) ||
        number(root, "focus_distance_m", 1, &out->camera.focus_distance_m, path, error,
               error_size) ||
        resolution(root, out->resolution, path, error, error_size) ||
        number(root, "pixel_aspect", 1, &out->camera.pixel_aspect, path, error, error_size) ||
        choice(root, "depth", 0, depths, 2, &depth, path, error, error_size) ||
        number(root, "unit_scale_m", 0, &out->camera.depth_unit_m, path, error, error_size))
        goto done;
    out->camera.sensor_fit = (ddof_sensor_fit)fit;
    out->camera.depth_kind = depth ? DDOF_DEPTH_RADIAL : DDOF_DEPTH_PLANAR;
    rc = 0;
done:
    cJSON_Delete(root);
    free(text);
    return rc;
}
