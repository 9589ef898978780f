/* SPDX-License-Identifier: MIT */
/* far_layer_sink.h - where a depth slice's gather (far_field_gather.c) leaves each pixel, and
 * the rule that composites it over the slices before (far_layers.c reads the result): nearer
 * slices first, each covering what the ones before left uncovered, the farthest so far kept
 * apart for what stays uncovered at the end. */
#ifndef DDOF_FAR_LAYER_SINK_H
#define DDOF_FAR_LAYER_SINK_H

#include "runtime/float_ops.h"

#include <stddef.h>
#include <stdint.h>

#define TINY 1e-6f
#define NOT_TAKEN UINT32_MAX

struct far_layer_sink {
    uint32_t channels;    /* the frame's colour channels                              */
    const uint32_t *slot; /* per frame pixel: its place in the arrays below, or none  */
    float *acc;           /* per taken pixel: what the nearer slices gave (channels)   */
    float *last;          /* per taken pixel: the farthest slice's colour so far       */
    float *state;         /* per taken pixel: the transmittance left, nearer coverage  */
};

/* Composites one depth slice's gather (channels: colour, then coverage) at frame pixel i. */
static inline void ddof_far_layer_take(struct far_layer_sink *sink, size_t i,
                                       const float *gathered)
{
    const uint32_t channels = sink->channels, slot = sink->slot[i];
    const float cover = ddof_minf(gathered[channels], 1.0f);
    if (slot == NOT_TAKEN || !(cover > TINY))
        return;
    float *state = sink->state + (size_t)slot * 2;
    float *acc = sink->acc + (size_t)slot * channels, *last = sink->last + (size_t)slot * channels;
    const float left = 1.0f - state[1];
    const float covers = left > TINY ? ddof_minf(cover / left, 1.0f) : 1.0f;
    for (uint32_t c = 0; c < channels; c++) {
        last[c] = gathered[c] / cover;
        acc[c] += state[0] * covers * last[c];
    }
    state[0] *= 1.0f - covers;
    state[1] += cover;
}

#endif
