/* SPDX-License-Identifier: MIT */
/* test_gl_silhouettes.c - the silhouettes' split on the device (libddof/src/passes/gl) against
 * the CPU's (libddof/src/passes/silhouettes.c): in-focus bars of one pixel (thin: the shares
 * the rules give) and of five (the colours' projection) with mixed edge pixels over a blurred,
 * textured wall, in 3 and 4 channels, from the colours and from an object matte (two ranks).
 * Each must match the CPU within the frames' tolerance, say the same silhouettes line (the
 * same count of pixels split), and stay on the device: one upload, one read-back, none of the
 * split's host scratch (its colour copy and its changes: channels + 3 floats a pixel). With
 * the matte and highlights the split comes after the highlights' discs, on the device too.
 * Usage: test_gl_silhouettes osmesa|egl */
#include "gl_test.h"
#include "test_util.h"

#define TOL 1e-4
#define W 96
#define H 64

static ddof_context *cpu, *gl;

/* The bars' object ids (Cryptomatte's float bits). */
static float id_of(uint32_t bits)
{
    float f;
    memcpy(&f, &bits, sizeof f);
    return f;
}

/* A wall of CoC 16 + 8 y / H behind bars in focus: one pixel wide at x = 20 and 60, five wide
 * at 35-39, each edge pixel covered 0.4 by the bar (its depth the wall's); the matte's two
 * ranks say so (bar, then wall, or the world where `world`). `bright`: a light on the wall. */
static void scene(float *color, float *coc, float *matte, uint32_t ch, int bright)
{
    block_texture(color, W, H, ch, 5, 0.2, 0.8);
    const float bar[3] = {0.95f, 0.1f, 0.05f};
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            const size_t i = (size_t)y * W + x;
            float cover = 0.0f;
            if (x == 20 || x == 60 || (x >= 35 && x <= 39))
                cover = 1.0f;
            else if (x == 19 || x == 21 || x == 34 || x == 40 || x == 59 || x == 61)
                cover = 0.4f;
            coc[i] = cover == 1.0f ? 0.0f : 16.0f + 8.0f * (float)y / H;
            for (uint32_t c = 0; c < 3; c++)
                color[i * ch + c] = cover * bar[c] + (1.0f - cover) * color[i * ch + c];
            if (bright && (x - 80) * (x - 80) + (y - 30) * (y - 30) < 4)
                for (uint32_t c = 0; c < 3; c++)
                    color[i * ch + c] = 40.0f;
            float *m = matte + i * 4;
            m[0] = id_of(cover > 0.0f ? 0x3f0a1b2cu : 0x3e112233u);
            m[1] = cover > 0.0f ? cover : 1.0f;
            m[2] = id_of(cover > 0.0f ? 0x3e112233u : 0x3f0a1b2cu);
            m[3] = cover > 0.0f ? 1.0f - cover : 0.0f;
        }
}

/* The silhouettes' line of the context's last plan (whole: the stats' copy can end before it). */
static void silhouettes_line(const ddof_context *ctx, char *line, size_t size)
{
    const char *at = strstr(ddof_context_last_plan(ctx), "silhouettes:");
    line[0] = '\0';
    if (at)
        snprintf(line, size, "%.*s", (int)strcspn(at, "\n"), at);
}

static ddof_status render(ddof_context *ctx, const ddof_params *p, const float *color,
                          const float *coc, const float *matte, uint32_t ch, float *out,
                          ddof_stats *st)
{
    ddof_frame f;
    ddof_frame_init(&f);
    f.color = (ddof_image_in){color, W, H, ch, 0};
    f.coc = (ddof_image_in){coc, W, H, 1, 0};
    const ddof_image_in m = {matte, W, H, 4, 0};
    *st = stats_init();
    return ddof_render_frame_with_matte(ctx, p, &f, matte ? &m : NULL,
                                        &(ddof_image){out, W, H, ch, 0}, st);
}

static void compare(const char *name, uint32_t ch, int with_matte, int lights)
{
    const size_t n = (size_t)W * H * ch;
    float *color = alloc_f(n), *coc = alloc_f((size_t)W * H), *matte = alloc_f((size_t)W * H * 4);
    float *want = alloc_f(n), *got = alloc_f(n);
    scene(color, coc, matte, ch, lights);
    ddof_params p;
    ddof_params_init(&p);
    p.coc_signed = 1;
    p.silhouettes = DDOF_LAYER_ON;
    p.highlights = lights ? DDOF_LAYER_ON : DDOF_LAYER_OFF;
    ddof_stats sc, sg;
    const float *m = with_matte ? matte : NULL;
    ddof_status s = render(cpu, &p, color, coc, m, ch, want, &sc);
    CHECK_MSG(s == DDOF_OK, "%s: CPU %d (%s)", name, (int)s, ddof_context_last_error(cpu));
    s = render(gl, &p, color, coc, m, ch, got, &sg);
    CHECK_MSG(s == DDOF_OK, "%s: GL %d (%s)", name, (int)s, ddof_context_last_error(gl));
    const double e = max_diff(got, want, n);
    char cl[160], gll[160];
    silhouettes_line(cpu, cl, sizeof cl);
    silhouettes_line(gl, gll, sizeof gll);
    if (verbose_test())
        printf("  %-30s GL vs CPU %.3g; %s; host %.2f MB (CPU %.2f MB)\n", name, e, gll,
               (double)sg.host_bytes / 1e6, (double)sc.host_bytes / 1e6);
    CHECK_MSG(e <= TOL, "%s: GL vs CPU %.3g > %.3g", name, e, TOL);
    CHECK_MSG(cl[0] && strcmp(cl, gll) == 0, "%s: the CPU says \"%s\", GL \"%s\"", name, cl,
              gll);
    CHECK_MSG(sc.effects & DDOF_EFFECT_SILHOUETTES, "%s: no split (%s)", name, cl);
    /* With the matte and a light the discs go before the split, on the device too. */
    CHECK_PASS_ON_DEVICE(name, sc, sg, (uint64_t)W * H * (ch + 3) * sizeof(float));
    free(color);
    free(coc);
    free(matte);
    free(want);
    free(got);
}

int main(int argc, char **argv)
{
    gl = gl_context_for(backend_from_name(argc > 1 ? argv[1] : NULL));
    if (!gl)
        return GL_TEST_SKIP;
    cpu = make_context(0);
    compare("RGB, the colours' shares", 3, 0, 0);
    compare("RGBA, the colours' shares", 4, 0, 0);
    compare("RGB, the matte's shares", 3, 1, 0);
    compare("RGBA, the matte's shares", 4, 1, 0);
    compare("RGB, the colours, a light", 3, 0, 1);
    compare("RGBA, the matte, a light", 4, 1, 1);
    ddof_context_free(cpu);
    ddof_context_free(gl);
    return test_report("test_gl_silhouettes");
}
