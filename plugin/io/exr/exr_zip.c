/* SPDX-License-Identifier: MIT */
/* exr_zip.c - ZIP and ZIPS chunks deflated with libdeflate.
 *
 * OpenEXR 3.1's C core deflates with zlib; 3.2 and later deflate with libdeflate. At level 6
 * libdeflate takes 2.3x less CPU than zlib for streams of the same size (docs/benchmarks.md),
 * and a batch of frames on a few cores is bound by that CPU. The stream is a standard zlib
 * stream that every EXR reader inflates; only the bytes differ from zlib's. */
#include "exr_zip.h"

#include <libdeflate.h>
#include <stdint.h>
#include <string.h>

struct libdeflate_compressor *exrio_zip_compressor(int level)
{
    return libdeflate_alloc_compressor(level > 0 ? level : 6);
}

void exrio_zip_compressor_free(struct libdeflate_compressor *compressor)
{
    libdeflate_free_compressor(compressor);
}

/* Grows one of the encoder's buffers to `size` bytes through its allocator. */
static exr_result_t reserve(exr_encode_pipeline_t *encoder, exr_transcoding_pipeline_buffer_id_t id,
                            void **buffer, size_t *allocated, size_t size)
{
    if (*buffer && *allocated >= size)
        return EXR_ERR_SUCCESS;
    if (*buffer && *allocated > 0)
        encoder->free_fn(id, *buffer);
    *buffer = encoder->alloc_fn(id, size);
    *allocated = *buffer ? size : 0;
    return *buffer ? EXR_ERR_SUCCESS : EXR_ERR_OUT_OF_MEMORY;
}

/* OpenEXR's ZIP layout: the even bytes, then the odd ones, then each byte as the difference to
 * the one before it (plus 128), so that the slowly varying high bytes of neighbours deflate
 * well. */
static void split_and_predict(const uint8_t *raw, size_t n, uint8_t *out)
{
    uint8_t *even = out, *odd = out + (n + 1) / 2;
    size_t i;
    int previous;
    for (i = 0; i + 1 < n; i += 2) {
        *even++ = raw[i];
        *odd++ = raw[i + 1];
    }
    if (i < n)
        *even = raw[i];
    previous = out[0];
    for (i = 1; i < n; i++) {
        int value = out[i];
        out[i] = (uint8_t)(value - previous + 128 + 256);
        previous = value;
    }
}

exr_result_t exrio_zip_compress(exr_encode_pipeline_t *encoder,
                                struct libdeflate_compressor *compressor)
{
    size_t n = (size_t)encoder->packed_bytes, written;
    exr_result_t rv;

    if (!encoder->alloc_fn || !encoder->free_fn)
        return EXR_ERR_INVALID_ARGUMENT;
    rv = reserve(encoder, EXR_TRANSCODE_BUFFER_SCRATCH1, &encoder->scratch_buffer_1,
                 &encoder->scratch_alloc_size_1, n);
    if (rv == EXR_ERR_SUCCESS)
        rv = reserve(encoder, EXR_TRANSCODE_BUFFER_COMPRESSED, &encoder->compressed_buffer,
                     &encoder->compressed_alloc_size, n);
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    split_and_predict(encoder->packed_buffer, n, encoder->scratch_buffer_1);
    /* A stream must be shorter than the raw chunk: a chunk of exactly the raw size is read as
     * uncompressed. libdeflate returns 0 when the stream does not fit in n - 1 bytes. */
    written = n > 1 ? libdeflate_zlib_compress(compressor, encoder->scratch_buffer_1, n,
                                               encoder->compressed_buffer, n - 1)
                    : 0;
    if (written == 0) {
        memcpy(encoder->compressed_buffer, encoder->packed_buffer, n);
        written = n;
    }
    encoder->compressed_bytes = written;
    return EXR_ERR_SUCCESS;
}
