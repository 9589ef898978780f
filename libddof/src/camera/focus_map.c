/* SPDX-License-Identifier: MIT */
/* focus_map.c - the focal-plane view (ddof_focus_map, ddof.h): the frame in false colour by its
 * circle of confusion, and the camera's aperture as its legend. The `ddof` command's
 * --focus-map and the Blender add-on's focal-plane view both draw it through these calls. */
#include "coc.h"

#include <math.h>

#define PI 3.14159265358979323846
#define FOCUS_MAP_SHARP_PX 1.0 /* |CoC| under this is in focus (green) */

static const double SHARP_HUE[3] = {0.15, 1.0, 0.2}, NEAR_HUE[3] = {1.0, 0.45, 0.1},
                    FAR_HUE[3] = {0.2, 0.45, 1.0};

static uint8_t byte_of(double v)
{
    return (uint8_t)(fmin(fmax(v, 0.0), 1.0) * 255.0 + 0.5);
}

static float coc_of(const ddof_image_in *coc, size_t stride, uint32_t x, uint32_t y)
{
    return coc->pixels[(size_t)y * stride + x];
}

/* Blur strength t = (|CoC| - sharp) / (largest - sharp), clamped to 0..1, is the hue's
 * brightness 0.35 + 0.65 t; every colour is shaded by the picture's luminance (0.35 + 0.65
 * sqrt(Y)) so that the frame stays recognisable. A NaN CoC is far blur at its brightest. */
static void map_pixels(const ddof_image_in *color, size_t color_stride, const ddof_image_in *coc,
                       size_t coc_stride, uint8_t *rgb, uint64_t counts[3])
{
    double largest = 0.0;
    for (uint32_t y = 0; y < coc->height; y++)
        for (uint32_t x = 0; x < coc->width; x++) {
            const float d = coc_of(coc, coc_stride, x, y);
            if (isfinite(d))
                largest = fmax(largest, fabs((double)d));
        }
    const double span = largest - FOCUS_MAP_SHARP_PX;
    for (uint32_t y = 0; y < coc->height; y++)
        for (uint32_t x = 0; x < coc->width; x++) {
            const float *p =
                color->pixels + (size_t)y * color_stride + (size_t)x * color->channels;
            const float d = coc_of(coc, coc_stride, x, y);
            const double lum =
                fmin(fmax(0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2], 0.0), 1.0);
            const double shade = 0.35 + 0.65 * sqrt(lum);
            const double a = fabs((double)d);
            const double *hue = SHARP_HUE;
            double v = 1.0;
            int band = 0;
            if (!(a < FOCUS_MAP_SHARP_PX)) {
                const double t = span > 0.0 ? fmin((a - FOCUS_MAP_SHARP_PX) / span, 1.0) : 1.0;
                band = d < 0.0f ? 1 : 2;
                hue = band == 1 ? NEAR_HUE : FAR_HUE;
                v = 0.35 + 0.65 * t;
            }
            counts[band]++;
            uint8_t *out = rgb + ((size_t)y * coc->width + x) * 3;
            for (int c = 0; c < 3; c++)
                out[c] = byte_of(hue[c] * v * shade);
        }
}

/* Whether the legend's point (x, y) (image axes, y down, the shape's unit radius at height 1)
 * lies in the aperture, as a light behind the focus draws it: an aperture image's texel at
 * least half its brightest, else the round aperture or Cycles' polygon (at rotation 0 an
 * edge's middle on the +x axis, y up), 1 / ratio wide. */
static int in_aperture(const ddof_camera *camera, float peak, double x, double y)
{
    const double ratio = camera->aperture_ratio;
    if (camera->aperture_image) {
        const uint32_t w = camera->aperture_image_width, h = camera->aperture_image_height;
        const double u = (x * ratio + 1.0) * 0.5 * w, v = (y + 1.0) * 0.5 * h;
        if (!(u >= 0.0 && u < w && v >= 0.0 && v < h))
            return 0;
        return camera->aperture_image[(size_t)v * w + (size_t)u] >= 0.5f * peak;
    }
    const double ax = x * ratio, ay = -y;
    if (camera->aperture_blades < 3)
        return ax * ax + ay * ay <= 1.0;
    double far = -INFINITY;
    for (uint32_t k = 0; k < camera->aperture_blades; k++) {
        const double a = camera->aperture_rotation_deg * (PI / 180.0) +
                         2.0 * PI * k / camera->aperture_blades;
        far = fmax(far, ax * cos(a) + ay * sin(a));
    }
    return far <= cos(PI / camera->aperture_blades);
}

/* The legend: a square of min(64, the smaller side / 4) pixels, 2 from the top and right
 * edges, white inside the shape and black around it; nothing for a round aperture or a map
 * under 48 pixels a side. */
static void draw_legend(const ddof_camera *camera, uint32_t width, uint32_t height, uint8_t *rgb)
{
    if (camera->aperture_blades < 3 && camera->aperture_ratio == 1.0 && !camera->aperture_image)
        return;
    const uint32_t side = (width < height ? width : height) / 4;
    const uint32_t s = side > 64 ? 64 : side;
    if (s < 12)
        return;
    const uint32_t x0 = width - s - 2, y0 = 2;
    const double half = 0.5 * s, scale = half - 1.0;
    /* The shape is 1 / ratio wide and 1 tall: the larger of the two fills the square. */
    const double extent = camera->aperture_ratio < 1.0 ? 1.0 / camera->aperture_ratio : 1.0;
    float peak = 0.0f;
    const size_t texels = camera->aperture_image ? (size_t)camera->aperture_image_width *
                                                       camera->aperture_image_height
                                                 : 0;
    for (size_t i = 0; i < texels; i++)
        peak = camera->aperture_image[i] > peak ? camera->aperture_image[i] : peak;
    for (uint32_t y = y0; y < y0 + s; y++)
        for (uint32_t x = x0; x < x0 + s; x++) {
            const double u = (x + 0.5 - (x0 + half)) / scale * extent;
            const double v = (y + 0.5 - (y0 + half)) / scale * extent;
            const uint8_t value = in_aperture(camera, peak, u, v) ? 255 : 0;
            for (int c = 0; c < 3; c++)
                rgb[((size_t)y * width + x) * 3 + (size_t)c] = value;
        }
}

static ddof_status check_rgb(ddof_context *context, uint32_t width, uint32_t height,
                             const uint8_t *rgb, size_t rgb_size)
{
    if (!rgb)
        return ddof_fail(context, DDOF_ERROR_NULL_POINTER, "the map's bytes are NULL");
    if (rgb_size / 3 / width < height)
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "the map's %zu bytes are too few for %ux%u RGB (%zu)", rgb_size, width,
                         height, (size_t)width * height * 3);
    return DDOF_OK;
}

static ddof_status check_map_images(ddof_context *context, const ddof_image_in *color,
                                    const ddof_image_in *coc, size_t *color_stride,
                                    size_t *coc_stride)
{
    const ddof_status status =
        ddof_check_image_and_coc(context, "colour", color, coc, color_stride, coc_stride);
    if (status == DDOF_OK && color->channels < 3)
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "the colour has %u channels; the map needs RGB (3 or 4)",
                         color->channels);
    return status;
}

static ddof_status focus_map(ddof_context *context, const ddof_image_in *color,
                             const ddof_image_in *coc, const ddof_camera *camera, uint8_t *rgb,
                             size_t rgb_size, uint64_t *counts)
{
    size_t color_stride, coc_stride;
    ddof_camera full;
    ddof_status status = check_map_images(context, color, coc, &color_stride, &coc_stride);
    if (status == DDOF_OK)
        status = check_rgb(context, color->width, color->height, rgb, rgb_size);
    if (status == DDOF_OK && camera)
        status = ddof_read_camera(context, camera, &full);
    if (status != DDOF_OK)
        return status;
    uint64_t bands[3] = {0, 0, 0};
    map_pixels(color, color_stride, coc, coc_stride, rgb, bands);
    if (camera)
        draw_legend(&full, color->width, color->height, rgb);
    for (int i = 0; counts && i < 3; i++)
        counts[i] = bands[i];
    return DDOF_OK;
}

static ddof_status focus_map_legend(ddof_context *context, const ddof_camera *camera,
                                    uint32_t width, uint32_t height, uint8_t *rgb,
                                    size_t rgb_size)
{
    ddof_camera full;
    if (!camera)
        return ddof_fail(context, DDOF_ERROR_NULL_POINTER, "camera is NULL");
    if (width == 0 || height == 0 || width > DDOF_MAX_DIMENSION || height > DDOF_MAX_DIMENSION ||
        (uint64_t)width * height > DDOF_MAX_PIXELS)
        return ddof_fail(context, DDOF_ERROR_BAD_SIZE,
                         "the map is %ux%u; each side must be 1 to %u, %llu pixels at most",
                         width, height, DDOF_MAX_DIMENSION,
                         (unsigned long long)DDOF_MAX_PIXELS);
    ddof_status status = check_rgb(context, width, height, rgb, rgb_size);
    if (status == DDOF_OK)
        status = ddof_read_camera(context, camera, &full);
    if (status == DDOF_OK)
        draw_legend(&full, width, height, rgb);
    return status;
}

ddof_status ddof_focus_map(ddof_context *context, const ddof_image_in *color,
                           const ddof_image_in *coc, const ddof_camera *camera, uint8_t *rgb,
                           size_t rgb_size, uint64_t counts[3])
{
    DDOF_EXCLUSIVE_CALL(context, focus_map(context, color, coc, camera, rgb, rgb_size, counts));
}

ddof_status ddof_focus_map_legend(ddof_context *context, const ddof_camera *camera,
                                  uint32_t width, uint32_t height, uint8_t *rgb, size_t rgb_size)
{
    DDOF_EXCLUSIVE_CALL(context,
                        focus_map_legend(context, camera, width, height, rgb, rgb_size));
}
