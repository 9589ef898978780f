/* SPDX-License-Identifier: MIT */
/* test_exr_roundtrip.c - what exrio writes, it reads back: every pixel type with every
 * compression the C core encodes (bit-exact where the compression is lossless, within its
 * documented loss where not), windows that do not start at the origin, interleaved input,
 * partial loads, tiled files and multi-part files written with the C core API directly, and
 * header attributes carried over by --keep-metadata's copy, and chunks that do not compress.
 *
 * Files written by OpenEXR's C++ library (tests/exr/data, see its README) read as it wrote them.
 *
 *   test_exr_roundtrip SCRATCH_DIR DATA_DIR */
#include "exr_test_util.h"

#include <openexr.h>

#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define W 37 /* odd sizes: chunks of 1, 16 and 32 lines and 4x4 blocks all end part-way */
#define H 41

static const char *dir;
static const char *data_dir;

/* Values a type can hold exactly: halves are multiples of 1/64 in (-32, 32) (11 bits), floats
 * are anything finite (including tiny and huge), uints use all 32 bits. `smooth` gives a gentle
 * gradient instead, for the lossy methods. */
static void fill(exrio_pixel_type type, int channel, int smooth, void *plane)
{
    uint32_t x, y;
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            const size_t i = (size_t)y * W + x;
            const uint32_t h = (x * 2654435761u) ^ (y * 40503u) ^ ((uint32_t)channel * 977u);
            if (type == EXRIO_UINT)
                ((uint32_t *)plane)[i] = smooth ? x * 1000u + y : h * 2246822519u;
            else if (smooth)
                ((float *)plane)[i] = 0.25f + 0.01f * (float)x + 0.005f * (float)y +
                                      0.1f * (float)channel;
            else if (type == EXRIO_HALF)
                ((float *)plane)[i] = (float)((int)(h % 4095u) - 2047) / 64.0f;
            else
                ((float *)plane)[i] = (float)((double)(int32_t)h * 1e-3 *
                                              pow(10.0, (double)(h % 13u) - 6.0));
        }
    }
}

/* Compression x type combinations the format defines as lossless. */
static int lossless(exrio_compression c, exrio_pixel_type t)
{
    switch (c) {
    case EXRIO_COMPRESSION_PXR24:
        return t != EXRIO_FLOAT; /* float rounds to 24 bits */
    case EXRIO_COMPRESSION_B44:
    case EXRIO_COMPRESSION_B44A:
        return t != EXRIO_HALF; /* only half is packed lossily; float/uint stay as they are */
    default:
        return 1;
    }
}

static void roundtrip(exrio_pixel_type type, exrio_compression compression)
{
    static const char *const names[4] = {"A", "B", "G", "R"};
    const exrio_pixel_type types[4] = {type, type, type, type};
    const int exact = lossless(compression, type);
    void *planes[4];
    const void *cplanes[4];
    char name[64], error[1024];
    exrio_image image;
    exrio_box data = test_box(-3, 5, W, H);
    exrio_box display = test_box(0, 0, 64, 48);
    int c, mismatches = 0;
    double worst = 0.0;

    for (c = 0; c < 4; c++) {
        planes[c] = malloc((size_t)W * H * 4);
        fill(type, c, !exact, planes[c]);
        cplanes[c] = planes[c];
    }
    snprintf(name, sizeof name, "rt_%s_%s.exr", exrio_pixel_type_name(type),
             exrio_compression_name(compression));
    CHECK(test_write_exr(test_path(dir, name), &data, &display, 4, names, types, cplanes,
                         compression) == 0);
    if (exrio_open(test_path(dir, name), &image, error, sizeof error) != EXRIO_OK) {
        CHECK_MSG(0, "%s", error);
        goto done;
    }
    CHECK(image.part_count == 1 && image.channel_count == 4);
    /* B44 without a half channel is stored uncompressed: as B44 Blender reads it shuffled. */
    CHECK_MSG(image.parts[0].compression == (type != EXRIO_HALF &&
                                                     (compression == EXRIO_COMPRESSION_B44 ||
                                                      compression == EXRIO_COMPRESSION_B44A)
                                                 ? EXRIO_COMPRESSION_NONE
                                                 : compression),
              "%s: stored as %s", name, exrio_compression_name(image.parts[0].compression));
    CHECK(image.parts[0].width == W && image.parts[0].height == H);
    CHECK(image.parts[0].data_window.min_x == -3 && image.parts[0].data_window.min_y == 5);
    CHECK(image.parts[0].display_window.max_x == 63 && image.parts[0].display_window.max_y == 47);
    CHECK(!image.parts[0].tiled && !image.parts[0].deep);
    if (exrio_load(&image, NULL, error, sizeof error) != EXRIO_OK) {
        CHECK_MSG(0, "%s", error);
        exrio_close(&image);
        goto done;
    }
    for (c = 0; c < 4; c++) {
        const int idx = exrio_find_channel(&image, names[c], 0);
        size_t i;
        CHECK(idx >= 0 && image.channels[idx].type == type);
        if (idx < 0)
            continue;
        for (i = 0; i < (size_t)W * H; i++) {
            if (type == EXRIO_UINT) {
                mismatches += ((uint32_t *)image.channels[idx].pixels)[i] !=
                              ((uint32_t *)planes[c])[i];
            } else {
                const float got = ((float *)image.channels[idx].pixels)[i];
                const float want = ((float *)planes[c])[i];
                if (exact) {
                    mismatches += memcmp(&got, &want, 4) != 0;
                } else {
                    const double rel = fabs((double)got - want) / fabs((double)want);
                    worst = rel > worst ? rel : worst;
                }
            }
        }
    }
    CHECK_MSG(mismatches == 0, "%s: %d values differ", name, mismatches);
    /* Lossy: PXR24 keeps 15 mantissa bits of float (2^-16 relative); B44 on a smooth half
     * gradient stays within a few half steps (2^-10 each). */
    if (!exact)
        CHECK_MSG(worst < (compression == EXRIO_COMPRESSION_PXR24 ? 3e-5 : 4e-3),
                  "%s: largest relative error %g", name, worst);
    exrio_close(&image);
done:
    for (c = 0; c < 4; c++)
        free(planes[c]);
}

/* An interleaved RGBA buffer (pixel stride 16 bytes) is written without copying. */
static void interleaved(void)
{
    float *rgba = malloc((size_t)W * H * 4 * sizeof *rgba);
    exrio_write_channel ch[4];
    exrio_write_spec spec;
    exrio_image image;
    char error[1024];
    const char *path = test_path(dir, "interleaved.exr");
    const char *names[4] = {"R", "G", "B", "A"};
    size_t i;
    int fd, c, bad = 0;
    for (i = 0; i < (size_t)W * H * 4; i++)
        rgba[i] = (float)i * 0.5f - 100.0f;
    for (c = 0; c < 4; c++) {
        ch[c].name = names[c];
        ch[c].type = EXRIO_FLOAT;
        ch[c].pixels = rgba + c;
        ch[c].pixel_stride = 16;
        ch[c].line_stride = (size_t)W * 16;
    }
    memset(&spec, 0, sizeof spec);
    spec.data_window = spec.display_window = test_box(0, 0, W, H);
    spec.compression = EXRIO_COMPRESSION_PIZ;
    spec.channel_count = 4;
    spec.channels = ch;
    fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0666);
    CHECK(exrio_write_fd(fd, path, &spec, error, sizeof error) == EXRIO_OK);
    close(fd);
    CHECK(exrio_open(path, &image, error, sizeof error) == EXRIO_OK);
    CHECK(exrio_load(&image, NULL, error, sizeof error) == EXRIO_OK);
    for (c = 0; c < 4; c++) {
        const float *p = image.channels[exrio_find_channel(&image, names[c], 0)].pixels;
        for (i = 0; i < (size_t)W * H; i++)
            bad += p[i] != rgba[i * 4 + (size_t)c];
    }
    CHECK_MSG(bad == 0, "%d interleaved values differ", bad);
    exrio_close(&image);
    free(rgba);
}

/* Names past 31 characters, as Blender writes them (its layered channel names, and attributes
 * such as cycles.ViewLayer.synchronization_time), round-trip. A name past the format's limit
 * fails with a message: the core reports it from inside its locked write context, which once
 * deadlocked the error handler (the test would then hang until ctest's timeout). */
static void long_names(void)
{
    static char too_long[301];
    float plane[W * H];
    exrio_write_channel ch;
    exrio_write_spec spec;
    exrio_image image;
    char error[1024];
    const char *path = test_path(dir, "long_names.exr");
    const char *name = "ViewLayer.AVeryLongAndDescriptivePassName.R"; /* 42 characters */
    size_t i;
    int fd, bad = 0, k;
    for (i = 0; i < (size_t)W * H; i++)
        plane[i] = (float)i;
    ch.name = name;
    ch.type = EXRIO_FLOAT;
    ch.pixels = plane;
    ch.pixel_stride = sizeof(float);
    ch.line_stride = (size_t)W * sizeof(float);
    memset(&spec, 0, sizeof spec);
    spec.data_window = spec.display_window = test_box(0, 0, W, H);
    spec.compression = EXRIO_COMPRESSION_ZIP;
    spec.channel_count = 1;
    spec.channels = &ch;
    fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0666);
    CHECK_MSG(exrio_write_fd(fd, path, &spec, error, sizeof error) == EXRIO_OK, "%s", error);
    close(fd);
    CHECK(exrio_open(path, &image, error, sizeof error) == EXRIO_OK);
    CHECK(exrio_load(&image, NULL, error, sizeof error) == EXRIO_OK);
    k = exrio_find_channel(&image, name, 0);
    CHECK_MSG(k >= 0, "the 42-character channel name did not come back");
    for (i = 0; k >= 0 && i < (size_t)W * H; i++)
        bad += ((const float *)image.channels[k].pixels)[i] != plane[i];
    CHECK_MSG(bad == 0, "%d values differ", bad);
    exrio_close(&image);

    memset(too_long, 'x', sizeof too_long - 1);
    ch.name = too_long;
    error[0] = '\0';
    fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0666);
    CHECK(exrio_write_fd(fd, path, &spec, error, sizeof error) != EXRIO_OK);
    CHECK_MSG(error[0] != '\0', "a failed write says nothing");
    close(fd);
}

/* Loading some channels only (the others of the same chunks go to scratch) gives the same
 * values; asking again for the rest keeps what was loaded. */
static void partial_load(void)
{
    static const char *const names[5] = {"A", "B", "G", "R", "Z"};
    const exrio_pixel_type types[5] = {EXRIO_HALF, EXRIO_HALF, EXRIO_HALF, EXRIO_HALF,
                                       EXRIO_FLOAT};
    void *planes[5];
    const void *cplanes[5];
    unsigned char wanted[5] = {0, 1, 0, 1, 0};
    exrio_image image;
    exrio_box box = test_box(0, 0, W, H);
    char error[1024];
    int c, bad = 0;
    size_t i;
    for (c = 0; c < 5; c++) {
        planes[c] = malloc((size_t)W * H * 4);
        fill(types[c], c, 0, planes[c]);
        cplanes[c] = planes[c];
    }
    CHECK(test_write_exr(test_path(dir, "partial.exr"), &box, NULL, 5, names, types, cplanes,
                         EXRIO_COMPRESSION_ZIP) == 0);
    CHECK(exrio_open(test_path(dir, "partial.exr"), &image, error, sizeof error) == EXRIO_OK);
    CHECK(exrio_load(&image, wanted, error, sizeof error) == EXRIO_OK);
    CHECK(image.channels[0].pixels == NULL && image.channels[2].pixels == NULL &&
          image.channels[4].pixels == NULL);
    CHECK(image.channels[1].pixels != NULL && image.channels[3].pixels != NULL);
    CHECK(exrio_load(&image, NULL, error, sizeof error) == EXRIO_OK);
    for (c = 0; c < 5; c++)
        for (i = 0; i < (size_t)W * H; i++)
            bad += ((float *)image.channels[c].pixels)[i] != ((float *)planes[c])[i];
    CHECK_MSG(bad == 0, "%d values differ after partial loads", bad);
    exrio_close(&image);
    for (c = 0; c < 5; c++)
        free(planes[c]);
}

/* Writes a tiled file (tiles 16x8, ZIP) with the C core directly: ddof writes scanlines only,
 * but renderers such as Arnold write tiles by default. */
static int write_tiled(const char *path, const float *r, const float *z)
{
    exr_context_t ctxt = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    exr_chunk_info_t cinfo;
    int part = 0, tx, ty, first = 1;
    exr_result_t rv = exr_start_write(&ctxt, path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv) return -1;
    rv |= exr_add_part(ctxt, NULL, EXR_STORAGE_TILED, &part);
    rv |= exr_initialize_required_attr_simple(ctxt, part, W, H, EXR_COMPRESSION_ZIP);
    rv |= exr_set_tile_descriptor(ctxt, part, 16, 8, EXR_TILE_ONE_LEVEL, EXR_TILE_ROUND_DOWN);
    rv |= exr_add_channel(ctxt, part, "R", EXR_PIXEL_HALF, EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
    rv |= exr_add_channel(ctxt, part, "Z", EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR, 1, 1);
    rv |= exr_write_header(ctxt);
    for (ty = 0; !rv && ty < (H + 7) / 8; ty++) {
        for (tx = 0; !rv && tx < (W + 15) / 16; tx++) {
            int c;
            rv = exr_write_tile_chunk_info(ctxt, part, tx, ty, 0, 0, &cinfo);
            if (!rv)
                rv = first ? exr_encoding_initialize(ctxt, part, &cinfo, &enc)
                           : exr_encoding_update(ctxt, part, &cinfo, &enc);
            for (c = 0; !rv && c < enc.channel_count; c++) {
                const float *src = strcmp(enc.channels[c].channel_name, "R") == 0 ? r : z;
                enc.channels[c].encode_from_ptr =
                    (const uint8_t *)(src + (size_t)ty * 8 * W + (size_t)tx * 16);
                enc.channels[c].user_pixel_stride = 4;
                enc.channels[c].user_line_stride = W * 4;
                enc.channels[c].user_bytes_per_element = 4;
                enc.channels[c].user_data_type = EXR_PIXEL_FLOAT;
            }
            if (!rv && first)
                rv = exr_encoding_choose_default_routines(ctxt, part, &enc);
            first = 0;
            if (!rv)
                rv = exr_encoding_run(ctxt, part, &enc);
        }
    }
    exr_encoding_destroy(ctxt, &enc);
    rv |= exr_finish(&ctxt);
    return rv ? -1 : 0;
}

static void tiled(void)
{
    float *r = malloc((size_t)W * H * 4), *z = malloc((size_t)W * H * 4);
    exrio_image image;
    char error[1024];
    size_t i;
    int bad = 0;
    fill(EXRIO_HALF, 0, 0, r);
    fill(EXRIO_FLOAT, 1, 0, z);
    CHECK(write_tiled(test_path(dir, "tiled.exr"), r, z) == 0);
    CHECK(exrio_open(test_path(dir, "tiled.exr"), &image, error, sizeof error) == EXRIO_OK);
    CHECK(image.parts[0].tiled == 1);
    CHECK(exrio_load(&image, NULL, error, sizeof error) == EXRIO_OK);
    for (i = 0; i < (size_t)W * H; i++) {
        bad += ((float *)image.channels[exrio_find_channel(&image, "R", 0)].pixels)[i] != r[i];
        bad += ((float *)image.channels[exrio_find_channel(&image, "Z", 0)].pixels)[i] != z[i];
    }
    CHECK_MSG(bad == 0, "%d tiled values differ", bad);
    exrio_close(&image);
    /* Tiles decoded on threads land where they belong too. */
    CHECK(exrio_open(test_path(dir, "tiled.exr"), &image, error, sizeof error) == EXRIO_OK);
    CHECK(exrio_load_threads(&image, NULL, 3, error, sizeof error) == EXRIO_OK);
    for (bad = 0, i = 0; i < (size_t)W * H; i++) {
        bad += ((float *)image.channels[exrio_find_channel(&image, "R", 0)].pixels)[i] != r[i];
        bad += ((float *)image.channels[exrio_find_channel(&image, "Z", 0)].pixels)[i] != z[i];
    }
    CHECK_MSG(bad == 0, "%d tiled values differ when decoded on 3 threads", bad);
    exrio_close(&image);
    free(r);
    free(z);
}

/* Header attributes of the source reach the output (--keep-metadata), layout ones do not. */
static void metadata(void)
{
    const char *src = test_path(dir, "meta_src.exr");
    const char *dst = test_path(dir, "meta_dst.exr");
    exr_context_t ctxt = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    exr_attr_m44f_t m;
    exr_attr_v2f_t v = {{{1.5f, -2.0f}}};
    float plane[16] = {0};
    exrio_image image;
    exrio_write_channel ch = {"Y", EXRIO_FLOAT, plane, 4, 16};
    exrio_write_spec spec;
    char error[1024];
    int part = 0, fd, i;
    const char *owner = NULL;
    int32_t length = 0, ival = 0;
    float f = 0.0f;
    exr_attr_m44f_t mback;
    exr_attr_v2f_t vback;
    exr_compression_t comp = EXR_COMPRESSION_NONE;

    for (i = 0; i < 16; i++)
        m.m[i] = (float)i * 0.25f;
    memset(&spec, 0, sizeof spec);
    spec.data_window = spec.display_window = test_box(0, 0, 4, 4);
    spec.compression = EXRIO_COMPRESSION_RLE;
    spec.channel_count = 1;
    spec.channels = &ch;

    /* The source, with attributes of several types. */
    CHECK(exr_start_write(&ctxt, src, EXR_WRITE_FILE_DIRECTLY, &init) == 0);
    exr_add_part(ctxt, NULL, EXR_STORAGE_SCANLINE, &part);
    exr_initialize_required_attr_simple(ctxt, part, 4, 4, EXR_COMPRESSION_NONE);
    exr_add_channel(ctxt, part, "Y", EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR, 1, 1);
    CHECK(exr_attr_set_string(ctxt, part, "owner", "ddof test") == 0);
    CHECK(exr_attr_set_m44f(ctxt, part, "worldToCamera", &m) == 0);
    CHECK(exr_attr_set_float(ctxt, part, "expTime", 0.02f) == 0);
    CHECK(exr_attr_set_int(ctxt, part, "frame", 42) == 0);
    CHECK(exr_attr_set_v2f(ctxt, part, "custom.offset", &v) == 0);
    exr_write_header(ctxt);
    {
        exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
        exr_chunk_info_t cinfo;
        int y;
        for (y = 0; y < 4; y++) {
            exr_write_scanline_chunk_info(ctxt, part, y, &cinfo);
            if (y == 0)
                exr_encoding_initialize(ctxt, part, &cinfo, &enc);
            else
                exr_encoding_update(ctxt, part, &cinfo, &enc);
            enc.channels[0].encode_from_ptr = (const uint8_t *)(plane + y * 4);
            enc.channels[0].user_pixel_stride = 4;
            enc.channels[0].user_line_stride = 16;
            enc.channels[0].user_bytes_per_element = 4;
            enc.channels[0].user_data_type = EXR_PIXEL_FLOAT;
            if (y == 0)
                exr_encoding_choose_default_routines(ctxt, part, &enc);
            CHECK(exr_encoding_run(ctxt, part, &enc) == 0);
        }
        exr_encoding_destroy(ctxt, &enc);
    }
    CHECK(exr_finish(&ctxt) == 0);

    CHECK(exrio_open(src, &image, error, sizeof error) == EXRIO_OK);
    spec.metadata_from = &image;
    spec.metadata_part = 0;
    fd = open(dst, O_WRONLY | O_CREAT | O_TRUNC, 0666);
    CHECK(exrio_write_fd(fd, dst, &spec, error, sizeof error) == EXRIO_OK);
    close(fd);
    exrio_close(&image);

    CHECK(exr_start_read(&ctxt, dst, &init) == 0);
    CHECK(exr_attr_get_string(ctxt, 0, "owner", &length, &owner) == 0 && owner &&
          strcmp(owner, "ddof test") == 0);
    CHECK(exr_attr_get_m44f(ctxt, 0, "worldToCamera", &mback) == 0 &&
          memcmp(&mback, &m, sizeof m) == 0);
    CHECK(exr_attr_get_float(ctxt, 0, "expTime", &f) == 0 && f == 0.02f);
    CHECK(exr_attr_get_int(ctxt, 0, "frame", &ival) == 0 && ival == 42);
    CHECK(exr_attr_get_v2f(ctxt, 0, "custom.offset", &vback) == 0 && vback.x == 1.5f &&
          vback.y == -2.0f);
    /* The writer's own layout wins over the source's. */
    CHECK(exr_get_compression(ctxt, 0, &comp) == 0 && comp == EXR_COMPRESSION_RLE);
    exr_finish(&ctxt);
}

/* Two parts with their names; channels know their part. */
static void multipart(void)
{
    const char *path = test_path(dir, "multipart.exr");
    exr_context_t ctxt = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    exrio_image image;
    char error[1024];
    float plane[6 * 4];
    int a = 0, b = 0, p, i;
    for (i = 0; i < 24; i++)
        plane[i] = (float)i;
    CHECK(exr_start_write(&ctxt, path, EXR_WRITE_FILE_DIRECTLY, &init) == 0);
    exr_add_part(ctxt, "beauty", EXR_STORAGE_SCANLINE, &a);
    exr_initialize_required_attr_simple(ctxt, a, 6, 4, EXR_COMPRESSION_ZIPS);
    exr_add_channel(ctxt, a, "R", EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
    exr_add_part(ctxt, "depth", EXR_STORAGE_SCANLINE, &b);
    exr_initialize_required_attr_simple(ctxt, b, 6, 4, EXR_COMPRESSION_NONE);
    exr_add_channel(ctxt, b, "Z", EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR, 1, 1);
    CHECK(exr_write_header(ctxt) == 0);
    for (p = 0; p < 2; p++) {
        exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
        exr_chunk_info_t cinfo;
        int y;
        for (y = 0; y < 4; y++) {
            exr_write_scanline_chunk_info(ctxt, p, y, &cinfo);
            if (y == 0)
                exr_encoding_initialize(ctxt, p, &cinfo, &enc);
            else
                exr_encoding_update(ctxt, p, &cinfo, &enc);
            enc.channels[0].encode_from_ptr = (const uint8_t *)(plane + y * 6);
            enc.channels[0].user_pixel_stride = 4;
            enc.channels[0].user_line_stride = 24;
            enc.channels[0].user_bytes_per_element = 4;
            enc.channels[0].user_data_type = EXR_PIXEL_FLOAT;
            if (y == 0)
                exr_encoding_choose_default_routines(ctxt, p, &enc);
            CHECK(exr_encoding_run(ctxt, p, &enc) == 0);
        }
        exr_encoding_destroy(ctxt, &enc);
    }
    CHECK(exr_finish(&ctxt) == 0);
    CHECK(exrio_open(path, &image, error, sizeof error) == EXRIO_OK);
    CHECK(image.part_count == 2 && image.channel_count == 2);
    CHECK(image.parts[0].name && strcmp(image.parts[0].name, "beauty") == 0);
    CHECK(image.parts[1].name && strcmp(image.parts[1].name, "depth") == 0);
    CHECK(exrio_find_channel(&image, "Z", -1) == 1 && image.channels[1].part == 1);
    CHECK(exrio_find_channel(&image, "Z", 0) == -1);
    CHECK(exrio_load(&image, NULL, error, sizeof error) == EXRIO_OK);
    CHECK(((float *)image.channels[1].pixels)[23] == 23.0f);
    exrio_close(&image);
}

/* A chunk whose compressed size equals its raw size must be stored raw: a reader takes a chunk of
 * exactly the raw size as uncompressed. These 16 bytes deflate to exactly 16 (found by fuzzing);
 * OpenEXR 3.1's zip encoder kept them compressed and the copy read back the zlib stream. */
static void raw_size_chunk(void)
{
    static const uint32_t bits[4] = {0x00000000u, 0x69000000u, 0x00001000u, 0x00000000u};
    static const exrio_compression lossless_codecs[] = {
        EXRIO_COMPRESSION_NONE, EXRIO_COMPRESSION_RLE, EXRIO_COMPRESSION_ZIPS,
        EXRIO_COMPRESSION_ZIP, EXRIO_COMPRESSION_PIZ};
    float plane[4];
    exrio_write_channel ch;
    exrio_write_spec spec;
    exrio_image image;
    char error[1024];
    const char *path = test_path(dir, "raw_size_chunk.exr");
    size_t c;
    memcpy(plane, bits, sizeof plane);
    ch.name = "Y";
    ch.type = EXRIO_FLOAT;
    ch.pixels = plane;
    ch.pixel_stride = sizeof(float);
    ch.line_stride = sizeof plane;
    memset(&spec, 0, sizeof spec);
    spec.data_window = spec.display_window = test_box(0, 0, 4, 1);
    spec.channel_count = 1;
    spec.channels = &ch;
    for (c = 0; c < sizeof lossless_codecs / sizeof lossless_codecs[0]; c++) {
        int fd, k, i, bad = 0;
        spec.compression = lossless_codecs[c];
        fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0666);
        CHECK_MSG(exrio_write_fd(fd, path, &spec, error, sizeof error) == EXRIO_OK, "%s", error);
        close(fd);
        CHECK(exrio_open(path, &image, error, sizeof error) == EXRIO_OK);
        CHECK(exrio_load(&image, NULL, error, sizeof error) == EXRIO_OK);
        k = exrio_find_channel(&image, "Y", 0);
        CHECK(k >= 0);
        for (i = 0; k >= 0 && i < 4; i++)
            bad += memcmp((const float *)image.channels[k].pixels + i, &bits[i], 4) != 0;
        CHECK_MSG(bad == 0, "4x1 float with %s: %d of 4 values differ",
                  exrio_compression_name(spec.compression), bad);
        exrio_close(&image);
    }
}

/* OpenEXR's C++ writer stores a B44 chunk raw when B44 does not make it smaller: always for a
 * float-only part, and for a 1x1 half image (one 4x4 block is 14 bytes, the pixel 2). OpenEXR
 * 3.1's C core decoded such chunks as B44 and shuffled the float channels. */
static void cpp_b44(void)
{
    static const char *const names[4] = {"A", "B", "G", "R"};
    exrio_image image;
    char error[1024];
    int c, x, y, bad = 0;
    CHECK(exrio_open(test_path(data_dir, "cpp_b44_float.exr"), &image, error, sizeof error) ==
          EXRIO_OK);
    CHECK(exrio_load(&image, NULL, error, sizeof error) == EXRIO_OK);
    CHECK(image.parts[0].compression == EXRIO_COMPRESSION_B44 && image.parts[0].width == 9 &&
          image.parts[0].height == 7);
    for (c = 0; c < 4; c++) {
        const int k = exrio_find_channel(&image, names[c], 0);
        const float *p = k >= 0 ? image.channels[k].pixels : NULL;
        CHECK(p != NULL);
        for (y = 0; p && y < 7; y++)
            for (x = 0; x < 9; x++)
                bad += p[y * 9 + x] != (float)(c * 100 + y * 10 + x);
    }
    CHECK_MSG(bad == 0, "float B44 from the C++ writer: %d of 252 values differ", bad);
    exrio_close(&image);

    CHECK(exrio_open(test_path(data_dir, "cpp_b44a_half_1x1.exr"), &image, error,
                     sizeof error) == EXRIO_OK);
    CHECK(exrio_load(&image, NULL, error, sizeof error) == EXRIO_OK);
    CHECK_MSG(image.channel_count == 1 && ((const float *)image.channels[0].pixels)[0] == 1.5f,
              "1x1 half B44A from the C++ writer: %g instead of 1.5",
              image.channel_count == 1 ? ((const float *)image.channels[0].pixels)[0] : -1.0);
    exrio_close(&image);
}

int main(int argc, char **argv)
{
    static const exrio_compression all[] = {
        EXRIO_COMPRESSION_NONE, EXRIO_COMPRESSION_RLE,   EXRIO_COMPRESSION_ZIPS,
        EXRIO_COMPRESSION_ZIP,  EXRIO_COMPRESSION_PIZ,   EXRIO_COMPRESSION_PXR24,
        EXRIO_COMPRESSION_B44,  EXRIO_COMPRESSION_B44A};
    size_t c;
    int t;
    if (argc != 3) {
        fprintf(stderr, "usage: test_exr_roundtrip SCRATCH_DIR DATA_DIR\n");
        return 2;
    }
    dir = argv[1];
    data_dir = argv[2];
    test_fresh_dir(dir);
    for (t = EXRIO_UINT; t <= EXRIO_FLOAT; t++)
        for (c = 0; c < sizeof all / sizeof all[0]; c++)
            roundtrip((exrio_pixel_type)t, all[c]);
    interleaved();
    partial_load();
    tiled();
    metadata();
    multipart();
    long_names();
    raw_size_chunk();
    cpp_b44();
    return test_finish("test_exr_roundtrip");
}
