/* SPDX-License-Identifier: MIT */
/* exrio.h - OpenEXR input and output for ddof's tools, on OpenEXR's C core API (OpenEXRCore).
 *
 * What it does and why it is shaped this way:
 *  - Reading is two steps. exrio_open() parses the header only (parts, channels, windows,
 *    compression) so that a caller can find the channels it needs (exrio_layout.h) and list
 *    the others in an error message; exrio_load() then decodes just the channels asked for.
 *    A render with thirty AOVs costs the time of the three or four channels ddof uses.
 *  - Every decoded channel is one plane of 32-bit values covering its part's data window,
 *    rows top first: float for HALF and FLOAT channels (half converts to float exactly), uint32
 *    for UINT channels (kept bit-exact so that pass-through channels such as object ids survive).
 *  - Scanline and tiled parts are read (tiled: level 0 only); deep parts and subsampled
 *    channels are reported, not guessed at.
 *  - Writing makes one scanline part from caller-owned channel planes (any pixel and line
 *    stride, so an interleaved RGBA buffer is written without copying), as HALF, FLOAT or UINT,
 *    with any compression. It writes to an already open file descriptor: the caller owns the
 *    temporary file and its rename (see plugin/apps/cli/output_file.h).
 *  - Chunks are compressed and decompressed on as many threads as the caller gives, through the
 *    C core's chunk API (written in file order: the bytes do not depend on the thread count).
 *    DWAA/DWAB, which OpenEXR 3.1's C core cannot code, go through OpenEXR's C++ library
 *    (exr_dwa.cpp) and its thread pool.
 *  - Functions return an exrio_status and fill a one-line message; the library never prints.
 */
#ifndef DDOF_EXRIO_H
#define DDOF_EXRIO_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum exrio_status {
    EXRIO_OK = 0,
    EXRIO_ERROR_MISSING,     /* the file does not exist (or a path component is missing)      */
    EXRIO_ERROR_ACCESS,      /* the file exists but cannot be opened or read (permissions, dir) */
    EXRIO_ERROR_NOT_EXR,     /* no OpenEXR magic number: some other kind of file                */
    EXRIO_ERROR_UNSUPPORTED, /* valid EXR that this reader cannot decode (deep, subsampled)     */
    EXRIO_ERROR_CORRUPT,     /* header or pixel data damaged or truncated                       */
    EXRIO_ERROR_WRITE,       /* writing failed (disk full, I/O error)                           */
    EXRIO_ERROR_ARGUMENT,    /* the caller asked for something impossible                       */
    EXRIO_ERROR_MEMORY       /* out of memory                                                   */
} exrio_status;

/* Pixel types, numbered as in the file format (and as OpenEXR's exr_pixel_type_t). */
typedef enum exrio_pixel_type {
    EXRIO_UINT = 0,
    EXRIO_HALF = 1,
    EXRIO_FLOAT = 2
} exrio_pixel_type;

/* Compression methods, numbered as in the file format (and as OpenEXR's exr_compression_t). */
typedef enum exrio_compression {
    EXRIO_COMPRESSION_NONE = 0,
    EXRIO_COMPRESSION_RLE = 1,
    EXRIO_COMPRESSION_ZIPS = 2,
    EXRIO_COMPRESSION_ZIP = 3,
    EXRIO_COMPRESSION_PIZ = 4,
    EXRIO_COMPRESSION_PXR24 = 5,
    EXRIO_COMPRESSION_B44 = 6,
    EXRIO_COMPRESSION_B44A = 7,
    EXRIO_COMPRESSION_DWAA = 8,
    EXRIO_COMPRESSION_DWAB = 9,
    EXRIO_COMPRESSION_COUNT_
} exrio_compression;

/* An inclusive pixel rectangle, as EXR's box2i: width = max_x - min_x + 1. */
typedef struct exrio_box {
    int32_t min_x, min_y, max_x, max_y;
} exrio_box;

typedef struct exrio_part {
    char *name;                  /* NULL when a single-part file has no name                */
    exrio_box data_window;       /* the pixels stored                                        */
    exrio_box display_window;    /* the frame they belong to                                 */
    uint32_t width, height;      /* of the data window                                       */
    exrio_compression compression;
    int tiled;                   /* 1 for tiled parts                                        */
    int deep;                    /* 1 for deep parts (not decodable here)                    */
    float pixel_aspect;          /* pixelAspectRatio attribute                               */
} exrio_part;

typedef struct exrio_channel {
    char *name;                  /* full name as stored, e.g. "ViewLayer.Combined.R"        */
    int part;                    /* index into exrio_image.parts                             */
    exrio_pixel_type type;       /* as stored in the file                                    */
    int32_t x_sampling, y_sampling;
    /* After exrio_load(): width * height values of the part's data window, rows top first:
     * float for HALF/FLOAT, uint32_t for UINT. NULL when not loaded. Owned by the image. */
    void *pixels;
} exrio_channel;

typedef struct exrio_image {
    char *path;
    int part_count;
    exrio_part *parts;
    int channel_count;
    exrio_channel *channels;     /* in file order: by part, then alphabetical                */
    void *source_;               /* private: the open OpenEXR read context                   */
} exrio_image;

/* "none", "rle", "zips", "zip", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab"; "?" if unknown. */
const char *exrio_compression_name(exrio_compression compression);
/* Parses one of those names (case-insensitive); returns 0 or -1. */
int exrio_compression_parse(const char *name, exrio_compression *out);
/* 1 when exrio can decode (and, separately, encode) this compression: every one the format
 * defines, DWAA/DWAB through OpenEXR's C++ library. */
int exrio_compression_can_decode(exrio_compression compression);
int exrio_compression_can_encode(exrio_compression compression);
/* 1 for DWAA and DWAB. */
int exrio_compression_is_dwa(exrio_compression compression);
/* "uint", "half", "float". */
const char *exrio_pixel_type_name(exrio_pixel_type type);

/* Opens `path` and reads its header. On success *image describes it (no pixels yet); on
 * failure *image is empty and `error` says what is wrong with the file, naming it. */
exrio_status exrio_open(const char *path, exrio_image *image, char *error, size_t error_size);

/* Decodes the channels whose `wanted[i]` is non-zero (all when wanted is NULL). Channels that
 * are subsampled or in deep parts fail with EXRIO_ERROR_UNSUPPORTED;
 * truncated or damaged data with EXRIO_ERROR_CORRUPT. Already loaded channels are kept. */
exrio_status exrio_load(exrio_image *image, const unsigned char *wanted, char *error,
                        size_t error_size);

/* The same, with `threads` threads decoding chunks (the caller's included; 0 and 1: the
 * caller's only). A damaged chunk is reported as the lowest-numbered one, whatever the count. */
exrio_status exrio_load_threads(exrio_image *image, const unsigned char *wanted, unsigned threads,
                                char *error, size_t error_size);

/* Index of the channel called `name` (in `part`, or in any part when part < 0); -1 if none. */
int exrio_find_channel(const exrio_image *image, const char *name, int part);

/* Frees everything and closes the file. Accepts an empty or already freed image. */
void exrio_close(exrio_image *image);

/* One channel to write: `name`, the type to store, and where its values are: the value of
 * pixel (x, y) of the data window is at pixels + y * line_stride + x * pixel_stride (bytes),
 * a float for HALF/FLOAT output and a uint32_t for UINT output. */
typedef struct exrio_write_channel {
    const char *name;
    exrio_pixel_type type;
    const void *pixels;
    size_t pixel_stride;
    size_t line_stride;
} exrio_write_channel;

typedef struct exrio_write_spec {
    exrio_box data_window;
    exrio_box display_window;
    float pixel_aspect;                   /* 0 means 1                                        */
    exrio_compression compression;
    int channel_count;
    const exrio_write_channel *channels;
    /* Optional: copy the header attributes of this part of this (open) image, except those
     * that describe the layout (channels, windows, compression, tiles, ...). */
    const exrio_image *metadata_from;
    int metadata_part;
    /* Threads that compress chunks (the caller's included); 0 and 1: the caller's only. The
     * file is the same byte for byte whatever the count. */
    unsigned threads;
    /* DWAA/DWAB only: the compression level (OpenEXR's dwaCompressionLevel); 0 means its
     * default, 45. */
    float dwa_level;
    /* ZIP/ZIPS only: the deflate level, 1 (fastest) to 9 (smallest) as zlib counts them; 0
     * means 6. libdeflate deflates (exr_zip.c). */
    int zip_level;
} exrio_write_spec;

/* Writes one scanline part to the open, empty, seekable file `fd` (it is not closed). `name`
 * is used in messages only. */
exrio_status exrio_write_fd(int fd, const char *name, const exrio_write_spec *spec, char *error,
                            size_t error_size);

#ifdef __cplusplus
}
#endif

#endif
