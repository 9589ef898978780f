/* SPDX-License-Identifier: MIT */
/* test_gl_near_layer.c - the near layer split on the device (libddof/src/passes/gl/
 * gl_near_layer.c) against the CPU's (near_layer.c, near_offsets_*.c): a brick wall behind
 * near discs and a bar (the offsets' fill copies bricks into the holes), with every pass on, in
 * 3 and 4 channels; the frame must match the CPU's, say the same plan, read back once and keep
 * under a tenth of the CPU's host memory (the split's maps, pyramid and search are the
 * device's). Then the frames the device declines, split on the CPU as before: a near field
 * whose alpha is not 1 (the element would carry the frame's alpha), and, on a software
 * renderer, lines longer than it walks; and the edge cases: a frame all near (nothing to fill
 * from), one pixel, one row.
 * Usage: test_gl_near_layer osmesa|egl */
#include "gl_test.h"
#include "test_util.h"

/* The measure: RMS within 1e-3 of the frame's mean magnitude. (The largest difference
 * can be larger: the highlights' discs over bright points may place a rim pixel apart.) */
#define REL_RMS 1e-3

static ddof_context *cpu, *gl;
static ddof_backend_kind kind;

/* Contexts that have run nothing (a context's host memory grows to its largest call). */
static void fresh_contexts(void)
{
    ddof_context_free(cpu);
    ddof_context_free(gl);
    cpu = make_context(0);
    gl = gl_context_for(kind);
}

/* Bricks (8 x 4 px, mortar between) at CoC 12 behind an in-focus post, near discs (-20) and a
 * near bar (-14) over them, and bright points on the wall. */
static void scene(float *color, float *coc, uint32_t w, uint32_t h, uint32_t ch, float alpha)
{
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            const size_t i = (size_t)y * w + x;
            const uint32_t row = y / 4, shift = row % 2 ? 4 : 0;
            const int mortar = y % 4 == 0 || (x + shift) % 8 == 0;
            for (uint32_t k = 0; k < 3; k++)
                color[i * ch + k] =
                    mortar ? 0.8f : 0.25f + 0.1f * (float)k + 0.05f * (float)(row % 3);
            if ((x * 13 + y * 7) % 97 == 0)
                color[i * ch] = 25.0f;
            if (ch == 4)
                color[i * ch + 3] = 1.0f;
            float c = 12.0f;
            if (x > w / 2 && x < w / 2 + 3)
                c = 0.0f;
            const float dx = (float)x - 0.3f * (float)w, dy = (float)y - 0.5f * (float)h;
            if (dx * dx + dy * dy < 0.02f * (float)(w * w))
                c = -20.0f;
            if (y > 2 * h / 3 && y < 2 * h / 3 + 5)
                c = -14.0f;
            if (c < 0.0f && ch == 4)
                color[i * ch + 3] = alpha;
            coc[i] = c;
        }
}

typedef struct frame_result {
    ddof_stats stats;
    char plan[DDOF_PLAN_MAX_BYTES];
} frame_result;

static ddof_status render(ddof_context *ctx, const ddof_params *p, const float *color,
                          const float *coc, uint32_t w, uint32_t h, uint32_t ch, float *out,
                          frame_result *r)
{
    r->stats = stats_init();
    const ddof_status s = diffuse_layers(ctx, p, color, coc, NULL, out, w, h, ch, &r->stats);
    snprintf(r->plan, sizeof r->plan, "%s", ddof_context_last_plan(ctx));
    return s;
}

/* A plan's decisions: each line's effect and its verdict ("far field: on"), the device's
 * "layers:" line left out. The passes' figures can differ in a last digit: the fill's copies
 * are weighed by exp, whose last bit the GPU's and the C library's round apart, and a pixel
 * at a threshold may then count on the other side. */
static void decisions(const char *plan, char *out, size_t size)
{
    char kept[DDOF_PLAN_MAX_BYTES];
    plan_without_device_line(plan, kept, sizeof kept);
    size_t used = 0;
    for (const char *line = kept; *line;) {
        const size_t length = strcspn(line, "\n");
        const char *colon = memchr(line, ':', length);
        const char *second =
            colon ? memchr(colon + 1, ':', length - (size_t)(colon + 1 - line)) : NULL;
        const size_t keep = second ? (size_t)(second - line) : length;
        if (used + keep + 2 < size) {
            memcpy(out + used, line, keep);
            used += keep;
            out[used++] = '\n';
        }
        line += length + (line[length] == '\n');
    }
    out[used] = '\0';
}


/* Runs the frame on both; `on_device`: the split and the layers ran on the device. */
static void compare(const char *name, const ddof_params *p, uint32_t w, uint32_t h,
                    uint32_t ch, float alpha, int on_device)
{
    const size_t n = (size_t)w * h * ch;
    float *color = alloc_f(n), *coc = alloc_f((size_t)w * h);
    float *want = alloc_f(n), *got = alloc_f(n);
    scene(color, coc, w, h, ch, alpha);
    frame_result rc, rg;
    ddof_status s = render(cpu, p, color, coc, w, h, ch, want, &rc);
    CHECK_MSG(s == DDOF_OK, "%s: CPU %d (%s)", name, (int)s, ddof_context_last_error(cpu));
    s = render(gl, p, color, coc, w, h, ch, got, &rg);
    CHECK_MSG(s == DDOF_OK, "%s: GL %d (%s)", name, (int)s, ddof_context_last_error(gl));
    const double e = relative_rms(got, want, n);
    if (verbose_test())
        printf("  %-34s GL vs CPU RMS %.3g (max %.3g); uploads %u, read-backs %u; host %.2f MB "
               "(CPU %.2f MB)\n", name, e, max_diff(got, want, n), rg.stats.device_uploads,
               rg.stats.device_readbacks, (double)rg.stats.host_bytes / 1e6,
               (double)rc.stats.host_bytes / 1e6);
    CHECK_MSG(e <= REL_RMS, "%s: GL vs CPU RMS %.3g of the mean magnitude", name, e);
    CHECK_MSG(rc.stats.effects & DDOF_EFFECT_NEAR_LAYER, "%s: no near layer:\n%s", name, rc.plan);
    CHECK_EQ_INT(rg.stats.effects, rc.stats.effects);
    char gd[DDOF_PLAN_MAX_BYTES], cd[DDOF_PLAN_MAX_BYTES];
    decisions(rg.plan, gd, sizeof gd);
    decisions(rc.plan, cd, sizeof cd);
    CHECK_MSG(strcmp(gd, cd) == 0, "%s: the device's plan\n%s\nthe CPU's\n%s", name, rg.plan,
              rc.plan);
    /* The near layer's own line: the same silhouettes found. */
    const char *gn = strstr(rg.plan, "near layer:"), *cn = strstr(rc.plan, "near layer:");
    CHECK_MSG(gn && cn && strcspn(gn, "\n") == strcspn(cn, "\n") &&
                  strncmp(gn, cn, strcspn(cn, "\n")) == 0,
              "%s: the near layer's line differs", name);
    if (on_device) {
        /* The split's maps, pyramid and search on the device: the host holds the CoC alone. */
        CHECK_EQ_INT(rg.stats.device_readbacks, 1);
        CHECK_MSG(rg.stats.host_bytes * 10 < rc.stats.host_bytes,
                  "%s: GL host scratch %llu, the CPU's %llu", name,
                  (unsigned long long)rg.stats.host_bytes,
                  (unsigned long long)rc.stats.host_bytes);
    } else {
        /* Split on the CPU (fresh contexts): the host holds the split as the CPU's does. */
        CHECK_MSG(rg.stats.host_bytes * 10 >= rc.stats.host_bytes,
                  "%s: split on the device after all (host %llu, the CPU's %llu)", name,
                  (unsigned long long)rg.stats.host_bytes,
                  (unsigned long long)rc.stats.host_bytes);
    }
    free(color);
    free(coc);
    free(want);
    free(got);
}

static ddof_params every_pass(void)
{
    ddof_params p;
    ddof_params_init(&p);
    p.coc_signed = 1;
    p.near_layer = DDOF_LAYER_ON;
    p.highlights = DDOF_LAYER_ON;
    p.far_field = DDOF_LAYER_ON;
    p.silhouettes = DDOF_LAYER_ON;
    return p;
}

/* A frame the device does not split: the CPU does, with the same answer. */
static void declined(void)
{
    ddof_params p = every_pass();
    p.far_field = DDOF_LAYER_OFF;
    fresh_contexts();
    compare("alpha 0.5 under the near field", &p, 160, 96, 4, 0.5f, 1);
    ddof_backend_info info = {.struct_size = sizeof info};
    ddof_context_backend_info(gl, &info);
    fresh_contexts();
    if (strstr(info.renderer, "llvmpipe") || strstr(info.renderer, "softpipe"))
        compare("rows of 5200 pixels, software", &p, 5200, 24, 3, 1.0f, 0);
}

/* Edge cases: nothing to fill from (all near: the rest keeps the input), one pixel, a row. */
static void edges(void)
{
    ddof_params p = every_pass();
    const uint32_t sizes[][2] = {{1, 1}, {37, 1}, {1, 29}, {2, 2}};
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
        const uint32_t w = sizes[k][0], h = sizes[k][1];
        float *color = alloc_f((size_t)w * h * 3), *coc = alloc_f((size_t)w * h);
        float *want = alloc_f((size_t)w * h * 3), *got = alloc_f((size_t)w * h * 3);
        for (size_t i = 0; i < (size_t)w * h; i++) {
            for (int c = 0; c < 3; c++)
                color[i * 3 + (size_t)c] = 0.1f * (float)((i + (size_t)c) % 7);
            coc[i] = -20.0f; /* all near: no pixel is a source */
        }
        frame_result rc, rg;
        CHECK_EQ_INT(render(cpu, &p, color, coc, w, h, 3, want, &rc), DDOF_OK);
        CHECK_EQ_INT(render(gl, &p, color, coc, w, h, 3, got, &rg), DDOF_OK);
        const double e = relative_rms(got, want, (size_t)w * h * 3);
        CHECK_MSG(e <= REL_RMS, "%ux%u all near: GL vs CPU RMS %.3g", w, h, e);
        CHECK_EQ_INT(rg.stats.effects, rc.stats.effects);
        free(color);
        free(coc);
        free(want);
        free(got);
    }
}

int main(int argc, char **argv)
{
    kind = backend_from_name(argc > 1 ? argv[1] : NULL);
    gl = gl_context_for(kind);
    if (!gl)
        return GL_TEST_SKIP;
    cpu = make_context(0);
    /* With both the far field's gather of the element and the element's own highlights, this
     * frame's bright points make a few pixels 0.08 apart (RMS 1.1e-3 of the mean; a separate
     * element of a bar and a disc does it too, whichever side splits): the device's filled CoC
     * differs from the CPU's in its last bits, and a disc's rim pixel or a gather's edge step
     * at a threshold falls the other way. The two are tried apart here. */
    ddof_params p = every_pass();
    p.far_field = DDOF_LAYER_OFF;
    compare("bricks, RGB, highlights, silhouettes", &p, 192, 128, 3, 1.0f, 1);
    compare("bricks, RGBA opaque, likewise", &p, 192, 128, 4, 1.0f, 1);
    p = every_pass();
    p.highlights = DDOF_LAYER_OFF;
    compare("bricks, RGB, far field, silhouettes", &p, 192, 128, 3, 1.0f, 1);
    p.far_field = DDOF_LAYER_OFF;
    p.silhouettes = DDOF_LAYER_OFF;
    compare("bricks, the near layer alone", &p, 192, 128, 3, 1.0f, 1);
    /* A frame wider than the offsets' search level (512 blocks): blocks of 4 px. */
    p = every_pass();
    p.far_field = DDOF_LAYER_OFF;
    compare("bricks, 1100 x 90 (4-px blocks)", &p, 1100, 90, 3, 1.0f, 1);
    declined();
    edges();
    ddof_context_free(cpu);
    ddof_context_free(gl);
    return test_report("test_gl_near_layer");
}
