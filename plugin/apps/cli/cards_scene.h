/* SPDX-License-Identifier: MIT */
/* cards_scene.h - `ddof --cards scene.json`: a scene of textured cards (docs/cards.md).
 *
 *   {"camera": {the sidecar's keys, docs/cli.md: focal_length_mm, ..., "resolution": [w, h]},
 *    "cards": [{"image": "far.exr", "corners": [[x, y, z], [x, y, z], [x, y, z], [x, y, z]]},
 *              {"image": "leaf.png", "corners": [[x, y, z], ...], "uv": [[u, v], ...]}]}
 *
 * Corners in camera space, metres (x right, y up, looking down -z: every z < 0). Four corners
 * without "uv" are the image's bottom-left, bottom-right, top-right and top-left; 3..8 corners
 * with "uv" (0..1, (0, 0) the image's bottom-left) for any convex card. Images: EXR (linear,
 * R, G, B and A if present, premultiplied as EXR stores it) or PNG (sRGB decoded to linear,
 * alpha premultiplied). Relative paths are relative to the JSON file's folder. */
#ifndef DDOF_CLI_CARDS_SCENE_H
#define DDOF_CLI_CARDS_SCENE_H

#ifndef DDOF_EXPERIMENTAL
#define DDOF_EXPERIMENTAL 1
#endif
#include "ddof.h"

#include <stddef.h>
#include <stdint.h>
#include <sys/types.h>

/* One image file, decoded once however many cards show it. */
typedef struct cards_texture {
    char *path;              /* as resolved: the scene's folder and the card's "image" */
    dev_t device;            /* the file's identity: the same under any spelling or link */
    ino_t inode;
    float *pixels;           /* premultiplied linear RGBA */
    uint32_t width, height;
} cards_texture;

typedef struct cards_scene {
    ddof_camera camera;
    uint32_t width, height;  /* the camera's resolution: the output's size */
    ddof_card *cards;
    uint32_t count;
    cards_texture *textures; /* owned: one per distinct file, shared by the cards showing it */
    uint32_t texture_count;
} cards_scene;

/* Reads the scene and its images. Returns 0, or -1 with a message naming the file and what is
 * wrong (the library judges the geometry: cards_scene_render). */
int cards_scene_read(const char *path, cards_scene *scene, char *error, size_t error_size);

/* The input, the scene file `path` or one of its textures, that `candidate` is (the same
 * device and inode: any spelling, symbolic or hard link), or NULL (a missing candidate is no
 * input). For refusing an output that would overwrite one. */
const char *cards_scene_input_at(const cards_scene *scene, const char *path,
                                 const char *candidate);

void cards_scene_free(cards_scene *scene);

#endif
