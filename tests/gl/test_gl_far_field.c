/* SPDX-License-Identifier: MIT */
/* test_gl_far_field.c - the far field on the device (libddof/src/passes/gl) against the CPU's
 * (libddof/src/passes/far_field*.c, far_layers.c): frames whose far field gathers with image
 * levels, cuts depth slices where blurred surfaces meet, and walks lines longer than one
 * dispatch's segment (rows and columns of 9000 pixels), in 1 to 4 channels and with anamorphic
 * pixels. Each must match the CPU within the frames' tolerance, say the same far-field line in
 * its plan (the pixels, the levels, the slices: the same decisions), and stay on the device:
 * one upload, one read-back, and none of the far field's host scratch (its maps alone are five
 * floats a pixel).
 * Usage: test_gl_far_field osmesa|egl */
#include "gl_test.h"
#include "test_util.h"

#define TOL 1e-4

static ddof_context *cpu, *gl;

/* A far backdrop (CoC 30), a tree's crown before it (CoC 10-14: edges between blurred
 * surfaces), a bush (22), a near blob over the crown's edge (-18 when signed), an in-focus
 * post, over a blocky texture: four depth slices; the CoC `scale` times those. */
static void scene(float *color, float *coc, uint32_t w, uint32_t h, uint32_t ch, float scale)
{
    block_texture(color, w, h, ch, 11, 0.05, 0.95);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            const float u = (float)x / (float)w, v = (float)y / (float)h;
            float c = 30.0f;
            const float du = u - 0.35f, dv = v - 0.4f;
            if (du * du + dv * dv < 0.04f)
                c = 10.0f + 4.0f * v; /* a crown */
            const float fu = u - 0.2f, fv = v - 0.6f;
            if (fu * fu + fv * fv < 0.0064f)
                c = 22.0f; /* a bush between the crown and the backdrop */
            const float eu = u - 0.5f, ev = v - 0.45f;
            if (eu * eu + ev * ev < 0.01f)
                c = -18.0f; /* a near blob over the crown's edge */
            if (u > 0.55f && u < 0.58f)
                c = 0.0f; /* a post in focus */
            coc[(size_t)y * w + x] = c * scale;
        }
}

/* The plan's "far field:" line into `line` (empty when it has none). */
static void far_line(const ddof_stats *st, char *line, size_t size)
{
    const char *at = strstr(st->plan, "far field:");
    line[0] = '\0';
    if (at)
        snprintf(line, size, "%.*s", (int)strcspn(at, "\n"), at);
}

static void compare(const char *name, uint32_t w, uint32_t h, uint32_t ch, float scale,
                    float pixel_aspect, ddof_layer_mode blurred_edges, int want_slices)
{
    const size_t n = (size_t)w * h * ch;
    float *color = alloc_f(n), *coc = alloc_f((size_t)w * h);
    float *want = alloc_f(n), *got = alloc_f(n);
    scene(color, coc, w, h, ch, scale);
    ddof_params p;
    ddof_params_init(&p);
    p.coc_signed = 1;
    p.pixel_aspect = pixel_aspect;
    p.blurred_edges = blurred_edges;
    p.highlights = DDOF_LAYER_OFF;
    p.silhouettes = DDOF_LAYER_OFF;
    p.near_layer = DDOF_LAYER_OFF;
    p.far_field = DDOF_LAYER_ON;
    ddof_stats sc = stats_init(), sg = stats_init();
    ddof_status s = diffuse_layers(cpu, &p, color, coc, NULL, want, w, h, ch, &sc);
    CHECK_MSG(s == DDOF_OK, "%s: CPU %d (%s)", name, (int)s, ddof_context_last_error(cpu));
    s = diffuse_layers(gl, &p, color, coc, NULL, got, w, h, ch, &sg);
    CHECK_MSG(s == DDOF_OK, "%s: GL %d (%s)", name, (int)s, ddof_context_last_error(gl));
    const double e = max_diff(got, want, n);
    char cl[160], gll[160];
    far_line(&sc, cl, sizeof cl);
    far_line(&sg, gll, sizeof gll);
    if (verbose_test())
        printf("  %-36s GL vs CPU %.3g; %s; host %.1f MB (CPU %.1f MB)\n", name, e, gll,
               (double)sg.host_bytes / 1e6, (double)sc.host_bytes / 1e6);
    CHECK_MSG(e <= TOL, "%s: GL vs CPU %.3g > %.3g", name, e, TOL);
    CHECK_MSG(strcmp(cl, gll) == 0, "%s: the CPU says \"%s\", GL \"%s\"", name, cl, gll);
    CHECK_MSG(sc.effects & DDOF_EFFECT_FAR_FIELD, "%s: no far field (%s)", name, cl);
    CHECK_MSG((strstr(cl, want_slices ? "4 depth slices" : "blurred edges: forced off") !=
               NULL), "%s: %s", name, cl);
    /* The far field's maps (five floats a pixel) and levels stay on the device. */
    CHECK_PASS_ON_DEVICE(name, sc, sg, (uint64_t)w * h * 5 * sizeof(float));
    free(color);
    free(coc);
    free(want);
    free(got);
}

int main(int argc, char **argv)
{
    gl = gl_context_for(backend_from_name(argc > 1 ? argv[1] : NULL));
    if (!gl)
        return GL_TEST_SKIP;
    cpu = make_context(0);
    compare("slices, RGBA", 160, 96, 4, 1.0f, 1.0f, DDOF_LAYER_AUTO, 1);
    compare("slices, RGB, pixel aspect 2", 160, 96, 3, 1.0f, 2.0f, DDOF_LAYER_AUTO, 1);
    compare("slices, RGB, pixel aspect 0.5", 160, 96, 3, 1.0f, 0.5f, DDOF_LAYER_AUTO, 1);
    compare("no slices, RGBA", 160, 96, 4, 1.0f, 1.0f, DDOF_LAYER_OFF, 0);
    compare("one channel, five levels", 192, 128, 1, 5.0f, 1.0f, DDOF_LAYER_AUTO, 1);
    compare("two channels", 160, 96, 2, 1.0f, 1.0f, DDOF_LAYER_AUTO, 1);
    /* Lines longer than a dispatch's segment (4096 steps): the rows' prefix sums and box sums,
     * the columns' running sums. */
    compare("rows of 9000 pixels", 9000, 12, 3, 0.4f, 1.0f, DDOF_LAYER_AUTO, 1);
    compare("columns of 9000 pixels", 12, 9000, 3, 0.4f, 1.0f, DDOF_LAYER_AUTO, 1);
    ddof_context_free(cpu);
    ddof_context_free(gl);
    return test_report("test_gl_far_field");
}
