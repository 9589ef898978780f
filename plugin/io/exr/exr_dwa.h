/* SPDX-License-Identifier: MIT */
/* exr_dwa.h - DWAA and DWAB, read and written through OpenEXR's C++ library (exr_dwa.cpp):
 * OpenEXR 3.1's C core has no DWA codec ("not yet implemented in C"); the C++ library of the
 * same package has the reference one. A C interface, so that the rest of exrio stays C. */
#ifndef DDOF_EXR_DWA_H
#define DDOF_EXR_DWA_H

#include "exrio.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Decodes part `part` of the open image (the file at image->path) into the planes of the
 * channels c of that part with fill[c] != 0 (indices into image->channels; their planes are
 * allocated, width * height values of 4 bytes), on up to `threads` threads. */
exrio_status exrio_dwa_load_part(const exrio_image *image, int part, const unsigned char *fill,
                                 unsigned threads, char *error, size_t error_size);

/* Writes spec (its compression DWAA or DWAB) as one scanline part to the open, empty,
 * seekable `fd`, as exrio_write_fd does. */
exrio_status exrio_dwa_write_fd(int fd, const char *name, const exrio_write_spec *spec,
                                char *error, size_t error_size);

/* 1 for the header attributes the writer sets itself (exr_metadata.c's list). */
int exrio_is_layout_attribute(const char *name);

#ifdef __cplusplus
}
#endif

#endif
