/* SPDX-License-Identifier: MIT */
/* gl_io.h - host-memory images in and out of the GPU (gl_io.c). */
#ifndef DDOF_GL_IO_H
#define DDOF_GL_IO_H

#include "gl_solve.h"

/* Uploads the request's colour, CoC and gamma (one mapped write) and packs them (IMAGE_A,
 * COC, GAMMA). */
int gl_io_upload(ddof_device *device, const adi_request *request, char *message, size_t size);
/* IMAGE_A into request->out in its layout. */
int gl_io_download(ddof_device *device, const adi_request *request, char *message, size_t size);

/* Floats from the first to the last one read of a strided image whose pixels are `step`
 * floats apart and of which `used` floats each are read (CoC and gamma: only the first of
 * their channels, and the pointer may be into the middle of a pixel, so no more may be read). */
uint64_t gl_span_floats(uint32_t width, uint32_t height, size_t stride, uint32_t step,
                        uint32_t used);

/* Host images, each as it lies, uploaded in one mapped write into sections of one buffer
 * (`slot`): section i gets floats[i] floats from source[i] (none where floats[i] is 0), at[i]
 * and bytes[i] set to where (sections start at the renderer's binding alignment and are bound
 * one at a time, so each must fit the storage-block limit, not the whole). Nothing is mapped
 * when every section is empty. 0 with a sentence on failure. */
int gl_io_upload_sections(ddof_device *device, gl_buffer_slot slot, int count,
                          const void *const *source, const uint64_t *floats, uint64_t *at,
                          uint64_t *bytes, char *message, size_t size);

#endif
