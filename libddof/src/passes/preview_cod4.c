/* SPDX-License-Identifier: MIT */
/* preview_cod4.c - the practical post-process depth of field of Call of Duty 4 (GPU Gems 3
 * ch. 28, Earl Hammon Jr.) as libddof's fast preview, adapted to CoC diameters in pixels, any
 * image size, 1..4 float channels and CoC up to DDOF_MAX_COC_PX.
 *
 * The chapter's pipeline, and what it becomes here (W x H image, C channels, every channel
 * blurred alike, alpha too):
 *
 *  1. Downsample to quarter resolution, Q = ceil(W/4) x ceil(H/4): each quarter pixel is the
 *     average of its 4x4 block (the partial blocks of sizes not divisible by 4 average only the
 *     pixels they hold). The near-field CoC D0 (|CoC| where CoC < 0; none without coc_signed) of
 *     a quarter pixel is the maximum over its block. The same pass finds each channel's range,
 *     the largest |CoC| and the largest near CoC.
 *  2. Near CoC: D0 is blurred (three box passes per axis, a Gaussian to within a few percent)
 *     with the per-axis variance of a disk of the largest near CoC, dn^2 / 16; then
 *     D = max(D0, 2 D_blurred - D0) (the chapter's formula; the diffusion's near spread in
 *     layers.c uses a cone dilation instead, which small objects survive), limited to
 *     the largest near CoC, so a blurred near object's CoC spreads over what lies behind it.
 *  3. Three blur levels, as in the chapter:
 *       small   full resolution, 17 taps: the pixel and four 2x2 blocks in a pinwheel around it
 *               (the chapter's four bilinear taps at (0.5, -1.5), (-1.5, -0.5), (-0.5, 1.5),
 *               (1.5, 0.5) plus the centre), all weighted 1/17;
 *       medium  the quarter-resolution image blurred by a 3x3 box (the chapter's small-blur
 *               pass, which also smooths the near CoC: D_med = 3x3 box of D), sampled
 *               bilinearly at full resolution;
 *       large   the quarter-resolution image blurred by three box passes per axis (Gaussian),
 *               sampled bilinearly.
 *     Each level's size is the diameter of the uniform disk with the same per-axis variance
 *     (d^2 / 16, as docs/design.md matches the diffusion to a disk): small 4 sqrt(24/17) = 4.75 px;
 *     medium 4 sqrt(15/12 + 16 * 2/3 + 16/6) = 15.3 px (the block average, the 3x3 box at
 *     quarter resolution and the bilinear upsampling's tent); large D_L, chosen per frame:
 *     D_L = min(largest |CoC|, cap), cap = max(W, H) / 4 (a quarter of the image), and never
 *     less than the medium level. When no CoC exceeds the medium level the large level is not
 *     built at all.
 *  4. Per pixel, d = max(|CoC|, D_med upsampled bilinearly), and the chapter's piecewise-linear
 *     weights (d0, d1, d2 with t = d / D_L) become a blend between the two levels whose sizes
 *     bracket d: 0 -> unblurred, 4.75 px -> small, 15.3 px -> medium, D_L -> large, linear in d
 *     in between, large beyond D_L (a CoC above the cap saturates at the largest blur).
 *
 * Every level is a normalised weighted average of input pixels (box windows at the borders
 * average only the pixels inside the image), bilinear sampling and the final blend are convex,
 * so the output is a convex combination of the input; float rounding can still step an ulp
 * outside, so the result is clamped to each channel's input range (which makes a constant image
 * stay exactly constant). A pixel with d = 0 is copied exactly, so CoC 0 everywhere gives the
 * input back bit for bit.
 *
 * Cost: one full-resolution pass that reads the image (step 1), a few passes over the
 * quarter-resolution images (1/16 of the pixels; box passes cost the same at any radius: running
 * sums in double), and one full-resolution pass that writes the output (step 4).
 *
 * In place (out == colour): the last pass reads rows y - 2 .. y + 2 for row y. It works in
 * bands of 64 rows; the first pass saves the first two and last two rows of every band (rows a
 * neighbouring band may overwrite first), and each band keeps copies of the two rows above the
 * one it writes. */
#include "preview_cod4.h"

#include "runtime/parallel_rows.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

/* Per-axis variances in full-resolution px^2, and the disk diameters that match them. */
#define SMALL_VARIANCE (24.0 / 17.0)  /* the 17-tap pinwheel                                 */
#define DOWN_VARIANCE (15.0 / 12.0)   /* a 4-pixel box                                        */
#define UP_VARIANCE (16.0 / 6.0)      /* bilinear from quarter resolution: a tent, half-width 4 */
#define MEDIUM_BOX_VARIANCE (2.0 / 3.0) /* the 3x3 box, in quarter px^2                       */
#define DIAMETER_OF(variance) (4.0 * sqrt(variance))

#define BAND_ROWS 64u        /* rows of one task of the last pass                            */
#define FLUSH_NEAR (1.0f / 1024.0f) /* a spread CoC below this is 0 (running-sum residue)    */

/* A box window of radius r + f: weight 1 within r of the centre, f (0 <= f < 1) at r + 1. */
typedef struct box {
    int64_t r;
    double f;
} box;

/* The box whose variance (in its own pixels^2) is v. */
static box box_for_variance(double v)
{
    box b = {0, 0.0};
    if (!(v > 0.0))
        return b;
    int64_t r = (int64_t)floor((sqrt(1.0 + 12.0 * v) - 1.0) / 2.0); /* r (r + 1) / 3 <= v */
    while (r > 0 && (double)r * (double)(r + 1) / 3.0 > v)
        r--;
    while ((double)(r + 1) * (double)(r + 2) / 3.0 <= v)
        r++;
    const double rr = (double)r;
    const double sum_sq = rr * (rr + 1.0) * (2.0 * rr + 1.0) / 3.0; /* sum of j^2, |j| <= r */
    const double f = (v * (2.0 * rr + 1.0) - sum_sq) / (2.0 * ((rr + 1.0) * (rr + 1.0) - v));
    b.r = r;
    b.f = f < 0.0 ? 0.0 : (f >= 1.0 ? 0.999999 : f);
    return b;
}

typedef struct chunk_stats {
    float lo[4], hi[4];
    float max_abs, max_near;
} chunk_stats;

typedef struct preview {
    /* the request */
    const float *color, *coc;
    size_t color_stride, coc_stride, out_stride;
    uint32_t coc_channels;
    float *out;
    uint32_t width, height, channels;
    int in_place;

    /* quarter resolution */
    uint32_t qw, qh;
    float *down;              /* block averages                                            */
    float *medium_h, *medium; /* the 3x3 box: horizontal, then vertical                   */
    float *large_a, *large_b; /* ping-pong of the large blur; the result ends in large_a  */
    float *near0;             /* D0, then the spread near CoC D                            */
    float *near_a, *near_b;   /* ping-pong of D0's blur (ends in near_a); then D_med in b  */
    box large_box, near_box, medium_box;
    int has_large, has_near;
    float max_near;

    /* statistics of the first pass, one per chunk */
    chunk_stats *stats;
    float lo[4], hi[4];

    /* the blend: level sizes in px */
    float d_small, d_medium, d_large;

    /* the last pass */
    float *band_memory;
    size_t band_floats;
    float *halo; /* in place: 4 rows per band */
} preview;

/* ---- pass 1: downsample, near CoC, statistics ------------------------------------------- */

/* Which of a band's saved rows y is (0, 1: its first two; 2, 3: its last two), or -1. */
static DDOF_ALWAYS_INLINE int halo_slot(uint32_t y)
{
    const uint32_t m = y % BAND_ROWS;
    return m < 2 ? (int)m : (m >= BAND_ROWS - 2 ? (int)(m - (BAND_ROWS - 4)) : -1);
}

/* Lanes of the running minimum and maximum: a multiple of 1, 2, 3 and 4 channels. */
#define RANGE_LANES 48u

static DDOF_ALWAYS_INLINE void down_rows_c(const preview *p, uint32_t qy0, uint32_t qy1,
                                           uint32_t chunk, const uint32_t C)
{
    float lo[RANGE_LANES], hi[RANGE_LANES];
    for (uint32_t j = 0; j < RANGE_LANES; j++) {
        lo[j] = INFINITY;
        hi[j] = -INFINITY;
    }
    float coc_max[RANGE_LANES];
    for (uint32_t j = 0; j < RANGE_LANES; j++)
        coc_max[j] = 0.0f;
    float max_near = 0.0f;
    const uint32_t W = p->width, qw = p->qw, full = W / 4;
    const size_t kc = p->coc_channels, n = (size_t)W * C;
    for (uint32_t qy = qy0; qy < qy1; qy++) {
        float *restrict a = p->down + (size_t)qy * qw * C;
        float *restrict d0 = p->has_near ? p->near0 + (size_t)qy * qw : NULL;
        const uint32_t y_begin = 4 * qy, y_end = y_begin + 4 < p->height ? y_begin + 4 : p->height;
        memset(a, 0, (size_t)qw * C * sizeof(float));
        if (d0)
            memset(d0, 0, (size_t)qw * sizeof(float));
        for (uint32_t y = y_begin; y < y_end; y++) {
            const float *restrict src = p->color + (size_t)y * p->color_stride;
            if (p->halo) {
                const int slot = halo_slot(y);
                if (slot >= 0)
                    memcpy(p->halo + ((size_t)(y / BAND_ROWS) * 4 + (size_t)slot) * n, src,
                           n * sizeof(float));
            }
            /* the channel ranges, RANGE_LANES floats at a time (lane j holds channel j % C) */
            size_t i = 0;
            for (; i + RANGE_LANES <= n; i += RANGE_LANES)
                for (uint32_t j = 0; j < RANGE_LANES; j++) {
                    lo[j] = ddof_minf(lo[j], src[i + j]);
                    hi[j] = ddof_maxf(hi[j], src[i + j]);
                }
            for (uint32_t j = 0; i < n; i++, j++) {
                lo[j] = ddof_minf(lo[j], src[i]);
                hi[j] = ddof_maxf(hi[j], src[i]);
            }
            /* block sums */
            for (size_t qx = 0; qx < full; qx++)
                for (size_t c = 0; c < C; c++)
                    a[qx * C + c] += (src[(4 * qx) * C + c] + src[(4 * qx + 1) * C + c]) +
                                     (src[(4 * qx + 2) * C + c] + src[(4 * qx + 3) * C + c]);
            for (size_t x = 4 * (size_t)full; x < W; x++)
                for (size_t c = 0; c < C; c++)
                    a[(size_t)full * C + c] += src[x * C + c];
            /* CoC: the largest |CoC| (lane-wise, so that it vectorises), and the near CoC's
             * block maxima */
            const float *restrict k = p->coc + (size_t)y * p->coc_stride;
            size_t x = 0;
            if (kc == 1)
                for (; x + RANGE_LANES <= W; x += RANGE_LANES)
                    for (size_t j = 0; j < RANGE_LANES; j++)
                        coc_max[j] = ddof_maxf(coc_max[j], fabsf(k[x + j]));
            for (; x < W; x++)
                coc_max[0] = ddof_maxf(coc_max[0], fabsf(k[x * kc]));
            if (d0) {
                if (kc == 1)
                    for (size_t qx = 0; qx < full; qx++) {
                        const float *b = k + 4 * qx;
                        d0[qx] = ddof_maxf(d0[qx], ddof_maxf(ddof_maxf(-b[0], -b[1]),
                                                             ddof_maxf(-b[2], -b[3])));
                    }
                else
                    for (size_t qx = 0; qx < full; qx++) {
                        const float *b = k + 4 * qx * kc;
                        d0[qx] = ddof_maxf(d0[qx], ddof_maxf(ddof_maxf(-b[0], -b[kc]),
                                                             ddof_maxf(-b[2 * kc], -b[3 * kc])));
                    }
                for (size_t xx = 4 * (size_t)full; xx < W; xx++)
                    d0[full] = ddof_maxf(d0[full], -k[xx * kc]);
            }
        }
        const uint32_t rows = y_end - y_begin;
        const float inv_full = 1.0f / (float)(4 * rows);
        for (uint32_t i = 0; i < full * C; i++)
            a[i] *= inv_full;
        if (full < qw) {
            const float inv_tail = 1.0f / (float)((W - 4 * full) * rows);
            for (uint32_t c = 0; c < C; c++)
                a[full * C + c] *= inv_tail;
        }
        if (d0)
            for (uint32_t qx = 0; qx < qw; qx++)
                max_near = ddof_maxf(max_near, d0[qx]);
    }
    chunk_stats st;
    for (uint32_t c = 0; c < 4; c++) {
        st.lo[c] = INFINITY;
        st.hi[c] = -INFINITY;
    }
    for (uint32_t j = 0; j < RANGE_LANES; j++) {
        st.lo[j % C] = ddof_minf(st.lo[j % C], lo[j]);
        st.hi[j % C] = ddof_maxf(st.hi[j % C], hi[j]);
    }
    st.max_abs = 0.0f;
    for (uint32_t j = 0; j < RANGE_LANES; j++)
        st.max_abs = ddof_maxf(st.max_abs, coc_max[j]);
    st.max_near = max_near;
    p->stats[chunk] = st;
}

DDOF_MULTIVERSION static void down_rows(void *user, uint32_t qy0, uint32_t qy1, uint32_t chunk)
{
    const preview *p = user;
    switch (p->channels) {
    case 1: down_rows_c(p, qy0, qy1, chunk, 1); break;
    case 2: down_rows_c(p, qy0, qy1, chunk, 2); break;
    case 3: down_rows_c(p, qy0, qy1, chunk, 3); break;
    default: down_rows_c(p, qy0, qy1, chunk, 4); break;
    }
}

/* ---- box passes at quarter resolution (running sums in double) -------------------------- */

/* One box pass along `lines` lines of n pixels (src != dst). Pixel i of line g, lane l is at
 * g * line_stride + i * step + l. The window holds only pixels inside the line, and the
 * weights are normalised by what it holds. Running sums in double: the cost does not depend
 * on the radius. Each lane of each line is its own chain of additions, so several lines at a
 * time keep the adder busy where one line of few lanes would wait on it. */
static DDOF_ALWAYS_INLINE void box_lines_n(const float *src, float *dst, int64_t n, size_t step,
                                           size_t line_stride, const uint32_t lines,
                                           const uint32_t lanes, box b)
{
    enum { MAX_LANES = 64 };
    double acc[MAX_LANES];
    const uint32_t total = lines * lanes;
    const int64_t R = b.r;
    const double f = b.f;
#define BOX_AT(base, i, g, l) ((base)[(size_t)(g) * line_stride + (size_t)(i) * step + (l)])
    for (uint32_t k = 0; k < total; k++)
        acc[k] = 0.0;
    for (int64_t j = 0; j <= R && j < n; j++)
        for (uint32_t g = 0; g < lines; g++)
            for (uint32_t l = 0; l < lanes; l++)
                acc[g * lanes + l] += (double)BOX_AT(src, j, g, l);
    /* Pixels whose window and both fractional ends lie inside: [R + 1, n - R - 2]. */
    const int64_t inner_begin = R + 1 < n ? R + 1 : n;
    const int64_t inner_end = n - R - 1 > inner_begin ? n - R - 1 : inner_begin;
    for (int64_t i = 0; i < n; i++) {
        if (i == inner_begin && inner_end > inner_begin) {
            const double inv = 1.0 / ((double)(2 * R + 1) + 2.0 * f);
            for (; i < inner_end; i++)
                for (uint32_t g = 0; g < lines; g++)
                    for (uint32_t l = 0; l < lanes; l++) {
                        const double out_end = BOX_AT(src, i - R - 1, g, l);
                        const double in_end = BOX_AT(src, i + R + 1, g, l);
                        double *a = &acc[g * lanes + l];
                        BOX_AT(dst, i, g, l) = (float)((*a + f * (out_end + in_end)) * inv);
                        *a += in_end - (double)BOX_AT(src, i - R, g, l);
                    }
            if (i >= n)
                break;
        }
        const int64_t lo = i - R, hi = i + R; /* the inner window */
        double weight = (double)((hi < n - 1 ? hi : n - 1) - (lo > 0 ? lo : 0) + 1);
        const int has_lo = lo - 1 >= 0, has_hi = hi + 1 < n;
        weight += f * (double)(has_lo + has_hi);
        const double inv = 1.0 / weight;
        for (uint32_t g = 0; g < lines; g++)
            for (uint32_t l = 0; l < lanes; l++) {
                double sum = acc[g * lanes + l];
                if (has_lo)
                    sum += f * (double)BOX_AT(src, lo - 1, g, l);
                if (has_hi)
                    sum += f * (double)BOX_AT(src, hi + 1, g, l);
                BOX_AT(dst, i, g, l) = (float)(sum * inv);
                if (has_hi)
                    acc[g * lanes + l] += (double)BOX_AT(src, hi + 1, g, l);
                if (lo >= 0)
                    acc[g * lanes + l] -= (double)BOX_AT(src, lo, g, l);
            }
    }
#undef BOX_AT
}

DDOF_MULTIVERSION static void box_lines(const float *src, float *dst, int64_t n, size_t step,
                                        size_t line_stride, uint32_t lines, uint32_t lanes,
                                        box b)
{
    /* the shapes the passes use: rows (16 / C lines of C lanes), columns (one line of up to
     * 64 lanes) */
#define BOX_CASE(L, N)                                                                         \
    if (lines == (L) && lanes == (N)) {                                                       \
        box_lines_n(src, dst, n, step, line_stride, L, N, b);                                 \
        return;                                                                               \
    }
    BOX_CASE(16, 1)
    BOX_CASE(8, 2)
    BOX_CASE(5, 3)
    BOX_CASE(4, 4)
    BOX_CASE(1, 16)
    BOX_CASE(1, 32)
    BOX_CASE(1, 48)
    BOX_CASE(1, 64)
#undef BOX_CASE
    box_lines_n(src, dst, n, step, line_stride, lines, lanes, b);
}

/* Horizontal pass over rows [y0, y1) of a qw-wide image of `channels`. */
static void box_rows(const preview *p, const float *src, float *dst, uint32_t y0, uint32_t y1,
                     uint32_t channels, box b)
{
    const size_t stride = (size_t)p->qw * channels;
    const uint32_t group = 16 / channels;
    for (uint32_t y = y0; y < y1; y += group) {
        const uint32_t lines = y1 - y < group ? y1 - y : group;
        box_lines(src + y * stride, dst + y * stride, p->qw, channels, stride, lines, channels,
                  b);
    }
}

/* Vertical pass over columns [x0, x1) of a qw-wide image of `channels`. */
static void box_columns(const preview *p, const float *src, float *dst, uint32_t x0,
                        uint32_t x1, uint32_t channels, box b)
{
    const size_t stride = (size_t)p->qw * channels;
    for (uint32_t x = x0; x < x1;) {
        const uint32_t n = (64 / channels < x1 - x) ? 64 / channels : x1 - x;
        box_lines(src + (size_t)x * channels, dst + (size_t)x * channels, p->qh, stride, 0, 1,
                  n * channels, b);
        x += n;
    }
}

/* box_rows or box_columns: one box pass over lines [first, end) of a quarter image. */
typedef void (*box_pass)(const preview *p, const float *src, float *dst, uint32_t first,
                         uint32_t end, uint32_t channels, box b);

/* A separable blur of the quarter-resolution images: `passes` box passes per axis (1, or 3 for a
 * Gaussian to within a few percent) that ping-pong between a and b. */
typedef struct quarter_blur {
    const float *src;
    float *a, *b;
    uint32_t channels, passes;
    box window;
} quarter_blur;

/* One stage of a blur over lines [first, end): the row stage starts from src and ends in b
 * (src -> b -> a -> b), the column stage goes on from b and ends in a (b -> a -> b -> a). */
static void blur_stage(const preview *p, const quarter_blur *q, int along_columns,
                       uint32_t first, uint32_t end)
{
    const box_pass pass = along_columns ? box_columns : box_rows;
    const float *from = along_columns ? q->b : q->src;
    float *into = along_columns ? q->a : q->b, *other = along_columns ? q->b : q->a;
    pass(p, from, into, first, end, q->channels, q->window);
    for (uint32_t k = 1; k < q->passes; k += 2) {
        pass(p, into, other, first, end, q->channels, q->window);
        pass(p, other, into, first, end, q->channels, q->window);
    }
}

/* One stage of every blur the frame needs: the 3x3 box (the medium level: down -> medium_h ->
 * medium), the large blur (ends in large_a) and the near CoC's (ends in near_a). */
static void quarter_stage(const preview *p, int along_columns, uint32_t first, uint32_t end)
{
    const quarter_blur blurs[3] = {
        {p->down, p->medium, p->medium_h, p->channels, 1, p->medium_box},
        {p->down, p->large_a, p->large_b, p->channels, 3, p->large_box},
        {p->near0, p->near_a, p->near_b, 1, 3, p->near_box},
    };
    const int wanted[3] = {1, p->has_large, p->has_near};
    for (int i = 0; i < 3; i++)
        if (wanted[i])
            blur_stage(p, &blurs[i], along_columns, first, end);
}

/* Row stage: every horizontal pass of rows [y0, y1). */
static void quarter_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    quarter_stage(user, 0, y0, y1);
}

/* Column stage: every vertical pass of columns [x0, x1). A column's passes need nothing from
 * other columns, so one task runs all of them on its strip while it is in cache, then the
 * spread near CoC D = min(max(D0, 2 D_blurred - D0), largest near CoC) into near0. */
static void quarter_columns(void *user, uint32_t x0, uint32_t x1, uint32_t chunk)
{
    (void)chunk;
    const preview *p = user;
    quarter_stage(p, 1, x0, x1);
    if (p->has_near) {
        for (uint32_t y = 0; y < p->qh; y++) {
            float *restrict d0 = p->near0 + (size_t)y * p->qw;
            const float *restrict blurred = p->near_a + (size_t)y * p->qw;
            for (uint32_t x = x0; x < x1; x++)
                d0[x] = ddof_minf(ddof_maxf(d0[x], 2.0f * blurred[x] - d0[x]), p->max_near);
        }
    }
}

/* D_med (into near_b) = 3x3 box of the spread near CoC D (in near0), averaging what lies inside
 * the image; below FLUSH_NEAR it is 0. */
DDOF_MULTIVERSION static void near_medium_rows(void *user, uint32_t y0, uint32_t y1,
                                               uint32_t chunk)
{
    (void)chunk;
    const preview *p = user;
    const uint32_t qw = p->qw, qh = p->qh;
    for (uint32_t y = y0; y < y1; y++) {
        /* the rows y - 1 .. y + 1 inside the image, first; the others repeat the first */
        const uint32_t first = y ? y - 1 : 0, last = y + 1 < qh ? y + 1 : y;
        const uint32_t n_rows = last - first + 1;
        const float *rows[3];
        for (uint32_t k = 0; k < 3; k++)
            rows[k] = p->near0 + (size_t)(first + (k < n_rows ? k : 0)) * qw;
        /* rows missing at the top or bottom border count 0 */
        const float wb = n_rows > 1 ? 1.0f : 0.0f, wc = n_rows > 2 ? 1.0f : 0.0f;
        const float *restrict a = rows[0], *restrict b = rows[1], *restrict c = rows[2];
        float *restrict out = p->near_b + (size_t)y * qw;
        const float inv_inner = 1.0f / (3.0f * (float)n_rows);
        for (uint32_t x = 1; x + 1 < qw; x++) {
            const float sum = (a[x - 1] + a[x] + a[x + 1]) +
                              wb * (b[x - 1] + b[x] + b[x + 1]) +
                              wc * (c[x - 1] + c[x] + c[x + 1]);
            const float d = sum * inv_inner;
            out[x] = d < FLUSH_NEAR ? 0.0f : d;
        }
        const uint32_t edges[2] = {0, qw - 1};
        for (uint32_t e = 0; e < (qw > 1 ? 2u : 1u); e++) { /* the first and last column */
            const uint32_t x = edges[e];
            const uint32_t i0 = x ? x - 1 : x, i1 = x + 1 < qw ? x + 1 : x;
            float sum = 0.0f;
            for (uint32_t i = i0; i <= i1; i++)
                sum += a[i] + wb * b[i] + wc * c[i];
            const float d = sum / (float)((i1 - i0 + 1) * n_rows);
            out[x] = d < FLUSH_NEAR ? 0.0f : d;
        }
    }
}

/* n floats rounded up to 64 bytes. */
static size_t align_floats(size_t n)
{
    return (n + 15) & ~(size_t)15;
}

/* ---- the last pass: blend the levels per pixel ------------------------------------------ */

/* Two quarter-resolution rows of one image, upsampled along x to full width: the two that the
 * full-resolution rows between them interpolate (four full rows share each pair). */
typedef struct wide_rows {
    float *row[2];
    int64_t quarter_row[2]; /* which quarter row each holds (slot = quarter row % 2) */
} wide_rows;

typedef struct band_state {
    const preview *p;
    uint32_t y0, y1;
    float *sums[4];      /* 2x2 block sums of rows r, r + 1 for 4 values of r, x from -2 to W */
    int64_t sums_row[4]; /* which r each holds                                             */
    float *copies[3];    /* in place: the original rows y - 2, y - 1, y, ring by y % 3        */
    float *d;            /* the row's blend CoC                                            */
    float *d_values;     /* d repeated for each channel                                    */
    wide_rows near_wide, medium_wide, large_wide; /* quarter-res rows upsampled along x      */
    float *small, *medium, *large;           /* the levels at full resolution, one row     */
} band_state;

/* The original row y (0 <= y < H) while row `current` of the band is being written. */
static const float *original_row(const band_state *b, int64_t y, uint32_t current)
{
    const preview *p = b->p;
    if (!p->in_place || (y >= current && y < b->y1))
        return p->color + (size_t)y * p->color_stride;
    if (y >= b->y0 && y < current)
        return b->copies[y % 3];
    /* another band's row: saved by the first pass */
    const size_t rowf = (size_t)p->width * p->channels;
    return p->halo + ((size_t)((uint64_t)y / BAND_ROWS) * 4 + (size_t)halo_slot((uint32_t)y)) * rowf;
}

/* sums[slot] = 2x2 block sums with top-left (x', r), x' = -2 .. W (index x' + 2), of the
 * pixels inside the image. */
DDOF_MULTIVERSION static void block_sums(band_state *b, int slot, int64_t r, uint32_t current)
{
    const preview *p = b->p;
    const uint32_t W = p->width, C = p->channels;
    float *dst = b->sums[slot];
    const float *rows[2] = {NULL, NULL};
    for (int j = 0; j < 2; j++)
        if (r + j >= 0 && r + j < (int64_t)p->height)
            rows[j] = original_row(b, r + j, current);
    if (!rows[0] && !rows[1]) { /* both rows outside the image: all zero */
        memset(dst, 0, (size_t)(W + 3) * C * sizeof(float));
        b->sums_row[slot] = r;
        return;
    }
    float *restrict d = dst + 2 * (size_t)C; /* x' = 0 */
    const size_t n = (size_t)(W - 1) * C;    /* x' = 0 .. W - 2 hold two columns */
    if (rows[0] && rows[1]) {
        const float *restrict s0 = rows[0], *restrict s1 = rows[1];
        for (size_t i = 0; i < n; i++)
            d[i] = (s0[i] + s1[i]) + (s0[i + C] + s1[i + C]);
    } else {
        const float *restrict s0 = rows[0] ? rows[0] : rows[1];
        for (size_t i = 0; i < n; i++)
            d[i] = s0[i] + s0[i + C];
    }
    /* x' = -2 and x' = W hold nothing; x' = -1 and x' = W - 1 one column (the same one when
     * W = 1) */
    for (uint32_t c = 0; c < C; c++) {
        const float first = rows[0] && rows[1] ? rows[0][c] + rows[1][c]
                                               : (rows[0] ? rows[0] : rows[1])[c];
        const float last = rows[0] && rows[1] ? rows[0][n + c] + rows[1][n + c]
                                              : (rows[0] ? rows[0] : rows[1])[n + c];
        dst[c] = 0.0f;
        d[c - (int64_t)C] = first;
        d[n + c] = last;
        d[n + C + c] = 0.0f;
    }
    b->sums_row[slot] = r;
}

static const float *sums_for(band_state *b, int64_t r, uint32_t current)
{
    const int slot = (int)((r + 4) & 3);
    if (b->sums_row[slot] != r)
        block_sums(b, slot, r, current);
    return b->sums[slot] + 2 * (size_t)b->p->channels;
}

/* Pixels of a 2-wide block starting at v inside [0, n). */
static DDOF_ALWAYS_INLINE uint32_t inside_2(int64_t v, int64_t n)
{
    return (uint32_t)(v >= 0 && v < n) + (uint32_t)(v + 1 >= 0 && v + 1 < n);
}

/* Bilinear upsampling along x of a quarter-resolution row: pixel x = 4 i + k sits at quarter
 * coordinate (x - 1.5) / 4 = i + (k - 1.5) / 4, between i - 1 and i (k < 2) or i and i + 1,
 * clamped to the row. */
static const float up_prev[4] = {0.375f, 0.125f, 0.0f, 0.0f};
static const float up_cur[4] = {0.625f, 0.875f, 0.875f, 0.625f};
static const float up_next[4] = {0.0f, 0.0f, 0.125f, 0.375f};

static DDOF_ALWAYS_INLINE void upsample_block(const float *restrict q, uint32_t qw, uint32_t W,
                                              uint32_t i, float *restrict out, const uint32_t C)
{
    const float *prev = q + (size_t)(i ? i - 1 : 0) * C, *cur = q + (size_t)i * C;
    const float *next = q + (size_t)(i + 1 < qw ? i + 1 : i) * C;
    for (uint32_t x = 4 * i; x < W && x < 4 * i + 4; x++)
        for (uint32_t c = 0; c < C; c++)
            out[(size_t)x * C + c] = up_prev[x - 4 * i] * prev[c] + up_cur[x - 4 * i] * cur[c] +
                                     up_next[x - 4 * i] * next[c];
}

static DDOF_ALWAYS_INLINE void upsample_row(const float *restrict q, uint32_t qw, uint32_t W,
                                            float *restrict out, const uint32_t C)
{
    /* blocks 1 .. end - 1 are whole and have both neighbours */
    const uint32_t end = W / 4 < qw - 1 ? W / 4 : qw - 1;
    upsample_block(q, qw, W, 0, out, C);
    for (uint32_t i = 1; i < end; i++) {
        const float *restrict prev = q + (size_t)(i - 1) * C;
        float *restrict o = out + (size_t)4 * i * C;
        for (uint32_t c = 0; c < C; c++) {
            const float a = prev[c], b = prev[C + c], n = prev[2 * C + c];
            o[c] = 0.375f * a + 0.625f * b;
            o[C + c] = 0.125f * a + 0.875f * b;
            o[2 * C + c] = 0.875f * b + 0.125f * n;
            o[3 * C + c] = 0.625f * b + 0.375f * n;
        }
    }
    for (uint32_t i = end > 1 ? end : 1; i < qw; i++)
        upsample_block(q, qw, W, i, out, C);
}

/* The small level of row y, from the original row and the 2x2 block sums of rows y - 2 .. y + 1:
 * the pixel and the blocks with top-left (x, y-2), (x-2, y-1), (x-1, y+1), (x+1, y), divided by
 * how many of those 17 pixels lie inside the image. */
static DDOF_ALWAYS_INLINE void small_row(band_state *b, uint32_t y, const float *restrict px,
                                         const uint32_t C)
{
    const preview *p = b->p;
    const uint32_t W = p->width, H = p->height;
    const float *restrict up2 = sums_for(b, (int64_t)y - 2, y);
    const float *restrict up1 = sums_for(b, (int64_t)y - 1, y) - 2 * (size_t)C;
    const float *restrict down1 = sums_for(b, (int64_t)y + 1, y) - (size_t)C;
    const float *restrict same = sums_for(b, (int64_t)y, y) + C;
    float *restrict out = b->small;
    const size_t n = (size_t)W * C;
    for (size_t i = 0; i < n; i++)
        out[i] = ((px[i] + up2[i]) + (up1[i] + down1[i]) + same[i]) * (1.0f / 17.0f);
    const int64_t w = W, h = H;
    for (uint32_t x = 0; x < W; x++) {
        if (y >= 2 && y + 2 < H && x >= 2 && x + 2 < W) {
            x = W - 3; /* jump to the right border */
            continue;
        }
        const int64_t xi = x;
        const uint32_t count = 1 + inside_2(xi, w) * inside_2((int64_t)y - 2, h) +
                               inside_2(xi - 2, w) * inside_2((int64_t)y - 1, h) +
                               inside_2(xi - 1, w) * inside_2((int64_t)y + 1, h) +
                               inside_2(xi + 1, w) * inside_2((int64_t)y, h);
        const float inv = 1.0f / (float)count;
        for (uint32_t c = 0; c < C; c++) {
            const size_t i = (size_t)x * C + c;
            out[i] = ((px[i] + up2[i]) + (up1[i] + down1[i]) + same[i]) * inv;
        }
    }
}

/* The blend: per value i (pixel i / C), with A, M, L the pieces of the piecewise-linear ramp
 * in the blend CoC d (A = min(d / d_small, 1): from the pixel to small; M: from small to
 * medium over d_small .. d_medium; L: from medium to large over d_medium .. d_large),
 * out = clamp((1 - A) x + (A - M) small + (M - L) medium + L large) to the channel's range.
 * Everything is per value (d repeated for each channel), so that it vectorises without
 * shuffling channels apart. */
typedef struct blend_ramp {
    float inv_small, d_small, inv_medium, d_medium, inv_large;
} blend_ramp;

static DDOF_ALWAYS_INLINE float blend_value(float d, float px, float small, float medium,
                                            float large, float lo, float hi, blend_ramp r)
{
    const float a = ddof_minf(d * r.inv_small, 1.0f);
    const float m = ddof_minf(ddof_maxf((d - r.d_small) * r.inv_medium, 0.0f), 1.0f);
    const float l = ddof_minf(ddof_maxf((d - r.d_medium) * r.inv_large, 0.0f), 1.0f);
    const float v = ((1.0f - a) * px + (a - m) * small) + ((m - l) * medium + l * large);
    return ddof_minf(ddof_maxf(v, lo), hi);
}

/* lo48 / hi48: the channel ranges repeated over RANGE_LANES values (a multiple of C). */
static DDOF_ALWAYS_INLINE void blend_row(const float *restrict d, const float *restrict px,
                                         const float *restrict small, const float *restrict medium,
                                         const float *restrict large, float *restrict out,
                                         size_t n, const float *restrict lo48,
                                         const float *restrict hi48, blend_ramp r)
{
    size_t i0 = 0;
    for (; i0 + RANGE_LANES <= n; i0 += RANGE_LANES)
        for (size_t j = 0; j < RANGE_LANES; j++) {
            const size_t i = i0 + j;
            out[i] = blend_value(d[i], px[i], small[i], medium[i], large[i], lo48[j], hi48[j], r);
        }
    for (size_t i = i0; i < n; i++)
        out[i] = blend_value(d[i], px[i], small[i], medium[i], large[i], lo48[i - i0],
                             hi48[i - i0], r);
}

/* out[x * C + c] = d[x] */
static DDOF_ALWAYS_INLINE void repeat_per_channel(const float *restrict d, float *restrict out,
                                                  uint32_t W, const uint32_t C)
{
    for (size_t x = 0; x < W; x++)
        for (size_t c = 0; c < C; c++)
            out[x * C + c] = d[x];
}

/* Quarter row r of img (rows `stride` floats apart), upsampled along x to full width. */
static DDOF_ALWAYS_INLINE const float *wide_row(wide_rows *w, const float *img, size_t stride,
                                                size_t r, uint32_t qw, uint32_t W,
                                                const uint32_t C)
{
    const int slot = (int)(r & 1);
    if (w->quarter_row[slot] != (int64_t)r) {
        upsample_row(img + r * stride, qw, W, w->row[slot], C);
        w->quarter_row[slot] = (int64_t)r;
    }
    return w->row[slot];
}

/* out = the bilinear sample of img for every pixel of a full-resolution row: quarter rows r0
 * and r1 upsampled along x, then (1 - wy) r0 + wy r1. */
static DDOF_ALWAYS_INLINE void level_row(wide_rows *w, const float *img, size_t stride,
                                         size_t r0, size_t r1, float wy, uint32_t qw, uint32_t W,
                                         float *restrict out, const uint32_t C)
{
    const float *restrict a = wide_row(w, img, stride, r0, qw, W, C);
    const float *restrict b = wide_row(w, img, stride, r1, qw, W, C);
    const size_t n = (size_t)W * C;
    for (size_t i = 0; i < n; i++)
        out[i] = (1.0f - wy) * a[i] + wy * b[i];
}

static DDOF_ALWAYS_INLINE void band_rows_c(band_state *b, const uint32_t C)
{
    const preview *p = b->p;
    const uint32_t W = p->width, qw = p->qw;
    const float d_small = p->d_small, d_medium = p->d_medium;
    const float medium_top = p->has_large ? p->d_large : INFINITY;
    const blend_ramp ramp = {1.0f / d_small, d_small, 1.0f / (d_medium - d_small), d_medium,
                             p->has_large ? 1.0f / (p->d_large - d_medium) : 0.0f};
    const size_t qstride = (size_t)qw * C;
    float lo48[RANGE_LANES], hi48[RANGE_LANES];
    for (uint32_t j = 0; j < RANGE_LANES; j++) {
        lo48[j] = p->lo[j % C];
        hi48[j] = p->hi[j % C];
    }
    for (uint32_t y = b->y0; y < b->y1; y++) {
        /* bilinear rows at quarter resolution: y sits at (y - 1.5) / 4 */
        const float qy = ((float)y - 1.5f) * 0.25f;
        size_t r0 = 0, r1 = 0;
        float wy = 0.0f;
        if (qy > 0.0f) {
            r0 = (size_t)qy;
            wy = qy - (float)r0;
            r1 = r0 + 1;
            if (r1 >= p->qh) {
                r0 = r1 = p->qh - 1;
                wy = 0.0f;
            }
        }
        /* the blend CoC d = max(|CoC|, D_med), and the weights of the levels:
         * piecewise linear in d through 0, d_small, d_medium, d_large */
        const float *restrict k = p->coc + (size_t)y * p->coc_stride;
        const size_t kc = p->coc_channels;
        float *restrict d = b->d;
        if (p->has_near) {
            level_row(&b->near_wide, p->near_b, qw, r0, r1, wy, qw, W, d, 1);
            if (kc == 1)
                for (uint32_t x = 0; x < W; x++)
                    d[x] = ddof_maxf(fabsf(k[x]), d[x]);
            else
                for (uint32_t x = 0; x < W; x++)
                    d[x] = ddof_maxf(fabsf(k[x * kc]), d[x]);
        } else if (kc == 1) {
            for (uint32_t x = 0; x < W; x++)
                d[x] = fabsf(k[x]);
        } else {
            for (uint32_t x = 0; x < W; x++)
                d[x] = fabsf(k[x * kc]);
        }
        /* Which levels the row uses: small where 0 < d < d_medium, medium where d_small < d <
         * d_large (or beyond, with no large level), large beyond d_medium; the input row is
         * read only where a pixel blends it or the small level (d < d_medium). */
        uint32_t any_blur = 0, any_small = 0, any_medium = 0, any_large = 0, any_sharp = 0;
        for (uint32_t x = 0; x < W; x++) {
            any_blur |= (uint32_t)(d[x] > 0.0f);
            any_small |= (uint32_t)(d[x] > 0.0f) & (uint32_t)(d[x] < d_medium);
            any_medium |= (uint32_t)(d[x] > d_small) & (uint32_t)(d[x] < medium_top);
            any_large |= (uint32_t)(d[x] > d_medium);
            any_sharp |= (uint32_t)(d[x] < d_medium);
        }
        const float *src = original_row(b, y, y);
        float *dst = p->out + (size_t)y * p->out_stride;
        if (!any_blur) { /* all in focus: the row as it is */
            if (p->in_place)
                memcpy(b->copies[y % 3], src, (size_t)W * C * sizeof(float));
            else
                memcpy(dst, src, (size_t)W * C * sizeof(float));
            continue;
        }
        any_large &= (uint32_t)p->has_large;
        const int need_src = any_sharp || p->in_place;
        /* Only the levels some pixel uses are built; the others point at one that is (their
         * weights are 0 there; the values are finite). */
        if (any_small)
            small_row(b, y, src, C);
        if (any_medium)
            level_row(&b->medium_wide, p->medium, qstride, r0, r1, wy, qw, W, b->medium, C);
        if (any_large)
            level_row(&b->large_wide, p->large_a, qstride, r0, r1, wy, qw, W, b->large, C);
        if (p->in_place) { /* the rows below still need this one */
            memcpy(b->copies[y % 3], src, (size_t)W * C * sizeof(float));
            src = b->copies[y % 3];
        }
        const float *fallback = need_src ? src : (any_medium ? b->medium : b->large);
        const float *px = need_src ? src : fallback;
        const float *small = any_small ? b->small : fallback;
        const float *medium = any_medium ? b->medium : fallback;
        const float *large = any_large ? b->large : fallback;
        const float *d_values = d;
        if (C > 1) {
            repeat_per_channel(d, b->d_values, W, C);
            d_values = b->d_values;
        }
        blend_row(d_values, px, small, medium, large, dst, (size_t)W * C, lo48, hi48, ramp);
    }
}

DDOF_MULTIVERSION static void band_rows(void *user, uint32_t first, uint32_t end, uint32_t band)
{
    (void)first;
    (void)end;
    const preview *p = user;
    const uint32_t W = p->width, C = p->channels;
    float *mem = p->band_memory + p->band_floats * band;
    band_state b = {.p = p, .y0 = band * BAND_ROWS};
    b.y1 = b.y0 + BAND_ROWS < p->height ? b.y0 + BAND_ROWS : p->height;
    const size_t sums_floats = align_floats((size_t)(W + 3) * C);
    const size_t row_floats = align_floats((size_t)W * C);
    for (int i = 0; i < 4; i++) {
        b.sums[i] = mem;
        mem += sums_floats;
        b.sums_row[i] = INT64_MIN;
    }
    b.d = mem;
    mem += align_floats(W);
    b.d_values = mem;
    mem += row_floats;
    wide_rows *wides[3] = {&b.near_wide, &b.medium_wide, &b.large_wide};
    for (int k = 0; k < 3; k++)
        for (int i = 0; i < 2; i++) {
            wides[k]->row[i] = mem;
            wides[k]->quarter_row[i] = -1;
            mem += k ? row_floats : align_floats(W);
        }
    b.small = mem;
    mem += row_floats;
    b.medium = mem;
    mem += row_floats;
    b.large = mem;
    mem += row_floats;
    for (int i = 0; i < 3; i++) {
        b.copies[i] = p->in_place ? mem : NULL;
        mem += p->in_place ? row_floats : 0;
    }
    switch (C) {
    case 1: band_rows_c(&b, 1); break;
    case 2: band_rows_c(&b, 2); break;
    case 3: band_rows_c(&b, 3); break;
    default: band_rows_c(&b, 4); break;
    }
}

/* Floats of one band's working memory (as band_rows lays it out): 4 rows of block sums; d and
 * the near CoC's two wide rows (W floats each); d per value; the medium and large levels' two
 * wide rows each; the small, medium and large rows; in place, 3 input rows. */
static size_t band_floats(uint32_t W, uint32_t C, int in_place)
{
    const size_t row = align_floats((size_t)W * C);
    return 4 * align_floats((size_t)(W + 3) * C) + 3 * align_floats(W) + row + 4 * row +
           3 * row + (in_place ? 3 * row : 0);
}

/* ---- the call ----------------------------------------------------------------------------- */

/* Bytes of n floats rounded up to 64; 0 when that does not fit in a size_t. */
static size_t round_bytes(uint64_t floats)
{
    if (floats > (UINT64_MAX - 63) / sizeof(float))
        return 0;
    const uint64_t bytes = (floats * sizeof(float) + 63) & ~(uint64_t)63;
    return bytes > SIZE_MAX / 2 ? 0 : (size_t)bytes;
}

static void copy_input(const adi_request *r)
{
    if (r->out != r->color)
        for (uint32_t y = 0; y < r->height; y++)
            memcpy(r->out + (size_t)y * r->out_stride, r->color + (size_t)y * r->color_stride,
                   (size_t)r->width * r->channels * sizeof(float));
}

static ddof_status cancelled(ddof_context *context, const adi_request *r, adi_report *report,
                             double t0)
{
    copy_input(r);
    report->seconds_rows = ddof_seconds() - t0;
    return ddof_fail(context, DDOF_ERROR_CANCELLED, "cancelled by the progress callback");
}

/* The preview's working memory from the context's scratch; 0 when some could not be had. */
static int allocate(ddof_context *context, preview *p, uint32_t chunks, uint32_t bands)
{
    const uint32_t C = p->channels;
    const uint64_t quarter = (uint64_t)p->qw * p->qh;
    const uint64_t quarter_floats = (uint64_t)round_bytes(quarter * C) / sizeof(float);
    const uint64_t near_floats = (uint64_t)round_bytes(quarter) / sizeof(float);
    const uint64_t stats_floats =
        round_bytes(((uint64_t)chunks * sizeof(chunk_stats) + 3) / sizeof(float)) / sizeof(float);
    p->band_floats = band_floats(p->width, C, p->in_place);
    const size_t quarter_bytes = round_bytes(5 * quarter_floats);
    const size_t near_bytes = round_bytes(3 * near_floats);
    const size_t stats_bytes = round_bytes(stats_floats);
    const size_t band_bytes = round_bytes((uint64_t)p->band_floats * bands);
    const size_t halo_bytes = round_bytes((uint64_t)bands * 4 * p->width * C);
    float *quarter_mem =
        quarter_bytes ? ddof_scratch_get(context, DDOF_SCRATCH_COD4_QUARTER, quarter_bytes)
                      : NULL;
    float *near_mem = p->has_near && near_bytes
                          ? ddof_scratch_get(context, DDOF_SCRATCH_COD4_NEAR, near_bytes)
                          : NULL;
    p->stats =
        stats_bytes ? ddof_scratch_get(context, DDOF_SCRATCH_COD4_STATS, stats_bytes) : NULL;
    p->band_memory =
        band_bytes ? ddof_scratch_get(context, DDOF_SCRATCH_COD4_BANDS, band_bytes) : NULL;
    p->halo = p->in_place && halo_bytes
                  ? ddof_scratch_get(context, DDOF_SCRATCH_COD4_HALO, halo_bytes)
                  : NULL;
    if (!quarter_mem || (p->has_near && !near_mem) || !p->stats || !p->band_memory ||
        (p->in_place && !p->halo))
        return 0;
    p->down = quarter_mem;
    p->medium_h = quarter_mem + quarter_floats;
    p->medium = quarter_mem + 2 * quarter_floats;
    p->large_a = quarter_mem + 3 * quarter_floats;
    p->large_b = quarter_mem + 4 * quarter_floats;
    if (p->has_near) {
        p->near0 = near_mem;
        p->near_a = near_mem + near_floats;
        p->near_b = near_mem + 2 * near_floats;
    }
    return 1;
}

/* The blur levels' sizes and box windows, from the largest CoC. */
static void choose_levels(preview *p, float max_abs)
{
    const double cap = (double)(p->width > p->height ? p->width : p->height) / 4.0;
    p->has_large = max_abs > p->d_medium && cap > (double)p->d_medium;
    p->d_large =
        p->has_large ? (float)((double)max_abs < cap ? (double)max_abs : cap) : p->d_medium;
    if (p->has_large) {
        const double d = p->d_large;
        const double v = (d * d / 16.0 - DOWN_VARIANCE - UP_VARIANCE) / 16.0; /* quarter px^2 */
        p->large_box = box_for_variance(v / 3.0);
    }
    p->has_near = p->has_near && p->max_near > 0.0f;
    if (p->has_near) {
        const double d = (double)p->max_near < cap ? (double)p->max_near : cap;
        p->near_box = box_for_variance(d * d / 256.0 / 3.0);
    }
    p->medium_box = (box){1, 0.0};
}

ddof_status ddof_cod4_preview(ddof_context *context, const adi_request *r, int coc_signed,
                              adi_report *report)
{
    const double t0 = ddof_seconds();
    const uint32_t W = r->width, H = r->height, C = r->channels;
    report->threads = context->thread_count;
    report->max_coc = 0.0f;
    report->seconds_rows = 0.0;

    preview p;
    memset(&p, 0, sizeof p);
    p.color = r->color;
    p.color_stride = r->color_stride;
    p.coc = r->coc ? r->coc : &r->uniform_coc;
    p.coc_stride = r->coc ? r->coc_stride : 0;
    p.coc_channels = r->coc ? r->coc_channels : 0;
    p.out = r->out;
    p.out_stride = r->out_stride;
    p.width = W;
    p.height = H;
    p.channels = C;
    p.in_place = r->out == r->color;
    p.qw = (W + 3) / 4;
    p.qh = (H + 3) / 4;
    p.has_near = coc_signed != 0;
    p.d_small = (float)DIAMETER_OF(SMALL_VARIANCE);
    p.d_medium = (float)DIAMETER_OF(DOWN_VARIANCE + 16.0 * MEDIUM_BOX_VARIANCE + UP_VARIANCE);

    /* All working memory first, so that a failure leaves out untouched. */
    const uint32_t chunks = ddof_row_chunks(p.qh);
    const uint32_t bands = (H + BAND_ROWS - 1) / BAND_ROWS;
    if (!allocate(context, &p, chunks, bands))
        return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                         "could not allocate the CoD4 preview's working memory for %ux%u, "
                         "%u channels", W, H, C);

    /* Pass 1: quarter resolution, near CoC, ranges. */
    ddof_parallel_rows(context, p.qh, down_rows, &p);
    float max_abs = 0.0f;
    for (uint32_t c = 0; c < C; c++) {
        p.lo[c] = INFINITY;
        p.hi[c] = -INFINITY;
    }
    for (uint32_t i = 0; i < chunks; i++) {
        const chunk_stats *s = &p.stats[i];
        for (uint32_t c = 0; c < C; c++) {
            p.lo[c] = ddof_minf(p.lo[c], s->lo[c]);
            p.hi[c] = ddof_maxf(p.hi[c], s->hi[c]);
        }
        max_abs = ddof_maxf(max_abs, s->max_abs);
        p.max_near = ddof_maxf(p.max_near, s->max_near);
    }
    report->max_coc = max_abs;
    if (max_abs <= 0.0f) { /* nothing out of focus: a copy */
        copy_input(r);
        report->seconds_rows = ddof_seconds() - t0;
        if (r->progress)
            r->progress(r->progress_user, 1.0f);
        return DDOF_OK;
    }
    if (r->progress && r->progress(r->progress_user, 0.3f))
        return cancelled(context, r, report, t0);

    choose_levels(&p, max_abs);

    /* Quarter-resolution passes: the horizontal ones (ending in large_b and near_b), the
     * vertical ones (b -> a -> b -> a: the large level ends in large_a, the blurred near CoC in
     * near_a, the spread near CoC D in near0), then D_med into near_b. */
    ddof_parallel_rows(context, p.qh, quarter_rows, &p);
    ddof_parallel_rows(context, p.qw, quarter_columns, &p);
    if (p.has_near)
        ddof_parallel_rows(context, p.qh, near_medium_rows, &p);
    if (r->progress && r->progress(r->progress_user, 0.6f))
        return cancelled(context, r, report, t0);

    /* The last pass, one task per band of BAND_ROWS rows: ddof_parallel_rows hands each task
     * DDOF_ROWS_PER_CHUNK indices and its chunk number, which is the band. */
    ddof_parallel_rows(context, bands * DDOF_ROWS_PER_CHUNK, band_rows, &p);
    report->seconds_rows = ddof_seconds() - t0;
    if (r->progress)
        r->progress(r->progress_user, 1.0f);
    return DDOF_OK;
}
