/* SPDX-License-Identifier: MIT */
/* cards_request.c - the seam's cards request (ddof_backend_seam.h's adi_cards_request): the
 * visible cards near to far, each card's geometry, and its summed-area table built by the core
 * (cards_table.c) only when the backend asks for it, in the form it asks for: in double with
 * its counts (the CPU's), or split into the two float parts a GL device reads: a part rounded
 * to a multiple of a power of two small enough that every value, and every sum or difference
 * of four, is exact in float, and the small rest. A box's sum from its four corners is then
 * exact on the device, which a plain float table is not (a 512x512 texture's sums reach 2^18,
 * where a float's step is 1/32). */
#include "cards.h"

#include "backends/backend.h"
#include "camera/coc.h"

#include <math.h>
#include <string.h>

typedef struct request_cards {
    ddof_context *context;
    const card_setup *setups;
    const uint32_t *list; /* the visible cards, near to far */
    card_table table;
    float *hi, *lo;
    size_t capacity; /* floats in hi and in lo */
} request_cards;

/* The table of card c as hi + lo (see the file's comment). */
static void split_table(request_cards *d, size_t values)
{
    double largest = 0.0;
    for (size_t k = 0; k < values; k++)
        largest = fmax(largest, fabs(d->table.sum[k]));
    int exponent = 0;
    frexp(largest, &exponent); /* largest < 2^exponent */
    /* values below 2^22 steps: four of them add up below 2^24, a float's exact integers */
    const double step = ldexp(1.0, exponent - 22), inv = 1.0 / step;
    for (size_t k = 0; k < values; k++) {
        const double hi = nearbyint(d->table.sum[k] * inv) * step;
        d->hi[k] = (float)hi;
        d->lo[k] = (float)(d->table.sum[k] - hi);
    }
}

static ddof_status next_card(void *user, uint32_t i, uint32_t parts, adi_card *out)
{
    request_cards *d = user;
    const card_setup *c = &d->setups[d->list[i]];
    memset(out, 0, sizeof *out);
    out->vertex_count = c->n;
    memcpy(out->expanded, c->expanded, sizeof out->expanded);
    memcpy(out->box, c->box, sizeof out->box);
    memcpy(out->normal, c->normal, sizeof out->normal);
    memcpy(out->origin, c->origin, sizeof out->origin);
    memcpy(out->e1, c->e1, sizeof out->e1);
    memcpy(out->e2, c->e2, sizeof out->e2);
    memcpy(out->uv_affine, c->uv_affine, sizeof out->uv_affine);
    out->tw = c->texture.width;
    out->th = c->texture.height;
    if (!(parts & (ADI_CARD_TABLE | ADI_CARD_SPLIT_TABLE)))
        return DDOF_OK;
    ddof_status status = cards_table_build(d->context, c, &d->table);
    if (status != DDOF_OK)
        return status;
    if (parts & ADI_CARD_TABLE) {
        out->table_sum = d->table.sum;
        out->table_count = d->table.count;
    }
    if (!(parts & ADI_CARD_SPLIT_TABLE))
        return DDOF_OK;
    const size_t values = (size_t)(d->table.tw + 1) * (d->table.th + 1) * 4;
    if (values > d->capacity) {
        ddof_free(&d->context->allocator, d->hi);
        ddof_free(&d->context->allocator, d->lo);
        d->hi = ddof_alloc(&d->context->allocator, values * sizeof *d->hi);
        d->lo = ddof_alloc(&d->context->allocator, values * sizeof *d->lo);
        d->capacity = d->hi && d->lo ? values : 0;
        if (!d->capacity)
            return ddof_fail(d->context, DDOF_ERROR_OUT_OF_MEMORY,
                             "no memory for card %u's device table", c->index);
    }
    split_table(d, values);
    out->table_hi = d->hi;
    out->table_lo = d->lo;
    return DDOF_OK;
}

static double unit_disc_below(double t) /* area of the unit disc's part below height t */
{
    return t * sqrt(fmax(0.0, 1.0 - t * t)) + asin(t) + 0.5 * CARDS_PI;
}

ddof_status cards_render(ddof_context *context, const cards_view *view,
                         const ddof_cards_params *params, const card_setup *setups,
                         const uint32_t *order, uint32_t count, const ddof_image *out,
                         size_t out_stride)
{
    uint32_t *list = count ? ddof_alloc(&context->allocator, count * sizeof *list) : NULL;
    if (count && !list)
        return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY, "no memory for %u cards", count);
    uint32_t visible = 0;
    for (uint32_t i = count; i-- > 0;) /* order is far to near */
        if (setups[order[i]].visible)
            list[visible++] = order[i];
    adi_cards_request r = {
        .width = out->width, .height = out->height, .out = out->pixels,
        .out_stride = out_stride, .ray_a = view->ray_a, .ray_bx = view->ray_bx,
        .ray_c = view->ray_c, .ray_by = view->ray_by, .k_px = view->k_px,
        .focus_m = view->focus_m, .aspect = view->aspect,
        .max_radius_px = 0.5f * DDOF_MAX_COC_PX, .min_radius_px = 0.5f,
        .strips = params->strips, .card_count = visible, .card = next_card};
    for (uint32_t k = 0; k <= params->strips; k++)
        r.line[k] = -1.0 + 2.0 * k / params->strips;
    for (uint32_t k = 0; k < params->strips; k++) {
        r.mid[k] = -1.0 + (2.0 * k + 1.0) / params->strips;
        r.slice[k] = unit_disc_below(r.line[k + 1]) - unit_disc_below(r.line[k]);
    }
    request_cards d = {.context = context, .setups = setups, .list = list};
    r.user = &d;
    ddof_status status = ddof_backend_render_cards(context, &r);
    cards_table_free(context, &d.table);
    ddof_free(&context->allocator, d.hi);
    ddof_free(&context->allocator, d.lo);
    ddof_free(&context->allocator, list);
    return status;
}
