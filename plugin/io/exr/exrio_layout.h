/* SPDX-License-Identifier: MIT */
/* exrio_layout.h - finding the colour, depth and CoC channels of a render in an EXR header.
 *
 * Renders name their channels by convention, not by schema. Two layouts are recognised
 * automatically:
 *  - Blender multilayer: "<view layer>.Combined.R/G/B/A" for colour and "<view layer>.Depth.Z"
 *    for depth (other passes, such as "<view layer>.DiffCol.R", are never taken for colour);
 *  - single layer: "R", "G", "B", optional "A", and depth in "Z" (or "depth", "Depth.Z", ...).
 * Everything can also be named explicitly, and when a choice is ambiguous (two view layers) the
 * error says which names to choose from rather than picking one silently. */
#ifndef DDOF_EXRIO_LAYOUT_H
#define DDOF_EXRIO_LAYOUT_H

#include "exrio.h"

#include <stddef.h>

typedef struct exrio_layout_request {
    const char *layer; /* a Blender view layer ("ViewLayer") or a part name; NULL: automatic   */
    const char *color; /* a channel prefix ("ViewLayer.Combined") or a comma-separated list of
                          3 or 4 channel names ("R,G,B,A"); NULL: automatic                    */
    const char *depth; /* the depth channel's full name; NULL: automatic                       */
    const char *coc;   /* a channel holding CoC diameters in pixels; NULL: none                */
    int need_depth;    /* 1 when the CoC is to be computed from depth                           */
    const char *exclude_layer; /* a layer (or part) never taken automatically for colour: the
                                  foreground element's, when it lives in the same file       */
} exrio_layout_request;

typedef enum exrio_layout_status {
    EXRIO_LAYOUT_OK = 0,
    EXRIO_LAYOUT_MISSING,   /* a needed channel is not there (the message lists what is)       */
    EXRIO_LAYOUT_AMBIGUOUS, /* several candidates; the message names them                     */
    EXRIO_LAYOUT_MISMATCH   /* the channels found lie in parts of different sizes               */
} exrio_layout_status;

typedef struct exrio_layout {
    int color[4];        /* channel indices into image->channels: R, G, B and A (or -1)      */
    int color_count;     /* 3 or 4                                                            */
    int depth;           /* channel index, -1 when not needed and not found                   */
    int coc;             /* channel index, -1 when none asked for                             */
    int part;            /* the part the colour comes from                                    */
    char color_prefix[256]; /* e.g. "ViewLayer.Combined", "" for plain R, G, B               */
} exrio_layout;

exrio_layout_status exrio_find_layout(const exrio_image *image,
                                      const exrio_layout_request *request, exrio_layout *layout,
                                      char *error, size_t error_size);

/* The depth channel that goes with colour prefix `color_prefix` ("" for plain R, G, B): the
 * channel called `name` when given, else "<layer>.Depth.Z", "<layer>.Z", then the plain names
 * (Z, Depth.Z, depth.Z, depth, ...), then the one "<layer>.Depth.Z" of a file with one such
 * layer, looked for in any part. -1 when there is none. Used for
 * depth that comes from a separate file. */
int exrio_find_depth(const exrio_image *image, const char *color_prefix, const char *name);

/* Writes "A, B, G, R, ViewLayer.Depth.Z" (at most `max_names` names, then "and N more") into
 * `out`: the channel list that error messages show. */
void exrio_list_channels(const exrio_image *image, int max_names, char *out, size_t out_size);

#endif
