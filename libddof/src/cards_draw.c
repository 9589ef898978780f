/* SPDX-License-Identifier: MIT */
/* cards_draw.c - one card composited over the image: its texture's summed-area table (double,
 * texels outside the uv polygon transparent), then per pixel of the expanded polygon the ray's
 * point on the card's plane (perspective-correct depth and uv), the CoC radius of that depth,
 * and the texture's average over that disc mapped into texels by the local projection, as
 * `strips` rectangles of the disc's exact slice areas. */
#include "cards.h"

#include "parallel_rows.h"

#include <math.h>
#include <string.h>

#define CARDS_PI 3.14159265358979323846
#define CARDS_MIN_RADIUS_PX 0.5 /* an in-focus pixel averages its own footprint */

typedef struct card_table {
    double *sum;        /* (tw + 1) x (th + 1) x 4: texels in rows < j, columns < i */
    uint32_t tw, th;
} card_table;

/* Whether texel (i, j)'s centre lies in the card's uv polygon (row 0 at the top: v = 1). */
static int texel_in_card(const card_setup *c, double orientation, const card_table *t,
                         uint32_t i, uint32_t j)
{
    const double u = (i + 0.5) / t->tw, v = 1.0 - (j + 0.5) / t->th;
    for (uint32_t k = 0; k < c->n; k++) {
        const double *a = c->uv[k], *b = c->uv[(k + 1) % c->n];
        if (orientation * ((b[0] - a[0]) * (v - a[1]) - (b[1] - a[1]) * (u - a[0])) < -1e-12)
            return 0;
    }
    return 1;
}

static void build_table(const card_setup *c, card_table *t)
{
    double area = 0.0;
    for (uint32_t k = 0; k < c->n; k++) {
        const double *a = c->uv[k], *b = c->uv[(k + 1) % c->n];
        area += a[0] * b[1] - b[0] * a[1];
    }
    const double orientation = area >= 0.0 ? 1.0 : -1.0;
    const size_t row = (size_t)(t->tw + 1) * 4;
    memset(t->sum, 0, row * sizeof *t->sum);
    for (uint32_t j = 0; j < t->th; j++) {
        const float *texel = c->texture.pixels + (size_t)j * c->texture_stride;
        double *above = t->sum + (size_t)j * row, *here = above + row;
        double run[4] = {0, 0, 0, 0};
        memset(here, 0, 4 * sizeof *here);
        for (uint32_t i = 0; i < t->tw; i++) {
            const int in = texel_in_card(c, orientation, t, i, j);
            for (int ch = 0; ch < 4; ch++) {
                run[ch] += in ? texel[(size_t)i * 4 + ch] : 0.0;
                here[(i + 1) * 4 + ch] = above[(i + 1) * 4 + ch] + run[ch];
            }
        }
    }
}

/* The integral of the texture over [0, x] x [0, y] (texels), x and y clamped to it: exact for
 * piecewise-constant texels, as the bilinear blend of the table's corners. */
static void integral(const card_table *t, double x, double y, double out[4])
{
    x = x < 0.0 ? 0.0 : x > t->tw ? t->tw : x;
    y = y < 0.0 ? 0.0 : y > t->th ? t->th : y;
    uint32_t i = (uint32_t)x, j = (uint32_t)y;
    i = i >= t->tw ? t->tw - 1 : i;
    j = j >= t->th ? t->th - 1 : j;
    const double fx = x - i, fy = y - j;
    const size_t row = (size_t)(t->tw + 1) * 4;
    const double *s00 = t->sum + j * row + (size_t)i * 4, *s10 = s00 + 4, *s01 = s00 + row,
                 *s11 = s01 + 4;
    for (int ch = 0; ch < 4; ch++)
        out[ch] = (1 - fy) * ((1 - fx) * s00[ch] + fx * s10[ch]) +
                  fy * ((1 - fx) * s01[ch] + fx * s11[ch]);
}

typedef struct draw_job {
    const cards_view *view;
    const card_setup *card;
    card_table table;
    uint32_t strips;
    double slice[64];   /* unit-disc area of each strip (sums to pi) */
    uint32_t x0, x1, y0;
    float *out;
    size_t out_stride;
} draw_job;

static int inside_expanded(const card_setup *c, double x, double y)
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
static int card_at(const draw_job *job, double x, double y, double tex[2], double jac[2][2],
                   double *radius)
{
    const cards_view *v = job->view;
    const card_setup *c = job->card;
    const double d[3] = {v->ray_a * x + v->ray_bx, v->ray_by - v->ray_c * y, -1.0};
    const double *nr = c->normal, *o = c->origin;
    const double w = nr[0] * d[0] + nr[1] * d[1] + nr[2] * d[2];
    const double z = (nr[0] * o[0] + nr[1] * o[1] + nr[2] * o[2]) / w;
    if (!(z > 0.0) || !isfinite(z))
        return 0;
    const double dzx = -z * nr[0] * v->ray_a / w, dzy = z * nr[1] * v->ray_c / w;
    double sq[2], dsq[2][2];
    for (int a = 0; a < 2; a++) {
        const double *e = a ? c->e2 : c->e1;
        const double de = d[0] * e[0] + d[1] * e[1] + d[2] * e[2];
        sq[a] = z * de - (o[0] * e[0] + o[1] * e[1] + o[2] * e[2]);
        dsq[a][0] = dzx * de + z * v->ray_a * e[0];
        dsq[a][1] = dzy * de - z * v->ray_c * e[1];
    }
    const double scale[2] = {job->table.tw, -(double)job->table.th};
    for (int t = 0; t < 2; t++) {
        const double *m = c->uv_affine[t];
        tex[t] = scale[t] * (m[0] + m[1] * sq[0] + m[2] * sq[1]) + (t ? job->table.th : 0.0);
        for (int a = 0; a < 2; a++)
            jac[t][a] = scale[t] * (m[1] * dsq[0][a] + m[2] * dsq[1][a]);
    }
    *radius = cards_radius(v, z);
    return isfinite(tex[0]) && isfinite(tex[1]) && isfinite(jac[0][0]) &&
           isfinite(jac[0][1]) && isfinite(jac[1][0]) && isfinite(jac[1][1]);
}

/* The texture's average over the disc of radius r pixels (r * aspect rows) about screen point
 * (x, y), premultiplied RGBA; 0 where the card is not there. */
static int disc_average(const draw_job *job, double x, double y, double avg[4])
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
    const double reach_y = r * sqrt(bb), shear = (a0 * b0 + a1 * b1) / bb;
    double total[4] = {0, 0, 0, 0};
    for (uint32_t k = 0; k < job->strips; k++) {
        const double ta = -1.0 + 2.0 * k / job->strips, tb = ta + 2.0 / job->strips;
        const double y0 = tex[1] + reach_y * ta, y1 = tex[1] + reach_y * tb;
        const double xc = tex[0] + shear * reach_y * 0.5 * (ta + tb);
        const double half = 0.5 * r * r * det * job->slice[k] / (y1 - y0);
        double f00[4], f10[4], f01[4], f11[4];
        integral(&job->table, xc - half, y0, f00);
        integral(&job->table, xc + half, y0, f10);
        integral(&job->table, xc - half, y1, f01);
        integral(&job->table, xc + half, y1, f11);
        for (int ch = 0; ch < 4; ch++)
            total[ch] += f11[ch] - f10[ch] - f01[ch] + f00[ch];
    }
    for (int ch = 0; ch < 4; ch++)
        avg[ch] = total[ch] / area;
    return 1;
}

/* Cards are drawn near to far, each under what is already there (`out += (1 - out.a) card`,
 * the same image as far to near with `over`); a pixel this opaque takes nothing more from the
 * cards behind it, which then change it by at most 1e-6 of their value. */
#define CARDS_OPAQUE (1.0f - 1e-6f)

static void draw_rows(void *user, uint32_t r0, uint32_t r1, uint32_t chunk)
{
    (void)chunk;
    const draw_job *job = user;
    for (uint32_t y = job->y0 + r0; y < job->y0 + r1; y++) {
        float *row = job->out + (size_t)y * job->out_stride;
        for (uint32_t x = job->x0; x < job->x1; x++) {
            float *px = row + (size_t)x * 4;
            double avg[4];
            if (px[3] >= CARDS_OPAQUE || !inside_expanded(job->card, x + 0.5, y + 0.5) ||
                !disc_average(job, x + 0.5, y + 0.5, avg))
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
                       const ddof_cards_params *params, const card_setup *s, float *out,
                       size_t out_stride)
{
    draw_job job = {.view = view, .card = s, .strips = params->strips, .out = out,
                    .out_stride = out_stride};
    job.table.tw = s->texture.width;
    job.table.th = s->texture.height;
    job.x0 = (uint32_t)fmax(0.0, floor(s->box[0]));
    job.y0 = (uint32_t)fmax(0.0, floor(s->box[1]));
    job.x1 = (uint32_t)fmin((double)view->width, ceil(s->box[2]));
    const uint32_t y1 = (uint32_t)fmin((double)view->height, ceil(s->box[3]));
    if (job.x0 >= job.x1 || job.y0 >= y1 || box_opaque(&job, y1))
        return DDOF_OK;
    for (uint32_t k = 0; k < job.strips; k++)
        job.slice[k] = unit_disc_below(-1.0 + 2.0 * (k + 1) / job.strips) -
                       unit_disc_below(-1.0 + 2.0 * k / job.strips);
    const size_t cells = (size_t)(job.table.tw + 1) * (job.table.th + 1) * 4;
    job.table.sum = ddof_alloc(&context->allocator, cells * sizeof(double));
    if (!job.table.sum)
        return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                         "no memory for card %u's summed-area table (%zu bytes)", s->index,
                         cells * sizeof(double));
    build_table(s, &job.table);
    ddof_parallel_rows(context, y1 - job.y0, draw_rows, &job);
    ddof_free(&context->allocator, job.table.sum);
    return DDOF_OK;
}
