/* SPDX-License-Identifier: MIT */
/* test_cards_table.c - the cards' summed-area tables (libddof/src/cards/cards_table.c: built on the
 * context's threads, each texel row's in-card span found from the polygon's edges) against a
 * plain serial build written here from the definition: a texel counts when its centre lies in
 * the card's uv polygon (either winding, edges inclusive to 1e-12), the sum table holds the
 * texels of rows < j and columns < i, the count table those of them not wholly zero. Random
 * convex polygons of 3 to 8 vertices (partly outside the texture, thin slivers, a whole-texture
 * square), random sizes from 1x1, textures with exact zeros; every entry compared bit for bit,
 * on 1 and 3 threads. */
#ifndef DDOF_EXPERIMENTAL
#define DDOF_EXPERIMENTAL
#endif
#include "test_util.h"

#include "cards/cards.h"

#include <stdlib.h>
#include <string.h>

#define MAX_SIDE 41u

static int texel_in(double uv[][2], uint32_t n, double u, double v)
{
    double area = 0.0;
    for (uint32_t k = 0; k < n; k++)
        area += uv[k][0] * uv[(k + 1) % n][1] - uv[(k + 1) % n][0] * uv[k][1];
    const double orientation = area >= 0.0 ? 1.0 : -1.0;
    for (uint32_t k = 0; k < n; k++) {
        const double *a = uv[k], *b = uv[(k + 1) % n];
        if (orientation * ((b[0] - a[0]) * (v - a[1]) - (b[1] - a[1]) * (u - a[0])) < -1e-12)
            return 0;
    }
    return 1;
}

/* A random convex polygon: n angles sorted around a centre, radii 0.2..1 of `size`. */
static uint32_t random_polygon(test_rng *rng, double uv[][2])
{
    const uint32_t n = 3 + (uint32_t)(test_uniform(rng) * 6.0);
    double angle[DDOF_CARD_MAX_VERTICES];
    for (uint32_t k = 0; k < n; k++)
        angle[k] = 6.283185307179586 * test_uniform(rng);
    for (uint32_t k = 1; k < n; k++) /* insertion sort */
        for (uint32_t j = k; j > 0 && angle[j] < angle[j - 1]; j--) {
            const double t = angle[j];
            angle[j] = angle[j - 1];
            angle[j - 1] = t;
        }
    const double cx = -0.2 + 1.4 * test_uniform(rng), cy = -0.2 + 1.4 * test_uniform(rng);
    const double size = 0.05 + 0.9 * test_uniform(rng), squash = 0.02 + test_uniform(rng);
    const int reverse = test_uniform(rng) < 0.5;
    for (uint32_t k = 0; k < n; k++) { /* an ellipse's points: still convex */
        const double a = angle[reverse ? n - 1 - k : k];
        uv[k][0] = cx + size * cos(a);
        uv[k][1] = cy + size * squash * sin(a);
    }
    return n;
}

static void check_case(ddof_context *ctx, const float *texels, uint32_t tw, uint32_t th,
                       double uv[][2], uint32_t n, card_table *table, int *bad)
{
    card_setup c;
    memset(&c, 0, sizeof c);
    c.n = n;
    for (uint32_t k = 0; k < n; k++) {
        c.uv[k][0] = uv[k][0];
        c.uv[k][1] = uv[k][1];
    }
    c.texture = (ddof_image_in){texels, tw, th, 4, 0};
    c.texture_stride = (size_t)tw * 4;
    CHECK_EQ_INT(cards_table_build(ctx, &c, table), DDOF_OK);
    static double sum[(MAX_SIDE + 1) * (MAX_SIDE + 1) * 4];
    static uint32_t count[(MAX_SIDE + 1) * (MAX_SIDE + 1)];
    memset(sum, 0, sizeof sum);
    memset(count, 0, sizeof count);
    const size_t row = (size_t)(tw + 1) * 4;
    for (uint32_t j = 0; j < th; j++) {
        double run[4] = {0, 0, 0, 0};
        uint32_t run_count = 0;
        for (uint32_t i = 0; i < tw; i++) {
            const int in = texel_in(uv, n, (i + 0.5) / tw, 1.0 - (j + 0.5) / th);
            int nonzero = 0;
            for (int ch = 0; ch < 4; ch++) {
                const double value = in ? texels[((size_t)j * tw + i) * 4 + ch] : 0.0;
                run[ch] += value;
                nonzero |= value != 0.0;
                sum[(j + 1) * row + (i + 1) * 4 + ch] = sum[j * row + (i + 1) * 4 + ch] + run[ch];
            }
            run_count += (uint32_t)nonzero;
            count[(j + 1) * (tw + 1) + i + 1] = count[j * (tw + 1) + i + 1] + run_count;
        }
    }
    const size_t cells = (size_t)(tw + 1) * (th + 1);
    if (memcmp(sum, table->sum, cells * 4 * sizeof *sum) != 0 ||
        memcmp(count, table->count, cells * sizeof *count) != 0) {
        if (*bad < 5)
            CHECK_MSG(0, "%ux%u texture, %u-gon from (%g, %g): tables differ", tw, th, n,
                      uv[0][0], uv[0][1]);
        (*bad)++;
    }
}

static void run_cases(uint32_t threads)
{
    ddof_context_options options;
    ddof_context_options_init(&options);
    options.thread_count = threads;
    ddof_context *ctx = NULL;
    CHECK_EQ_INT(ddof_context_create(&options, &ctx), DDOF_OK);
    static float texels[MAX_SIDE * MAX_SIDE * 4];
    test_rng rng = {2025 + threads};
    card_table table = {0};
    int bad = 0, cases = 0;
    for (int t = 0; t < 400; t++) {
        const uint32_t tw = 1 + (uint32_t)(test_uniform(&rng) * MAX_SIDE);
        const uint32_t th = 1 + (uint32_t)(test_uniform(&rng) * MAX_SIDE);
        for (uint32_t i = 0; i < tw * th * 4; i++) /* about a third exactly 0 */
            texels[i] = test_uniform(&rng) < 0.35 ? 0.0f : (float)(test_uniform(&rng) - 0.2);
        double uv[DDOF_CARD_MAX_VERTICES][2];
        uint32_t n = random_polygon(&rng, uv);
        if (t % 10 == 0) { /* the whole texture, as a plain rectangle card has it */
            const double square[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
            memcpy(uv, square, sizeof square);
            n = 4;
        }
        check_case(ctx, texels, tw, th, uv, n, &table, &bad);
        cases++;
    }
    printf("%u thread(s): %d cases, %d with different tables\n", threads, cases, bad);
    CHECK(bad == 0);
    cards_table_free(ctx, &table);
    ddof_context_free(ctx);
}

int main(void)
{
    run_cases(1);
    run_cases(3);
    return test_report("test_cards_table");
}
