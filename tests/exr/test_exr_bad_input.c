/* SPDX-License-Identifier: MIT */
/* test_exr_bad_input.c - every bad input of issue 3 at the exrio level, each with a real file:
 * missing, not an EXR (text, PNG, empty), truncated (in the header and in the pixel data), an
 * uncompressed chunk shorter than its rows,
 * a DWA header over other data (and one whose attribute claims more than the file holds, one
 * hiding such a claim behind a channel list, one declaring tiles far larger than its window),
 * missing colour or depth channels (the message lists what is there),
 * mismatched layer sizes in a multi-part file, ambiguous view layers, and a data window that
 * differs from the display window (read correctly, windows reported).
 *
 *   test_exr_bad_input SCRATCH_DIR */
#include "exr_test_util.h"
#include "exrio_layout.h"

#include <openexr.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *dir;

static int contains(const char *text, const char *part)
{
    return strstr(text, part) != NULL;
}

/* A small valid RGBA + Z file, ZIP-compressed, 24x20 of smooth-ish content. */
static void write_rgbaz(const char *path, exrio_compression compression, int with_depth)
{
    static const char *const names[5] = {"R", "G", "B", "A", "Z"};
    const exrio_pixel_type types[5] = {EXRIO_HALF, EXRIO_HALF, EXRIO_HALF, EXRIO_HALF,
                                       EXRIO_FLOAT};
    float planes[5][24 * 20];
    const void *cplanes[5];
    exrio_box box = test_box(0, 0, 24, 20);
    int c, i;
    for (c = 0; c < 5; c++) {
        for (i = 0; i < 24 * 20; i++)
            planes[c][i] = c == 4 ? 2.0f + (float)(i % 24) * 0.25f : (float)((i * 7 + c) % 97) / 97.0f;
        cplanes[c] = planes[c];
    }
    CHECK(test_write_exr(path, &box, NULL, with_depth ? 5 : 4, names, types, cplanes,
                         compression) == 0);
}

static exrio_status open_and_load(const char *path, char *error, size_t size)
{
    exrio_image image;
    exrio_status s = exrio_open(path, &image, error, size);
    if (s != EXRIO_OK)
        return s;
    s = exrio_load(&image, NULL, error, size);
    exrio_close(&image);
    return s;
}

static void missing_and_not_exr(void)
{
    char error[2048];
    static const unsigned char png[16] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n',
                                          0, 0, 0, 13, 'I', 'H', 'D', 'R'};
    exrio_image image;

    CHECK(exrio_open(test_path(dir, "nope.exr"), &image, error, sizeof error) ==
          EXRIO_ERROR_MISSING);
    CHECK_MSG(contains(error, "nope.exr") && contains(error, "No such file"), "%s", error);

    test_write_file(test_path(dir, "text.exr"), "hello, not an image\n", 20);
    CHECK(exrio_open(test_path(dir, "text.exr"), &image, error, sizeof error) ==
          EXRIO_ERROR_NOT_EXR);
    CHECK_MSG(contains(error, "not an OpenEXR file") && contains(error, "text.exr"), "%s", error);

    test_write_file(test_path(dir, "image.exr"), png, sizeof png);
    CHECK(exrio_open(test_path(dir, "image.exr"), &image, error, sizeof error) ==
          EXRIO_ERROR_NOT_EXR);
    CHECK_MSG(contains(error, "PNG"), "%s", error);

    test_write_file(test_path(dir, "empty.exr"), "", 0);
    CHECK(exrio_open(test_path(dir, "empty.exr"), &image, error, sizeof error) ==
          EXRIO_ERROR_NOT_EXR);
    CHECK_MSG(contains(error, "empty"), "%s", error);

    CHECK(exrio_open(dir, &image, error, sizeof error) == EXRIO_ERROR_ACCESS);
    CHECK_MSG(contains(error, "directory"), "%s", error);
}

static void truncated(void)
{
    static const double keep[] = {0.02, 0.1, 0.5, 0.9, 0.99};
    const char *full = test_path(dir, "full.exr");
    size_t size = 0, k;
    char *bytes;
    write_rgbaz(full, EXRIO_COMPRESSION_ZIP, 1);
    bytes = test_read_file(full, &size);
    CHECK(bytes && size > 200);
    if (!bytes)
        return;
    for (k = 0; k < sizeof keep / sizeof keep[0]; k++) {
        char name[64], error[2048];
        exrio_status s;
        snprintf(name, sizeof name, "truncated_%02d.exr", (int)(keep[k] * 100));
        test_write_file(test_path(dir, name), bytes, (size_t)(keep[k] * (double)size));
        s = open_and_load(test_path(dir, name), error, sizeof error);
        CHECK_MSG(s == EXRIO_ERROR_CORRUPT, "%s: status %d: %s", name, (int)s, error);
        CHECK_MSG(contains(error, "truncated") && contains(error, name), "%s", error);
    }
    free(bytes);
}

/* An uncompressed scanline chunk that says it holds one byte less than its rows take: OpenEXR
 * 3.1's C core decodes it as a black row without a word. It must fail, naming the file and the
 * scanline, on one thread and on several. */
static void short_chunk(void)
{
    static const char *const names[5] = {"R", "G", "B", "A", "Z"};
    const exrio_pixel_type types[5] = {EXRIO_HALF, EXRIO_HALF, EXRIO_HALF, EXRIO_HALF,
                                       EXRIO_FLOAT};
    static float planes[5][64 * 36];
    const void *cplanes[5];
    const char *path = test_path(dir, "short_chunk.exr");
    exrio_box box = test_box(0, 0, 64, 36);
    exr_context_t ctxt = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    exr_chunk_info_t cinfo;
    size_t size = 0;
    unsigned threads;
    char *bytes;
    int c, i;

    for (c = 0; c < 5; c++) {
        for (i = 0; i < 64 * 36; i++)
            planes[c][i] = c == 4 ? 2.0f : c == 3 ? 1.0f : 0.5f;
        cplanes[c] = planes[c];
    }
    CHECK(test_write_exr(path, &box, NULL, 5, names, types, cplanes, EXRIO_COMPRESSION_NONE) ==
          0);
    CHECK(exr_start_read(&ctxt, path, &init) == EXR_ERR_SUCCESS);
    CHECK(exr_read_scanline_chunk_info(ctxt, 0, 5, &cinfo) == EXR_ERR_SUCCESS);
    exr_finish(&ctxt);
    CHECK(cinfo.packed_size == 64 * (4 * 2 + 4));
    bytes = test_read_file(path, &size);
    if (!bytes || cinfo.data_offset < 4 || cinfo.data_offset > size) {
        CHECK(0);
        free(bytes);
        return;
    }
    /* The chunk is (int32 y, int32 size, data): its size field just before the data. */
    bytes[cinfo.data_offset - 4] = (char)((64 * 12 - 1) & 0xff);
    bytes[cinfo.data_offset - 3] = (char)((64 * 12 - 1) >> 8);
    test_write_file(path, bytes, size);
    free(bytes);
    for (threads = 1; threads <= 4; threads += 3) {
        char error[2048];
        exrio_image image;
        exrio_status s;
        CHECK(exrio_open(path, &image, error, sizeof error) == EXRIO_OK);
        s = exrio_load_threads(&image, NULL, threads, error, sizeof error);
        CHECK_MSG(s == EXRIO_ERROR_CORRUPT, "%u threads: status %d", threads, (int)s);
        CHECK_MSG(contains(error, "short_chunk.exr") && contains(error, "scanline 5") &&
                      contains(error, "767 bytes"),
                  "%s", error);
        exrio_close(&image);
    }
}

/* The value byte of a file's "compression" header attribute (name, type, size 1, value);
 * NULL when there is none. */
static char *compression_value(char *bytes, size_t size)
{
    static const char key[] = "compression\0compression\0\1\0\0\0";
    for (size_t i = 0; i + sizeof key < size; i++)
        if (memcmp(bytes + i, key, sizeof key - 1) == 0)
            return bytes + i + sizeof key - 1;
    return NULL;
}

/* The DWA file `bytes` with `attribute` (its name, type name, size and no value) inserted
 * before its first attribute, written as `name`: it opens, and loading it is refused with
 * `expected` in the message before OpenEXR's C++ reader allocates what it claims. */
static void refused_claim(const char *bytes, size_t size, const char *attribute, size_t length,
                          const char *name, const char *expected)
{
    char *grown = malloc(size + length), error[2048];
    exrio_image image;
    if (!grown) {
        CHECK(grown != NULL);
        return;
    }
    memcpy(grown, bytes, 8); /* magic and version, then the attribute, then the rest */
    memcpy(grown + 8, attribute, length);
    memcpy(grown + 8 + length, bytes + 8, size - 8);
    test_write_file(test_path(dir, name), grown, size + length);
    free(grown);
    CHECK(exrio_open(test_path(dir, name), &image, error, sizeof error) == EXRIO_OK);
    CHECK(exrio_load(&image, NULL, error, sizeof error) == EXRIO_ERROR_CORRUPT);
    CHECK_MSG(contains(error, name) && contains(error, expected), "%s", error);
    exrio_close(&image);
}

/* fuzz_exr_read's input fuzz/corpus/exr_read/dwa_window_3801104x1793_on_64x64: a DWAA file
 * whose dataWindow attribute claims 32784 bytes, not a box2i's 16, over the box
 * (0,0)-(3801103,1792). OpenEXR's C core reports the size and keeps a 64x64 window, by which
 * the planes are sized; the C++ library reads the box and allocated 1.46 GB of line buffers
 * for it. The reader refuses the file where the two windows differ. */
static void dwa_window_disagrees(const char *corpus)
{
    const char *path = test_path(corpus, "dwa_window_3801104x1793_on_64x64");
    char error[2048];
    exrio_image image;
    CHECK_MSG(exrio_open(path, &image, error, sizeof error) == EXRIO_OK, "%s", error);
    CHECK(image.parts && image.parts[0].data_window.max_x == 63 &&
          image.parts[0].data_window.max_y == 63);
    CHECK(exrio_load(&image, NULL, error, sizeof error) == EXRIO_ERROR_CORRUPT);
    CHECK_MSG(contains(error, "dwa_window_3801104x1793_on_64x64") &&
                  contains(error, "reads the data window as (0,0)-(3801103,1792), its C core "
                                  "as (0,0)-(63,63)"),
              "%s", error);
    exrio_close(&image);
}

/* A DWAA or DWAB header over ZIP data: a ZIP file with the value byte of its "compression"
 * header attribute (name, type, size 1, value) changed to DWAA (8) or DWAB (9). The header is
 * then exactly that of a DWA file; the reader takes it for one (OpenEXR's C++ library decodes
 * DWA), finds the data damaged and says so, naming the file. */
static void dwa(void)
{
    const char *zip = test_path(dir, "for_dwa.exr");
    size_t size = 0;
    char *bytes;
    int variant;
    write_rgbaz(zip, EXRIO_COMPRESSION_ZIP, 1);
    bytes = test_read_file(zip, &size);
    if (!bytes) {
        CHECK(bytes != NULL);
        return;
    }
    char *value = compression_value(bytes, size);
    CHECK(value && *value == EXRIO_COMPRESSION_ZIP);
    if (!value) {
        free(bytes);
        return;
    }
    for (variant = 0; variant < 2; variant++) {
        const char *name = variant ? "dwab.exr" : "dwaa.exr";
        char error[2048];
        exrio_image image;
        *value = (char)(variant ? EXRIO_COMPRESSION_DWAB : EXRIO_COMPRESSION_DWAA);
        test_write_file(test_path(dir, name), bytes, size);
        CHECK(exrio_open(test_path(dir, name), &image, error, sizeof error) == EXRIO_OK);
        CHECK(image.parts && image.parts[0].compression ==
                                 (variant ? EXRIO_COMPRESSION_DWAB : EXRIO_COMPRESSION_DWAA));
        CHECK(exrio_load(&image, NULL, error, sizeof error) == EXRIO_ERROR_CORRUPT);
        CHECK_MSG(contains(error, name) && contains(error, "damaged or truncated pixel data (DWA"),
                  "%s", error);
        CHECK(image.channels[0].pixels == NULL);
        exrio_close(&image);
    }
    /* The same DWAA header with a first attribute "type" that claims 1.76 GB: OpenEXR 3.1's
     * C++ reader allocated that much before finding the file short (fuzz_exr_read); the claim
     * is refused before it reads, naming the attribute. */
    *value = (char)EXRIO_COMPRESSION_DWAA;
    {
        static const char claim[] = "type\0string\0\x0d\x00\x00\x69";
        refused_claim(bytes, size, claim, sizeof claim - 1, "dwa_huge_attribute.exr",
                      "\"type\" (string, 1761607693 bytes)");
    }
    /* A channel list whose records end before its declared size, hiding an attribute that
     * claims 1.76 GB: OpenEXR's C core and a walk by declared sizes step over the claim, the
     * C++ reader reads the list's records, then the claim, and allocated it (fuzz_exr_read). */
    {
        static const char hidden[] = "extra\0chlist\0\x11\0\0\0"
                                     "\0huge\0opaque\0\x00\x00\x00\x69";
        refused_claim(bytes, size, hidden, sizeof hidden - 1, "dwa_hidden_attribute.exr",
                      "\"huge\" (opaque, 1761607680 bytes)");
    }
    free(bytes);
}

/* A tiled DWAA file of 64x64 pixels declaring tiles of 8715279x8: OpenEXR's C++ reader
 * allocates its tile buffers at the declared size (558 MB; fuzz_exr_read), so the reader
 * refuses the tiles before it reads. Written uncompressed with the C core (which writes no
 * DWA), then the "compression" value byte set to DWAA, as dwa() does. */
static void dwa_huge_tiles(void)
{
    const char *path = test_path(dir, "dwa_huge_tiles.exr");
    static float plane[64 * 64];
    exr_context_t ctxt = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    exr_chunk_info_t cinfo;
    exrio_image image;
    char error[2048], *bytes;
    size_t size = 0;
    int part = 0, ty;
    exr_result_t rv = exr_start_write(&ctxt, path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (!rv) {
        rv |= exr_add_part(ctxt, NULL, EXR_STORAGE_TILED, &part);
        rv |= exr_initialize_required_attr_simple(ctxt, part, 64, 64, EXR_COMPRESSION_NONE);
        rv |= exr_set_tile_descriptor(ctxt, part, 8715279, 8, EXR_TILE_ONE_LEVEL,
                                      EXR_TILE_ROUND_DOWN);
        rv |= exr_add_channel(ctxt, part, "R", EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR, 1, 1);
        rv |= exr_write_header(ctxt);
        for (ty = 0; !rv && ty < 8; ty++) {
            rv = exr_write_tile_chunk_info(ctxt, part, 0, ty, 0, 0, &cinfo);
            if (!rv)
                rv = ty ? exr_encoding_update(ctxt, part, &cinfo, &enc)
                        : exr_encoding_initialize(ctxt, part, &cinfo, &enc);
            if (!rv) {
                enc.channels[0].encode_from_ptr = (const uint8_t *)(plane + (size_t)ty * 8 * 64);
                enc.channels[0].user_pixel_stride = 4;
                enc.channels[0].user_line_stride = 64 * 4;
                enc.channels[0].user_bytes_per_element = 4;
                enc.channels[0].user_data_type = EXR_PIXEL_FLOAT;
            }
            if (!rv && !ty)
                rv = exr_encoding_choose_default_routines(ctxt, part, &enc);
            if (!rv)
                rv = exr_encoding_run(ctxt, part, &enc);
        }
        exr_encoding_destroy(ctxt, &enc);
        rv |= exr_finish(&ctxt);
    }
    CHECK_MSG(rv == EXR_ERR_SUCCESS, "writing the file: %d", (int)rv);
    bytes = test_read_file(path, &size);
    if (!bytes) {
        CHECK(bytes != NULL);
        return;
    }
    char *value = compression_value(bytes, size);
    CHECK(value && *value == EXRIO_COMPRESSION_NONE);
    if (value)
        *value = (char)EXRIO_COMPRESSION_DWAA;
    test_write_file(path, bytes, size);
    free(bytes);
    CHECK(exrio_open(path, &image, error, sizeof error) == EXRIO_OK);
    CHECK(image.parts && image.parts[0].tiled);
    CHECK(exrio_load(&image, NULL, error, sizeof error) == EXRIO_ERROR_CORRUPT);
    CHECK_MSG(contains(error, "dwa_huge_tiles.exr") &&
                  contains(error, "tiles of 8715279x8 pixels for a 64x64 image"),
              "%s", error);
    exrio_close(&image);
}

static void missing_channels(void)
{
    static const char *const names[2] = {"foo.X", "Y"};
    const exrio_pixel_type types[2] = {EXRIO_FLOAT, EXRIO_HALF};
    float plane[4 * 4] = {0};
    const void *planes[2] = {plane, plane};
    exrio_box box = test_box(0, 0, 4, 4);
    exrio_layout_request req;
    exrio_layout layout;
    exrio_image image;
    char error[2048];

    memset(&req, 0, sizeof req);
    req.need_depth = 1;
    test_write_exr(test_path(dir, "nocolor.exr"), &box, NULL, 2, names, types, planes,
                   EXRIO_COMPRESSION_NONE);
    CHECK(exrio_open(test_path(dir, "nocolor.exr"), &image, error, sizeof error) == EXRIO_OK);
    CHECK(exrio_find_layout(&image, &req, &layout, error, sizeof error) == EXRIO_LAYOUT_MISSING);
    CHECK_MSG(contains(error, "no colour") && contains(error, "Y, foo.X"), "%s", error);
    exrio_close(&image);

    write_rgbaz(test_path(dir, "nodepth.exr"), EXRIO_COMPRESSION_RLE, 0);
    CHECK(exrio_open(test_path(dir, "nodepth.exr"), &image, error, sizeof error) == EXRIO_OK);
    CHECK(exrio_find_layout(&image, &req, &layout, error, sizeof error) == EXRIO_LAYOUT_MISSING);
    CHECK_MSG(contains(error, "no depth") && contains(error, "A, B, G, R"), "%s", error);
    /* Without a depth requirement (CoC from a channel) the same file is fine. */
    req.need_depth = 0;
    CHECK(exrio_find_layout(&image, &req, &layout, error, sizeof error) == EXRIO_LAYOUT_OK);
    CHECK(layout.color_count == 4 &&
          strcmp(image.channels[layout.color[0]].name, "R") == 0 &&
          strcmp(image.channels[layout.color[3]].name, "A") == 0);
    req.color = "R,G,Q";
    CHECK(exrio_find_layout(&image, &req, &layout, error, sizeof error) == EXRIO_LAYOUT_MISSING);
    CHECK_MSG(contains(error, "'Q'"), "%s", error);
    exrio_close(&image);
}

/* Blender-style layers: the one with depth wins; two with depth need --layer. */
static void layers(void)
{
    static const char *const two[8] = {"A.Combined.B", "A.Combined.G", "A.Combined.R",
                                       "A.Depth.Z",    "B.Combined.B", "B.Combined.G",
                                       "B.Combined.R", "B.Depth.Z"};
    static const char *const comp[7] = {"Composite.Combined.B", "Composite.Combined.G",
                                        "Composite.Combined.R", "ViewLayer.Combined.B",
                                        "ViewLayer.Combined.G", "ViewLayer.Combined.R",
                                        "ViewLayer.Depth.Z"};
    exrio_pixel_type types[8];
    float plane[4] = {1, 1, 1, 1};
    const void *planes[8];
    exrio_box box = test_box(0, 0, 2, 2);
    exrio_layout_request req;
    exrio_layout layout;
    exrio_image image;
    char error[2048];
    int i;
    for (i = 0; i < 8; i++) {
        types[i] = EXRIO_FLOAT;
        planes[i] = plane;
    }
    memset(&req, 0, sizeof req);
    req.need_depth = 1;
    test_write_exr(test_path(dir, "two_layers.exr"), &box, NULL, 8, two, types, planes,
                   EXRIO_COMPRESSION_NONE);
    CHECK(exrio_open(test_path(dir, "two_layers.exr"), &image, error, sizeof error) == EXRIO_OK);
    CHECK(exrio_find_layout(&image, &req, &layout, error, sizeof error) ==
          EXRIO_LAYOUT_AMBIGUOUS);
    CHECK_MSG(contains(error, "'A.Combined'") && contains(error, "'B.Combined'"), "%s", error);
    req.layer = "B";
    CHECK(exrio_find_layout(&image, &req, &layout, error, sizeof error) == EXRIO_LAYOUT_OK);
    CHECK(strcmp(image.channels[layout.color[0]].name, "B.Combined.R") == 0);
    CHECK(strcmp(image.channels[layout.depth].name, "B.Depth.Z") == 0);
    exrio_close(&image);

    req.layer = NULL;
    test_write_exr(test_path(dir, "composite.exr"), &box, NULL, 7, comp, types, planes,
                   EXRIO_COMPRESSION_NONE);
    CHECK(exrio_open(test_path(dir, "composite.exr"), &image, error, sizeof error) == EXRIO_OK);
    CHECK(exrio_find_layout(&image, &req, &layout, error, sizeof error) == EXRIO_LAYOUT_OK);
    CHECK(strcmp(layout.color_prefix, "ViewLayer.Combined") == 0 && layout.color_count == 3);
    CHECK(strcmp(image.channels[layout.depth].name, "ViewLayer.Depth.Z") == 0);
    exrio_close(&image);
}

/* A multi-part file whose depth part is smaller than its colour part. */
static void mismatched_parts(void)
{
    const char *path = test_path(dir, "mismatch.exr");
    exr_context_t ctxt = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    static const char *const rgb[3] = {"R", "G", "B"};
    float plane[16 * 8];
    exrio_layout_request req;
    exrio_layout layout;
    exrio_image image;
    char error[2048];
    int a = 0, b = 0, c, p;
    memset(plane, 0, sizeof plane);
    CHECK(exr_start_write(&ctxt, path, EXR_WRITE_FILE_DIRECTLY, &init) == 0);
    exr_add_part(ctxt, "rgba", EXR_STORAGE_SCANLINE, &a);
    exr_initialize_required_attr_simple(ctxt, a, 16, 8, EXR_COMPRESSION_NONE);
    for (c = 0; c < 3; c++)
        exr_add_channel(ctxt, a, rgb[c], EXR_PIXEL_HALF, EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
    exr_add_part(ctxt, "depth", EXR_STORAGE_SCANLINE, &b);
    exr_initialize_required_attr_simple(ctxt, b, 8, 4, EXR_COMPRESSION_NONE);
    exr_add_channel(ctxt, b, "Z", EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR, 1, 1);
    CHECK(exr_write_header(ctxt) == 0);
    for (p = 0; p < 2; p++) {
        exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
        exr_chunk_info_t cinfo;
        const int w = p ? 8 : 16, h = p ? 4 : 8;
        int y;
        for (y = 0; y < h; y++) {
            exr_write_scanline_chunk_info(ctxt, p, y, &cinfo);
            if (y == 0)
                exr_encoding_initialize(ctxt, p, &cinfo, &enc);
            else
                exr_encoding_update(ctxt, p, &cinfo, &enc);
            for (c = 0; c < enc.channel_count; c++) {
                enc.channels[c].encode_from_ptr = (const uint8_t *)(plane + y * w);
                enc.channels[c].user_pixel_stride = 4;
                enc.channels[c].user_line_stride = w * 4;
                enc.channels[c].user_bytes_per_element = 4;
                enc.channels[c].user_data_type = EXR_PIXEL_FLOAT;
            }
            if (y == 0)
                exr_encoding_choose_default_routines(ctxt, p, &enc);
            CHECK(exr_encoding_run(ctxt, p, &enc) == 0);
        }
        exr_encoding_destroy(ctxt, &enc);
    }
    CHECK(exr_finish(&ctxt) == 0);

    memset(&req, 0, sizeof req);
    req.need_depth = 1;
    CHECK(exrio_open(path, &image, error, sizeof error) == EXRIO_OK);
    CHECK(exrio_find_layout(&image, &req, &layout, error, sizeof error) ==
          EXRIO_LAYOUT_MISMATCH);
    CHECK_MSG(contains(error, "mismatched layer sizes") && contains(error, "8x4") &&
              contains(error, "16x8"), "%s", error);
    exrio_close(&image);
}

/* Data window (5,3)-(20,12) inside display window (0,0)-(31,19): read as it is, with both
 * windows reported, and pixel values where they were written. */
static void windows(void)
{
    static const char *const names[1] = {"Y"};
    const exrio_pixel_type types[1] = {EXRIO_FLOAT};
    float plane[16 * 10];
    const void *planes[1] = {plane};
    exrio_box data = test_box(5, 3, 16, 10), display = test_box(0, 0, 32, 20);
    exrio_image image;
    char error[2048];
    int i, bad = 0;
    for (i = 0; i < 160; i++)
        plane[i] = (float)i;
    test_write_exr(test_path(dir, "window.exr"), &data, &display, 1, names, types, planes,
                   EXRIO_COMPRESSION_ZIPS);
    CHECK(exrio_open(test_path(dir, "window.exr"), &image, error, sizeof error) == EXRIO_OK);
    CHECK(image.parts[0].data_window.min_x == 5 && image.parts[0].data_window.max_y == 12);
    CHECK(image.parts[0].display_window.max_x == 31 && image.parts[0].display_window.max_y == 19);
    CHECK(image.parts[0].width == 16 && image.parts[0].height == 10);
    CHECK(exrio_load(&image, NULL, error, sizeof error) == EXRIO_OK);
    for (i = 0; i < 160; i++)
        bad += ((float *)image.channels[0].pixels)[i] != (float)i;
    CHECK(bad == 0);
    exrio_close(&image);
}

int main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: test_exr_bad_input SCRATCH_DIR EXR_READ_CORPUS_DIR\n");
        return 2;
    }
    dir = argv[1];
    test_fresh_dir(dir);
    missing_and_not_exr();
    truncated();
    short_chunk();
    dwa();
    dwa_huge_tiles();
    dwa_window_disagrees(argv[2]);
    missing_channels();
    layers();
    mismatched_parts();
    windows();
    return test_finish("test_exr_bad_input");
}
