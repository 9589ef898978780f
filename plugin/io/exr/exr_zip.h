/* SPDX-License-Identifier: MIT */
/* exr_zip.h - ZIP and ZIPS chunks deflated with libdeflate instead of OpenEXR 3.1's zlib. */
#ifndef DDOF_EXR_ZIP_H
#define DDOF_EXR_ZIP_H

#include <openexr.h>

struct libdeflate_compressor;

/* One writer thread's ZIP encoder; `level` is zlib's scale (1 fastest .. 9 smallest, 0: 6).
 * NULL when out of memory. */
struct libdeflate_compressor *exrio_zip_compressor(int level);
void exrio_zip_compressor_free(struct libdeflate_compressor *compressor);

/* The encode pipeline's compress step for ZIP and ZIPS: OpenEXR's byte split and predictor,
 * then a zlib stream from libdeflate; a chunk whose stream is not smaller than its raw bytes is
 * stored raw, as readers expect. The encoder's buffers are allocated through its alloc_fn,
 * which must be set (exr_encoding_destroy frees them through its free_fn). */
exr_result_t exrio_zip_compress(exr_encode_pipeline_t *encoder,
                                struct libdeflate_compressor *compressor);

#endif
