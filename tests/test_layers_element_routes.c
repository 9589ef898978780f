/* SPDX-License-Identifier: MIT */
/* test_layers_element_routes.c - the two routes of a foreground element on the CPU give the
 * same bits: inside the CPU table's run_layers request (ddof_run_layers_on_cpu, what the
 * planner picks where nothing comes between the layers and the element) and after the layers
 * by the CPU's steps (ddof_run_foreground_on_cpu, where something does), with and without the
 * element's own highlights (found by the run inside, by the caller for the steps after) and
 * the far field's gather of its blur (fg_gather). The planner moves an element between the
 * routes by what the frame holds, so an output must not depend on which it took. With the heat
 * kernel and disc-2x2, a background level and the near spread on, in 1 and 2 threads. */
#include "frame/call_checks.h"
#include "layers/layers.h"
#include "test_images.h"
#include "test_util.h"

#include <string.h>

enum { W = 96, H = 64, CH = 4 };

/* Far background with in-focus bars and a near disc (signed CoC), and a soft element disc. */
static void scene(float *color, float *coc, float *fg, float *fg_coc, int lights)
{
    test_rng rng = {11};
    fill_uniform(color, (size_t)W * H * CH, &rng, 0.05, 0.9);
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            float d = 12.0f + 28.0f * (float)y / (float)H;
            if (x % 23 < 3)
                d = 0.0f;
            const float nx = (float)x - 70.0f, ny = (float)y - 40.0f;
            if (nx * nx + ny * ny < 64.0f)
                d = -24.0f;
            coc[(size_t)y * W + x] = d;
            const float ex = (float)x - 30.0f, ey = (float)y - 24.0f;
            const float r = sqrtf(ex * ex + ey * ey);
            const float a = r < 7.0f ? 1.0f : r < 10.0f ? (10.0f - r) / 3.0f : 0.0f;
            float *px = fg + ((size_t)y * W + x) * 4;
            px[0] = 0.8f * a;
            px[1] = 0.4f * a;
            px[2] = 0.2f * a;
            px[3] = a;
            fg_coc[(size_t)y * W + x] = 14.0f;
        }
    if (lights) /* two lights in the element: its own highlights */
        for (int k = 0; k < 2; k++) {
            float *px = fg + ((size_t)(22 + 4 * k) * W + 28 + 3 * k) * 4;
            px[0] = px[1] = px[2] = 40.0f;
        }
}

static void routes(ddof_context *ctx, ddof_kernel kernel, int gather, int lights)
{
    const size_t n = (size_t)W * H * CH;
    float *color = alloc_f(n), *coc = alloc_f((size_t)W * H);
    float *fg = alloc_f((size_t)W * H * 4), *fg_coc = alloc_f((size_t)W * H);
    float *inside = alloc_f(n), *after = alloc_f(n), *layers_only = alloc_f(n);
    scene(color, coc, fg, fg_coc, lights);

    ddof_params p;
    ddof_params_init(&p);
    p.solver = DDOF_SOLVER_THOMAS;
    p.kernel = kernel;
    p.coc_signed = 1;
    p.highlights = lights ? DDOF_LAYER_ON : DDOF_LAYER_OFF;
    p.far_field = gather ? DDOF_LAYER_AUTO : DDOF_LAYER_OFF;
    adi_request r = {.color = color, .color_stride = (size_t)W * CH, .coc = coc,
                     .coc_stride = W, .coc_channels = 1, .width = W, .height = H,
                     .channels = CH, .out_stride = (size_t)W * CH};
    ddof_fill_request_params(ctx, &r, &p);
    adi_layers_request d = {.base = r, .near_spread = 1, .near_slope = DDOF_NEAR_SPREAD_SLOPE,
                            .near_dilate = {0, 0, W, H}, .background_levels = 1,
                            .background_threshold_px = p.background_threshold_px,
                            .background_ramp_start_px = p.background_ramp_start_px,
                            .background_edges = {0, 0, W, H}};
    adi_layers_report a;

    /* The layers alone, then the element after them by the CPU's steps. */
    d.base.out = layers_only;
    CHECK_EQ_INT(ddof_run_layers_on_cpu(ctx, &d, &a), DDOF_OK);
    memcpy(after, layers_only, n * sizeof(float));
    layers_request q = {.base = r, .params = &p};
    q.base.out = after;
    q.fg = (layers_element){.color = fg, .color_stride = (size_t)W * 4, .coc = fg_coc,
                            .coc_stride = W, .coc_channels = 1, .premultiplied = 1,
                            .box = {0, 0, W, H}, .max_coc = 14.0f};
    /* The element's own highlights: found here for the CPU's steps, by the run inside it. */
    highlight_set found = {0};
    if (lights)
        CHECK_EQ_INT(ddof_find_element_highlights(ctx, &q, (pixel_box){0, 0, W, H},
                                                  p.highlight_threshold, NULL, &found),
                     DDOF_OK);
    CHECK_MSG((found.count > 0) == lights, "%s: %u of the element's highlights",
              ddof_kernel_name(kernel), found.count);
    adi_highlights fg_lights = ddof_request_highlights(&q, lights, 0, NULL);
    fg_lights.items = found.items;
    fg_lights.count = found.count;
    layer_stages st = {0};
    layers_report report = {0};
    CHECK_EQ_INT(ddof_run_foreground_on_cpu(ctx, &q, &fg_lights, &st, &report), DDOF_OK);

    /* The element inside the request, over the area ddof_run_foreground_on_cpu used. */
    d.base.out = inside;
    d.fg_color = fg;
    d.fg_color_stride = (size_t)W * 4;
    d.fg_coc = fg_coc;
    d.fg_coc_stride = W;
    d.fg_coc_channels = 1;
    d.fg_premultiplied = 1;
    d.fg_max_coc = 14.0f;
    d.fg_area = (adi_box){0, 0, W, H};
    d.fg_gather = (uint32_t)gather;
    d.fg_highlights = ddof_request_highlights(&q, lights, 0, NULL);
    CHECK_EQ_INT(ddof_run_layers_on_cpu(ctx, &d, &a), DDOF_OK);
    const uint32_t extra = (uint32_t)DDOF_EFFECT_FAR_FIELD | (uint32_t)DDOF_EFFECT_HIGHLIGHTS;
    CHECK_EQ_INT(a.element_effects, report.effects & extra);
    CHECK_EQ_INT(a.element_effects, (gather ? (uint32_t)DDOF_EFFECT_FAR_FIELD : 0u) |
                                        (lights ? (uint32_t)DDOF_EFFECT_HIGHLIGHTS : 0u));

    size_t differ = 0, changed = 0;
    for (size_t i = 0; i < n; i++) {
        differ += memcmp(&inside[i], &after[i], sizeof(float)) != 0;
        changed += inside[i] != layers_only[i];
    }
    printf("%s%s%s: %zu of %zu values differ between the routes; the element changed %zu\n",
           ddof_kernel_name(kernel), gather ? ", gathered" : "", lights ? ", its lights" : "",
           differ, n, changed);
    CHECK_MSG(differ == 0, "%s: %zu values differ", ddof_kernel_name(kernel), differ);
    CHECK_MSG(changed > (size_t)W * H / 20, "%s: the element changed only %zu values",
              ddof_kernel_name(kernel), changed);
    free(color);
    free(coc);
    free(fg);
    free(fg_coc);
    free(inside);
    free(after);
    free(layers_only);
}

int main(void)
{
    for (uint32_t threads = 1; threads <= 2; threads++) {
        ddof_context *ctx = make_context(threads);
        for (int gather = 0; gather < 2; gather++)
            for (int lights = 0; lights < 2; lights++) {
                routes(ctx, DDOF_KERNEL_HEAT, gather, lights);
                routes(ctx, DDOF_KERNEL_DISC_2X2, gather, lights);
            }
        ddof_context_free(ctx);
    }
    return test_report("test_layers_element_routes");
}
