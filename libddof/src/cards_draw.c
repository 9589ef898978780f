/* SPDX-License-Identifier: MIT */
/* cards_draw.c - one card drawn under the image: per pixel of the expanded polygon the ray's
 * point on the card's plane (perspective-correct depth and uv), the CoC radius of that depth,
 * and the texture's average over that disc mapped into texels by the local projection, as
 * `strips` rectangles of the disc's exact slice areas read from the summed-area table
 * (cards_table.c). */
#include "cards.h"

#include "float_ops.h"
#include "parallel_rows.h"

#include <math.h>
#include <string.h>

#define CARDS_PI 3.14159265358979323846
#define CARDS_MIN_RADIUS_PX 0.5 /* an in-focus pixel averages its own footprint */

typedef struct draw_job {
    const cards_view *view;
    const card_setup *card;
    const card_table *table;
    uint32_t strips;
    double slice[CARDS_MAX_STRIPS];   /* unit-disc area of each strip (sums to pi) */
    double line[CARDS_MAX_STRIPS + 1]; /* strip edges on the unit disc: -1 + 2 k / strips */
    double mid[CARDS_MAX_STRIPS];      /* strip middles */
    uint32_t x0, x1, y0;
    float *out;
    size_t out_stride;
} draw_job;

static DDOF_ALWAYS_INLINE int inside_expanded(const card_setup *c, double x, double y)
{
    for (uint32_t k = 0; k < c->n; k++) {
        const double *a = c->expanded[k], *b = c->expanded[(k + 1) % c->n];
        if ((b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0]) < 0.0)
            return 0;
    }
    return 1;
}

/* The card at screen point (x, y): texel position and its derivatives along x and y, and the
 * CoC radius; 0 where the ray misses the card's plane. */
static DDOF_ALWAYS_INLINE int card_at(const draw_job *job, double x, double y, double tex[2],
                                      double jac[2][2], double *radius)
{
    const cards_view *v = job->view;
    const card_setup *c = job->card;
    const double d[3] = {v->ray_a * x + v->ray_bx, v->ray_by - v->ray_c * y, -1.0};
    const double *nr = c->normal, *o = c->origin;
    const double w = nr[0] * d[0] + nr[1] * d[1] + nr[2] * d[2], inv_w = 1.0 / w;
    const double z = (nr[0] * o[0] + nr[1] * o[1] + nr[2] * o[2]) * inv_w;
    if (!(z > 0.0) || !isfinite(z))
        return 0;
    const double dzx = -z * nr[0] * v->ray_a * inv_w, dzy = z * nr[1] * v->ray_c * inv_w;
    double sq[2], dsq[2][2];
    for (int a = 0; a < 2; a++) {
        const double *e = a ? c->e2 : c->e1;
        const double de = d[0] * e[0] + d[1] * e[1] + d[2] * e[2];
        sq[a] = z * de - (o[0] * e[0] + o[1] * e[1] + o[2] * e[2]);
        dsq[a][0] = dzx * de + z * v->ray_a * e[0];
        dsq[a][1] = dzy * de - z * v->ray_c * e[1];
    }
    const double scale[2] = {job->table->tw, -(double)job->table->th};
    for (int t = 0; t < 2; t++) {
        const double *m = c->uv_affine[t];
        tex[t] = scale[t] * (m[0] + m[1] * sq[0] + m[2] * sq[1]) + (t ? job->table->th : 0.0);
        for (int a = 0; a < 2; a++)
            jac[t][a] = scale[t] * (m[1] * dsq[0][a] + m[2] * dsq[1][a]);
    }
    *radius = cards_radius(v, z);
    return isfinite(tex[0]) && isfinite(tex[1]) && isfinite(jac[0][0]) &&
           isfinite(jac[0][1]) && isfinite(jac[1][0]) && isfinite(jac[1][1]);
}

/* A position along the table's x (or y) axis: the cell and the fraction into it, clamped to
 * the texture (the table is constant beyond it: outside the card is transparent). */
static DDOF_ALWAYS_INLINE void table_at(double x, uint32_t size, uint32_t *cell, double *frac)
{
    x = x < 0.0 ? 0.0 : x > size ? size : x;
    uint32_t i = (uint32_t)x;
    i = i >= size ? size - 1 : i;
    *cell = i;
    *frac = x - i;
}

/* Row r of the table at x = (ib, fb) minus at x = (ia, fa), times w, added to acc: the
 * integral of the texture over [xa, xb] x [0, row), each position linear between its cells
 * (exact for piecewise-constant texels). */
static DDOF_ALWAYS_INLINE void add_row_span(const double *r, uint32_t ia, double fa, uint32_t ib,
                                            double fb, double w, double acc[4])
{
    const double *a = r + (size_t)ia * 4, *b = r + (size_t)ib * 4;
    for (int ch = 0; ch < 4; ch++)
        acc[ch] += w * ((b[ch] + fb * (b[ch + 4] - b[ch])) - (a[ch] + fa * (a[ch + 4] - a[ch])));
}

/* Whether the texture is wholly zero over the texels the box [x0, x1] x [y0, y1] touches: the
 * count table, 4 reads. The strips' rectangles lie in the disc's bounding box (each is as wide
 * as its slice's mean chord, centred on the slice's mean centre), so such a disc averages 0. */
static DDOF_ALWAYS_INLINE int texture_empty(const card_table *t, double x0, double x1,
                                            double y0, double y1)
{
    const double tw = t->tw, th = t->th;
    const size_t i0 = (size_t)fmax(0.0, floor(x0 - 1e-6));
    const size_t j0 = (size_t)fmax(0.0, floor(y0 - 1e-6));
    const size_t i1 = (size_t)fmin(tw, fmax(0.0, ceil(x1 + 1e-6)));
    const size_t j1 = (size_t)fmin(th, fmax(0.0, ceil(y1 + 1e-6)));
    if (i0 >= i1 || j0 >= j1)
        return 1;
    const size_t row = (size_t)t->tw + 1;
    const uint32_t *c = t->count;
    return c[j1 * row + i1] - c[j1 * row + i0] - c[j0 * row + i1] + c[j0 * row + i0] == 0;
}

/* The texture's average over the disc of radius r pixels (r * aspect rows) about screen point
 * (x, y), premultiplied RGBA; 0 where the card is not there or its texture there is empty.
 * `strips` is job->strips, passed so that the default's loops are unrolled at compile time. */
static DDOF_ALWAYS_INLINE int disc_average(const draw_job *job, uint32_t strips, double x,
                                           double y, double avg[4])
{
    double tex[2], jac[2][2], r;
    if (!card_at(job, x, y, tex, jac, &r))
        return 0;
    r = fmax(r, CARDS_MIN_RADIUS_PX);
    /* The disc's image in texels: {A e : |e| <= r}, A = jac * diag(1, aspect). */
    const double a0 = jac[0][0], a1 = jac[0][1] * job->view->aspect;
    const double b0 = jac[1][0], b1 = jac[1][1] * job->view->aspect;
    const double det = fabs(a0 * b1 - a1 * b0), bb = b0 * b0 + b1 * b1;
    const double area = CARDS_PI * r * r * det;
    if (!(area > 1e-12) || !(bb > 0.0))
        return 0;
    const double reach_y = r * sqrt(bb), reach_x = r * sqrt(a0 * a0 + a1 * a1);
    if (texture_empty(job->table, tex[0] - reach_x, tex[0] + reach_x, tex[1] - reach_y,
                      tex[1] + reach_y))
        return 0;
    const double shear = (a0 * b0 + a1 * b1) / bb;
    /* Strip k's rectangle: half as wide as its slice's area over its height 2 reach_y / strips. */
    const double half_per_slice = 0.25 * strips * r * r * det / reach_y;
    const card_table *t = job->table;
    const size_t row = (size_t)(t->tw + 1) * 4;
    /* The strips' edges: strip k lies between lines k and k + 1. */
    uint32_t line_cell[CARDS_MAX_STRIPS + 1];
    double line_frac[CARDS_MAX_STRIPS + 1];
    for (uint32_t k = 0; k <= strips; k++)
        table_at(tex[1] + reach_y * job->line[k], t->th, &line_cell[k], &line_frac[k]);
    double total[4] = {0, 0, 0, 0};
    for (uint32_t k = 0; k < strips; k++) {
        const double xc = tex[0] + shear * reach_y * job->mid[k];
        const double half = half_per_slice * job->slice[k];
        uint32_t ia, ib;
        double fa, fb;
        table_at(xc - half, t->tw, &ia, &fa);
        table_at(xc + half, t->tw, &ib, &fb);
        const double *lo = t->sum + line_cell[k] * row, *hi = t->sum + line_cell[k + 1] * row;
        add_row_span(hi, ia, fa, ib, fb, 1.0 - line_frac[k + 1], total);
        add_row_span(hi + row, ia, fa, ib, fb, line_frac[k + 1], total);
        add_row_span(lo, ia, fa, ib, fb, line_frac[k] - 1.0, total);
        add_row_span(lo + row, ia, fa, ib, fb, -line_frac[k], total);
    }
    const double inv_area = 1.0 / area;
    for (int ch = 0; ch < 4; ch++)
        avg[ch] = total[ch] * inv_area;
    return 1;
}

/* Cards are drawn near to far, each under what is already there (`out += (1 - out.a) card`,
 * the same image as far to near with `over`); a pixel this opaque takes nothing more from the
 * cards behind it, which then change it by at most 1e-6 of their value. */
#define CARDS_OPAQUE (1.0f - 1e-6f)

/* The pixels of row y whose centres lie in the expanded polygon: an interval, its ends from
 * the edges' half-planes, then settled by inside_expanded itself (the same pixels as testing
 * each one). */
static void row_span(const draw_job *job, double y, uint32_t *first, uint32_t *end)
{
    const card_setup *c = job->card;
    double lo = job->x0, hi = job->x1; /* pixel indices: x = i + 0.5 */
    for (uint32_t k = 0; k < c->n; k++) {
        const double *a = c->expanded[k], *b = c->expanded[(k + 1) % c->n];
        /* (b0 - a0)(y - a1) - (b1 - a1)(x - a0) >= 0 */
        const double q = b[1] - a[1], p = (b[0] - a[0]) * (y - a[1]) + q * a[0];
        if (q > 0.0)
            hi = fmin(hi, p / q + 0.5);
        else if (q < 0.0)
            lo = fmax(lo, p / q - 0.5);
        else if (p < 0.0)
            lo = hi;
    }
    uint32_t a = lo <= job->x0 ? job->x0 : lo >= job->x1 ? job->x1 : (uint32_t)lo;
    uint32_t e = hi <= job->x0 ? job->x0 : hi >= job->x1 ? job->x1 : (uint32_t)ceil(hi);
    e = e < a ? a : e;
    while (a > job->x0 && inside_expanded(c, a - 0.5, y))
        a--;
    while (a < e && !inside_expanded(c, a + 0.5, y))
        a++;
    if (a == e) /* the estimate missed (an edge along the row): test the row */
        while (a < job->x1 && !inside_expanded(c, a + 0.5, y))
            a++;
    e = e < a ? a : e;
    while (e < job->x1 && inside_expanded(c, e + 0.5, y))
        e++;
    while (e > a && !inside_expanded(c, e - 0.5, y))
        e--;
    *first = a;
    *end = e;
}

/* Pixels are taken in blocks CARDS_BLOCK wide across the chunk's rows: the table rows that
 * neighbouring discs read then stay in the core's cache (row by row, a wide card's discs
 * sweep more table than the cache holds before the next pixel row reads it again). */
#define CARDS_BLOCK 64u

DDOF_MULTIVERSION static void draw_rows(void *user, uint32_t r0, uint32_t r1, uint32_t chunk)
{
    (void)chunk;
    const draw_job *job = user;
    uint32_t first[DDOF_ROWS_PER_CHUNK], end[DDOF_ROWS_PER_CHUNK], lo = job->x1, hi = job->x0;
    for (uint32_t r = r0; r < r1; r++) {
        row_span(job, job->y0 + r + 0.5, &first[r - r0], &end[r - r0]);
        lo = first[r - r0] < end[r - r0] && first[r - r0] < lo ? first[r - r0] : lo;
        hi = end[r - r0] > hi ? end[r - r0] : hi;
    }
    for (uint32_t bx = lo; bx < hi; bx += CARDS_BLOCK)
        for (uint32_t r = r0; r < r1; r++) {
            const uint32_t y = job->y0 + r;
            float *row = job->out + (size_t)y * job->out_stride;
            const uint32_t x0 = first[r - r0] > bx ? first[r - r0] : bx;
            const uint32_t x1 = end[r - r0] < bx + CARDS_BLOCK ? end[r - r0] : bx + CARDS_BLOCK;
            for (uint32_t x = x0; x < x1; x++) {
                float *px = row + (size_t)x * 4;
                double avg[4];
                if (px[3] >= CARDS_OPAQUE)
                    continue;
                if (!(job->strips == CARDS_DEFAULT_STRIPS
                          ? disc_average(job, CARDS_DEFAULT_STRIPS, x + 0.5, y + 0.5, avg)
                          : disc_average(job, job->strips, x + 0.5, y + 0.5, avg)))
                    continue;
                const double keep = 1.0 - px[3];
                for (int ch = 0; ch < 4; ch++)
                    px[ch] = (float)(px[ch] + keep * avg[ch]);
            }
        }
}

/* Whether every pixel of the card's box is already opaque (a card wholly hidden by nearer
 * ones: its table is not even built). */
static int box_opaque(const draw_job *job, uint32_t y1)
{
    for (uint32_t y = job->y0; y < y1; y++) {
        const float *row = job->out + (size_t)y * job->out_stride;
        for (uint32_t x = job->x0; x < job->x1; x++)
            if (row[(size_t)x * 4 + 3] < CARDS_OPAQUE)
                return 0;
    }
    return 1;
}

static double unit_disc_below(double t) /* area of the unit disc's part below height t */
{
    return t * sqrt(fmax(0.0, 1.0 - t * t)) + asin(t) + 0.5 * CARDS_PI;
}

ddof_status cards_draw(ddof_context *context, const cards_view *view,
                       const ddof_cards_params *params, const card_setup *s, card_table *table,
                       float *out, size_t out_stride)
{
    draw_job job = {.view = view, .card = s, .table = table, .strips = params->strips,
                    .out = out, .out_stride = out_stride};
    job.x0 = (uint32_t)fmax(0.0, floor(s->box[0]));
    job.y0 = (uint32_t)fmax(0.0, floor(s->box[1]));
    job.x1 = (uint32_t)fmin((double)view->width, ceil(s->box[2]));
    const uint32_t y1 = (uint32_t)fmin((double)view->height, ceil(s->box[3]));
    if (job.x0 >= job.x1 || job.y0 >= y1 || box_opaque(&job, y1))
        return DDOF_OK;
    for (uint32_t k = 0; k <= job.strips; k++)
        job.line[k] = -1.0 + 2.0 * k / job.strips;
    for (uint32_t k = 0; k < job.strips; k++) {
        job.mid[k] = -1.0 + (2.0 * k + 1.0) / job.strips;
        job.slice[k] = unit_disc_below(job.line[k + 1]) - unit_disc_below(job.line[k]);
    }
    ddof_status status = cards_table_build(context, s, table);
    if (status == DDOF_OK)
        ddof_parallel_rows(context, y1 - job.y0, draw_rows, &job);
    return status;
}
