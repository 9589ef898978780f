/* SPDX-License-Identifier: MIT */
/* test_exr_blender.c - reading real Blender output.
 *
 *   test_exr_blender sample SAMPLES_DIR SCRATCH_DIR
 *       the committed sample (samples/pinhole.exr, truth.exr, camera.json): Blender's
 *       multilayer names and pixel types, the scene's known depths, and the sidecar.
 *   test_exr_blender fresh MAKE_SAMPLE_PY SCRATCH_DIR
 *       renders the "flat" scene of samples/make_sample.py with `blender -b` now (an emissive
 *       plane of colour (0.25, 0.5, 0.75) facing the camera at 5 m) and checks every pixel:
 *       exact colour, alpha 1 and planar depth 5 (radial depth would reach 5.14 in the
 *       corners). Exits 77 (skipped) when `blender` is not on PATH. */
#include "camera_json.h"
#include "exr_test_util.h"
#include "exrio_layout.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const exrio_channel *channel(const exrio_image *image, const char *name)
{
    int i = exrio_find_channel(image, name, -1);
    return i >= 0 ? &image->channels[i] : NULL;
}

static float at(const exrio_image *image, const char *name, uint32_t x, uint32_t y)
{
    const exrio_channel *ch = channel(image, name);
    return ch && ch->pixels ? ((const float *)ch->pixels)[(size_t)y * image->parts[0].width + x]
                            : NAN;
}

/* Opens a Blender multilayer render and checks its layout; loads every channel. */
static int open_blender(const char *path, exrio_image *image, uint32_t w, uint32_t h)
{
    static const char *const rgba[4] = {"ViewLayer.Combined.R", "ViewLayer.Combined.G",
                                        "ViewLayer.Combined.B", "ViewLayer.Combined.A"};
    exrio_layout_request req;
    exrio_layout layout;
    char error[2048];
    int c;
    if (exrio_open(path, image, error, sizeof error) != EXRIO_OK) {
        CHECK_MSG(0, "%s", error);
        return -1;
    }
    CHECK(image->part_count == 1 && image->channel_count == 5);
    CHECK(image->parts[0].width == w && image->parts[0].height == h);
    for (c = 0; c < 4; c++)
        CHECK_MSG(channel(image, rgba[c]) && channel(image, rgba[c])->type == EXRIO_HALF, "%s",
                  rgba[c]);
    CHECK(channel(image, "ViewLayer.Depth.Z") &&
          channel(image, "ViewLayer.Depth.Z")->type == EXRIO_FLOAT);
    memset(&req, 0, sizeof req);
    req.need_depth = 1;
    CHECK(exrio_find_layout(image, &req, &layout, error, sizeof error) == EXRIO_LAYOUT_OK);
    CHECK(strcmp(layout.color_prefix, "ViewLayer.Combined") == 0 && layout.color_count == 4);
    CHECK(layout.depth >= 0 && strcmp(image->channels[layout.depth].name, "ViewLayer.Depth.Z") == 0);
    if (exrio_load(image, NULL, error, sizeof error) != EXRIO_OK) {
        CHECK_MSG(0, "%s", error);
        return -1;
    }
    return 0;
}

static int committed_sample(const char *samples, const char *scratch)
{
    exrio_image pinhole, truth;
    camera_sidecar sidecar;
    char error[2048];
    const size_t n = 320 * 180;
    double mean_pinhole = 0.0, mean_truth = 0.0, zmin = INFINITY;
    size_t i;
    int bad = 0, sky = 0;
    (void)scratch;

    if (open_blender(test_path(samples, "pinhole.exr"), &pinhole, 320, 180) != 0)
        return test_finish("test_exr_blender sample");
    CHECK(pinhole.parts[0].compression == EXRIO_COMPRESSION_ZIP);
    for (i = 0; i < n; i++) {
        const float a = ((const float *)channel(&pinhole, "ViewLayer.Combined.A")->pixels)[i];
        const float z = ((const float *)channel(&pinhole, "ViewLayer.Depth.Z")->pixels)[i];
        const float r = ((const float *)channel(&pinhole, "ViewLayer.Combined.R")->pixels)[i];
        bad += a != 1.0f || !(r >= 0.0f) || !isfinite(r) || !(z > 0.0f);
        if (z > 1e6f)
            sky++;
        else if (z < zmin)
            zmin = z;
        mean_pinhole += r;
    }
    CHECK_MSG(bad == 0, "%d pixels with alpha != 1, negative colour or bad depth", bad);
    /* The scene: the nearest surface is the post (1.6 m away, radius 6 cm); the sky strip
     * above the wall has no surface (Cycles writes 1e10); Suzanne's face at the frame centre
     * is in front of the focus plane at 4 m; the brick wall is at 25 m. */
    CHECK_MSG(zmin > 1.5 && zmin < 1.6, "nearest depth %g", zmin);
    CHECK_MSG(sky > 320 * 10 && sky < 320 * 60, "%d sky pixels", sky);
    CHECK_MSG(at(&pinhole, "ViewLayer.Depth.Z", 160, 90) > 3.5f &&
              at(&pinhole, "ViewLayer.Depth.Z", 160, 90) < 4.0f, "centre depth %g",
              (double)at(&pinhole, "ViewLayer.Depth.Z", 160, 90));
    CHECK_MSG(fabsf(at(&pinhole, "ViewLayer.Depth.Z", 300, 60) - 25.0f) < 0.01f,
              "wall depth %g", (double)at(&pinhole, "ViewLayer.Depth.Z", 300, 60));
    CHECK(at(&pinhole, "ViewLayer.Depth.Z", 160, 2) > 1e6f);

    if (exrio_open(test_path(samples, "truth.exr"), &truth, error, sizeof error) != EXRIO_OK ||
        exrio_load(&truth, NULL, error, sizeof error) != EXRIO_OK) {
        CHECK_MSG(0, "%s", error);
    } else {
        CHECK(truth.channel_count == 4 && truth.parts[0].width == 320 &&
              truth.parts[0].height == 180);
        CHECK(channel(&truth, "R") && channel(&truth, "R")->type == EXRIO_HALF);
        for (i = 0; i < n; i++)
            mean_truth += ((const float *)channel(&truth, "R")->pixels)[i];
        /* Lens blur moves light around but keeps it: the means agree closely. */
        CHECK_MSG(fabs(mean_truth - mean_pinhole) < 0.03 * mean_pinhole,
                  "mean red: truth %g, pinhole %g", mean_truth / n, mean_pinhole / n);
    }
    exrio_close(&truth);
    exrio_close(&pinhole);

    CHECK_MSG(camera_sidecar_read(test_path(samples, "camera.json"), &sidecar, error,
                                  sizeof error) == 0, "%s", error);
    CHECK(sidecar.camera.focal_length_mm == 85.0 && sidecar.camera.sensor_width_mm == 36.0 &&
          sidecar.camera.fstop == 1.4 && sidecar.camera.focus_distance_m == 4.0 &&
          sidecar.camera.sensor_fit == DDOF_SENSOR_FIT_AUTO &&
          sidecar.camera.depth_kind == DDOF_DEPTH_PLANAR && sidecar.resolution[0] == 320 &&
          sidecar.resolution[1] == 180);
    return test_finish("test_exr_blender sample");
}

static int find_blender(char *out, size_t size)
{
    const char *path = getenv("PATH");
    const char *p = path;
    while (p && *p) {
        const char *end = strchr(p, ':');
        size_t len = end ? (size_t)(end - p) : strlen(p);
        snprintf(out, size, "%.*s/blender", (int)len, p);
        if (len > 0 && access(out, X_OK) == 0)
            return 0;
        p = end ? end + 1 : NULL;
    }
    return -1;
}

static int fresh(const char *script, const char *scratch)
{
    char blender[4096];
    exrio_image image;
    uint32_t x, y;
    int bad_color = 0, bad_depth = 0, rc;
    char *argv[] = {blender, "-b", "--factory-startup", "--python-exit-code", "1",
                    "--python", (char *)script, "--", "--out", (char *)scratch,
                    "--scene", "flat", "--size", "48x27", "--samples-pinhole", "4",
                    "--only", "pinhole", "--threads", "1", NULL};
    if (find_blender(blender, sizeof blender) != 0) {
        printf("test_exr_blender fresh: skipped: blender is not on PATH\n");
        return 77;
    }
    test_fresh_dir(scratch);
    rc = test_run(scratch, argv);
    CHECK_MSG(rc == 0, "blender exited with %d (see %s/run.err)", rc, scratch);
    if (rc != 0 || open_blender(test_path(scratch, "pinhole.exr"), &image, 48, 27) != 0)
        return test_finish("test_exr_blender fresh");
    for (y = 0; y < 27; y++) {
        for (x = 0; x < 48; x++) {
            bad_color += fabsf(at(&image, "ViewLayer.Combined.R", x, y) - 0.25f) > 1e-3f ||
                         fabsf(at(&image, "ViewLayer.Combined.G", x, y) - 0.5f) > 1e-3f ||
                         fabsf(at(&image, "ViewLayer.Combined.B", x, y) - 0.75f) > 1e-3f ||
                         at(&image, "ViewLayer.Combined.A", x, y) != 1.0f;
            bad_depth += fabsf(at(&image, "ViewLayer.Depth.Z", x, y) - 5.0f) > 1e-3f;
        }
    }
    CHECK_MSG(bad_color == 0, "%d pixels are not (0.25, 0.5, 0.75, 1)", bad_color);
    CHECK_MSG(bad_depth == 0, "%d pixels do not have planar depth 5 (corner %g)", bad_depth,
              (double)at(&image, "ViewLayer.Depth.Z", 0, 0));
    exrio_close(&image);
    return test_finish("test_exr_blender fresh");
}

int main(int argc, char **argv)
{
    if (argc == 4 && strcmp(argv[1], "sample") == 0)
        return committed_sample(argv[2], argv[3]);
    if (argc == 4 && strcmp(argv[1], "fresh") == 0)
        return fresh(argv[2], argv[3]);
    fprintf(stderr, "usage: test_exr_blender sample SAMPLES_DIR SCRATCH | fresh SCRIPT SCRATCH\n");
    return 2;
}
