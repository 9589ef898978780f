/* SPDX-License-Identifier: MIT */
/* fuzz_reader.h - the fuzz targets' input as a stream of values: bytes (0 past the end), 32-bit
 * words, and floats that are plausible most of the time and raw bit patterns (NaN, infinities,
 * denormals, values near FLT_MAX) now and then. */
#ifndef DDOF_FUZZ_READER_H
#define DDOF_FUZZ_READER_H

#ifndef DDOF_EXPERIMENTAL
#define DDOF_EXPERIMENTAL 1
#endif
#include <ddof.h>

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct fuzz_reader {
    const uint8_t *data;
    size_t size, at;
} fuzz_reader;

static inline uint8_t fuzz_byte(fuzz_reader *r)
{
    return r->at < r->size ? r->data[r->at++] : 0;
}

static inline uint32_t fuzz_u32(fuzz_reader *r)
{
    uint32_t v = 0;
    for (int i = 0; i < 4; i++)
        v = v << 8 | fuzz_byte(r);
    return v;
}

/* Within +-scale most of the time; any bits now and then. */
static inline float fuzz_float(fuzz_reader *r, float scale)
{
    const uint8_t kind = fuzz_byte(r);
    if (kind < 200)
        return scale * (float)fuzz_byte(r) / 255.0f;
    if (kind < 230)
        return -scale * (float)fuzz_byte(r) / 255.0f;
    const uint32_t bits = fuzz_u32(r);
    float f;
    memcpy(&f, &bits, sizeof f);
    return f;
}

static inline int fuzz_known_status(ddof_status s)
{
    return s == DDOF_OK || ddof_status_string(s) != NULL;
}

#endif
