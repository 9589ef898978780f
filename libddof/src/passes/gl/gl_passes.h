/* SPDX-License-Identifier: MIT */
/* gl_passes.h - the passes on the device, on images that already lie in device buffers: the
 * cone dilation (gl_cone_dilate.c, cone_dilate.comp), the far field (gl_far_field.c,
 * far_field.comp), the silhouettes' split (gl_silhouettes.c, silhouettes.comp) and the
 * highlights' take-out and discs (gl_highlights.c, highlights.comp). */
#ifndef DDOF_GL_PASSES_H
#define DDOF_GL_PASSES_H

#include "gl_solve.h"

#include "ddof_highlight_rules.h"

/* ../cone_dilate.c on the map in `buffer`: the box at `base` (floats), rows `stride` apart,
 * both passes. 0 with a sentence in message on failure. */
int gl_cone_dilate(ddof_device *device, GLuint buffer, uint32_t base, uint32_t width,
                   uint32_t height, uint32_t stride, float slope, char *message,
                   size_t message_size);

/* The far field of a frame whose layers' result lies in `out` (width x channels floats a row,
 * blended in place), with ../far_field.h's meaning for each field. */
typedef struct gl_far_field_request {
    uint32_t width, height, channels;
    gl_image_ref color; /* what the layers diffused: stride floats a row, channels a pixel */
    gl_image_ref coc;   /* the frame's signed CoC: stride floats a row, step a pixel         */
    GLuint out;
    float in_focus_px, pixel_aspect;
    int slices;         /* gather where two blurred surfaces meet in depth slices           */
} gl_far_field_request;

/* ../far_field.h's far_field_report. */
typedef struct gl_far_field_report {
    uint64_t pixels, layered_pixels;
    uint32_t slices, levels;
} gl_far_field_report;

/* Runs it: the maps, the depth slices and the gathers on the device; the host reads only the
 * counts that size the next step (a few bytes, and the cuts' counters). 0 with a sentence in
 * message on failure. */
int gl_far_field(ddof_device *device, const gl_far_field_request *q, gl_far_field_report *report,
                 char *message, size_t message_size);

/* The silhouettes of a frame (../silhouettes.h), with its meaning for each field. */
typedef struct gl_silhouettes_request {
    uint32_t width, height, channels; /* 3 or 4 channels */
    gl_image_ref color; /* the colour before the clean: stride floats a row, channels a pixel */
    gl_image_ref coc;   /* the frame's signed CoC: stride floats a row, step a pixel          */
    gl_image_ref matte; /* the object matte's (id, coverage) pairs, `ranks` a pixel; buffer 0:
                         * none (the shares from the colours)                                  */
    uint32_t ranks;
    float in_focus_px;
} gl_silhouettes_request;

/* ddof_clean_silhouettes: the colour the layers diffuse into `cleaned` (width x channels
 * floats a row). 0 with a sentence in message on failure. */
int gl_clean_silhouettes(ddof_device *device, const gl_silhouettes_request *q, GLuint cleaned,
                         char *message, size_t message_size);

/* ddof_split_silhouettes on the result in `out` (width x channels floats a row), in place;
 * *pixels: the mixed pixels split (4 bytes read back). 0 with a sentence on failure. */
int gl_split_silhouettes(ddof_device *device, const gl_silhouettes_request *q, GLuint out,
                         uint64_t *pixels, char *message, size_t message_size);

/* ---- the near layer ---------------------------------------------------------------------- */

/* ../near_layer.h's split of the request's frame on the device (gl_near_layer.c): the images
 * stay in the NEAR slots (the rest, its CoC, the element, its |CoC|, the alpha it carries in
 * the maps) for the layers' run; `split` gets the figures and boxes, its images ADI_ON_DEVICE.
 * 0 with a sentence on failure; with *declined 1 the device does not take this frame (lines
 * longer than a software renderer walks) and the CPU splits it. */
int gl_split_near(ddof_device *device, const adi_near_request *q, adi_near_split *split,
                  int *declined, char *message, size_t message_size);

/* The alpha the element carries: a plane of the NEAR_MAPS slot (floats; near_layer.comp's
 * CARRIED). */
static inline uint32_t gl_near_carried_at(uint32_t width, uint32_t height)
{
    return width * height;
}

/* ---- the highlights ---------------------------------------------------------------------- */

/* A size class of highlights (highlights_draw.c): its place in the sorted list, where its
 * light lands, and the box its shapes cover. */
typedef struct gl_highlight_class {
    uint32_t first, count;
    float threshold;
    int reach_rows, reach_x; /* its largest half height and half width */
    int bx0, bx1, by0, by1;
} gl_highlight_class;

#define GL_HIGHLIGHT_CLASSES (DDOF_HIGHLIGHT_SIZE_CLASSES + 1)

/* The aperture the highlights are drawn with, for pixel aspect `aspect`. */
ddof_highlight_shape gl_highlight_shape(const adi_highlights *h, float aspect);

/* Finding a frame's or an element's highlights on the device (gl_highlights_find.c,
 * ../highlights_find.c's rules). */
typedef struct gl_find_request {
    uint32_t width, height;
    gl_image_ref color;  /* its colour: stride floats a row, step (3 or 4) a pixel          */
    gl_image_ref coc;    /* its CoC: stride floats a row, step a pixel                      */
    uint32_t owner;      /* highlights.h's highlight_owner: 1 the frame (the hidden parts
                          * too), 0 an element premultiplied, 2 an element straight          */
    uint32_t coc_signed, area; /* area: an aperture image (a highlight costs its area)     */
    float threshold, aspect;
    gl_buffer_slot sorted; /* where the items go, by size class                           */
} gl_find_request;

/* What it found (highlights.h's highlight_set's figures) and the classes' table. */
typedef struct gl_found {
    uint32_t count, hidden, over_budget;
    float threshold;
    uint64_t cost;
    gl_highlight_class classes[GL_HIGHLIGHT_CLASSES];
} gl_found;

/* Finds them: the host reads only counts (the classes' totals, which the budget chooses from
 * on the host with the CPU's rule; the entries and the parts kept; the classes' table). 0 with
 * a sentence in message on failure. */
int gl_find_highlights(ddof_device *device, const gl_find_request *q, gl_found *found,
                       char *message, size_t message_size);

/* A frame's highlights on the device: the upload's sections and what the find made. */
typedef struct gl_highlights_request {
    uint32_t width, height, channels;
    gl_image_ref color;  /* the colour they come out of: stride floats a row, channels a pixel */
    gl_image_ref coc;    /* the frame's CoC: stride floats a row, step a pixel                */
    gl_image_ref items;  /* the highlights by size class (gl_find_highlights)                  */
    gl_image_ref shape;  /* the ddof_highlight_shape                                           */
    gl_image_ref sums;   /* the aperture image's table (doubles); buffer 0: none              */
    uint32_t count, coc_signed;
    const gl_highlight_class *classes;
} gl_highlights_request;

/* The colour with the highlights' excess taken out into `base` (width x channels floats a
 * row). 0 with a sentence in message on failure. */
int gl_take_out_highlights(ddof_device *device, const gl_highlights_request *q, GLuint base,
                           char *message, size_t message_size);

/* The highlights drawn into `out` (width x channels floats a row). 0 with a sentence on
 * failure. */
int gl_draw_highlights(ddof_device *device, const gl_highlights_request *q, GLuint out,
                       char *message, size_t message_size);

#endif
