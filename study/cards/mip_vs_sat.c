/* SPDX-License-Identifier: MIT */
/* mip_vs_sat.c - the texture average over a pixel's disc, two ways, against a brute force
 * (issue 25: "a summed-area table or a mip pyramid: measure each against a brute-force disc
 * average and keep the better"; docs/cards.md, Accuracy).
 *   SAT : ddof_render_cards itself (double summed-area table, 8 strips: 32 bilinear table
 *         reads, 128 values, per pixel)
 *   mip1: one trilinear tap of a mip pyramid at the disc's centre, level log2(sqrt(area)),
 *         area the ellipse's in texels (what a fragment shader's textureLod gives: 8 texels)
 *   mip16: 16 trilinear taps spread evenly over the ellipse (a Vogel spiral), each at the
 *         level of a 16th of its area (128 texels: the SAT's cost)
 * The brute force is test_cards.c's: per pixel the Cycles CoC of the ray's depth, a 40x40 grid
 * over the screen disc, each point's own ray onto the card, the texel hit (transparent off the
 * card). The mip variants get each pixel's ellipse from the same rays (centre and finite
 * differences), so they differ from the reference only in how they average the texture.
 * Usage: mip_vs_sat (prints a table). Built by study/cards/run.sh. */
#define DDOF_EXPERIMENTAL
#include "cards_reference.h"
#include "ddof.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define W 96
#define H 64
#define MAX_LEVELS 12

typedef struct texture {
    uint32_t w, h;
    float *texels; /* premultiplied RGBA, row 0 at the top */
} texture;

typedef struct pyramid {
    uint32_t levels, w[MAX_LEVELS], h[MAX_LEVELS];
    double *texels[MAX_LEVELS];
} pyramid;

static double uniform(unsigned long long *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) / 9007199254740992.0;
}

/* Random premultiplied RGBA, alpha 0.2..1 (as test_cards.c's). */
static texture random_texture(uint32_t w, uint32_t h, unsigned long long seed)
{
    texture t = {w, h, malloc((size_t)w * h * 4 * sizeof(float))};
    for (size_t i = 0; i < (size_t)w * h; i++) {
        const double a = 0.2 + 0.8 * uniform(&seed);
        for (int c = 0; c < 3; c++)
            t.texels[i * 4 + c] = (float)(a * uniform(&seed));
        t.texels[i * 4 + 3] = (float)a;
    }
    return t;
}

/* 2x2 box levels down to 1x1 (an odd last row or column joins the box before it). */
static pyramid build_pyramid(const texture *t)
{
    pyramid p;
    memset(&p, 0, sizeof p);
    p.w[0] = t->w;
    p.h[0] = t->h;
    p.texels[0] = malloc((size_t)t->w * t->h * 4 * sizeof(double));
    for (size_t i = 0; i < (size_t)t->w * t->h * 4; i++)
        p.texels[0][i] = t->texels[i];
    p.levels = 1;
    while (p.levels < MAX_LEVELS && (p.w[p.levels - 1] > 1 || p.h[p.levels - 1] > 1)) {
        const uint32_t l = p.levels, pw = p.w[l - 1], ph = p.h[l - 1];
        p.w[l] = pw > 1 ? pw / 2 : 1;
        p.h[l] = ph > 1 ? ph / 2 : 1;
        p.texels[l] = calloc((size_t)p.w[l] * p.h[l] * 4, sizeof(double));
        for (uint32_t y = 0; y < ph; y++)
            for (uint32_t x = 0; x < pw; x++) {
                uint32_t X = x * p.w[l] / pw, Y = y * p.h[l] / ph;
                const double share = (double)(p.w[l] * p.h[l]) / ((double)pw * ph);
                for (int c = 0; c < 4; c++)
                    p.texels[l][((size_t)Y * p.w[l] + X) * 4 + c] +=
                        share * p.texels[l - 1][((size_t)y * pw + x) * 4 + c];
            }
        p.levels++;
    }
    return p;
}

/* Bilinear at level l, position (x, y) in level-0 texels (x right, y down), transparent
 * beyond the texture (as the summed-area table: off the card is transparent). */
static void bilinear(const pyramid *p, uint32_t l, double x, double y, double out[4])
{
    const double sx = x * p->w[l] / p->w[0] - 0.5, sy = y * p->h[l] / p->h[0] - 0.5;
    const double fx = sx - floor(sx), fy = sy - floor(sy);
    const long x0 = (long)floor(sx), y0 = (long)floor(sy);
    memset(out, 0, 4 * sizeof *out);
    for (int j = 0; j < 2; j++)
        for (int i = 0; i < 2; i++) {
            const long X = x0 + i, Y = y0 + j;
            if (X < 0 || Y < 0 || X >= (long)p->w[l] || Y >= (long)p->h[l])
                continue;
            const double wgt = (i ? fx : 1 - fx) * (j ? fy : 1 - fy);
            for (int c = 0; c < 4; c++)
                out[c] += wgt * p->texels[l][((size_t)Y * p->w[l] + X) * 4 + c];
        }
}

/* Trilinear at a fractional level (clamped to the pyramid). */
static void trilinear(const pyramid *p, double level, double x, double y, double out[4])
{
    level = fmax(0.0, fmin(level, p->levels - 1.0));
    const uint32_t l = (uint32_t)level;
    const double f = level - l;
    double a[4], b[4];
    bilinear(p, l, x, y, a);
    if (f > 0.0 && l + 1 < p->levels) {
        bilinear(p, l + 1, x, y, b);
        for (int c = 0; c < 4; c++)
            a[c] += f * (b[c] - a[c]);
    }
    memcpy(out, a, sizeof a);
}

/* ---- the scene: test_cards.c's camera and rectangle cards ---------------------------------- */

typedef struct scene {
    ddof_camera cam;
    double corner[4][3]; /* bottom-left, bottom-right, top-right, top-left */
    const texture *tex;
} scene;

static double radius_px(const scene *s, double z)
{
    const double f = s->cam.focal_length_mm, s1 = s->cam.focus_distance_m * 1000.0;
    const double coc_mm = f * f / (s->cam.fstop * s1) * fabs(z * 1000.0 - s1) / (z * 1000.0);
    return fmax(0.5 * coc_mm / (s->cam.sensor_width_mm / W), 0.5);
}

static void reference(const scene *s, int x, int y, double out[4])
{
    memset(out, 0, 4 * sizeof *out);
    double d[3], z, u, v;
    cards_ref_ray(&s->cam, W, H, x + 0.5, y + 0.5, d);
    if (!cards_ref_hit(&s->corner[0][0], d, &z, &u, &v))
        return;
    const double r = radius_px(s, z);
    const int grid = 40;
    int count = 0;
    for (int j = 0; j < grid; j++)
        for (int i = 0; i < grid; i++) {
            const double ex = -1.0 + (2.0 * i + 1.0) / grid, ey = -1.0 + (2.0 * j + 1.0) / grid;
            if (ex * ex + ey * ey > 1.0)
                continue;
            count++;
            double e[3];
            cards_ref_ray(&s->cam, W, H, x + 0.5 + r * ex, y + 0.5 + r * ey, e);
            if (!cards_ref_hit(&s->corner[0][0], e, &z, &u, &v) || u < 0.0 || u >= 1.0 || v <= 0.0 || v > 1.0)
                continue;
            const uint32_t tx = (uint32_t)(u * s->tex->w), ty = (uint32_t)((1.0 - v) * s->tex->h);
            for (int c = 0; c < 4; c++)
                out[c] += s->tex->texels[((size_t)ty * s->tex->w + tx) * 4 + c];
        }
    for (int c = 0; c < 4; c++)
        out[c] /= count;
}

/* Screen point -> texel position (x right, y down, level-0 texels); 0 off the plane. */
static int texel_at(const scene *s, double x, double y, double t[2], double *z)
{
    double d[3], u, v;
    cards_ref_ray(&s->cam, W, H, x, y, d);
    if (!cards_ref_hit(&s->corner[0][0], d, z, &u, &v))
        return 0;
    t[0] = u * s->tex->w;
    t[1] = (1.0 - v) * s->tex->h;
    return 1;
}

/* The mip averages over pixel (x, y)'s disc: taps 1 (centre) or 16 (a Vogel spiral). */
static void mip_average(const scene *s, const pyramid *p, int taps, int x, int y, double out[4])
{
    memset(out, 0, 4 * sizeof *out);
    double c[2], ax[2], bx[2], ay[2], by[2], z, zz;
    const double px = x + 0.5, py = y + 0.5, h = 0.01;
    if (!texel_at(s, px, py, c, &z) || !texel_at(s, px - h, py, ax, &zz) ||
        !texel_at(s, px + h, py, bx, &zz) || !texel_at(s, px, py - h, ay, &zz) ||
        !texel_at(s, px, py + h, by, &zz))
        return;
    const double r = radius_px(s, z);
    const double j00 = (bx[0] - ax[0]) / (2 * h), j10 = (bx[1] - ax[1]) / (2 * h);
    const double j01 = (by[0] - ay[0]) / (2 * h), j11 = (by[1] - ay[1]) / (2 * h);
    const double area = 3.14159265358979323846 * r * r * fabs(j00 * j11 - j01 * j10);
    const double level = 0.5 * log2(fmax(area / taps, 1e-12));
    for (int k = 0; k < taps; k++) {
        double e[2] = {0.0, 0.0};
        if (taps > 1) { /* equal-area points: radius sqrt((k + 0.5) / n), golden angle */
            const double rho = sqrt((k + 0.5) / taps), phi = k * 2.39996322972865332;
            e[0] = rho * cos(phi);
            e[1] = rho * sin(phi);
        }
        const double dx = r * e[0], dy = r * e[1];
        double sample[4];
        trilinear(p, level, c[0] + j00 * dx + j01 * dy, c[1] + j10 * dx + j11 * dy, sample);
        for (int ch = 0; ch < 4; ch++)
            out[ch] += sample[ch] / taps;
    }
}

static void measure(ddof_context *ctx, const char *name, const scene *s)
{
    static float sat[W * H * 4];
    ddof_card card;
    memset(&card, 0, sizeof card);
    card.vertex_count = 4;
    const float uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int k = 0; k < 4; k++) {
        for (int a = 0; a < 3; a++)
            card.position[k][a] = (float)s->corner[k][a];
        card.uv[k][0] = uv[k][0];
        card.uv[k][1] = uv[k][1];
    }
    card.texture = (ddof_image_in){s->tex->texels, s->tex->w, s->tex->h, 4, 0};
    ddof_image img = {sat, W, H, 4, 0};
    if (ddof_render_cards(ctx, NULL, &s->cam, &card, 1, &img) != DDOF_OK) {
        fprintf(stderr, "%s\n", ddof_context_last_error(ctx));
        exit(1);
    }
    pyramid p = build_pyramid(s->tex);
    double max_err[3] = {0, 0, 0}, sum[3] = {0, 0, 0};
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double ref[4], m1[4], m16[4];
            reference(s, x, y, ref);
            mip_average(s, &p, 1, x, y, m1);
            mip_average(s, &p, 16, x, y, m16);
            for (int c = 0; c < 4; c++) {
                const double e[3] = {sat[(y * W + x) * 4 + c] - ref[c], m1[c] - ref[c],
                                     m16[c] - ref[c]};
                for (int m = 0; m < 3; m++) {
                    max_err[m] = fmax(max_err[m], fabs(e[m]));
                    sum[m] += e[m] * e[m];
                }
            }
        }
    const char *methods[3] = {"SAT, 8 strips", "mip, 1 trilinear tap", "mip, 16 trilinear taps"};
    for (int m = 0; m < 3; m++)
        printf("| %s | %ux%u | %s | %.4f | %.5f |\n", name, s->tex->w, s->tex->h, methods[m],
               max_err[m], sqrt(sum[m] / (W * H * 4)));
    for (uint32_t l = 0; l < p.levels; l++)
        free(p.texels[l]);
}

int main(void)
{
    ddof_context *ctx = NULL;
    if (ddof_context_create(NULL, &ctx) != DDOF_OK)
        return 1;
    texture coarse = random_texture(24, 16, 12345), fine = random_texture(96, 64, 777);
    scene s;
    ddof_camera_init(&s.cam);
    s.cam.focal_length_mm = 50.0;
    s.cam.sensor_width_mm = 36.0;
    s.cam.fstop = 1.0;
    s.cam.focus_distance_m = 0.5;
    const double fronto[4][3] = {{-0.36, -0.24, -2}, {0.36, -0.24, -2}, {0.36, 0.24, -2},
                                 {-0.36, 0.24, -2}};
    const double slanted[4][3] = {{-0.3, -0.2, -1}, {0.9, -0.2, -3.5}, {0.9, 0.2, -3.5},
                                  {-0.3, 0.2, -1}};
    printf("| card | texture | method | max abs error | RMS |\n|---|---|---|---|---|\n");
    const texture *textures[2] = {&coarse, &fine};
    for (int t = 0; t < 2; t++) {
        s.tex = textures[t];
        memcpy(s.corner, fronto, sizeof fronto);
        measure(ctx, "fronto-parallel, Z = 2 m", &s);
        memcpy(s.corner, slanted, sizeof slanted);
        measure(ctx, "slanted, Z 1 to 3.5 m", &s);
    }
    free(coarse.texels);
    free(fine.texels);
    ddof_context_free(ctx);
    return 0;
}
