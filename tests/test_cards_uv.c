/* SPDX-License-Identifier: MIT */
/* test_cards_uv.c - ddof_render_cards on a slanted triangle whose uv is a sub-triangle of a
 * texture with an exactly empty (all zero) part, against a double-precision brute force
 * written here from docs/cards.md's definition: per pixel the Cycles CoC of the ray's depth,
 * a dense grid of points over the screen disc, each cast by its own ray onto the card's plane;
 * the point's uv (the plane's affine map) picks the texel containing it, which counts only if
 * the texel's centre lies inside the card's uv triangle (texels are in or out whole). This
 * covers what the rectangle cards of test_cards.c do not: a uv polygon inside the texture (the
 * summed-area table's per-row spans), and discs over empty texture (skipped by the count
 * table). The image is also the same, bit for bit, on 1 and 3 threads. */
#ifndef DDOF_EXPERIMENTAL
#define DDOF_EXPERIMENTAL
#endif
#include "cards_reference.h"
#include "test_util.h"

#include <string.h>

#define W 96
#define H 64
#define TW 24
#define TH 16

static float texture[TH * TW * 4];

/* Random premultiplied RGBA (alpha 0.2..1), columns 14..23 of rows 0..7 exactly zero. */
static void make_texture(void)
{
    test_rng rng = {4242};
    for (int j = 0; j < TH; j++)
        for (int i = 0; i < TW; i++) {
            float *t = texture + (j * TW + i) * 4;
            const double a = 0.2 + 0.8 * test_uniform(&rng);
            for (int c = 0; c < 3; c++)
                t[c] = (float)(a * test_uniform(&rng));
            t[3] = (float)a;
            if (i >= 14 && j < 8)
                memset(t, 0, 4 * sizeof *t);
        }
}

static const double corner[3][3] = {{-0.35, -0.25, -1.2}, {0.45, -0.15, -2.6}, {0.0, 0.3, -1.8}};
static const double corner_uv[3][2] = {{0.05, 0.1}, {0.95, 0.3}, {0.4, 0.95}};

static ddof_camera test_camera(void)
{
    ddof_camera cam;
    ddof_camera_init(&cam);
    cam.focal_length_mm = 50.0;
    cam.sensor_width_mm = 36.0;
    cam.fstop = 1.4;
    cam.focus_distance_m = 0.8;
    return cam;
}

static ddof_card triangle_card(void)
{
    ddof_card card;
    memset(&card, 0, sizeof card);
    card.vertex_count = 3;
    for (int k = 0; k < 3; k++) {
        for (int a = 0; a < 3; a++)
            card.position[k][a] = (float)corner[k][a];
        card.uv[k][0] = (float)corner_uv[k][0];
        card.uv[k][1] = (float)corner_uv[k][1];
    }
    card.texture = (ddof_image_in){texture, TW, TH, 4, 0};
    return card;
}

/* ---- the brute force ---------------------------------------------------------------------- */

/* Barycentric coordinates of point p in the 2D triangle t. */
static void barycentric(const double t[3][2], double px, double py, double b[3])
{
    const double det = (t[1][0] - t[0][0]) * (t[2][1] - t[0][1]) -
                       (t[2][0] - t[0][0]) * (t[1][1] - t[0][1]);
    b[1] = ((px - t[0][0]) * (t[2][1] - t[0][1]) - (t[2][0] - t[0][0]) * (py - t[0][1])) / det;
    b[2] = ((t[1][0] - t[0][0]) * (py - t[0][1]) - (px - t[0][0]) * (t[1][1] - t[0][1])) / det;
    b[0] = 1.0 - b[1] - b[2];
}

/* Ray d meets the card's plane at depth *z and texture coordinates (u, v). */
static int hit(const double d[3], double *z, double *u, double *v)
{
    double e1[3], e2[3], n[3];
    for (int a = 0; a < 3; a++) {
        e1[a] = corner[1][a] - corner[0][a];
        e2[a] = corner[2][a] - corner[0][a];
    }
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    const double t = (n[0] * corner[0][0] + n[1] * corner[0][1] + n[2] * corner[0][2]) /
                     (n[0] * d[0] + n[1] * d[1] + n[2] * d[2]);
    if (!(t > 0.0))
        return 0;
    /* q = corner0 + s e1 + r e2: solve the 2x2 normal equations for s, r. */
    double q[3], g11 = 0, g12 = 0, g22 = 0, h1 = 0, h2 = 0;
    for (int a = 0; a < 3; a++) {
        q[a] = t * d[a] - corner[0][a];
        g11 += e1[a] * e1[a];
        g12 += e1[a] * e2[a];
        g22 += e2[a] * e2[a];
        h1 += q[a] * e1[a];
        h2 += q[a] * e2[a];
    }
    const double det = g11 * g22 - g12 * g12, s = (h1 * g22 - h2 * g12) / det,
                 r = (g11 * h2 - g12 * h1) / det;
    *z = t;
    *u = corner_uv[0][0] + s * (corner_uv[1][0] - corner_uv[0][0]) +
         r * (corner_uv[2][0] - corner_uv[0][0]);
    *v = corner_uv[0][1] + s * (corner_uv[1][1] - corner_uv[0][1]) +
         r * (corner_uv[2][1] - corner_uv[0][1]);
    return 1;
}

/* The texel containing (u, v), if its centre lies inside the uv triangle; else 0. */
static void texel(double u, double v, double out[4])
{
    memset(out, 0, 4 * sizeof *out);
    if (u < 0.0 || u >= 1.0 || v <= 0.0 || v > 1.0)
        return;
    const int tx = (int)(u * TW), ty = (int)((1.0 - v) * TH);
    double b[3];
    barycentric(corner_uv, (tx + 0.5) / TW, 1.0 - (ty + 0.5) / TH, b);
    if (b[0] < 0.0 || b[1] < 0.0 || b[2] < 0.0)
        return;
    for (int c = 0; c < 4; c++)
        out[c] = texture[(ty * TW + tx) * 4 + c];
}

static void reference(const ddof_camera *cam, int x, int y, double out[4])
{
    memset(out, 0, 4 * sizeof *out);
    double d[3], z, u, v;
    cards_ref_ray(cam, W, H, x + 0.5, y + 0.5, d);
    if (!hit(d, &z, &u, &v))
        return;
    const double f = cam->focal_length_mm, s1 = cam->focus_distance_m * 1000.0;
    const double coc_mm = f * f / (cam->fstop * s1) * fabs(z * 1000.0 - s1) / (z * 1000.0);
    const double r = fmax(0.5 * coc_mm / (cam->sensor_width_mm / W), 0.5);
    const int grid = 40;
    int count = 0;
    for (int j = 0; j < grid; j++)
        for (int i = 0; i < grid; i++) {
            const double ex = -1.0 + (2.0 * i + 1.0) / grid, ey = -1.0 + (2.0 * j + 1.0) / grid;
            if (ex * ex + ey * ey > 1.0)
                continue;
            count++;
            double e[3], t[4];
            cards_ref_ray(cam, W, H, x + 0.5 + r * ex, y + 0.5 + r * ey, e);
            if (!hit(e, &z, &u, &v))
                continue;
            texel(u, v, t);
            for (int c = 0; c < 4; c++)
                out[c] += t[c];
        }
    for (int c = 0; c < 4; c++)
        out[c] /= count;
}

/* ---- the checks --------------------------------------------------------------------------- */

static ddof_status render(uint32_t threads, float *out)
{
    ddof_context_options options;
    ddof_context_options_init(&options);
    options.thread_count = threads;
    ddof_context *ctx = NULL;
    if (ddof_context_create(&options, &ctx) != DDOF_OK)
        return DDOF_ERROR_THREADS;
    const ddof_camera cam = test_camera();
    const ddof_card card = triangle_card();
    ddof_image img = {out, W, H, 4, 0};
    const ddof_status status = ddof_render_cards(ctx, NULL, &cam, &card, 1, &img);
    ddof_context_free(ctx);
    return status;
}

static void test_against_reference(const float *out)
{
    const ddof_camera cam = test_camera();
    double max_abs = 0.0, sum = 0.0, missed = 0.0, drawn_alpha = 0.0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double ref[4];
            reference(&cam, x, y, ref);
            for (int c = 0; c < 4; c++) {
                const double diff = out[(y * W + x) * 4 + c] - ref[c];
                max_abs = fmax(max_abs, fabs(diff));
                sum += diff * diff;
            }
            if (out[(y * W + x) * 4 + 3] == 0.0f)
                missed += ref[3];
            drawn_alpha += ref[3];
        }
    const double rms = sqrt(sum / (W * H * 4));
    printf("triangle card, uv inside the texture, an empty block: max |err| %.4f, rms %.5f, "
           "missed alpha %.3f px of %.1f\n", max_abs, rms, missed, drawn_alpha);
    CHECK(drawn_alpha > 500.0); /* the card covers a good part of the image */
    CHECK_MSG(max_abs < 0.06, "max %g", max_abs);
    CHECK_MSG(rms < 0.008, "rms %g", rms);
    CHECK_MSG(missed < 0.05, "missed %g", missed);
}

/* Pixels whose whole disc lies on empty texture or off the card are exactly 0 (and there are
 * some of each). */
static void test_empty_exact(const float *out)
{
    const ddof_camera cam = test_camera();
    int empty = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double ref[4];
            reference(&cam, x, y, ref);
            if (ref[0] == 0.0 && ref[1] == 0.0 && ref[2] == 0.0 && ref[3] == 0.0) {
                empty++;
                const float *p = out + (y * W + x) * 4;
                /* the brute force's grid may miss a sliver the library's exact area sees */
                CHECK_MSG(fabs(p[3]) < 0.02, "(%d, %d) alpha %g", x, y, p[3]);
            }
        }
    CHECK(empty > 100);
}

int main(void)
{
    make_texture();
    static float one[W * H * 4], three[W * H * 4];
    CHECK_EQ_INT(render(1, one), DDOF_OK);
    CHECK_EQ_INT(render(3, three), DDOF_OK);
    CHECK(memcmp(one, three, sizeof one) == 0);
    test_against_reference(one);
    test_empty_exact(one);
    return test_report("test_cards_uv");
}
