/* SPDX-License-Identifier: MIT */
/* focus_map.h - the focal-plane view (`ddof --focus-map OUT.png`): the frame in false colour by
 * its circle of confusion, so the focus can be checked before spending a render on it.
 *
 *   in focus  (|CoC| < DDOF_FOCUS_MAP_SHARP_PX): green
 *   near blur (CoC < 0, in front of the focus):  orange, brighter with more blur
 *   far blur  (CoC > 0, behind the focus):       blue, brighter with more blur
 *
 * Blur strength t = (|CoC| - sharp) / (largest |CoC| of the frame - sharp), clamped to 0..1,
 * gives the hue's brightness 0.35 + 0.65 t; every colour is shaded by the picture's luminance
 * (0.35 + 0.65 sqrt(Y)) so that the frame stays recognisable. An unsigned CoC (a CoC channel
 * read without --coc-signed) cannot tell near from far: all blur is shown as far. The same
 * mapping is the Blender add-on's focal-plane view (blender_addon/diffusion_dof/focus_map.py).
 *
 * A camera whose aperture is not round (blades, an anamorphic ratio, an aperture image) gets
 * its shape as a legend in the top-right corner: white inside, black around it, as a light
 * behind the focus draws it (focus_map_aperture; the add-on draws the same pixels). */
#ifndef DDOF_CLI_FOCUS_MAP_H
#define DDOF_CLI_FOCUS_MAP_H

#include "ddof.h"

#include <stddef.h>
#include <stdint.h>

#define DDOF_FOCUS_MAP_SHARP_PX 1.0f

/* 8-bit RGB of the map: coc (width * height, signed), rgb (`channels` >= 3 interleaved
 * floats, linear), rows top first; bytes: width * height * 3. */
void focus_map_pixels(const float *coc, const float *rgb, uint32_t channels, uint32_t width,
                      uint32_t height, uint8_t *bytes);

/* Draws the camera's aperture into the map's bytes as its legend: a square of min(64, the
 * smaller side / 4) pixels, 2 from the top and right edges; nothing for a round aperture
 * (blades < 3, ratio 1, no image) or a map under 48 pixels a side. */
void focus_map_aperture(const ddof_camera *camera, uint32_t width, uint32_t height,
                        uint8_t *bytes);

/* Writes the map as a PNG atomically (output_file.h), with the camera's aperture when camera
 * is not NULL. Returns 0, or -1 with a message. */
int focus_map_write(const char *path, const float *coc, const float *rgb, uint32_t channels,
                    uint32_t width, uint32_t height, const ddof_camera *camera, char *error,
                    size_t error_size);

#endif
