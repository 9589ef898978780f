/* SPDX-License-Identifier: MIT */
/* test_exr_threads.c - chunks compressed and decompressed on several threads: for every
 * compression the C core writes, the file written on 2, 3 and 8 threads is byte for byte the
 * one written on the caller's thread alone, and that one is the file recorded below (its FNV-1a
 * hash); decoding on threads gives the same planes,
 * and a damaged chunk is reported as the same (lowest) chunk whatever the thread count.
 *
 *   test_exr_threads SCRATCH_DIR */
#include "exr_test_util.h"

#include <libdeflate.h>
#include <openexr.h>
#include <zlib.h>

#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define W 301 /* 150 rows: chunks of 1, 16 and 32 lines, the last one short */
#define H 150

static const char *dir;

static const char *const names[5] = {"B", "G", "R", "Z", "id"};
static const exrio_pixel_type types[5] = {EXRIO_HALF, EXRIO_HALF, EXRIO_HALF, EXRIO_FLOAT,
                                          EXRIO_UINT};
static float planes[4][W * H];
static int zip_level; /* what write_with() asks for */
static uint32_t ids[W * H];

/* Whose deflate a compression's bytes depend on (another version may write other bytes). */
enum deflater { OWN_BYTES, ZLIB_BYTES, LIBDEFLATE_BYTES };

/* Hashes of the files exrio wrote from fill()'s image on one thread (Debian 12: OpenEXR 3.1.5,
 * zlib 1.2.13, libdeflate 1.14), by compression; the file's size after. ZIP and ZIPS were
 * zlib's until exrio deflated them with libdeflate (exr_zip.c): 266953 and 119056 bytes then. */
static const struct {
    uint64_t hash;
    size_t size;
    enum deflater deflater;
} reference[8] = {
    {0x610e3c886d2ad94bull, 634879, OWN_BYTES},        /* none  */
    {0xc945479ef4b37a48ull, 523408, OWN_BYTES},        /* rle   */
    {0xdbcf9ea9b455464full, 267084, LIBDEFLATE_BYTES}, /* zips  */
    {0x2616a5cb3a9b8ceaull, 118369, LIBDEFLATE_BYTES}, /* zip   */
    {0x20c00280970d7ce9ull, 208324, OWN_BYTES},        /* piz   */
    {0xca65d62b7f2c73fdull, 108131, ZLIB_BYTES},       /* pxr24 */
    {0x7162f98787c175baull, 482955, OWN_BYTES},        /* b44   */
    {0x56f0537199458d9aull, 482944, OWN_BYTES},        /* b44a  */
};

/* Whether this build's deflater is the one the reference was recorded with. */
static int deflater_as_recorded(enum deflater deflater)
{
    switch (deflater) {
    case ZLIB_BYTES:
        return strcmp(zlibVersion(), "1.2.13") == 0;
    case LIBDEFLATE_BYTES:
        return strcmp(LIBDEFLATE_VERSION_STRING, "1.14") == 0;
    default:
        return 1;
    }
}

static uint64_t fnv1a(const unsigned char *p, size_t n)
{
    uint64_t h = 1469598103934665603ull;
    size_t i;
    for (i = 0; i < n; i++) {
        h ^= p[i];
        h *= 1099511628211ull;
    }
    return h;
}

/* Gradients with a little noise (so every method has something to do), a stepped depth and
 * blocky object ids. */
static void fill(void)
{
    int x, y, c;
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            const size_t i = (size_t)y * W + (size_t)x;
            const uint32_t h = (uint32_t)(x * 2654435761u) ^ (uint32_t)(y * 40503u);
            for (c = 0; c < 3; c++)
                planes[c][i] = 0.2f + 0.003f * (float)x + 0.002f * (float)y * (float)(c + 1) +
                               (float)(h % 17u) / 512.0f;
            planes[3][i] = 1.0f + (float)((x / 20 + y / 15) % 7) + 0.001f * (float)x;
            ids[i] = (uint32_t)((x / 30) * 7 + (y / 25)) * 2246822519u;
        }
    }
}

static int write_with(const char *path, exrio_compression compression, unsigned threads)
{
    exrio_write_channel channels[5];
    exrio_write_spec spec;
    char error[1024];
    int fd, c;
    exrio_status status;
    for (c = 0; c < 5; c++) {
        channels[c].name = names[c];
        channels[c].type = types[c];
        channels[c].pixels = c < 4 ? (const void *)planes[c] : (const void *)ids;
        channels[c].pixel_stride = 4;
        channels[c].line_stride = (size_t)W * 4;
    }
    memset(&spec, 0, sizeof spec);
    spec.data_window = test_box(-7, 3, W, H);
    spec.display_window = spec.data_window;
    spec.pixel_aspect = 1.0f;
    spec.compression = compression;
    spec.channel_count = 5;
    spec.channels = channels;
    spec.threads = threads;
    spec.zip_level = zip_level;
    fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0666);
    if (fd < 0)
        return -1;
    status = exrio_write_fd(fd, path, &spec, error, sizeof error);
    close(fd);
    if (status != EXRIO_OK)
        fprintf(stderr, "%s\n", error);
    return status == EXRIO_OK ? 0 : -1;
}

/* Loads every channel of `path` on `threads` threads; 0 on success. */
static int load_with(const char *path, unsigned threads, exrio_image *image, char *error,
                     size_t size)
{
    if (exrio_open(path, image, error, size) != EXRIO_OK)
        return -1;
    if (exrio_load_threads(image, NULL, threads, error, size) != EXRIO_OK) {
        exrio_close(image);
        return -1;
    }
    return 0;
}

static void same_bytes(exrio_compression compression)
{
    static const unsigned counts[] = {2, 3, 8};
    char name[64], error[1024];
    size_t size = 0, other_size = 0, i;
    unsigned char *one, *other;
    exrio_image serial, parallel;

    snprintf(name, sizeof name, "t1_%s.exr", exrio_compression_name(compression));
    CHECK(write_with(test_path(dir, name), compression, 1) == 0);
    one = (unsigned char *)test_read_file(test_path(dir, name), &size);
    if (!one) {
        CHECK(one != NULL);
        return;
    }
    if (deflater_as_recorded(reference[compression].deflater))
        CHECK_MSG(size == reference[compression].size &&
                      fnv1a(one, size) == reference[compression].hash,
                  "%s: %zu bytes, hash 0x%016llx: not the file written before", name, size,
                  (unsigned long long)fnv1a(one, size));
    for (i = 0; i < sizeof counts / sizeof counts[0]; i++) {
        char many[64];
        snprintf(many, sizeof many, "t%u_%s.exr", counts[i], exrio_compression_name(compression));
        CHECK(write_with(test_path(dir, many), compression, counts[i]) == 0);
        other = (unsigned char *)test_read_file(test_path(dir, many), &other_size);
        CHECK_MSG(other && other_size == size && memcmp(one, other, size) == 0,
                  "%s differs from %s", many, name);
        free(other);
    }
    free(one);

    /* Decoded on 1 and on 4 threads: the same planes. */
    if (load_with(test_path(dir, name), 1, &serial, error, sizeof error) != 0) {
        CHECK_MSG(0, "%s", error);
        return;
    }
    if (load_with(test_path(dir, name), 4, &parallel, error, sizeof error) != 0) {
        CHECK_MSG(0, "%s", error);
        exrio_close(&serial);
        return;
    }
    CHECK(serial.channel_count == 5 && parallel.channel_count == 5);
    for (i = 0; i < 5 && i < (size_t)serial.channel_count; i++)
        CHECK_MSG(memcmp(serial.channels[i].pixels, parallel.channels[i].pixels,
                         (size_t)W * H * 4) == 0,
                  "%s: channel %s decoded on 4 threads differs", name, serial.channels[i].name);
    /* Lossless methods give back what was written. */
    if (compression != EXRIO_COMPRESSION_PXR24 && compression != EXRIO_COMPRESSION_B44 &&
        compression != EXRIO_COMPRESSION_B44A)
        CHECK_MSG(memcmp(parallel.channels[3].pixels, planes[3], sizeof planes[3]) == 0 &&
                      memcmp(parallel.channels[4].pixels, ids, sizeof ids) == 0,
                  "%s: Z or id changed", name);
    exrio_close(&serial);
    exrio_close(&parallel);
}

/* Damages the chunks of scanlines 16 and 48 of a ZIP file (16 lines a chunk): on any thread
 * count, the error is the first of them. */
static void damaged_chunk(void)
{
    const char *path = test_path(dir, "damaged.exr");
    exr_context_t ctxt = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    exr_chunk_info_t cinfo[2];
    unsigned char *bytes;
    size_t size = 0;
    unsigned threads;
    int k;

    CHECK(write_with(path, EXRIO_COMPRESSION_ZIP, 1) == 0);
    CHECK(exr_start_read(&ctxt, path, &init) == EXR_ERR_SUCCESS);
    CHECK(exr_read_scanline_chunk_info(ctxt, 0, 3 + 16, &cinfo[0]) == EXR_ERR_SUCCESS);
    CHECK(exr_read_scanline_chunk_info(ctxt, 0, 3 + 48, &cinfo[1]) == EXR_ERR_SUCCESS);
    exr_finish(&ctxt);
    bytes = (unsigned char *)test_read_file(path, &size);
    if (!bytes) {
        CHECK(bytes != NULL);
        return;
    }
    for (k = 0; k < 2; k++)
        memset(bytes + cinfo[k].data_offset + 2, 0x55, 64);
    test_write_file(path, bytes, size);
    free(bytes);
    for (threads = 1; threads <= 8; threads *= 2) {
        exrio_image image;
        char error[2048];
        CHECK(exrio_open(path, &image, error, sizeof error) == EXRIO_OK);
        CHECK(exrio_load_threads(&image, NULL, threads, error, sizeof error) ==
              EXRIO_ERROR_CORRUPT);
        CHECK_MSG(strstr(error, "damaged.exr") && strstr(error, "scanline 19"),
                  "%u threads: %s", threads, error);
        CHECK(image.channels[0].pixels == NULL);
        exrio_close(&image);
    }
}

/* ZIP at level 1: other bytes than level 6 (the default), the same on every thread count, and
 * the same values back. */
static void zip_fast(void)
{
    size_t n1 = 0, n3 = 0, n6 = 0;
    char *fast1, *fast3, *slow;
    char error[1024];
    exrio_image image;
    zip_level = 1;
    CHECK(write_with(test_path(dir, "zip1_1.exr"), EXRIO_COMPRESSION_ZIP, 1) == 0);
    CHECK(write_with(test_path(dir, "zip1_3.exr"), EXRIO_COMPRESSION_ZIP, 3) == 0);
    zip_level = 0;
    fast1 = test_read_file(test_path(dir, "zip1_1.exr"), &n1);
    fast3 = test_read_file(test_path(dir, "zip1_3.exr"), &n3);
    slow = test_read_file(test_path(dir, "t1_zip.exr"), &n6);
    CHECK(fast1 && fast3 && slow && n1 == n3 && memcmp(fast1, fast3, n1) == 0);
    CHECK_MSG(n1 != n6 || (fast1 && slow && memcmp(fast1, slow, n1) != 0),
              "zip level 1 wrote the bytes of level 6");
    free(fast1);
    free(fast3);
    free(slow);
    if (load_with(test_path(dir, "zip1_1.exr"), 2, &image, error, sizeof error) == 0) {
        CHECK(memcmp(image.channels[3].pixels, planes[3], sizeof planes[3]) == 0 &&
              memcmp(image.channels[4].pixels, ids, sizeof ids) == 0);
        exrio_close(&image);
    } else {
        CHECK_MSG(0, "%s", error);
    }
}

int main(int argc, char **argv)
{
    int c;
    if (argc != 2) {
        fprintf(stderr, "usage: test_exr_threads SCRATCH_DIR\n");
        return 2;
    }
    dir = argv[1];
    test_fresh_dir(dir);
    fill();
    for (c = EXRIO_COMPRESSION_NONE; c <= EXRIO_COMPRESSION_B44A; c++)
        same_bytes((exrio_compression)c);
    damaged_chunk();
    zip_fast();
    return test_finish("test_exr_threads");
}
