/* SPDX-License-Identifier: MIT */
/* cards_demo.c - the picture of docs/cards.md and the cards' timings (study/cards/run.sh).
 *   cards_demo picture OUT.rgba   a 640x360 three-card scene, raw float RGBA (premultiplied)
 *   cards_demo time N             N cards at 1920x1080, and ddof_depth_of_field's default frame
 *                                 at 1920x1080 on the same machine, runs interleaved, each the
 *                                 best of 5, and their ratio
 *   cards_demo time N egl|osmesa [PLUGIN]   the same on a GL backend (libddof_gl.so) */
#define DDOF_EXPERIMENTAL
#include "ddof.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

/* kind 0: a checker; 1: stripes; 2: a ring of opaque colour with a transparent centre. */
static float *make_texture(int kind, uint32_t size)
{
    float *t = malloc((size_t)size * size * 4 * sizeof *t);
    for (uint32_t y = 0; y < size; y++)
        for (uint32_t x = 0; x < size; x++) {
            float *p = t + ((size_t)y * size + x) * 4;
            double u = (x + 0.5) / size - 0.5, v = (y + 0.5) / size - 0.5, a = 1.0;
            double rgb[3];
            if (kind == 0) {
                int c = ((x * 8 / size) + (y * 8 / size)) & 1;
                rgb[0] = c ? 0.9 : 0.1; rgb[1] = c ? 0.8 : 0.15; rgb[2] = c ? 0.6 : 0.3;
            } else if (kind == 1) {
                int c = (x * 12 / size) & 1;
                rgb[0] = 0.1; rgb[1] = c ? 0.7 : 0.2; rgb[2] = c ? 0.3 : 0.1;
            } else {
                double r = sqrt(u * u + v * v);
                a = r < 0.45 && r > 0.25 ? 1.0 : 0.0;
                rgb[0] = 1.0; rgb[1] = 0.3; rgb[2] = 0.1;
            }
            for (int c = 0; c < 3; c++)
                p[c] = (float)(rgb[c] * a); /* premultiplied */
            p[3] = (float)a;
        }
    return t;
}

static ddof_card card_at(double cx, double cy, double z, double half_w, double half_h,
                         double tilt, const float *tex, uint32_t size)
{
    ddof_card c;
    memset(&c, 0, sizeof c);
    c.vertex_count = 4;
    const double sx[4] = {-1, 1, 1, -1}, sy[4] = {-1, -1, 1, 1};
    for (int k = 0; k < 4; k++) {
        c.position[k][0] = (float)(cx + sx[k] * half_w * cos(tilt));
        c.position[k][1] = (float)(cy + sy[k] * half_h);
        c.position[k][2] = (float)(z - sx[k] * half_w * sin(tilt));
        c.uv[k][0] = (float)(0.5 + 0.5 * sx[k]);
        c.uv[k][1] = (float)(0.5 + 0.5 * sy[k]);
    }
    c.texture = (ddof_image_in){tex, size, size, 4, 0};
    return c;
}

static int picture(ddof_context *ctx, const char *path)
{
    const uint32_t w = 640, h = 360, ts = 256;
    float *tex[3] = {make_texture(0, ts), make_texture(1, ts), make_texture(2, ts)};
    ddof_card cards[3] = {
        card_at(0.0, 0.0, -8.0, 5.0, 3.0, 0.0, tex[0], ts),    /* far wall, 8 m      */
        card_at(0.45, -0.05, -2.2, 0.6, 0.3, 1.1, tex[1], ts),  /* slanted, 1.7..2.7 m */
        card_at(-0.12, 0.02, -0.6, 0.12, 0.12, 0.0, tex[2], ts) /* near ring, 0.6 m  */
    };
    ddof_camera cam;
    ddof_camera_init(&cam);
    cam.fstop = 1.2;
    cam.focus_distance_m = 2.0;
    float *out = malloc((size_t)w * h * 4 * sizeof *out);
    ddof_image img = {out, w, h, 4, 0};
    ddof_status s = ddof_render_cards(ctx, NULL, &cam, cards, 3, &img);
    if (s != DDOF_OK) {
        fprintf(stderr, "%s\n", ddof_context_last_error(ctx));
        return 1;
    }
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(out, sizeof *out, (size_t)w * h * 4, f) != (size_t)w * h * 4)
        return 1;
    fclose(f);
    printf("%s: %ux%u\n", path, w, h);
    free(out);
    for (int i = 0; i < 3; i++)
        free(tex[i]);
    return 0;
}

static int timing(ddof_context *ctx, int n)
{
    const uint32_t w = 1920, h = 1080, ts = 512;
    float *tex[3] = {make_texture(0, ts), make_texture(1, ts), make_texture(2, ts)};
    ddof_card *cards = malloc((size_t)n * sizeof *cards);
    unsigned seed = 1;
    for (int i = 0; i < n; i++) { /* fronto-parallel, distinct depths 0.5..20 m: no crossings */
        double z = 0.5 + 19.5 * (i + 0.5) / n;
        seed = seed * 1103515245u + 12345u;
        double fx = ((seed >> 8) % 1000) / 1000.0 - 0.5;
        seed = seed * 1103515245u + 12345u;
        double fy = ((seed >> 8) % 1000) / 1000.0 - 0.5;
        double half = 0.12 * z; /* about a sixth of the frame wide at its depth */
        cards[i] = card_at(fx * 0.6 * z, fy * 0.35 * z, -z, half, half, 0.0, tex[i % 3], ts);
    }
    ddof_camera cam;
    ddof_camera_init(&cam);
    cam.fstop = 2.0;
    cam.focus_distance_m = 3.0;
    float *out = malloc((size_t)w * h * 4 * sizeof *out);
    ddof_image img = {out, w, h, 4, 0};
    /* The one-image default frame on the same machine. */
    float *color = malloc((size_t)w * h * 4 * sizeof *color), *depth = malloc((size_t)w * h * 4);
    for (size_t i = 0; i < (size_t)w * h; i++) {
        for (int c = 0; c < 4; c++)
            color[i * 4 + c] = (float)((i * 7 + c * 13) % 17) / 17.0f;
        depth[i] = 0.5f + 19.5f * (float)((i / w) % 97) / 97.0f;
    }
    ddof_params params;
    ddof_params_init(&params);
    ddof_image_in ci = {color, w, h, 4, 0}, di = {depth, w, h, 1, 0};
    /* Interleaved, so that both see the same load on a shared machine: best of 5 each
     * (CARDS_RUNS overrides: a software GL takes minutes for 100 cards). */
    const int runs = getenv("CARDS_RUNS") ? atoi(getenv("CARDS_RUNS")) : 5;
    double best_cards = 1e9, best_frame = 1e9;
    for (int r = 0; r < (runs > 0 ? runs : 1); r++) {
        double t0 = now();
        if (ddof_render_cards(ctx, NULL, &cam, cards, (uint32_t)n, &img) != DDOF_OK) {
            fprintf(stderr, "%s\n", ddof_context_last_error(ctx));
            return 1;
        }
        double t1 = now();
        if (ddof_depth_of_field(ctx, &params, &cam, &ci, &di, &img, NULL) != DDOF_OK) {
            fprintf(stderr, "%s\n", ddof_context_last_error(ctx));
            return 1;
        }
        best_cards = fmin(best_cards, t1 - t0);
        best_frame = fmin(best_frame, now() - t1);
    }
    printf("cards: %d cards (512x512 textures) at %ux%u: %.1f ms (best of %d)\n", n, w, h,
           1e3 * best_cards, runs);
    printf("one-image default frame (ddof_depth_of_field) at %ux%u: %.1f ms (best of %d, "
           "interleaved)\n", w, h, 1e3 * best_frame, runs);
    printf("cards / one-image frame: %.2f\n", best_cards / best_frame);
    free(color); free(depth); free(out); free(cards);
    for (int i = 0; i < 3; i++)
        free(tex[i]);
    return 0;
}

int main(int argc, char **argv)
{
    ddof_context *ctx = NULL;
    if (argc < 3 || argc > 5 || ddof_context_create(NULL, &ctx) != DDOF_OK) {
        fprintf(stderr, "usage: cards_demo picture OUT.rgba | cards_demo time N "
                        "[egl|osmesa [PLUGIN]]\n");
        return 2;
    }
    if (argc >= 4) { /* the cards (and the one-image frame) on a GL backend */
        const ddof_backend_kind kind = strcmp(argv[3], "egl") == 0 ? DDOF_BACKEND_EGL
                                                                   : DDOF_BACKEND_OSMESA;
        if (ddof_context_set_backend(ctx, kind, argc == 5 ? argv[4] : NULL) != DDOF_OK) {
            fprintf(stderr, "%s\n", ddof_context_last_error(ctx));
            return 1;
        }
        printf("backend %s\n", argv[3]);
    }
    int rc = strcmp(argv[1], "picture") == 0 ? picture(ctx, argv[2]) : timing(ctx, atoi(argv[2]));
    ddof_context_free(ctx);
    return rc;
}
