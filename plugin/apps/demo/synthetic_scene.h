/* SPDX-License-Identifier: MIT */
/* synthetic_scene.h - a small pinhole "render" made in code, so ddof-demo needs no input files.
 *
 * A brick wall with string lights 30 m away under a strip of sky, a tiled ground receding towards
 * it, a Siemens-star target and three striped bars at 4 m (the subject), a striped post at
 * ~1.2 m cutting into the right edge and a ball at ~1.5 m rising from the bottom-left. Colour is
 * linear RGB, supersampled; the lights are HDR (about 20). Depth is planar Z in metres from the
 * centre of each pixel (not anti-aliased, like Blender's Depth pass); the sky is +inf. */
#ifndef DDOF_DEMO_SYNTHETIC_SCENE_H
#define DDOF_DEMO_SYNTHETIC_SCENE_H

#include <stdint.h>

#define DEMO_SCENE_SUBJECT_DISTANCE_M 4.0 /* the target and the bars */
#define DEMO_SCENE_NEAR_DISTANCE_M 1.2    /* the front of the post   */
#define DEMO_SCENE_WALL_DISTANCE_M 30.0   /* the wall behind it all  */

typedef struct demo_scene {
    uint32_t width;
    uint32_t height;
    float *color; /* width * height * 3 floats, linear RGB, top row first */
    float *depth; /* width * height floats, planar metres, +inf for the sky */
} demo_scene;

/* Renders the scene through a pinhole camera at the origin looking along +Z whose sensor width
 * spans the image width (Blender's AUTO fit for landscape images). Returns 0 on success; -1 if
 * memory ran out, with the scene left empty. */
int demo_scene_render(demo_scene *scene, uint32_t width, uint32_t height, double focal_length_mm,
                      double sensor_width_mm);

/* Frees what demo_scene_render allocated; accepts an empty scene. */
void demo_scene_free(demo_scene *scene);

#endif
