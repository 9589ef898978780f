/* SPDX-License-Identifier: MIT */
/* cards_draw.c - one card drawn under the image: per pixel of the expanded polygon the ray's
 * point on the card's plane (perspective-correct depth and uv), the CoC radius of that depth,
 * and the texture's average over that disc mapped into texels by the local projection, as
 * `strips` rectangles of the disc's exact slice areas read from the summed-area table
 * (cards_table.c). */
#include "cards.h"

#include "runtime/float_ops.h"
#include "runtime/parallel_rows.h"

#include <math.h>
#include <string.h>

#define CARDS_MIN_RADIUS_PX 0.5 /* an in-focus pixel averages its own footprint */
/* Pixels are taken in blocks CARDS_BLOCK wide across the chunk's rows: the table rows that
 * neighbouring discs read then stay in the core's cache (row by row, a wide card's discs
 * sweep more table than the cache holds before the next pixel row reads it again). */
#define CARDS_BLOCK 64u

/* Which CARDS_TILE x CARDS_TILE tiles of the image are known to be opaque: found so while a
 * card's pixels are checked (a pixel only grows more opaque as cards go under it), then
 * skipped by every card behind. 0 or 1 per tile, row-major. */
#define CARDS_TILE 16u
typedef struct cards_coverage {
    unsigned char *opaque;
    uint32_t tiles_x, tiles_y;
} cards_coverage;

/* One card drawn: the request (its view, strips and out) and the card (its table read once
 * the card is known to show). */
typedef struct draw_job {
    const adi_cards_request *view;
    const adi_card *card;
    const cards_coverage *coverage;
    uint32_t x0, x1, y0;
} draw_job;

static DDOF_ALWAYS_INLINE int inside_expanded(const adi_card *c, double x, double y)
{
    for (uint32_t k = 0; k < c->vertex_count; k++) {
        const double *a = c->expanded[k], *b = c->expanded[(k + 1) % c->vertex_count];
        if ((b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0]) < 0.0)
            return 0;
    }
    return 1;
}

/* The discs of `count` pixels of row y (centres xs, at most CARDS_BLOCK), one array per quantity so
 * that the loop computing them vectorises (its divisions and roots are most of a pixel's
 * arithmetic). Each pixel's ray meets the card's plane at depth z = n.o / n.d (1/z linear on
 * screen: perspective-correct); the plane's point gives the texel position and its
 * derivatives along x and y; the Cycles CoC of z gives the radius r (at least
 * CARDS_MIN_RADIUS_PX); the screen disc {|e| <= r} (r * aspect rows) maps through
 * A = jac * diag(1, aspect) to an ellipse in texels. `valid` is 0 where the ray misses the
 * plane or the ellipse is degenerate. */
typedef struct pixel_discs {
    double tex0[CARDS_BLOCK], tex1[CARDS_BLOCK]; /* the centre, texels */
    double reach_x[CARDS_BLOCK], reach_y[CARDS_BLOCK]; /* half the bounding box */
    double shear[CARDS_BLOCK];      /* x shift of a chord's centre per unit of height */
    double half_width[CARDS_BLOCK]; /* r^2 |det A| / (4 reach_y): x slice[k] x strips is strip
                                       k's half width */
    double inv_area[CARDS_BLOCK];   /* 1 / (pi r^2 |det A|), texels^-2 */
    int valid[CARDS_BLOCK];
} pixel_discs;

static DDOF_ALWAYS_INLINE int finite_value(double v)
{
    return v - v == 0.0; /* NaN and +-inf give NaN; isfinite may not vectorise */
}

static DDOF_ALWAYS_INLINE void pixel_discs_of(const draw_job *job, double y, const double *xs,
                                              uint32_t count, pixel_discs *d)
{
    const adi_cards_request *v = job->view;
    const adi_card *c = job->card;
    const double *nr = c->normal, *o = c->origin, *e1 = c->e1, *e2 = c->e2;
    const double *mu = c->uv_affine[0], *mv = c->uv_affine[1];
    const double n_o = nr[0] * o[0] + nr[1] * o[1] + nr[2] * o[2];
    const double e1_o = o[0] * e1[0] + o[1] * e1[1] + o[2] * e1[2];
    const double e2_o = o[0] * e2[0] + o[1] * e2[1] + o[2] * e2[2];
    const double dy = v->ray_by - v->ray_c * y, tw = c->tw, th = c->th;
    const double aspect = v->aspect, focus_over_n_o = v->focus_m / n_o;
    for (uint32_t i = 0; i < count; i++) {
        const double dx = v->ray_a * xs[i] + v->ray_bx;
        const double w = nr[0] * dx + nr[1] * dy - nr[2], inv_w = 1.0 / w;
        const double z = n_o * inv_w;
        const double dzx = -z * nr[0] * v->ray_a * inv_w, dzy = z * nr[1] * v->ray_c * inv_w;
        const double de1 = dx * e1[0] + dy * e1[1] - e1[2], de2 = dx * e2[0] + dy * e2[1] - e2[2];
        const double s = z * de1 - e1_o, q = z * de2 - e2_o;
        const double s_x = dzx * de1 + z * v->ray_a * e1[0], s_y = dzy * de1 - z * v->ray_c * e1[1];
        const double q_x = dzx * de2 + z * v->ray_a * e2[0], q_y = dzy * de2 - z * v->ray_c * e2[1];
        /* texels: u * tw across, (1 - v) * th down */
        const double t0 = tw * (mu[0] + mu[1] * s + mu[2] * q);
        const double t1 = th - th * (mv[0] + mv[1] * s + mv[2] * q);
        const double a0 = tw * (mu[1] * s_x + mu[2] * q_x);
        const double a1 = tw * (mu[1] * s_y + mu[2] * q_y) * aspect;
        const double b0 = -th * (mv[1] * s_x + mv[2] * q_x);
        const double b1 = -th * (mv[1] * s_y + mv[2] * q_y) * aspect;
        /* the CoC radius: k_px |1 - S1 / z| / 2, S1 / z = S1 w / n.o */
        double coc = v->k_px * fabs(1.0 - focus_over_n_o * w);
        coc = coc < DDOF_MAX_COC_PX ? coc : DDOF_MAX_COC_PX;
        const double r = 0.5 * coc > CARDS_MIN_RADIUS_PX ? 0.5 * coc : CARDS_MIN_RADIUS_PX;
        const double det = fabs(a0 * b1 - a1 * b0), bb = b0 * b0 + b1 * b1;
        const double r2det = r * r * det;
        const double reach_y = r * sqrt(bb);
        d->tex0[i] = t0;
        d->tex1[i] = t1;
        d->reach_x[i] = r * sqrt(a0 * a0 + a1 * a1);
        d->reach_y[i] = reach_y;
        d->shear[i] = (a0 * b0 + a1 * b1) / bb;
        d->half_width[i] = 0.25 * r2det / reach_y;
        d->inv_area[i] = 1.0 / (CARDS_PI * r2det);
        /* Every texel position the disc's strips reach stays a finite number (disc_average:
         * rows t1 +- reach_y, columns t0 +- |shear| reach_y + half_width strips slice, a
         * slice at most pi): a finite but huge gradient would overflow them to inf - inf. */
        const double columns = fabs(t0) + fabs(d->shear[i] * reach_y) +
                               4.0 * CARDS_MAX_STRIPS * d->half_width[i];
        d->valid[i] = (z > 0.0) & finite_value(z) & finite_value(t0) & finite_value(t1) &
                      finite_value(a0 + a1 + b0 + b1) & (CARDS_PI * r2det > 1e-12) & (bb > 0.0) &
                      finite_value(columns) & finite_value(fabs(t1) + reach_y) &
                      finite_value(d->reach_x[i]);
    }
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
static DDOF_ALWAYS_INLINE int texture_empty(const adi_card *t, double x0, double x1,
                                            double y0, double y1)
{
    const double tw = t->tw, th = t->th;
    /* Every end clamped to the texture before it becomes an index: a box far outside it (a
     * pixel aspect of 1e82 made one at 9e62 texels; fuzz_cards_scene) touches none. */
    const size_t i0 = (size_t)fmin(tw, fmax(0.0, floor(x0 - 1e-6)));
    const size_t j0 = (size_t)fmin(th, fmax(0.0, floor(y0 - 1e-6)));
    const size_t i1 = (size_t)fmin(tw, fmax(0.0, ceil(x1 + 1e-6)));
    const size_t j1 = (size_t)fmin(th, fmax(0.0, ceil(y1 + 1e-6)));
    if (i0 >= i1 || j0 >= j1)
        return 1;
    const size_t row = (size_t)t->tw + 1;
    const uint32_t *c = t->table_count;
    return c[j1 * row + i1] - c[j1 * row + i0] - c[j0 * row + i1] + c[j0 * row + i0] == 0;
}

/* The texture's average over pixel i's disc (pixel_discs), premultiplied RGBA; 0 where its
 * texture is empty. `strips` is the request's, passed so that the default's loops are unrolled
 * at compile time. */
static DDOF_ALWAYS_INLINE int disc_average(const draw_job *job, uint32_t strips,
                                           const pixel_discs *d, uint32_t i, double avg[4])
{
    const double tex0 = d->tex0[i], tex1 = d->tex1[i], reach_y = d->reach_y[i];
    if (texture_empty(job->card, tex0 - d->reach_x[i], tex0 + d->reach_x[i], tex1 - reach_y,
                      tex1 + reach_y))
        return 0;
    const double shear_reach = d->shear[i] * reach_y, half_width = d->half_width[i] * strips;
    const adi_card *t = job->card;
    const size_t row = (size_t)(t->tw + 1) * 4;
    /* The strips' edges: strip k lies between lines k and k + 1. */
    uint32_t line_cell[CARDS_MAX_STRIPS + 1];
    double line_frac[CARDS_MAX_STRIPS + 1];
    for (uint32_t k = 0; k <= strips; k++)
        table_at(tex1 + reach_y * job->view->line[k], t->th, &line_cell[k], &line_frac[k]);
    double total[4] = {0, 0, 0, 0};
    for (uint32_t k = 0; k < strips; k++) {
        const double xc = tex0 + shear_reach * job->view->mid[k];
        const double half = half_width * job->view->slice[k];
        uint32_t ia, ib;
        double fa, fb;
        table_at(xc - half, t->tw, &ia, &fa);
        table_at(xc + half, t->tw, &ib, &fb);
        const double *lo = t->table_sum + line_cell[k] * row;
        const double *hi = t->table_sum + line_cell[k + 1] * row;
        add_row_span(hi, ia, fa, ib, fb, 1.0 - line_frac[k + 1], total);
        add_row_span(hi + row, ia, fa, ib, fb, line_frac[k + 1], total);
        add_row_span(lo, ia, fa, ib, fb, line_frac[k] - 1.0, total);
        add_row_span(lo + row, ia, fa, ib, fb, -line_frac[k], total);
    }
    for (int ch = 0; ch < 4; ch++)
        avg[ch] = total[ch] * d->inv_area[i];
    return 1;
}

/* Cards are drawn near to far, each under what is already there (`out += (1 - out.a) card`,
 * the same image as far to near with `over`); a pixel this opaque takes nothing more from the
 * cards behind it, which then change it by at most 1e-6 of their value. */
#define CARDS_OPAQUE (1.0f - 1e-6f)

/* Whether pixel x of row y lies in a tile known to be opaque. */
static DDOF_ALWAYS_INLINE int tile_opaque(const cards_coverage *c, uint32_t x, uint32_t y)
{
    return c->opaque[(size_t)(y / CARDS_TILE) * c->tiles_x + x / CARDS_TILE];
}


/* The pixels of row y whose centres lie in the expanded polygon: an interval, its ends from
 * the edges' half-planes, then settled by inside_expanded itself (the same pixels as testing
 * each one). */
static void row_span(const draw_job *job, double y, uint32_t *first, uint32_t *end)
{
    const adi_card *c = job->card;
    double lo = job->x0, hi = job->x1; /* pixel indices: x = i + 0.5 */
    for (uint32_t k = 0; k < c->vertex_count; k++) {
        const double *a = c->expanded[k], *b = c->expanded[(k + 1) % c->vertex_count];
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
            float *row = job->view->out + (size_t)y * job->view->out_stride;
            const uint32_t x0 = first[r - r0] > bx ? first[r - r0] : bx;
            const uint32_t x1 = end[r - r0] < bx + CARDS_BLOCK ? end[r - r0] : bx + CARDS_BLOCK;
            /* the pixels still open, then their discs together */
            double xs[CARDS_BLOCK];
            uint32_t open[CARDS_BLOCK], count = 0;
            for (uint32_t x = x0; x < x1; x++) {
                if (tile_opaque(job->coverage, x, y)) { /* the rest of the tile too */
                    x |= CARDS_TILE - 1;
                    continue;
                }
                if (row[(size_t)x * 4 + 3] < CARDS_OPAQUE) {
                    open[count] = x;
                    xs[count++] = x + 0.5;
                }
            }
            if (!count)
                continue;
            pixel_discs discs;
            pixel_discs_of(job, y + 0.5, xs, count, &discs);
            for (uint32_t i = 0; i < count; i++) {
                float *px = row + (size_t)open[i] * 4;
                double avg[4];
                if (!discs.valid[i] ||
                    !(job->view->strips == CARDS_DEFAULT_STRIPS
                          ? disc_average(job, CARDS_DEFAULT_STRIPS, &discs, i, avg)
                          : disc_average(job, job->view->strips, &discs, i, avg)))
                    continue;
                const double keep = 1.0 - px[3];
                for (int ch = 0; ch < 4; ch++)
                    px[ch] = (float)(px[ch] + keep * avg[ch]);
            }
        }
}

/* Whether every pixel of tile (tx, ty) is opaque (scanned whole, so that it vectorises). */
DDOF_MULTIVERSION static int tile_scan(const draw_job *job, uint32_t tx, uint32_t ty,
                                       uint32_t height)
{
    const uint32_t x0 = tx * CARDS_TILE, y0 = ty * CARDS_TILE;
    const uint32_t x1 = x0 + CARDS_TILE < job->view->width ? x0 + CARDS_TILE : job->view->width;
    const uint32_t y1 = y0 + CARDS_TILE < height ? y0 + CARDS_TILE : height;
    int open = 0;
    for (uint32_t y = y0; y < y1; y++) {
        const float *row = job->view->out + (size_t)y * job->view->out_stride;
        for (uint32_t x = x0; x < x1; x++)
            open |= row[(size_t)x * 4 + 3] < CARDS_OPAQUE;
    }
    return !open;
}

/* Whether every pixel the card would draw is already opaque (a card wholly hidden by nearer
 * ones: its table is not even built). Tile by tile over its box: a tile found opaque is
 * marked so for the cards behind; in a tile that is not, the card's own pixels are checked. */
static int spans_opaque(const draw_job *job, cards_coverage *coverage, uint32_t y1)
{
    const uint32_t height = job->view->height;
    for (uint32_t ty = job->y0 / CARDS_TILE; ty * CARDS_TILE < y1; ty++)
        for (uint32_t tx = job->x0 / CARDS_TILE; tx * CARDS_TILE < job->x1; tx++) {
            unsigned char *mark = &coverage->opaque[(size_t)ty * coverage->tiles_x + tx];
            if (*mark)
                continue;
            if (tile_scan(job, tx, ty, height)) {
                *mark = 1;
                continue;
            }
            const uint32_t ya = ty * CARDS_TILE > job->y0 ? ty * CARDS_TILE : job->y0;
            const uint32_t yb = (ty + 1) * CARDS_TILE < y1 ? (ty + 1) * CARDS_TILE : y1;
            for (uint32_t y = ya; y < yb; y++) {
                const float *row = job->view->out + (size_t)y * job->view->out_stride;
                uint32_t first, end;
                row_span(job, y + 0.5, &first, &end);
                first = first > tx * CARDS_TILE ? first : tx * CARDS_TILE;
                end = end < (tx + 1) * CARDS_TILE ? end : (tx + 1) * CARDS_TILE;
                for (uint32_t x = first; x < end; x++)
                    if (row[(size_t)x * 4 + 3] < CARDS_OPAQUE)
                        return 0;
            }
        }
    return 1;
}

/* Card i of the request drawn under what is there (its table built only if it shows). */
static ddof_status draw_card(ddof_context *context, const adi_cards_request *r, uint32_t i,
                             cards_coverage *coverage)
{
    adi_card card;
    ddof_status status = r->card(r->user, i, 0, &card);
    if (status != DDOF_OK)
        return status;
    draw_job job = {.view = r, .card = &card, .coverage = coverage};
    /* The card's box on the frame, each end clamped to it before it becomes an index. */
    const double w = (double)r->width, h = (double)r->height;
    job.x0 = (uint32_t)fmin(w, fmax(0.0, floor(card.box[0])));
    job.y0 = (uint32_t)fmin(h, fmax(0.0, floor(card.box[1])));
    job.x1 = (uint32_t)fmin(w, fmax(0.0, ceil(card.box[2])));
    const uint32_t y1 = (uint32_t)fmin(h, fmax(0.0, ceil(card.box[3])));
    if (job.x0 >= job.x1 || job.y0 >= y1 || spans_opaque(&job, coverage, y1))
        return DDOF_OK;
    status = r->card(r->user, i, ADI_CARD_TABLE, &card);
    if (status == DDOF_OK)
        ddof_parallel_rows(context, y1 - job.y0, draw_rows, &job);
    return status;
}

ddof_status ddof_draw_cards_on_cpu(ddof_context *context, const adi_cards_request *r)
{
    for (uint32_t y = 0; y < r->height; y++)
        memset(r->out + (size_t)y * r->out_stride, 0, (size_t)r->width * 4 * sizeof(float));
    /* Near to far, each card under the nearer ones. */
    cards_coverage coverage = {NULL, (r->width + CARDS_TILE - 1) / CARDS_TILE,
                               (r->height + CARDS_TILE - 1) / CARDS_TILE};
    if (!r->card_count)
        return DDOF_OK;
    const size_t tiles = (size_t)coverage.tiles_x * coverage.tiles_y;
    coverage.opaque = ddof_alloc(&context->allocator, tiles);
    if (!coverage.opaque)
        return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY, "no memory for %zu tiles", tiles);
    memset(coverage.opaque, 0, tiles);
    ddof_status status = DDOF_OK;
    for (uint32_t i = 0; status == DDOF_OK && i < r->card_count; i++)
        status = draw_card(context, r, i, &coverage);
    ddof_free(&context->allocator, coverage.opaque);
    return status;
}
