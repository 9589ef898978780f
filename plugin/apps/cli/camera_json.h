/* SPDX-License-Identifier: MIT */
/* camera_json.h - the camera sidecar (docs/design.md section 1) read into a ddof_camera.
 *
 * Schema: focal_length_mm, sensor_width_mm, sensor_fit ("AUTO" | "HORIZONTAL" | "VERTICAL"),
 * fstop, focus_distance_m, resolution [w, h], pixel_aspect, optional depth ("planar" |
 * "radial", default planar) and unit_scale_m (metres per scene unit, default 1). Unknown keys
 * are ignored, so the add-on may add its own. Parsed with cJSON, not by hand; refused with the
 * byte offset: data after the JSON value, a key written twice in one object (compared as
 * written), nesting deeper than 32 levels, a NUL byte. */
#ifndef DDOF_CLI_CAMERA_JSON_H
#define DDOF_CLI_CAMERA_JSON_H

#include <ddof.h>

#include <stddef.h>
#include <stdint.h>

typedef struct camera_sidecar {
    ddof_camera camera;
    uint32_t resolution[2]; /* 0, 0 when absent */
} camera_sidecar;

/* Reads `path` into *out (starting from ddof_camera_init's defaults). Every key of the schema
 * except depth and unit_scale_m must be present (resolution and pixel_aspect included, so
 * that a sidecar from another shot is caught). Returns 0, or -1 with a message naming the file
 * and the key. */
int camera_sidecar_read(const char *path, camera_sidecar *out, char *error, size_t error_size);

/* The same on text[0..size) (NUL-terminated at text[size]); `path` names it in messages. */
int camera_sidecar_parse(const char *text, size_t size, const char *path, camera_sidecar *out,
                         char *error, size_t error_size);

/* A value's spelling in the sidecar ("AUTO", "planar"), for writing one (the --stats camera). */
const char *camera_sidecar_fit_name(ddof_sensor_fit fit);
const char *camera_sidecar_depth_name(ddof_depth_kind kind);

#endif
