/* SPDX-License-Identifier: MIT */
/* camera_json.c - reading the camera sidecar JSON with cJSON. */
#include "camera_json.h"

#include "input_file.h"
#include "json_strict.h"

#include <cJSON.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* A sidecar is a few hundred bytes; anything past this is not one. */
#define MAX_SIDECAR_BYTES (1u << 20)

/* An optional finite number of any sign (the aperture's blades, rotation and cat's eye: the
 * library judges their ranges). */
static int finite_number(const cJSON *root, const char *key, double *out, const char *path,
                         char *error, size_t error_size)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(root, key);
    if (!item)
        return 0;
    if (!cJSON_IsNumber(item) || !isfinite(item->valuedouble)) {
        snprintf(error, error_size, "%s: \"%s\" must be a finite number", path, key);
        return -1;
    }
    *out = item->valuedouble;
    return 0;
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
    if (!cJSON_IsNumber(item)) {
        snprintf(error, error_size, "%s: \"%s\" must be a number > 0", path, key);
        return -1;
    }
    if (!isfinite(item->valuedouble)) { /* cJSON reads 1e999 as infinity */
        snprintf(error, error_size, "%s: \"%s\" is larger than a double can hold; it must be "
                 "a finite number > 0", path, key);
        return -1;
    }
    if (!(item->valuedouble > 0.0)) {
        snprintf(error, error_size, "%s: \"%s\" is %.9g%s; it must be a number > 0", path,
                 key, item->valuedouble,
                 item->valuedouble == 0.0 ? " (or closer to 0 than a double can hold)" : "");
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

/* The sidecar's spellings, in the order of ddof_sensor_fit and ddof_depth_kind. */
static const char *const fits[] = {"AUTO", "HORIZONTAL", "VERTICAL"};
static const char *const depths[] = {"planar", "radial"};

const char *camera_sidecar_fit_name(ddof_sensor_fit fit)
{
    return (unsigned)fit < 3u ? fits[fit] : "?";
}

const char *camera_sidecar_depth_name(ddof_depth_kind kind)
{
    return (unsigned)kind < 2u ? depths[kind] : "?";
}

int camera_sidecar_parse(const char *text, size_t size, const char *path, camera_sidecar *out,
                         char *error, size_t error_size)
{
    cJSON *root;
    int fit = 0, depth = 0, rc = -1;
    double blades = 0.0;

    memset(out, 0, sizeof *out);
    ddof_camera_init(&out->camera);
    root = json_strict_parse(text, size, path, "a camera sidecar is one object of numbers, "
                             "strings and [width, height]", error, error_size);
    if (!root)
        return -1;
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
        number(root, "unit_scale_m", 0, &out->camera.depth_unit_m, path, error, error_size) ||
        finite_number(root, "aperture_blades", &blades, path, error, error_size) ||
        finite_number(root, "aperture_rotation_deg", &out->camera.aperture_rotation_deg, path,
                      error, error_size) ||
        number(root, "aperture_ratio", 0, &out->camera.aperture_ratio, path, error,
               error_size) ||
        finite_number(root, "aperture_catseye", &out->camera.aperture_catseye, path, error,
                      error_size))
        goto done;
    if (!(blades >= 0.0 && blades <= DDOF_MAX_APERTURE_BLADES && blades == floor(blades))) {
        snprintf(error, error_size, "%s: \"aperture_blades\" must be a whole number within "
                 "0..%u (0: round)", path, DDOF_MAX_APERTURE_BLADES);
        goto done;
    }
    out->camera.aperture_blades = (uint32_t)blades;
    out->camera.sensor_fit = (ddof_sensor_fit)fit;
    out->camera.depth_kind = depth ? DDOF_DEPTH_RADIAL : DDOF_DEPTH_PLANAR;
    rc = 0;
done:
    cJSON_Delete(root);
    return rc;
}

int camera_sidecar_read(const char *path, camera_sidecar *out, char *error, size_t error_size)
{
    size_t size = 0;
    char *text =
        input_file_read_text(path, "camera file", MAX_SIDECAR_BYTES, &size, error, error_size);
    int rc;
    memset(out, 0, sizeof *out);
    ddof_camera_init(&out->camera);
    if (!text)
        return -1;
    rc = camera_sidecar_parse(text, size, path, out, error, error_size);
    free(text);
    return rc;
}
