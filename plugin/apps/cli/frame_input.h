/* SPDX-License-Identifier: MIT */
/* frame_input.h - a frame's inputs: the EXR opened and its channels found (colour, depth or
 * CoC), the planes loaded as floats and interleaved colour, the depth file and the foreground
 * element; and the refusals that depend on the input file. */
#ifndef DDOF_CLI_FRAME_INPUT_H
#define DDOF_CLI_FRAME_INPUT_H

#include "exrio.h"
#include "exrio_layout.h"
#include "frame.h"

#include <stddef.h>

/* The foreground element's buffers: interleaved premultiplied RGBA, and its depth or CoC. */
typedef struct foreground_data {
    float *color;         /* 4 channels, owned                                              */
    const float *depth;   /* its depth plane (camera/curve CoC); may point into the image  */
    const float *coc;     /* its CoC plane (--coc-channel)                                  */
    float *owned;         /* a converted uint plane, when one was needed                    */
} foreground_data;

/* One frame's images between reading, computing and writing. */
typedef struct frame_data {
    exrio_image image, depth_image, fg_image;
    exrio_layout layout;
    const exrio_part *part;       /* the colour's part of image                             */
    size_t pixels;
    float *color;                 /* interleaved colour channels, owned                     */
    const float *depth, *coc_in;  /* the depth plane (camera, curve) or the CoC channel       */
    float *depth_owned, *coc_owned; /* converted planes, when the channel was not float     */
    foreground_data fg;
    float *out;                   /* the result, owned                                      */
    float *coc;                   /* the CoC the library used (--write-coc), owned          */
    int matte_index[2 * DDOF_MATTE_MAX_RANKS]; /* the object matte's channels, by rank      */
    int matte_ranks;              /* 0: none                                                */
    float *matte;                 /* interleaved (id, coverage) ranks, owned                */
    unsigned io_threads;          /* threads that decode and encode the EXR: the context's   */
} frame_data;

/* Opens the input and finds its channels (colour, depth or CoC); names them in result.
 * Returns 0 or -1 (result->error). */
int frame_input_open(const frame_setup *setup, const frame_paths *paths, frame_data *d,
                     frame_result *result);
/* Loads the channels the frame needs (and those --keep-channels carries over), the depth file
 * and the foreground element. Returns 0 or -1 (result->error). */
int frame_input_load(const frame_setup *setup, const frame_paths *paths, frame_data *d,
                     frame_result *result);
/* Frees what open and load made; d may be half filled (zeroed before open). */
void frame_data_free(frame_data *d);

/* --keep-channels on a multipart input: refused (-1, error says why), since the other parts
 * would be dropped. Returns 0 otherwise. */
int frame_check_input_parts(const cli_options *options, const exrio_image *image,
                            const char *path, char *error, size_t error_size);

/* Interleaves channels `index[0..count)` into a new buffer of count floats per pixel (UINT
 * channels converted); NULL when out of memory. */
float *frame_interleave(const exrio_image *image, const int *index, int count, size_t pixels);
/* 1 when the two windows are the same box. */
int frame_same_window(const exrio_box *a, const exrio_box *b);

#endif
