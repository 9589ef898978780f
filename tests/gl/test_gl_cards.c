/* SPDX-License-Identifier: MIT */
/* test_gl_cards.c - ddof_render_cards on a GL backend (the device draws the cards: a vertex
 * shader places each expanded polygon, the rasteriser covers it, a fragment shader averages
 * the texture, blending composites) against the CPU path on the same cards: every pixel
 * within TOL_CARDS. Scenes: three overlapping cards (a far wall, a slanted card, a near card
 * whose texture is partly transparent) on small random textures; an opaque card in front of a
 * wall (the pixels it makes opaque skipped by the device, as by the CPU); a triangle whose uv lies
 * inside its texture; and a 512x512 texture, whose summed-area table reaches 2^18 where a
 * plain float table would be off by up to 1/64 (the device's table is split to stay exact);
 * textures magnified until a texel covers 55 px, and thousands; and a texture too large for
 * the renderer's textures (refused). Run as `test_gl_cards osmesa|egl`. */
#ifndef DDOF_EXPERIMENTAL
#define DDOF_EXPERIMENTAL
#endif
#include "gl_test.h"

#define TOL_CARDS 1e-4 /* relative to the colours' range (0..1 here): test_gl_frame's tolerance */
#define W 96
#define H 64

static ddof_context *gl, *cpu;

static float *random_texture(uint32_t w, uint32_t h, unsigned long long seed, int holes)
{
    float *t = malloc((size_t)w * h * 4 * sizeof *t);
    test_rng rng = {seed};
    for (size_t i = 0; i < (size_t)w * h; i++) {
        double a = 0.2 + 0.8 * test_uniform(&rng);
        if (holes && test_uniform(&rng) < 0.3)
            a = 0.0;
        for (int c = 0; c < 3; c++)
            t[i * 4 + c] = (float)(a * test_uniform(&rng));
        t[i * 4 + 3] = (float)a;
    }
    return t;
}

static ddof_card card_of(const double (*p)[3], const double (*uv)[2], uint32_t n,
                         const float *texture, uint32_t tw, uint32_t th)
{
    ddof_card c;
    memset(&c, 0, sizeof c);
    c.vertex_count = n;
    for (uint32_t k = 0; k < n; k++) {
        for (int a = 0; a < 3; a++)
            c.position[k][a] = (float)p[k][a];
        c.uv[k][0] = (float)uv[k][0];
        c.uv[k][1] = (float)uv[k][1];
    }
    c.texture = (ddof_image_in){texture, tw, th, 4, 0};
    return c;
}

static ddof_camera camera(void)
{
    ddof_camera cam;
    ddof_camera_init(&cam);
    cam.focal_length_mm = 50.0;
    cam.sensor_width_mm = 36.0;
    cam.fstop = 1.0;
    cam.focus_distance_m = 0.8;
    return cam;
}

/* The same cards on the CPU and on the device; the largest difference. */
static double compare(const char *name, const ddof_card *cards, uint32_t n)
{
    static float a[W * H * 4], b[W * H * 4];
    const ddof_camera cam = camera();
    ddof_image ia = {a, W, H, 4, 0}, ib = {b, W, H, 4, 0};
    CHECK_EQ_INT(ddof_render_cards(cpu, NULL, &cam, cards, n, &ia), DDOF_OK);
    ddof_status s = ddof_render_cards(gl, NULL, &cam, cards, n, &ib);
    CHECK_MSG(s == DDOF_OK, "%s on GL: %s", name, ddof_context_last_error(gl));
    const double worst = max_diff(a, b, W * H * 4);
    double alpha = 0.0;
    for (int i = 0; i < W * H; i++)
        alpha += a[i * 4 + 3];
    printf("%s: max |GL - CPU| %.2e (%.0f px of alpha)\n", name, worst, alpha);
    CHECK_MSG(worst <= TOL_CARDS, "%s: GL and CPU differ by %g", name, worst);
    /* float on the device against double on the CPU is never bit for bit: equal images mean
     * the device did not draw */
    CHECK_MSG(worst > 0.0, "%s: the GL backend's image is the CPU's bit for bit", name);
    CHECK(alpha > 100.0);
    return worst;
}

static void overlapping(void)
{
    float *t1 = random_texture(24, 16, 1, 0), *t2 = random_texture(24, 16, 2, 0),
          *t3 = random_texture(12, 12, 3, 1);
    static const double wall[4][3] = {{-0.9, -0.6, -3}, {0.9, -0.6, -3}, {0.9, 0.6, -3},
                                      {-0.9, 0.6, -3}};
    static const double slant[4][3] = {{-0.3, -0.2, -1}, {0.5, -0.2, -2.5}, {0.5, 0.15, -2.5},
                                       {-0.3, 0.15, -1}};
    static const double near_card[4][3] = {{-0.12, -0.1, -0.5}, {0.06, -0.1, -0.5},
                                           {0.06, 0.08, -0.5}, {-0.12, 0.08, -0.5}};
    static const double square[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const ddof_card cards[3] = {card_of(wall, square, 4, t1, 24, 16),
                                card_of(near_card, square, 4, t3, 12, 12),
                                card_of(slant, square, 4, t2, 24, 16)};
    compare("three overlapping cards", cards, 3);
    free(t1);
    free(t2);
    free(t3);
}

/* An opaque card in front of another: the device skips the pixels it made opaque (reading
 * the frame so far), as the CPU does; the image is the same. */
static void hidden(void)
{
    float *t1 = random_texture(24, 16, 6, 0), *t2 = random_texture(16, 16, 7, 0);
    for (int i = 0; i < 16 * 16; i++) { /* opaque */
        for (int c = 0; c < 3; c++)
            t2[i * 4 + c] /= t2[i * 4 + 3];
        t2[i * 4 + 3] = 1.0f;
    }
    static const double wall[4][3] = {{-0.9, -0.6, -3}, {0.9, -0.6, -3}, {0.9, 0.6, -3},
                                      {-0.9, 0.6, -3}};
    static const double front[4][3] = {{-0.2, -0.15, -0.8}, {0.2, -0.15, -0.8},
                                       {0.2, 0.15, -0.8}, {-0.2, 0.15, -0.8}};
    static const double square[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const ddof_card cards[2] = {card_of(wall, square, 4, t1, 24, 16),
                                card_of(front, square, 4, t2, 16, 16)};
    compare("an opaque card in front of another", cards, 2);
    free(t1);
    free(t2);
}

static void triangle(void)
{
    float *t = random_texture(24, 16, 4, 1);
    static const double p[3][3] = {{-0.35, -0.25, -1.2}, {0.45, -0.15, -2.6}, {0.0, 0.3, -1.8}};
    static const double uv[3][2] = {{0.05, 0.1}, {0.95, 0.3}, {0.4, 0.95}};
    const ddof_card card = card_of(p, uv, 3, t, 24, 16);
    compare("triangle, uv inside the texture", &card, 1);
    free(t);
}

static void large_texture(void)
{
    float *t = random_texture(512, 512, 5, 0);
    static const double p[4][3] = {{-0.25, -0.2, -0.9}, {0.25, -0.2, -0.9}, {0.25, 0.2, -0.7},
                                   {-0.25, 0.2, -0.7}};
    static const double square[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const ddof_card card = card_of(p, square, 4, t, 512, 512);
    compare("512x512 texture, tilted", &card, 1);
    free(t);
}

/* A texel covering many pixels (issue 40): the disc is a small fraction of a texel, whose
 * extent the shader once took as the difference of two float positions near the texel's
 * coordinate, and whose 9 boxes it weighted by products that cancel: an opaque white card
 * 1000 m wide at 2 m gave alpha -11.7..11.7; and its float texel positions put a disc of a
 * texel of 55 px in a large texture off by 4e-4. */
static void magnified(void)
{
    float white[8 * 8 * 4];
    for (int i = 0; i < 8 * 8 * 4; i++)
        white[i] = 1.0f;
    static const double square[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    static const double huge[4][3] = {{-500, -500, -2}, {500, -500, -2}, {500, 500, -2},
                                      {-500, 500, -2}};
    const ddof_card wall = card_of(huge, square, 4, white, 8, 8);
    static float a[W * H * 4], b[W * H * 4];
    const ddof_camera cam = camera();
    CHECK_EQ_INT(ddof_render_cards(cpu, NULL, &cam, &wall, 1, &(ddof_image){a, W, H, 4, 0}),
                 DDOF_OK);
    ddof_status s = ddof_render_cards(gl, NULL, &cam, &wall, 1, &(ddof_image){b, W, H, 4, 0});
    CHECK_MSG(s == DDOF_OK, "white wall on GL: %s", ddof_context_last_error(gl));
    double lo = 1.0, hi = 1.0;
    for (int i = 0; i < W * H * 4; i++) {
        lo = fmin(lo, b[i]);
        hi = fmax(hi, b[i]);
    }
    printf("opaque white wall, 1000 m at 2 m: GL %.7f..%.7f, max |GL - CPU| %.2e\n", lo, hi,
           max_diff(a, b, W * H * 4));
    CHECK_MSG(lo >= 1.0 - TOL_CARDS && hi <= 1.0 + TOL_CARDS, "white wall: GL %g..%g", lo, hi);
    CHECK(max_diff(a, b, W * H * 4) <= TOL_CARDS);
    /* about 55 px per texel: 2048 texels over 1690 m at 2 m (1.44 m per 96 px), the frame
     * seeing texels near 1024, where a float's step is 6e-5 texel (a fifth of a 1 px disc) */
    float *t = random_texture(2048, 2048, 8, 0);
    static const double wide[4][3] = {{-844.8, -844.8, -2}, {844.8, -844.8, -2},
                                      {844.8, 844.8, -2}, {-844.8, 844.8, -2}};
    const ddof_card card = card_of(wide, square, 4, t, 2048, 2048);
    compare("2048x2048 texture at 55 px per texel", &card, 1);
    free(t);
}

/* A texture whose summed-area table exceeds the renderer's GL_MAX_TEXTURE_SIZE (16,384 on
 * llvmpipe: a 16,384-texel texture's table is 16,385 wide) once failed with "GL error 0x501";
 * now DDOF_ERROR_UNSUPPORTED naming the limit, the output untouched (or, on a renderer with
 * larger textures, the CPU's image). */
static void texture_too_large(void)
{
    enum { TW = 16384 };
    float *t = random_texture(TW, 1, 9, 0);
    static const double p[4][3] = {{-0.5, -0.1, -2}, {0.5, -0.1, -2}, {0.5, 0.1, -2},
                                   {-0.5, 0.1, -2}};
    static const double square[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const ddof_card card = card_of(p, square, 4, t, TW, 1);
    static float a[W * H * 4], b[W * H * 4];
    for (int i = 0; i < W * H * 4; i++)
        b[i] = 7.0f;
    const ddof_camera cam = camera();
    CHECK_EQ_INT(ddof_render_cards(cpu, NULL, &cam, &card, 1, &(ddof_image){a, W, H, 4, 0}),
                 DDOF_OK);
    const ddof_status s =
        ddof_render_cards(gl, NULL, &cam, &card, 1, &(ddof_image){b, W, H, 4, 0});
    printf("a %dx1 texture: %d %s\n", TW, (int)s, ddof_context_last_error(gl));
    if (s == DDOF_OK) {
        CHECK(max_diff(a, b, W * H * 4) <= TOL_CARDS);
    } else {
        CHECK_EQ_INT(s, DDOF_ERROR_UNSUPPORTED);
        CHECK(strstr(ddof_context_last_error(gl), "GL_MAX_TEXTURE_SIZE") != NULL);
        int untouched = 1;
        for (int i = 0; i < W * H * 4; i++)
            untouched &= b[i] == 7.0f;
        CHECK(untouched);
    }
    free(t);
}

int main(int argc, char **argv)
{
    gl = gl_context_for(backend_from_name(argc > 1 ? argv[1] : NULL));
    if (!gl)
        return GL_TEST_SKIP;
    cpu = make_context(0);
    overlapping();
    hidden();
    triangle();
    large_texture();
    magnified();
    texture_too_large();
    ddof_context_free(cpu);
    ddof_context_free(gl);
    return test_report("test_gl_cards");
}
