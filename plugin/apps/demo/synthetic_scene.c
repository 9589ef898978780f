/* SPDX-License-Identifier: MIT */
/* synthetic_scene.c - ray casts the demo scene described in synthetic_scene.h.
 *
 * Camera at the origin, x right, y up, looking along +z; the ground is the plane y = -CAMERA_H.
 * A ray through an image point has direction (dx, dy, 1), so its parameter t is planar depth. */
#include "synthetic_scene.h"

#include <math.h>
#include <stdlib.h>

#define PI 3.14159265358979323846

#define CAMERA_H 0.4           /* camera height above the ground, metres   */
#define SUPERSAMPLES 4         /* per axis, for colour only                */

#define WALL_Z DEMO_SCENE_WALL_DISTANCE_M
#define WALL_TOP 3.2           /* above the ground                          */

#define SUBJECT_Z DEMO_SCENE_SUBJECT_DISTANCE_M
#define STAR_X (-0.36)         /* Siemens star centre and radius            */
#define STAR_Y 0.02
#define STAR_R 0.25
#define STAR_SPOKES 36

#define POST_X 0.30            /* near post: vertical cylinder              */
#define POST_Z (DEMO_SCENE_NEAR_DISTANCE_M + POST_R)
#define POST_R 0.10

#define BALL_X (-0.29)         /* near ball: sphere                         */
#define BALL_Y (-0.25)
#define BALL_Z 1.65
#define BALL_R 0.15

typedef struct rgb { double r, g, b; } rgb;

typedef struct hit {
    double t; /* planar depth; INFINITY for the sky */
    rgb color;
} hit;

static rgb make_rgb(double r, double g, double b)
{
    rgb c = {r, g, b};
    return c;
}

static rgb scale(rgb c, double k) { return make_rgb(c.r * k, c.g * k, c.b * k); }

static rgb mix(rgb a, rgb b, double k)
{
    return make_rgb(a.r + (b.r - a.r) * k, a.g + (b.g - a.g) * k, a.b + (b.b - a.b) * k);
}

/* Deterministic hash of two integers to [0, 1). */
static double hash2(long a, long b)
{
    uint32_t h = (uint32_t)a * 0x9e3779b1u ^ (uint32_t)b * 0x85ebca77u;
    h ^= h >> 15;
    h *= 0x2c1b3c6du;
    h ^= h >> 12;
    h *= 0x297a2d39u;
    h ^= h >> 15;
    return (double)h / 4294967296.0;
}

/* Lambert from a light above-left and behind the camera, plus ambient. */
static double shade(double nx, double ny, double nz)
{
    const double lx = -0.45, ly = 0.75, lz = -0.48; /* unit length */
    double d = nx * lx + ny * ly + nz * lz;
    return 0.3 + 0.75 * (d > 0.0 ? d : 0.0);
}

static rgb sky(double dy)
{
    double k = dy * 4.0;
    k = k < 0.0 ? 0.0 : k > 1.0 ? 1.0 : k;
    return mix(make_rgb(0.62, 0.74, 0.90), make_rgb(0.16, 0.32, 0.70), k);
}

/* A string light: HDR disc of radius 0.055 m, or a negative value for none. */
static double string_light(double x, double y, rgb *emit)
{
    /* Lights every 0.6 m, hanging in 3.6 m spans between poles. */
    double span = 3.6, pitch = 0.6;
    double xs = floor(x / pitch + 0.5) * pitch;
    double u = fmod(fabs(xs), span) / span * 2.0 - 1.0;
    double ys = 2.35 - 0.35 * (1.0 - u * u) - CAMERA_H;
    double d = hypot(x - xs, y - ys);
    *emit = make_rgb(22.0, 15.0, 7.0);
    return d < 0.055 ? d : -1.0;
}

/* Windows with cool lights scattered over the wall. */
static int window_light(double x, double y, rgb *emit)
{
    static const double spots[][2] = {{-5.1, 0.9}, {-3.3, 1.4}, {-1.8, 0.6}, {1.4, 1.1},
                                      {3.1, 0.5},  {4.6, 1.5},  {-0.4, 1.7}, {2.4, 1.9}};
    size_t i;
    for (i = 0; i < sizeof spots / sizeof spots[0]; i++) {
        double dx = x - spots[i][0], dy = y + CAMERA_H - spots[i][1];
        if (dx * dx + dy * dy < 0.07 * 0.07) {
            *emit = i % 2 ? make_rgb(9.0, 15.0, 22.0) : make_rgb(20.0, 20.0, 20.0);
            return 1;
        }
    }
    return 0;
}

/* Bricks 0.5 x 0.25 m with mortar, each brick a slightly different colour. */
static rgb wall(double x, double y)
{
    static const rgb palette[] = {{0.46, 0.16, 0.09}, {0.55, 0.25, 0.12}, {0.38, 0.12, 0.08},
                                  {0.60, 0.42, 0.20}, {0.18, 0.32, 0.36}, {0.50, 0.20, 0.12}};
    double h = y + CAMERA_H; /* height above the ground */
    double row = floor(h / 0.25);
    double shifted = x + ((long)row % 2 ? 0.25 : 0.0);
    double col = floor(shifted / 0.5);
    double bu = shifted - col * 0.5, bv = h - row * 0.25;
    rgb emit;
    if (string_light(x, y, &emit) >= 0.0 || window_light(x, y, &emit))
        return emit;
    if (bu < 0.03 || bv < 0.03)
        return make_rgb(0.30, 0.29, 0.27);
    {
        double n = hash2((long)col, (long)row);
        rgb c = palette[(size_t)(n * 6.0) % 6];
        return scale(c, 0.75 + 0.5 * hash2((long)row, (long)col + 7));
    }
}

/* Paving tiles, 0.5 m, fading to their mean where a pixel spans more than a tile. */
static rgb ground(double x, double z, double f_px)
{
    rgb a = make_rgb(0.30, 0.27, 0.23), b = make_rgb(0.12, 0.12, 0.12);
    double footprint = z * z / (f_px * CAMERA_H); /* metres of ground per pixel row */
    double fade = 1.6 - 1.2 * footprint / 0.5;
    int odd = ((long)floor(x / 0.5) + (long)floor(z / 0.5)) & 1;
    rgb c = odd ? a : b;
    fade = fade < 0.0 ? 0.0 : fade > 1.0 ? 1.0 : fade;
    return mix(mix(a, b, 0.5), c, fade);
}

/* The Siemens star: black and white spokes, a red rim, a grey hub. */
static rgb star(double x, double y)
{
    double dx = x - STAR_X, dy = y - STAR_Y;
    double r = sqrt(dx * dx + dy * dy);
    double a = atan2(dy, dx) / (2.0 * PI) + 0.5;
    if (r > STAR_R * 0.9)
        return make_rgb(0.70, 0.10, 0.04);
    if (r < STAR_R * 0.06)
        return make_rgb(0.35, 0.35, 0.35);
    return ((long)floor(a * STAR_SPOKES) & 1) ? make_rgb(0.85, 0.85, 0.82)
                                                 : make_rgb(0.02, 0.02, 0.02);
}

/* Three bars standing on the ground at the subject distance, each with white bands. */
static int bar(double x, double y, rgb *color)
{
    static const rgb colors[] = {{0.70, 0.06, 0.04}, {0.06, 0.42, 0.10}, {0.05, 0.12, 0.65}};
    static const double xs[] = {0.10, 0.23, 0.36}, tops[] = {0.10, 0.18, 0.02};
    int i;
    for (i = 0; i < 3; i++) {
        if (fabs(x - xs[i]) < 0.03 && y < tops[i]) {
            double band = (y + CAMERA_H) / 0.08;
            *color = band - floor(band) < 0.3 ? make_rgb(0.85, 0.85, 0.85) : colors[i];
            return 1;
        }
    }
    return 0;
}

/* The nearest thing along the ray (dx, dy, 1). */
static hit trace(double dx, double dy, double f_px)
{
    hit h;
    h.t = INFINITY;
    h.color = sky(dy);

    /* Wall and ground. */
    if (dy * WALL_Z < WALL_TOP - CAMERA_H) {
        h.t = WALL_Z;
        h.color = wall(dx * WALL_Z, dy * WALL_Z);
    }
    if (dy < 0.0 && CAMERA_H / -dy < h.t) {
        h.t = CAMERA_H / -dy;
        h.color = ground(dx * h.t, h.t, f_px);
    }

    /* Subject plane: star on a pole, and the bars. */
    if (SUBJECT_Z < h.t) {
        double x = dx * SUBJECT_Z, y = dy * SUBJECT_Z;
        rgb c;
        if (hypot(x - STAR_X, y - STAR_Y) < STAR_R) {
            h.t = SUBJECT_Z;
            h.color = star(x, y);
        } else if (fabs(x - STAR_X) < 0.012 && y < STAR_Y && y > -CAMERA_H) {
            h.t = SUBJECT_Z;
            h.color = make_rgb(0.08, 0.08, 0.09);
        } else if (y > -CAMERA_H && bar(x, y, &c)) {
            h.t = SUBJECT_Z;
            h.color = c;
        }
    }

    /* Ball: |t d - centre| = r. */
    {
        double a = dx * dx + dy * dy + 1.0;
        double b = dx * BALL_X + dy * BALL_Y + BALL_Z;
        double c = BALL_X * BALL_X + BALL_Y * BALL_Y + BALL_Z * BALL_Z - BALL_R * BALL_R;
        double disc = b * b - a * c;
        if (disc >= 0.0) {
            double t = (b - sqrt(disc)) / a;
            if (t > 0.0 && t < h.t) {
                double nx = (dx * t - BALL_X) / BALL_R, ny = (dy * t - BALL_Y) / BALL_R;
                double nz = (t - BALL_Z) / BALL_R;
                /* A beach ball: coloured segments around its vertical axis, a white cap. */
                static const rgb segments[] = {{0.75, 0.06, 0.04}, {0.85, 0.85, 0.80},
                                               {0.05, 0.20, 0.70}, {0.85, 0.65, 0.05},
                                               {0.85, 0.85, 0.80}, {0.08, 0.50, 0.12}};
                double turn = atan2(nz, nx) / (2.0 * PI) + 0.5;
                rgb base = ny > 0.93 ? make_rgb(0.85, 0.85, 0.80)
                                     : segments[(size_t)(turn * 12.0) % 6];
                h.t = t;
                h.color = scale(base, shade(nx, ny, nz));
            }
        }
    }

    /* Post: vertical cylinder, |(t dx, t) - (POST_X, POST_Z)| = r, with a red helix. */
    {
        double a = dx * dx + 1.0;
        double b = dx * POST_X + POST_Z;
        double c = POST_X * POST_X + POST_Z * POST_Z - POST_R * POST_R;
        double disc = b * b - a * c;
        if (disc >= 0.0) {
            double t = (b - sqrt(disc)) / a;
            if (t > 0.0 && t < h.t) {
                double nx = (dx * t - POST_X) / POST_R, nz = (t - POST_Z) / POST_R;
                double turn = atan2(nz, nx) / (2.0 * PI);
                double s = dy * t / 0.12 + turn;
                rgb base = s - floor(s) < 0.5 ? make_rgb(0.75, 0.05, 0.03) : make_rgb(0.8, 0.8, 0.78);
                h.t = t;
                h.color = scale(base, shade(nx, 0.0, nz));
            }
        }
    }
    return h;
}

int demo_scene_render(demo_scene *scene, uint32_t width, uint32_t height, double focal_length_mm,
                      double sensor_width_mm)
{
    const double f_px = focal_length_mm / sensor_width_mm * (double)width;
    const double cx = 0.5 * (double)width, cy = 0.5 * (double)height;
    const size_t pixels = (size_t)width * height;
    uint32_t x, y;
    int sx, sy;

    scene->width = width;
    scene->height = height;
    scene->color = malloc(pixels * 3 * sizeof(float));
    scene->depth = malloc(pixels * sizeof(float));
    if (!scene->color || !scene->depth) {
        demo_scene_free(scene);
        return -1;
    }

    for (y = 0; y < height; y++) {
        for (x = 0; x < width; x++) {
            size_t i = (size_t)y * width + x;
            rgb sum = make_rgb(0.0, 0.0, 0.0);
            hit centre = trace(((double)x + 0.5 - cx) / f_px, -((double)y + 0.5 - cy) / f_px, f_px);
            for (sy = 0; sy < SUPERSAMPLES; sy++) {
                for (sx = 0; sx < SUPERSAMPLES; sx++) {
                    double u = (double)x + ((double)sx + 0.5) / SUPERSAMPLES;
                    double v = (double)y + ((double)sy + 0.5) / SUPERSAMPLES;
                    hit h = trace((u - cx) / f_px, -(v - cy) / f_px, f_px);
                    sum.r += h.color.r;
                    sum.g += h.color.g;
                    sum.b += h.color.b;
                }
            }
            sum = scale(sum, 1.0 / (SUPERSAMPLES * SUPERSAMPLES));
            scene->color[i * 3 + 0] = (float)sum.r;
            scene->color[i * 3 + 1] = (float)sum.g;
            scene->color[i * 3 + 2] = (float)sum.b;
            scene->depth[i] = isinf(centre.t) ? INFINITY : (float)centre.t;
        }
    }
    return 0;
}

void demo_scene_free(demo_scene *scene)
{
    free(scene->color);
    free(scene->depth);
    scene->color = NULL;
    scene->depth = NULL;
    scene->width = scene->height = 0;
}
