/* SPDX-License-Identifier: MIT */
/* gather_blur.h - a naive gather depth-of-field blur, the baseline of the accuracy study
 * (docs/accuracy.md): the post-filter of Potmesil and Chakravarty (1981) at its simplest.
 *
 * Each output pixel is the uniform average of the input pixels whose centres lie within the
 * disk of its own CoC: pixel (x + i, y + j) is in when i^2 + j^2 <= (|CoC| / 2)^2, and only
 * pixels inside the image count (the average is over what the clipped disk holds). There is no
 * depth test and no weighting by the neighbours' CoC, on purpose: in-focus objects bleed into
 * the blurred background around them, and a blurred foreground object keeps a sharp silhouette
 * while gathering the background into its own edge (see README.md).
 *
 * Not part of libddof: plain C11 + pthreads + libm, no dependencies. */
#ifndef DDOF_STUDY_GATHER_BLUR_H
#define DDOF_STUDY_GATHER_BLUR_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Error codes of ddof_gather_blur (0 is success). */
#define DDOF_GATHER_OK 0
#define DDOF_GATHER_BAD_ARGUMENT (-1) /* NULL pointer, zero size, channels outside 1..16,   */
                                      /* width * height * channels overflows, or a CoC that */
                                      /* is NaN or infinite (out is then untouched)         */
#define DDOF_GATHER_OUT_OF_MEMORY (-2) /* out untouched                                     */

/* rgba: width x height pixels of `channels` interleaved floats, tightly packed (the name says
 * RGBA, which is what the study passes; any 1..16 channels work, every channel is averaged).
 * coc_px: one float per pixel, the CoC diameter in pixels; its sign is ignored (signed near-
 * field CoC works as is); any finite size (a disk larger than the image averages the part
 * inside). out: the same layout as rgba; it may be rgba itself (in place).
 * threads: how many threads share the rows (0 or 1: the caller's thread only); if a thread
 * cannot be started its rows run on the caller's thread. The result does not depend on it.
 * Cost: O(min(|CoC|, height)) per pixel (row spans of the disk summed from per-row prefix sums
 * in double), working memory (width + 1) * height * channels doubles. */
int ddof_gather_blur(const float *rgba, const float *coc_px, uint32_t width, uint32_t height,
                     uint32_t channels, float *out, uint32_t threads);

#ifdef __cplusplus
}
#endif

#endif
