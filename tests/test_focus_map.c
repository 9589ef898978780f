/* SPDX-License-Identifier: MIT */
/* test_focus_map.c - the focal-plane view (ddof_focus_map, ddof_focus_map_legend): hand-computed
 * bytes of each band through strided images, the band counts, the aperture's legend (white
 * counts of a hexagon, an ellipse, a wide pentagon and an aperture image; none when round or
 * small), the legend call and the map drawing the same pixels, and bad input refused with a
 * message and nothing written. */
#ifndef DDOF_EXPERIMENTAL /* the build may define it already */
#define DDOF_EXPERIMENTAL
#endif
#include "ddof.h"
#include "test_util.h"

#include <string.h>

static uint8_t byte_of(double v)
{
    return (uint8_t)(fmin(fmax(v, 0.0), 1.0) * 255.0 + 0.5);
}

/* Four pixels in a row: in focus on white, near at the frame's largest blur on grey 0.25, far
 * at half of it on white, far at the largest on black; colour RGBA with a padded stride, CoC
 * padded too. */
static void test_bands(ddof_context *ctx)
{
    float color[2 * 4 * 4], coc[2 * 8];
    const float values[4][3] = {{1, 1, 1}, {0.25f, 0.25f, 0.25f}, {1, 1, 1}, {0, 0, 0}};
    const float cocs[4] = {0.5f, -9.0f, 5.0f, 9.0f};
    memset(color, 0, sizeof color);
    for (int i = 0; i < 4; i++) {
        memcpy(color + i * 4, values[i], sizeof values[i]);
        coc[i] = cocs[i];
    }
    const ddof_image_in color_in = {color, 4, 1, 4, 8 * 4 * sizeof(float)};
    const ddof_image_in coc_in = {coc, 4, 1, 1, 8 * sizeof(float)};
    uint8_t rgb[12], want[12];
    uint64_t counts[3] = {9, 9, 9};
    const double grey = 0.35 + 0.65 * sqrt(0.25), half = 0.35 + 0.65 * 0.5;
    const double hues[4][3] = {{0.15, 1.0, 0.2}, {1.0 * grey, 0.45 * grey, 0.1 * grey},
                               {0.2 * half, 0.45 * half, 1.0 * half},
                               {0.2 * 0.35, 0.45 * 0.35, 1.0 * 0.35}};
    for (int i = 0; i < 12; i++)
        want[i] = byte_of(hues[i / 3][i % 3]);
    CHECK(ddof_focus_map(ctx, &color_in, &coc_in, NULL, rgb, sizeof rgb, counts) == DDOF_OK);
    CHECK_MSG(memcmp(rgb, want, sizeof rgb) == 0, "%d %d %d | %d %d %d | %d %d %d | %d %d %d",
              rgb[0], rgb[1], rgb[2], rgb[3], rgb[4], rgb[5], rgb[6], rgb[7], rgb[8], rgb[9],
              rgb[10], rgb[11]);
    CHECK(counts[0] == 1 && counts[1] == 1 && counts[2] == 2);

    /* NaN and infinite CoC: not the largest (the finite 9 stays the scale), shown as far. */
    coc[0] = NAN;
    coc[1] = INFINITY;
    CHECK(ddof_focus_map(ctx, &color_in, &coc_in, NULL, rgb, sizeof rgb, counts) == DDOF_OK);
    CHECK(rgb[0] == byte_of(0.2) && rgb[2] == 255 && rgb[6] == want[6] && rgb[8] == want[8]);
    CHECK(counts[0] == 0 && counts[1] == 0 && counts[2] == 4);

    /* A frame all in focus is green, shaded (no blur to scale by). */
    for (int i = 0; i < 4; i++)
        coc[i] = 0.2f * (float)i;
    CHECK(ddof_focus_map(ctx, &color_in, &coc_in, NULL, rgb, sizeof rgb, NULL) == DDOF_OK);
    CHECK(rgb[1] == 255 && rgb[4] == byte_of(grey) && rgb[10] == byte_of(0.35));
}

static uint32_t white_pixels(const uint8_t *rgb, uint32_t w, uint32_t h)
{
    uint32_t white = 0;
    for (size_t j = 0; j < (size_t)w * h * 3; j += 3)
        white += rgb[j] == 255 && rgb[j + 1] == 255 && rgb[j + 2] == 255;
    return white;
}

/* The white pixel counts are the ones `ddof --focus-map` drew before the view moved into the
 * library (and the add-on's copy of it drew alike). */
static void test_legend(ddof_context *ctx)
{
    static uint8_t legend[320 * 240 * 3], map[200 * 120 * 3];
    static float grey[200 * 120 * 3], blur[200 * 120];
    const struct {
        uint32_t blades;
        double rotation, ratio;
        uint32_t w, h, white;
    } cases[] = {{6, 15.0, 1.0, 200, 120, 514}, {0, 0.0, 2.0, 200, 120, 312},
                 {5, 0.0, 0.5, 320, 240, 990}, {0, 0.0, 1.0, 200, 120, 0},
                 {6, 0.0, 1.0, 47, 200, 0}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        ddof_camera cam;
        ddof_camera_init(&cam);
        cam.aperture_blades = cases[k].blades;
        cam.aperture_rotation_deg = cases[k].rotation;
        cam.aperture_ratio = cases[k].ratio;
        const uint32_t w = cases[k].w, h = cases[k].h;
        memset(legend, 7, sizeof legend);
        CHECK(ddof_focus_map_legend(ctx, &cam, w, h, legend, sizeof legend) == DDOF_OK);
        const uint32_t white = white_pixels(legend, w, h);
        CHECK_MSG(white == cases[k].white, "legend %zu: %u white pixels, want %u", k, white,
                  cases[k].white);
        if (cases[k].white) {
            const uint32_t s = (w < h ? w : h) / 4 > 64 ? 64 : (w < h ? w : h) / 4;
            const size_t middle = ((size_t)(2 + s / 2) * w + (w - 2 - s / 2)) * 3;
            const size_t corner = ((size_t)2 * w + (w - 3)) * 3;
            CHECK(legend[middle] == 255 && legend[corner] == 0);
            CHECK(legend[0] == 7 && legend[((size_t)h * w - 1) * 3] == 7); /* outside: kept */
        } else {
            CHECK(white_pixels(legend, w, h) == 0 && legend[((size_t)w * 3) * 3] == 7);
        }
    }
    /* The map with the camera draws the same legend over its own pixels. */
    ddof_camera hexagon;
    ddof_camera_init(&hexagon);
    hexagon.aperture_blades = 6;
    hexagon.aperture_rotation_deg = 15.0;
    for (size_t i = 0; i < 200 * 120; i++) {
        blur[i] = 5.0f;
        grey[i * 3] = grey[i * 3 + 1] = grey[i * 3 + 2] = 0.5f;
    }
    const ddof_image_in color = {grey, 200, 120, 3, 0}, coc = {blur, 200, 120, 1, 0};
    CHECK(ddof_focus_map(ctx, &color, &coc, &hexagon, map, sizeof map, NULL) == DDOF_OK);
    memset(legend, 0, sizeof legend);
    CHECK(ddof_focus_map_legend(ctx, &hexagon, 200, 120, legend, sizeof map) == DDOF_OK);
    CHECK(white_pixels(map, 200, 120) == 514);
    const size_t middle = ((size_t)(2 + 15) * 200 + (200 - 2 - 15)) * 3;
    CHECK(map[middle] == 255 && map[0] == map[3] && map[0] != 255);

    /* An aperture image: its texels at least half the brightest are the shape. A 16x16 image
     * bright in its left half only: the legend's left half white, its right half black. */
    static float image[16 * 16];
    for (int i = 0; i < 16 * 16; i++)
        image[i] = i % 16 < 8 ? 1.0f : 0.4f;
    ddof_camera custom;
    ddof_camera_init(&custom);
    custom.aperture_image = image;
    custom.aperture_image_width = custom.aperture_image_height = 16;
    memset(legend, 0, sizeof legend);
    CHECK(ddof_focus_map_legend(ctx, &custom, 200, 120, legend, sizeof map) == DDOF_OK);
    const size_t left = ((size_t)17 * 200 + (200 - 2 - 30 + 5)) * 3;
    const size_t right = ((size_t)17 * 200 + (200 - 2 - 5)) * 3;
    CHECK_MSG(legend[left] == 255 && legend[right] == 0, "left %d right %d", legend[left],
              legend[right]);
    const uint32_t white = white_pixels(legend, 200, 120);
    CHECK_MSG(white > 350 && white < 450, "%u white pixels in a 30x30 legend, half of it", white);
}

static int mentions(ddof_context *ctx, const char *text)
{
    return strstr(ddof_context_last_error(ctx), text) != NULL;
}

static void test_bad_input(ddof_context *ctx)
{
    float color[4 * 2 * 3] = {0}, coc[4 * 2] = {0};
    uint8_t rgb[4 * 2 * 3];
    const ddof_image_in color_in = {color, 4, 2, 3, 0}, coc_in = {coc, 4, 2, 1, 0};
    const ddof_image_in two_channels = {color, 4, 2, 2, 0}, small_coc = {coc, 4, 1, 1, 0};
    memset(rgb, 7, sizeof rgb);
    CHECK(ddof_focus_map(ctx, NULL, &coc_in, NULL, rgb, sizeof rgb, NULL) ==
          DDOF_ERROR_NULL_POINTER);
    CHECK(mentions(ctx, "colour image is NULL"));
    CHECK(ddof_focus_map(ctx, &color_in, NULL, NULL, rgb, sizeof rgb, NULL) ==
          DDOF_ERROR_NULL_POINTER);
    CHECK(ddof_focus_map(ctx, &color_in, &coc_in, NULL, NULL, sizeof rgb, NULL) ==
          DDOF_ERROR_NULL_POINTER);
    CHECK(ddof_focus_map(ctx, &two_channels, &coc_in, NULL, rgb, sizeof rgb, NULL) ==
          DDOF_ERROR_BAD_PARAMETER);
    CHECK(mentions(ctx, "needs RGB"));
    CHECK(ddof_focus_map(ctx, &color_in, &small_coc, NULL, rgb, sizeof rgb, NULL) ==
          DDOF_ERROR_SIZE_MISMATCH);
    CHECK(ddof_focus_map(ctx, &color_in, &coc_in, NULL, rgb, sizeof rgb - 1, NULL) ==
          DDOF_ERROR_BAD_PARAMETER);
    CHECK(mentions(ctx, "too few"));
    ddof_camera cam;
    ddof_camera_init(&cam);
    cam.aperture_blades = DDOF_MAX_APERTURE_BLADES + 1;
    CHECK(ddof_focus_map(ctx, &color_in, &coc_in, &cam, rgb, sizeof rgb, NULL) != DDOF_OK);
    CHECK(mentions(ctx, "blades"));
    CHECK(ddof_focus_map_legend(ctx, &cam, 4, 2, rgb, sizeof rgb) != DDOF_OK);
    CHECK(ddof_focus_map_legend(ctx, NULL, 4, 2, rgb, sizeof rgb) == DDOF_ERROR_NULL_POINTER);
    ddof_camera_init(&cam);
    CHECK(ddof_focus_map_legend(ctx, &cam, 0, 2, rgb, sizeof rgb) == DDOF_ERROR_BAD_SIZE);
    CHECK(ddof_focus_map_legend(ctx, &cam, 65536, 65536, rgb, sizeof rgb) ==
          DDOF_ERROR_BAD_SIZE);
    CHECK(ddof_focus_map(NULL, &color_in, &coc_in, NULL, rgb, sizeof rgb, NULL) ==
          DDOF_ERROR_NULL_POINTER);
    int untouched = 1;
    for (size_t i = 0; i < sizeof rgb; i++)
        untouched &= rgb[i] == 7;
    CHECK_MSG(untouched, "a refused call wrote the map");
}

int main(void)
{
    ddof_context *ctx = NULL;
    CHECK(ddof_context_create(NULL, &ctx) == DDOF_OK);
    test_bands(ctx);
    test_legend(ctx);
    test_bad_input(ctx);
    ddof_context_free(ctx);
    return test_report("test_focus_map");
}
