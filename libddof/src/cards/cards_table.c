/* SPDX-License-Identifier: MIT */
/* cards_table.c - a card's summed-area tables: the texture's (double, premultiplied RGBA,
 * texels whose centre lies outside the card's uv polygon transparent) and a count of the
 * texels that are not wholly zero (uint32), which lets the drawing skip a pixel whose disc
 * only covers empty texture. Built on the context's threads: each row's prefix sums, then the
 * columns' running sums, the same additions in the same order as a serial build. */
#include "cards.h"

#include "runtime/parallel_rows.h"

#include <math.h>
#include <string.h>

/* Whether texel (i, j)'s centre lies in the card's uv polygon (row 0 at the top: v = 1). */
static int texel_in_card(const card_setup *c, double orientation, uint32_t tw, uint32_t th,
                         uint32_t i, uint32_t j)
{
    const double u = (i + 0.5) / tw, v = 1.0 - (j + 0.5) / th;
    for (uint32_t k = 0; k < c->n; k++) {
        const double *a = c->uv[k], *b = c->uv[(k + 1) % c->n];
        if (orientation * ((b[0] - a[0]) * (v - a[1]) - (b[1] - a[1]) * (u - a[0])) < -1e-12)
            return 0;
    }
    return 1;
}

typedef struct table_job {
    const card_setup *card;
    card_table *table;
    double orientation;
    uint32_t column_blocks;
} table_job;

/* The texels of row j inside the polygon: an interval (a convex polygon cut by a line). Its
 * ends come from the edges' half-planes, then are settled by texel_in_card itself, so the set
 * is exactly the per-texel test's. */
static void row_span(const table_job *job, uint32_t j, uint32_t *first, uint32_t *end)
{
    const card_setup *c = job->card;
    const uint32_t tw = job->table->tw, th = job->table->th;
    const double v = 1.0 - (j + 0.5) / th;
    double lo = 0.0, hi = tw; /* in texel-centre index units: u = (i + 0.5) / tw */
    for (uint32_t k = 0; k < c->n; k++) {
        const double *a = c->uv[k], *b = c->uv[(k + 1) % c->n];
        /* orientation * (p - q u) >= 0 with p, q below */
        const double q = job->orientation * (b[1] - a[1]);
        const double p = job->orientation * ((b[0] - a[0]) * (v - a[1]) + (b[1] - a[1]) * a[0]);
        if (q > 0.0)
            hi = fmin(hi, p / q * tw - 0.5 + 1.0);
        else if (q < 0.0)
            lo = fmax(lo, p / q * tw - 0.5);
        else if (p < 0.0)
            lo = hi;
    }
    uint32_t a = lo <= 0.0 ? 0u : lo >= tw ? tw : (uint32_t)lo;
    uint32_t e = hi <= 0.0 ? 0u : hi >= tw ? tw : (uint32_t)ceil(hi);
    e = e < a ? a : e;
    while (a > 0 && texel_in_card(c, job->orientation, tw, th, a - 1, j))
        a--;
    while (a < e && !texel_in_card(c, job->orientation, tw, th, a, j))
        a++;
    if (a == e) /* the estimate missed (edges within the test's tolerance): scan the row */
        while (a < tw && !texel_in_card(c, job->orientation, tw, th, a, j))
            a++;
    e = e < a ? a : e;
    while (e < tw && texel_in_card(c, job->orientation, tw, th, e, j))
        e++;
    while (e > a && !texel_in_card(c, job->orientation, tw, th, e - 1, j))
        e--;
    *first = a;
    *end = e;
}

/* Table row j + 1 holds row j's running sums for now (the column pass adds the rows above). */
static void prefix_rows(void *user, uint32_t r0, uint32_t r1, uint32_t chunk)
{
    (void)chunk;
    const table_job *job = user;
    const card_setup *c = job->card;
    card_table *t = job->table;
    const size_t row = (size_t)(t->tw + 1) * 4, count_row = (size_t)t->tw + 1;
    for (uint32_t j = r0; j < r1; j++) {
        const float *texel = c->texture.pixels + (size_t)j * c->texture_stride;
        double *here = t->sum + (size_t)(j + 1) * row;
        uint32_t *count = t->count + (size_t)(j + 1) * count_row;
        uint32_t first, end;
        row_span(job, j, &first, &end);
        double run[4] = {0, 0, 0, 0};
        uint32_t run_count = 0;
        for (uint32_t i = 0; i < t->tw; i++) {
            const int in = i >= first && i < end;
            int nonzero = 0;
            for (int ch = 0; ch < 4; ch++) {
                const double value = in ? texel[(size_t)i * 4 + ch] : 0.0;
                run[ch] += value;
                nonzero |= value != 0.0;
                here[(i + 1) * 4 + ch] = run[ch];
            }
            run_count += (uint32_t)nonzero;
            count[i + 1] = run_count;
        }
        memset(here, 0, 4 * sizeof *here);
        count[0] = 0;
    }
}

#define CARDS_COLUMN_BLOCK 64u /* doubles (or counts) per block of the column pass */

/* Columns [block * 64, ...) of both tables: each row adds the finished row above. */
static void sum_columns(void *user, uint32_t b0, uint32_t b1, uint32_t chunk)
{
    (void)chunk;
    const table_job *job = user;
    card_table *t = job->table;
    const size_t row = (size_t)(t->tw + 1) * 4, count_row = (size_t)t->tw + 1;
    for (uint32_t b = b0; b < b1; b++) {
        const size_t c0 = (size_t)b * CARDS_COLUMN_BLOCK;
        const size_t c1 = c0 + CARDS_COLUMN_BLOCK < row ? c0 + CARDS_COLUMN_BLOCK : row;
        for (uint32_t j = 2; j <= t->th; j++) {
            double *here = t->sum + (size_t)j * row;
            const double *above = here - row;
            for (size_t k = c0; k < c1; k++)
                here[k] = above[k] + here[k];
            if (c0 < count_row) {
                uint32_t *count = t->count + (size_t)j * count_row;
                /* the row above by its own pointer: count[k - count_row] wraps k - count_row
                 * (k < count_row), an overflowing pointer offset (UBSan, fuzz_cards_scene) */
                const uint32_t *count_above = count - count_row;
                const size_t k1 = c1 < count_row ? c1 : count_row;
                for (size_t k = c0; k < k1; k++)
                    count[k] += count_above[k];
            }
        }
    }
}

ddof_status cards_table_build(ddof_context *context, const card_setup *c, card_table *t)
{
    t->tw = c->texture.width;
    t->th = c->texture.height;
    const size_t cells = (size_t)(t->tw + 1) * (t->th + 1);
    if (cells > t->capacity) {
        ddof_free(&context->allocator, t->sum);
        ddof_free(&context->allocator, t->count);
        t->sum = ddof_alloc(&context->allocator, cells * 4 * sizeof *t->sum);
        t->count = ddof_alloc(&context->allocator, cells * sizeof *t->count);
        t->capacity = t->sum && t->count ? cells : 0;
        if (!t->capacity)
            return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                             "no memory for card %u's summed-area tables (%zu bytes)", c->index,
                             cells * (4 * sizeof *t->sum + sizeof *t->count));
    }
    double area = 0.0;
    for (uint32_t k = 0; k < c->n; k++) {
        const double *a = c->uv[k], *b = c->uv[(k + 1) % c->n];
        area += a[0] * b[1] - b[0] * a[1];
    }
    table_job job = {.card = c, .table = t, .orientation = area >= 0.0 ? 1.0 : -1.0};
    memset(t->sum, 0, (size_t)(t->tw + 1) * 4 * sizeof *t->sum);
    memset(t->count, 0, (size_t)(t->tw + 1) * sizeof *t->count);
    ddof_parallel_rows(context, t->th, prefix_rows, &job);
    const size_t row = (size_t)(t->tw + 1) * 4;
    ddof_parallel_rows(context, (uint32_t)((row + CARDS_COLUMN_BLOCK - 1) / CARDS_COLUMN_BLOCK),
                       sum_columns, &job);
    return DDOF_OK;
}

void cards_table_free(ddof_context *context, card_table *t)
{
    ddof_free(&context->allocator, t->sum);
    ddof_free(&context->allocator, t->count);
    memset(t, 0, sizeof *t);
}
