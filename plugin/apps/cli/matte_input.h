/* SPDX-License-Identifier: MIT */
/* matte_input.h - a render's object matte (Cryptomatte) found among the input's channels, for
 * the silhouettes' split (ddof_render_frame_with_matte). */
#ifndef DDOF_CLI_MATTE_INPUT_H
#define DDOF_CLI_MATTE_INPUT_H

#include "ddof.h"
#include "exrio.h"
#include "exrio_layout.h"

#include <stddef.h>

/* The channels of the matte `name` (NULL or "auto": a layer CryptoObject or crypto_object, any
 * case, when the colour's part has one; "off": none) beside the colour (the same part and view
 * layer prefix): its sub-layers 00, 01, ... each r, g, b, a, ordered as ranks of (id,
 * coverage): 00.r, 00.g, 00.b, 00.a, 01.r, ... into index (2 * DDOF_MATTE_MAX_RANKS entries),
 * its name into found. Returns the ranks (0: no matte), or -1 with error: a named matte that is
 * not there, a sub-layer without its four channels, ids stored as half (which cannot hold
 * them). */
int matte_find(const exrio_image *image, const exrio_layout *layout, const char *name,
               int *index, char *found, size_t found_size, char *error, size_t error_size);

#endif
