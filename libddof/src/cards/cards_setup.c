/* SPDX-License-Identifier: MIT */
/* cards_setup.c - one card checked (vertices, plane, convexity, uv map, texture) and reduced
 * to its plane, its affine uv map and its expanded screen polygon. */
#include "cards.h"

#include "runtime/parallel_rows.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3(const double *a, const double *b, double *c)
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

static ddof_status card_fail(ddof_context *context, uint32_t index, const char *why)
{
    return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER, "card %u: %s", index, why);
}

/* Vertices finite and in front of the camera; the plane (Newell's normal) not degenerate and
 * the vertices on it. */
static ddof_status card_plane(ddof_context *context, const ddof_card *card, card_setup *s)
{
    if (card->vertex_count < 3 || card->vertex_count > DDOF_CARD_MAX_VERTICES)
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER, "card %u: %u vertices (3..%u)",
                         s->index, card->vertex_count, DDOF_CARD_MAX_VERTICES);
    s->n = card->vertex_count;
    double extent = 0.0, normal[3] = {0, 0, 0};
    memset(s->origin, 0, sizeof s->origin);
    for (uint32_t k = 0; k < s->n; k++) {
        for (int a = 0; a < 3; a++) {
            if (!isfinite(card->position[k][a]) || !isfinite(card->uv[k][a < 2 ? a : 0]))
                return card_fail(context, s->index, "a position or uv is NaN or infinite");
            s->p[k][a] = card->position[k][a];
            s->origin[a] += s->p[k][a] / s->n;
        }
        if (!(card->position[k][2] <= -(float)DDOF_CARD_MIN_DEPTH_M)) /* -1e-6f accepted */
            return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                             "card %u: vertex %u has z = %g: the card is behind, crosses or "
                             "nearly touches the camera's plane (every z must be <= -%g m; "
                             "split the card)",
                             s->index, k, s->p[k][2], DDOF_CARD_MIN_DEPTH_M);
    }
    for (uint32_t k = 0; k < s->n; k++) {
        const double *a = s->p[k], *b = s->p[(k + 1) % s->n];
        normal[0] += (a[1] - b[1]) * (a[2] + b[2]);
        normal[1] += (a[2] - b[2]) * (a[0] + b[0]);
        normal[2] += (a[0] - b[0]) * (a[1] + b[1]);
        for (int i = 0; i < 3; i++)
            extent = fmax(extent, fabs(a[i] - s->origin[i]));
    }
    const double length = sqrt(dot3(normal, normal));
    if (!(length > 1e-9 * extent * extent) || extent == 0.0)
        return card_fail(context, s->index, "degenerate polygon (zero area)");
    for (int i = 0; i < 3; i++)
        s->normal[i] = normal[i] / length;
    for (uint32_t k = 0; k < s->n; k++) {
        double d[3] = {s->p[k][0] - s->origin[0], s->p[k][1] - s->origin[1],
                       s->p[k][2] - s->origin[2]};
        if (fabs(dot3(d, s->normal)) > 1e-4 * extent)
            return card_fail(context, s->index, "the vertices are not on one plane");
    }
    double e1[3] = {s->p[1][0] - s->p[0][0], s->p[1][1] - s->p[0][1], s->p[1][2] - s->p[0][2]};
    double l1 = sqrt(dot3(e1, e1));
    if (!(l1 > 0.0))
        return card_fail(context, s->index, "degenerate polygon (repeated vertex)");
    for (int i = 0; i < 3; i++)
        s->e1[i] = e1[i] / l1;
    cross3(s->normal, s->e1, s->e2);
    return DDOF_OK;
}

/* Convex, winding once, no repeated vertex: in plane coordinates (s, q). */
static ddof_status card_convex(ddof_context *context, const card_setup *c, double sq[][2])
{
    double turn = 0.0;
    for (uint32_t k = 0; k < c->n; k++) {
        const double *a = sq[k], *b = sq[(k + 1) % c->n], *d = sq[(k + 2) % c->n];
        double ux = b[0] - a[0], uy = b[1] - a[1], vx = d[0] - b[0], vy = d[1] - b[1];
        double lu = hypot(ux, uy), lv = hypot(vx, vy);
        if (!(lu > 0.0) || !(lv > 0.0))
            return card_fail(context, c->index, "degenerate polygon (repeated vertex)");
        double cr = ux * vy - uy * vx;
        if (cr < -1e-9 * lu * lv) /* Newell's normal makes the winding counter-clockwise */
            return card_fail(context, c->index, "the polygon is not convex");
        turn += atan2(cr, ux * vx + uy * vy);
    }
    if (fabs(turn - 2.0 * 3.14159265358979323846) > 1e-6)
        return card_fail(context, c->index, "the polygon winds more than once (not convex)");
    return DDOF_OK;
}

/* Least-squares u, v = a0 + a1 s + a2 q over the vertices, which must fit it. */
static ddof_status card_uv(ddof_context *context, const ddof_card *card, card_setup *c,
                           double sq[][2])
{
    double m[3][3] = {{0}}, r[2][3] = {{0}};
    for (uint32_t k = 0; k < c->n; k++) {
        const double row[3] = {1.0, sq[k][0], sq[k][1]};
        for (int i = 0; i < 3; i++) {
            for (int j = 0; j < 3; j++)
                m[i][j] += row[i] * row[j];
            for (int t = 0; t < 2; t++)
                r[t][i] += row[i] * card->uv[k][t];
        }
    }
    const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                       m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                       m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    for (int t = 0; t < 2; t++)
        for (int i = 0; i < 3; i++) { /* Cramer's rule: 3x3 */
            double a[3][3];
            memcpy(a, m, sizeof a);
            for (int j = 0; j < 3; j++)
                a[j][i] = r[t][j];
            c->uv_affine[t][i] = (a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                                  a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                                  a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])) / det;
        }
    if (!isfinite(c->uv_affine[0][0]) || !isfinite(c->uv_affine[1][0]))
        return card_fail(context, c->index, "uv cannot be fitted");
    for (uint32_t k = 0; k < c->n; k++)
        for (int t = 0; t < 2; t++) {
            c->uv[k][t] = card->uv[k][t];
            double fit = c->uv_affine[t][0] + c->uv_affine[t][1] * sq[k][0] +
                         c->uv_affine[t][2] * sq[k][1];
            if (fabs(fit - card->uv[k][t]) > 1e-4)
                return card_fail(context, c->index,
                                 "uv is not affine over the card (a perspective-warped "
                                 "quad: split it into triangles)");
        }
    if (fabs(c->uv_affine[0][1] * c->uv_affine[1][2] - c->uv_affine[0][2] * c->uv_affine[1][1]) <
        1e-12)
        return card_fail(context, c->index, "uv is degenerate (the texture seen as a line)");
    return DDOF_OK;
}

static ddof_status card_texture(ddof_context *context, const ddof_card *card, card_setup *c)
{
    const ddof_image_in *t = &card->texture;
    char what[32];
    snprintf(what, sizeof what, "card %u texture", c->index);
    ddof_status status = ddof_check_image(context, what, t->pixels, t->width, t->height,
                                          t->channels, t->row_stride, &c->texture_stride);
    if (status != DDOF_OK)
        return status;
    if (t->channels != 4)
        return ddof_fail(context, DDOF_ERROR_BAD_CHANNELS,
                         "card %u texture has %u channels; cards need RGBA (4)", c->index,
                         t->channels);
    bad_value bad;
    if (ddof_find_bad_value(context, t->pixels, t->width, t->height, 4, 4, c->texture_stride,
                            VALUE_FINITE, &bad, NULL))
        return ddof_fail(context, DDOF_ERROR_BAD_COLOR,
                         "card %u texture: %g at (%u, %u) channel %u", c->index,
                         (double)bad.value, bad.x, bad.y, bad.channel);
    c->texture = *t;
    /* A texel is in or out of the card whole (by its centre), so one on the uv polygon's edge
     * overhangs the card by up to half its diagonal: (+-0.5 / tw, +-0.5 / th) in uv, mapped
     * back onto the plane through the inverse of the uv map. */
    const double a1 = c->uv_affine[0][1], a2 = c->uv_affine[0][2];
    const double b1 = c->uv_affine[1][1], b2 = c->uv_affine[1][2], det = a1 * b2 - a2 * b1;
    const double du = 0.5 / t->width, dv = 0.5 / t->height;
    for (int sign = -1; sign <= 1; sign += 2) {
        const double s = (b2 * du - a2 * sign * dv) / det, q = (a1 * sign * dv - b1 * du) / det;
        c->texel_reach_m = fmax(c->texel_reach_m, hypot(s, q));
    }
    return DDOF_OK;
}

ddof_status cards_setup(ddof_context *context, const cards_view *view,
                        const ddof_cards_params *params, const ddof_card *card, uint32_t index,
                        card_setup *s)
{
    memset(s, 0, sizeof *s);
    s->index = index;
    ddof_status status = card_plane(context, card, s);
    double sq[DDOF_CARD_MAX_VERTICES][2];
    for (uint32_t k = 0; status == DDOF_OK && k < s->n; k++) {
        double d[3] = {s->p[k][0] - s->origin[0], s->p[k][1] - s->origin[1],
                       s->p[k][2] - s->origin[2]};
        sq[k][0] = dot3(d, s->e1);
        sq[k][1] = dot3(d, s->e2);
    }
    if (status == DDOF_OK)
        status = card_convex(context, s, sq);
    if (status == DDOF_OK)
        status = card_uv(context, card, s, sq);
    if (status == DDOF_OK)
        status = card_texture(context, card, s);
    if (status != DDOF_OK)
        return status;
    /* Edge-on: the plane holds the camera, the card projects to a line and draws nothing. */
    if (fabs(dot3(s->normal, s->origin)) <= 1e-9 * sqrt(dot3(s->origin, s->origin)))
        return DDOF_OK;
    for (uint32_t k = 0; k < s->n; k++) {
        const double z = -s->p[k][2];
        s->screen[k][0] = (s->p[k][0] / z - view->ray_bx) / view->ray_a;
        s->screen[k][1] = (view->ray_by - s->p[k][1] / z) / view->ray_c;
    }
    cards_expand(view, params, s);
    return DDOF_OK;
}
