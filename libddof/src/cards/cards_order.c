/* SPDX-License-Identifier: MIT */
/* cards_order.c - each card's expanded screen polygon (an exact outward offset or the patent's
 * centroid push) and the far-to-near drawing order of the cards. */
#include "cards.h"

#include <math.h>
#include <string.h>

/* A pixel within this of a card's edge still sees it: the smallest disc (radius 0.5 px) and
 * the pixel centre's half-pixel. */
#define CARDS_EDGE_MARGIN_PX 1.0

/* CoC radius in horizontal pixels at planar depth z metres. */
static double cards_radius(const cards_view *view, double z)
{
    double coc = view->k_px * fabs(1.0 - view->focus_m / z);
    return 0.5 * (coc < DDOF_MAX_COC_PX ? coc : DDOF_MAX_COC_PX);
}

void cards_expand(const cards_view *view, const ddof_cards_params *params, card_setup *c)
{
    const uint32_t n = c->n;
    double v[DDOF_CARD_MAX_VERTICES][2], reach[DDOF_CARD_MAX_VERTICES], area = 0.0;
    for (uint32_t k = 0; k < n; k++) {
        const uint32_t j = (k + 1) % n;
        area += c->screen[k][0] * c->screen[j][1] - c->screen[j][0] * c->screen[k][1];
    }
    for (uint32_t k = 0; k < n; k++) { /* counter-clockwise in (x, y): outward is (dy, -dx) */
        const uint32_t src = area >= 0.0 ? k : n - 1 - k;
        v[k][0] = c->screen[src][0];
        v[k][1] = c->screen[src][1];
        /* and, for the exact offset, a texel straddling the edge: its overhang on screen,
         * bounded by the projection's largest stretch at that depth (1 + the ray's slope) in
         * the finer pixel axis (the patent's push is kept as the patent has it, measured) */
        const double z = -c->p[src][2], slope = hypot(c->p[src][0], c->p[src][1]) / z;
        const double overhang = params->expansion == DDOF_CARDS_EXPAND_CENTROID
                                    ? 0.0
                                    : c->texel_reach_m * (1.0 + slope) /
                                          (z * fmin(view->ray_a, view->ray_c));
        reach[k] = cards_radius(view, z) * fmax(1.0, view->aspect) + CARDS_EDGE_MARGIN_PX +
                   overhang;
    }
    if (params->expansion == DDOF_CARDS_EXPAND_CENTROID) {
        double cx = 0.0, cy = 0.0;
        for (uint32_t k = 0; k < n; k++) {
            cx += v[k][0] / n;
            cy += v[k][1] / n;
        }
        for (uint32_t k = 0; k < n; k++) {
            double dx = v[k][0] - cx, dy = v[k][1] - cy, l = hypot(dx, dy);
            c->expanded[k][0] = v[k][0] + (l > 0.0 ? dx / l * reach[k] : 0.0);
            c->expanded[k][1] = v[k][1] + (l > 0.0 ? dy / l * reach[k] : 0.0);
        }
    } else {
        double nx[DDOF_CARD_MAX_VERTICES], ny[DDOF_CARD_MAX_VERTICES], off[DDOF_CARD_MAX_VERTICES];
        for (uint32_t k = 0; k < n; k++) { /* edge k: v[k] -> v[k+1], moved out by its reach */
            const uint32_t j = (k + 1) % n;
            double dx = v[j][0] - v[k][0], dy = v[j][1] - v[k][1], l = hypot(dx, dy);
            nx[k] = l > 0.0 ? dy / l : 0.0;
            ny[k] = l > 0.0 ? -dx / l : 0.0;
            off[k] = nx[k] * v[k][0] + ny[k] * v[k][1] + fmax(reach[k], reach[j]);
        }
        for (uint32_t k = 0; k < n; k++) { /* vertex k: edges k-1 and k meet */
            const uint32_t p = (k + n - 1) % n;
            const double det = nx[p] * ny[k] - ny[p] * nx[k];
            if (fabs(det) > 1e-9) {
                c->expanded[k][0] = (off[p] * ny[k] - ny[p] * off[k]) / det;
                c->expanded[k][1] = (nx[p] * off[k] - off[p] * nx[k]) / det;
            } else { /* straight through the vertex, or a zero-length edge */
                const double r = fmax(reach[k], fmax(reach[p], reach[(k + 1) % n]));
                c->expanded[k][0] = v[k][0] + (nx[k] != 0.0 || ny[k] != 0.0 ? nx[k] : nx[p]) * r;
                c->expanded[k][1] = v[k][1] + (nx[k] != 0.0 || ny[k] != 0.0 ? ny[k] : ny[p]) * r;
            }
        }
    }
    c->box[0] = c->box[1] = INFINITY;
    c->box[2] = c->box[3] = -INFINITY;
    for (uint32_t k = 0; k < n; k++) {
        c->box[0] = fmin(c->box[0], c->expanded[k][0]);
        c->box[1] = fmin(c->box[1], c->expanded[k][1]);
        c->box[2] = fmax(c->box[2], c->expanded[k][0]);
        c->box[3] = fmax(c->box[3], c->expanded[k][1]);
    }
    c->visible = c->box[2] > 0.0 && c->box[3] > 0.0 && c->box[0] < view->width &&
                 c->box[1] < view->height;
}

/* Signed distances of b's vertices from a's plane, the camera's side positive: 1 when all are
 * >= -eps (b in front of a's plane), -1 when all <= eps (behind), 0 when both ways (coplanar),
 * 2 when b straddles it. */
static int side_of(const card_setup *a, const card_setup *b)
{
    const double *nr = a->normal, *o = a->origin;
    const double camera = -(nr[0] * o[0] + nr[1] * o[1] + nr[2] * o[2]) > 0.0 ? 1.0 : -1.0;
    const double eps = 1e-6 * (1.0 + sqrt(o[0] * o[0] + o[1] * o[1] + o[2] * o[2]));
    int front = 1, behind = 1;
    for (uint32_t k = 0; k < b->n; k++) {
        const double d = camera * (nr[0] * (b->p[k][0] - o[0]) + nr[1] * (b->p[k][1] - o[1]) +
                                   nr[2] * (b->p[k][2] - o[2]));
        front &= d >= -eps;
        behind &= d <= eps;
    }
    return front && behind ? 0 : front ? 1 : behind ? -1 : 2;
}

static int boxes_overlap(const card_setup *a, const card_setup *b)
{
    return a->box[0] < b->box[2] && b->box[0] < a->box[2] && a->box[1] < b->box[3] &&
           b->box[1] < a->box[3];
}

/* 1: a is drawn before b, -1: after, 0: either (they cannot cover each other), 2: no order. */
static int draw_before(const card_setup *a, const card_setup *b)
{
    if (!a->visible || !b->visible || !boxes_overlap(a, b))
        return 0;
    const int b_from_a = side_of(a, b), a_from_b = side_of(b, a);
    if (b_from_a == 0 || a_from_b == 0) /* coplanar: the list's order */
        return a->index < b->index ? 1 : -1;
    if (a_from_b == -1 || b_from_a == 1)
        return 1;
    if (a_from_b == 1 || b_from_a == -1)
        return -1;
    return 2;
}

ddof_status cards_order(ddof_context *context, const card_setup *cards, uint32_t count,
                        uint32_t *order)
{
    if (!count)
        return DDOF_OK;
    /* Kahn's sort over the pairs that overlap on screen; the earliest ready card first. */
    uint32_t *pending = ddof_alloc(&context->allocator, (size_t)count * sizeof *pending);
    signed char *before = ddof_alloc(&context->allocator, (size_t)count * count);
    ddof_status status = DDOF_OK;
    if (!pending || !before)
        status = ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY, "no memory to order %u cards",
                           count);
    else
        memset(pending, 0, (size_t)count * sizeof *pending);
    for (uint32_t i = 0; i < count && status == DDOF_OK; i++)
        for (uint32_t j = i + 1; j < count; j++) {
            const int rel = draw_before(&cards[i], &cards[j]);
            if (rel == 2) {
                status = ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                                   "cards %u and %u intersect or overlap in no depth order: "
                                   "split them", i, j);
                break;
            }
            before[(size_t)i * count + j] = (signed char)rel;
            before[(size_t)j * count + i] = (signed char)-rel;
            pending[j] += rel == 1;
            pending[i] += rel == -1;
        }
    for (uint32_t done = 0; status == DDOF_OK && done < count; done++) {
        uint32_t next = 0;
        while (next < count && pending[next] != 0)
            next++;
        if (next == count) {
            uint32_t a = 0;
            while (pending[a] == UINT32_MAX)
                a++;
            status = ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                               "card %u is in a cycle of cards each partly in front of the "
                               "next: split them", a);
            break;
        }
        order[done] = next;
        pending[next] = UINT32_MAX;
        for (uint32_t j = 0; j < count; j++)
            if (j != next && pending[j] != UINT32_MAX && before[(size_t)next * count + j] == 1)
                pending[j]--;
    }
    ddof_free(&context->allocator, pending);
    ddof_free(&context->allocator, before);
    return status;
}
