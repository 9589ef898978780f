/* SPDX-License-Identifier: MIT */
/* test_exr_dwa.c - DWAA and DWAB, which exrio codes through OpenEXR's C++ library.
 *
 *   test_exr_dwa roundtrip SCRATCH_DIR
 *       exrio writes an image as DWAA and DWAB (the same bytes on 1 and 3 threads) and reads it
 *       back (the same planes on 1 and 4 threads): alpha, depth and ids exact (DWA keeps
 *       them losslessly), colour within DWA's loss of the source and of its ZIP twin.
 *   test_exr_dwa exrheader SCRATCH_DIR
 *       OpenEXR's own `exrheader` reads exrio's DWAA and DWAB files. Exits 77 (skipped)
 *       without it.
 *   test_exr_dwa blender SCRIPT SCRATCH_DIR
 *       Blender writes one image as ZIP, DWAA and DWAB (dwa_blender.py): exrio reads the DWA
 *       ones within DWA's loss of their ZIP twin. Blender reads exrio's DWAA and ZIP files
 *       (the ZIP deflated by libdeflate, exr_zip.c): what it reads is exactly what exrio
 *       reads. Exits 77 (skipped) without `blender`.
 *
 * DWA's loss: the colour channels go through an 8x8 DCT quantised in a perceptual space (level
 * 45, OpenEXR's default): on this image (gradients, a hard-edged square, a highlight of 4) the
 * error measured 0.17% of the value on average and 3.0% at worst (ringing at the edges), for
 * exrio's files and Blender's alike; the bounds below are about twice that. */
#include "exr_test_util.h"

#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define W 96
#define H 64
#define MEAN_BOUND 0.004
#define WORST_BOUND 0.06

static float plane[5][W * H];
static uint32_t ids[W * H];

/* As dwa_blender.py: gradients, a square of G 0.9, a disc of B 4, alpha 1; depth and ids. */
static void pattern(void)
{
    int x, y;
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            const size_t i = (size_t)y * W + (size_t)x;
            const int inside = x >= 30 && x < 60 && y >= 20 && y < 44;
            plane[0][i] = 0.1f + 0.8f * (float)x / (W - 1);
            plane[1][i] = inside ? 0.9f : 0.2f + 0.5f * (float)y / (H - 1);
            plane[2][i] = (x - 75) * (x - 75) + (y - 15) * (y - 15) < 36 ? 4.0f : 0.3f;
            plane[3][i] = 1.0f;
            plane[4][i] = 2.0f + 0.01f * (float)(x * y);
            ids[i] = inside ? 7u : 0xdeadbeefu;
        }
    }
}

static const char *const names[6] = {"R", "G", "B", "A", "Z", "id"};

static int write_pattern(const char *path, exrio_compression compression, unsigned threads)
{
    const exrio_pixel_type types[6] = {EXRIO_HALF, EXRIO_HALF, EXRIO_HALF, EXRIO_HALF,
                                       EXRIO_FLOAT, EXRIO_UINT};
    exrio_write_channel channels[6];
    exrio_write_spec spec;
    char error[1024];
    exrio_status status;
    int fd, c;
    for (c = 0; c < 6; c++) {
        channels[c].name = names[c];
        channels[c].type = types[c];
        channels[c].pixels = c < 5 ? (const void *)plane[c] : (const void *)ids;
        channels[c].pixel_stride = 4;
        channels[c].line_stride = W * 4;
    }
    memset(&spec, 0, sizeof spec);
    spec.data_window = test_box(10, -4, W, H);
    spec.display_window = test_box(0, -10, W + 20, H + 20);
    spec.compression = compression;
    spec.channel_count = 6;
    spec.channels = channels;
    spec.threads = threads;
    fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0666);
    if (fd < 0)
        return -1;
    status = exrio_write_fd(fd, path, &spec, error, sizeof error);
    close(fd);
    if (status != EXRIO_OK)
        fprintf(stderr, "%s\n", error);
    return status == EXRIO_OK ? 0 : -1;
}

static int load(const char *path, unsigned threads, exrio_image *image)
{
    char error[2048];
    if (exrio_open(path, image, error, sizeof error) != EXRIO_OK ||
        exrio_load_threads(image, NULL, threads, error, sizeof error) != EXRIO_OK) {
        CHECK_MSG(0, "%s", error);
        exrio_close(image);
        return -1;
    }
    return 0;
}

static const float *values(const exrio_image *image, const char *name)
{
    const int i = exrio_find_channel(image, name, -1);
    return i >= 0 ? image->channels[i].pixels : NULL;
}

/* Mean and largest |a - b| / max(|b|, 0.05) over the colour channels of two images. */
static void colour_error(const exrio_image *a, const exrio_image *b, const char *const *rgb,
                         double *mean, double *worst)
{
    size_t i, n = 0;
    int c;
    *mean = *worst = 0.0;
    for (c = 0; c < 3; c++) {
        const float *pa = values(a, rgb[c]), *pb = values(b, rgb[c]);
        CHECK_MSG(pa && pb, "no channel %s", rgb[c]);
        if (!pa || !pb)
            continue;
        for (i = 0; i < (size_t)a->parts[0].width * a->parts[0].height; i++, n++) {
            const double e = fabs((double)pa[i] - pb[i]) / fmax(fabs((double)pb[i]), 0.05);
            *mean += e;
            *worst = e > *worst ? e : *worst;
        }
    }
    *mean /= n ? (double)n : 1.0;
}

static void dwa_roundtrip(const char *dir, exrio_compression compression)
{
    const char *name = exrio_compression_name(compression);
    char one[64], three[64];
    size_t n1 = 0, n3 = 0, i;
    char *b1, *b3;
    exrio_image serial, parallel, zip;
    double mean, worst;
    int c, bad = 0;

    snprintf(one, sizeof one, "%s_1.exr", name);
    snprintf(three, sizeof three, "%s_3.exr", name);
    CHECK(write_pattern(test_path(dir, one), compression, 1) == 0);
    CHECK(write_pattern(test_path(dir, three), compression, 3) == 0);
    b1 = test_read_file(test_path(dir, one), &n1);
    b3 = test_read_file(test_path(dir, three), &n3);
    CHECK_MSG(b1 && b3 && n1 == n3 && memcmp(b1, b3, n1) == 0, "%s: 3 threads wrote other bytes",
              name);
    free(b1);
    free(b3);
    if (load(test_path(dir, one), 1, &serial) != 0)
        return;
    if (load(test_path(dir, one), 4, &parallel) != 0) {
        exrio_close(&serial);
        return;
    }
    CHECK(serial.parts[0].compression == compression);
    CHECK(serial.parts[0].data_window.min_x == 10 && serial.parts[0].data_window.min_y == -4 &&
          serial.parts[0].width == W && serial.parts[0].height == H);
    CHECK(serial.channel_count == 6);
    for (c = 0; c < serial.channel_count; c++)
        bad += memcmp(serial.channels[c].pixels, parallel.channels[c].pixels, (size_t)W * H * 4);
    CHECK_MSG(bad == 0, "%s: decoded on 4 threads differs", name);
    /* Lossless in DWA: alpha (RLE), depth and ids (zlib). */
    CHECK_MSG(memcmp(values(&serial, "A"), plane[3], sizeof plane[3]) == 0, "%s: alpha", name);
    CHECK_MSG(memcmp(values(&serial, "Z"), plane[4], sizeof plane[4]) == 0, "%s: depth", name);
    CHECK_MSG(memcmp(values(&serial, "id"), ids, sizeof ids) == 0, "%s: ids", name);

    /* Colour: against its ZIP twin (the half-rounded source). */
    CHECK(write_pattern(test_path(dir, "twin_zip.exr"), EXRIO_COMPRESSION_ZIP, 1) == 0);
    if (load(test_path(dir, "twin_zip.exr"), 1, &zip) == 0) {
        colour_error(&serial, &zip, names, &mean, &worst);
        printf("%s against ZIP: mean relative error %.4f, largest %.4f\n", name, mean, worst);
        CHECK_MSG(mean > 0.0 && mean < MEAN_BOUND && worst < WORST_BOUND,
                  "%s: mean %g, largest %g", name, mean, worst);
        exrio_close(&zip);
    }
    for (i = 0; i < (size_t)W * H; i++)
        bad += !isfinite(values(&serial, "R")[i]);
    CHECK(bad == 0);
    exrio_close(&serial);
    exrio_close(&parallel);
}

static int find_program(const char *name, char *out, size_t size)
{
    const char *p = getenv("PATH");
    while (p && *p) {
        const char *end = strchr(p, ':');
        const size_t len = end ? (size_t)(end - p) : strlen(p);
        snprintf(out, size, "%.*s/%s", (int)len, p, name);
        if (len > 0 && access(out, X_OK) == 0)
            return 0;
        p = end ? end + 1 : NULL;
    }
    return -1;
}

static int exrheader_reads(const char *dir)
{
    static const struct {
        exrio_compression compression;
        const char *says;
    } cases[2] = {{EXRIO_COMPRESSION_DWAA, "dwa, small scanline blocks"},
                  {EXRIO_COMPRESSION_DWAB, "dwa, medium scanline blocks"}};
    char program[4096];
    int k;
    if (find_program("exrheader", program, sizeof program) != 0) {
        printf("test_exr_dwa exrheader: skipped: exrheader (package openexr) is not on PATH\n");
        return 77;
    }
    for (k = 0; k < 2; k++) {
        char file[64];
        char *argv[3];
        char *out;
        int rc;
        snprintf(file, sizeof file, "%s.exr", exrio_compression_name(cases[k].compression));
        CHECK(write_pattern(test_path(dir, file), cases[k].compression, 2) == 0);
        argv[0] = program;
        argv[1] = (char *)test_path(dir, file);
        argv[2] = NULL;
        rc = test_run(dir, argv);
        out = test_read_file(test_path(dir, "run.out"), NULL);
        CHECK_MSG(rc == 0 && out && strstr(out, cases[k].says) &&
                      strstr(out, "id, 32-bit unsigned integer") &&
                      strstr(out, "Z, 32-bit floating-point") &&
                      strstr(out, "R, 16-bit floating-point") &&
                      strstr(out, "dataWindow (type box2i): (10 -4) - (105 59)"),
                  "exrheader %s: exit %d:\n%s", file, rc, out ? out : "(no output)");
        free(out);
    }
    return test_finish("test_exr_dwa exrheader");
}

static int blender_files(const char *script, const char *dir)
{
    static const char *const rgb[3] = {"R", "G", "B"};
    char blender[4096];
    static const char *const ours_files[2] = {"ours_dwaa.exr", "ours_zip.exr"};
    char *argv[] = {blender, "-b", "--factory-startup", "--python-exit-code", "1", "--python",
                    (char *)script, "--", (char *)dir, NULL, NULL, NULL};
    exrio_image zip, dwa, ours, read_back;
    int rc, k, c;
    if (find_program("blender", blender, sizeof blender) != 0) {
        printf("test_exr_dwa blender: skipped: blender is not on PATH\n");
        return 77;
    }
    for (k = 0; k < 2; k++) {
        argv[9 + k] = strdup(test_path(dir, ours_files[k]));
        CHECK(argv[9 + k] && write_pattern(argv[9 + k], k ? EXRIO_COMPRESSION_ZIP
                                                           : EXRIO_COMPRESSION_DWAA, 2) == 0);
    }
    rc = test_run(dir, argv);
    CHECK_MSG(rc == 0, "blender exited with %d (see %s/run.err)", rc, dir);
    if (rc != 0 || load(test_path(dir, "blender_zip.exr"), 1, &zip) != 0) {
        free(argv[9]);
        free(argv[10]);
        return test_finish("test_exr_dwa blender");
    }
    for (k = 0; k < 2; k++) {
        const char *file = k ? "blender_dwab.exr" : "blender_dwaa.exr";
        double mean, worst;
        if (load(test_path(dir, file), 2, &dwa) != 0)
            continue;
        CHECK(dwa.parts[0].compression ==
              (k ? EXRIO_COMPRESSION_DWAB : EXRIO_COMPRESSION_DWAA));
        CHECK(dwa.parts[0].width == W && dwa.parts[0].height == H);
        colour_error(&dwa, &zip, rgb, &mean, &worst);
        printf("%s against blender_zip.exr: mean relative error %.4f, largest %.4f\n", file,
               mean, worst);
        CHECK_MSG(mean > 0.0 && mean < MEAN_BOUND && worst < WORST_BOUND,
                  "%s: mean %g, largest %g", file, mean, worst);
        CHECK(memcmp(values(&dwa, "A"), values(&zip, "A"), (size_t)W * H * 4) == 0);
        exrio_close(&dwa);
    }
    exrio_close(&zip);
    /* Blender's reading of exrio's DWAA and ZIP files, saved as 32-bit ZIP, is exrio's reading
     * of them (the ZIP's chunks are libdeflate's streams, inflated by OpenEXR's C++ library). */
    for (k = 0; k < 2; k++) {
        char back[64];
        snprintf(back, sizeof back, "%.*s_read_by_blender.exr",
                 (int)(strlen(ours_files[k]) - strlen(".exr")), ours_files[k]);
        if (load(argv[9 + k], 1, &ours) == 0) {
            if (load(test_path(dir, back), 1, &read_back) == 0) {
                for (c = 0; c < 3; c++)
                    CHECK_MSG(values(&read_back, rgb[c]) &&
                                  memcmp(values(&read_back, rgb[c]), values(&ours, rgb[c]),
                                         (size_t)W * H * 4) == 0,
                              "Blender read channel %s of exrio's %s otherwise", rgb[c],
                              ours_files[k]);
                exrio_close(&read_back);
            }
            exrio_close(&ours);
        }
        free(argv[9 + k]);
    }
    return test_finish("test_exr_dwa blender");
}

int main(int argc, char **argv)
{
    pattern();
    if (argc == 3 && strcmp(argv[1], "roundtrip") == 0) {
        test_fresh_dir(argv[2]);
        dwa_roundtrip(argv[2], EXRIO_COMPRESSION_DWAA);
        dwa_roundtrip(argv[2], EXRIO_COMPRESSION_DWAB);
        return test_finish("test_exr_dwa roundtrip");
    }
    if (argc == 3 && strcmp(argv[1], "exrheader") == 0) {
        test_fresh_dir(argv[2]);
        return exrheader_reads(argv[2]);
    }
    if (argc == 4 && strcmp(argv[1], "blender") == 0) {
        test_fresh_dir(argv[3]);
        return blender_files(argv[2], argv[3]);
    }
    fprintf(stderr, "usage: test_exr_dwa roundtrip SCRATCH | exrheader SCRATCH | "
            "blender SCRIPT SCRATCH\n");
    return 2;
}
