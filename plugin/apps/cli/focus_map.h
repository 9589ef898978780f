/* SPDX-License-Identifier: MIT */
/* focus_map.h - the focal-plane view as a file (`ddof --focus-map OUT.png`): the library's
 * ddof_focus_map (ddof.h: the frame in false colour by its CoC, the aperture's legend), the
 * same call the Blender add-on's view makes, written as a PNG. */
#ifndef DDOF_CLI_FOCUS_MAP_H
#define DDOF_CLI_FOCUS_MAP_H

#include "ddof.h"

#include <stddef.h>
#include <stdint.h>

/* Writes the map of coc (width * height, signed) over rgb (`channels` >= 3 interleaved linear
 * floats, rows top first) as a PNG atomically (output_file.h), with the camera's aperture as
 * its legend when camera is not NULL. Returns 0, or -1 with a message. */
int focus_map_write(ddof_context *context, const char *path, const float *coc, const float *rgb,
                    uint32_t channels, uint32_t width, uint32_t height,
                    const ddof_camera *camera, char *error, size_t error_size);

#endif
