/* SPDX-License-Identifier: MIT */
/* gl_buffers.h - the solver's GPU buffers, kept by the device between calls and grown to the
 * largest call (a sequence of frames of one size allocates once), like the CPU path's scratch. */
#ifndef DDOF_GL_BUFFERS_H
#define DDOF_GL_BUFFERS_H

#include "gl_functions.h"

#include <stdint.h>

typedef enum gl_buffer_slot {
    GL_BUF_RAW_COLOR, /* the caller's colour, CoC and gamma as they lie, one after the */
                      /* other (one upload); reused for the read-back                 */
    GL_BUF_COC,       /* |CoC| per pixel                       */
    GL_BUF_GAMMA,     /* gamma per pixel                       */
    GL_BUF_FLAGS,     /* singular-run marks per pixel          */
    GL_BUF_IMAGE_A,   /* vec4 working images: passes ping-pong */
    GL_BUF_IMAGE_B,   /* (the disc kernel's T_c: B + i C)    */
    GL_BUF_IMAGE_C,   /* Jacobi's second sweep buffer          */
    GL_BUF_WEIGHTS,   /* Thomas' back-substitution weights     */
    GL_BUF_RUNNING,   /* the disc kernel's output so far       */
    GL_BUF_PYRAMID,   /* reduced levels (CR, hybrid, Gruen)    */
    GL_BUF_COUNTERS,  /* active rows, columns, largest |CoC|   */
    GL_BUF_DUMMY,     /* bound where a kernel reads nothing    */
    GL_BUF_RANGE,     /* the disc's clamp range (8 uint keys)  */
    GL_BUF_FRAME,     /* a layered frame's one upload          */
    GL_BUF_OUT,       /* its result, read back at the end      */
    GL_BUF_MAP_A,     /* its maps (layers.c's scratch slots)   */
    GL_BUF_MAP_B,
    GL_BUF_MAP_C,
    GL_BUF_CAPACITY,
    GL_BUF_SPREAD,
    GL_BUF_LAYER,
    GL_BUF_LAYER_BLUR, /* the element's blur, beside it for the far field's gather */
    GL_BUF_FG_BASE,    /* the element without its own highlights */
    GL_BUF_CHECK,     /* a host texture's first bad pixel     */
    GL_BUF_FAR_RADIUS,  /* the far field (gl_far_field.c): its maps */
    GL_BUF_FAR_WEIGHT,
    GL_BUF_FAR_REACH,
    GL_BUF_FAR_LAYERED,
    GL_BUF_FAR_SHARP,
    GL_BUF_FAR_LEVELS,  /* image levels, prefix sums, samples   */
    GL_BUF_FAR_TABLE,   /* counts, the levels' table, the cuts  */
    GL_BUF_FAR_SINK,    /* the depth slices' composite so far   */
    GL_BUF_FAR_WORK,    /* a slice's image and box sums         */
    GL_BUF_FAR_DOUBLES, /* running sums in double               */
    GL_BUF_SIL_CLEAN,   /* the silhouettes (gl_silhouettes.c): the colour diffused */
    GL_BUF_SIL_DELTA,   /* the split's changes                  */
    GL_BUF_SIL_COUNTS,  /* pixels cleaned, pixels split         */
    GL_BUF_HL_BASE,     /* the highlights (gl_highlights.c): the colour without them */
    GL_BUF_HL_LANDING,  /* a class's landing counts             */
    GL_BUF_HL_WEIGHTS,  /* each highlight's weight              */
    GL_BUF_HL_DIFF,     /* the discs' rows' differences          */
    GL_BUF_HL_STATE,    /* running double sums                   */
    GL_BUF_HL_ITEMS,    /* the frame's highlights by size class (gl_highlights_find.c) */
    GL_BUF_HL_FG_ITEMS, /* the element's own                     */
    GL_BUF_HLF_BOUNDS,  /* the find: the class bounds' tables    */
    GL_BUF_HLF_COUNTS,  /* per chunk and class counts, offsets   */
    GL_BUF_HLF_COSTS,   /* per chunk and class costs (double)    */
    GL_BUF_HLF_FOUND,   /* the items in row order                */
    GL_BUF_HLF_PIXELS,  /* the hidden parts' marks and numbers   */
    GL_BUF_HLF_SCAN,    /* block sums                            */
    GL_BUF_HLF_MERGED,  /* the hidden parts, merged per pixel    */
    GL_BUF_HLF_KEPT,    /* those the budget keeps                */
    GL_BUF_HLF_ALL,     /* both lists in row order               */
    GL_BUF_HLF_CLASSES, /* the size classes' counts and boxes    */
    GL_BUF_NEAR_REST,   /* the near layer (gl_near_layer.c): the rest's colour, kept for */
    GL_BUF_NEAR_REST_COC, /* the layers' run, its CoC, the element (premultiplied RGBA) */
    GL_BUF_NEAR_ELEMENT,
    GL_BUF_NEAR_ELEMENT_COC, /* its |CoC|                              */
    GL_BUF_NEAR_MAPS,   /* the split's maps                      */
    GL_BUF_NEAR_PYRAMID, /* the pull-push levels                 */
    GL_BUF_NEAR_FACTS,  /* the split's figures and boxes         */
    GL_BUF_NEAR_OFF_LEVEL,  /* the offset fill: its search level    */
    GL_BUF_NEAR_OFF_BOX,    /* box sums                              */
    GL_BUF_NEAR_OFF_SEARCH, /* the search's planes and errors        */
    GL_BUF_NEAR_OFF_INTS,   /* counts, band samples, offsets to search */
    GL_BUF_COUNT
} gl_buffer_slot;

typedef struct gl_buffers {
    GLuint name[GL_BUF_COUNT];
    uint64_t capacity[GL_BUF_COUNT];
    uint64_t used[GL_BUF_COUNT]; /* what the current call asked for */
} gl_buffers;

/* Starts a call: forgets what the last call used (for the device_bytes report). */
void gl_buffers_begin(gl_buffers *buffers);
/* The buffer of `slot` with at least `bytes` bytes (contents undefined after growth); 0 on an
 * allocation failure (GL_OUT_OF_MEMORY). */
GLuint gl_buffers_get(const gl_functions *gl, gl_buffers *buffers, gl_buffer_slot slot,
                      uint64_t bytes);
/* Bytes the current call asked for, over all slots: its peak device memory. */
uint64_t gl_buffers_used(const gl_buffers *buffers);
void gl_buffers_free(const gl_functions *gl, gl_buffers *buffers);

#endif
