/* SPDX-License-Identifier: MIT */
/* lens_adi.c - the disc kernel's driver (disc_kernel.h) for the CPU.
 *
 * Per component c of the kernel: a row pass runs the component's chain of steps on each batch of
 * DDOF_LANES rows and writes the result T_c into a complex image (real and imaginary planes,
 * rows padded to whole batches of columns, so every column block is full); a column pass then
 * runs the chain on each block of T_c and folds the result Z_c into the output as a change:
 * out = x + sum_c Re(mix_c (Z_c - x)). A pixel without links is left exactly as it is by every
 * step, so Z_c - x is exactly 0 there and it comes out bit for bit as it went in (a weighted sum
 * of the Z_c themselves would round it). One complex image is alive at a time (2 x the colour).
 * Heat capacities (the layers) work as in heat_adi.c: the input is read as 0 where gamma is 0,
 * and a run that holds no heat keeps the values it had.
 * The disc's edge rings (its real part dips below 0 just outside the rim, by up to ~10% of its
 * height, and overshoots a little inside): the result is clamped to the range of the input it
 * read, per channel, as the heat kernel's convex combinations are by construction. Next to an
 * HDR highlight the ring would otherwise be negative light; against any truth within that
 * range the clamp only ever reduces the error, and it keeps alpha within [0, 1].
 */
#include "adi.h"

#include "disc/disc_kernel.h"
#include "solvers/lens_solver.h"
#include "line_gather.h"

#include <math.h>
#include <string.h>

#define L DDOF_LANES

typedef struct lens_thread {
    float *x;                /* [n][L][C] the gathered input of a row batch        */
    float *acc_re, *acc_im;  /* [n][L][C] the chain's result                      */
    float *b, *gamma;        /* [n][L] real link conductance, heat capacity       */
    float *solver;           /* ddof_lens_solver_scratch_floats                   */
    unsigned char *singular; /* [n][L]                                            */
    uint64_t lines_solved;
    float max_coc;
    float lo[4], hi[4];      /* the range of the input it read, per channel       */
} lens_thread;

typedef struct lens_job {
    const adi_request *r;
    const disc_kernel *k;
    uint32_t component;
    const float *src;     /* the input colour (a copy when diffusing in place) */
    size_t src_stride;
    float *t_re, *t_im;   /* the component's complex image                      */
    size_t t_stride;      /* floats per row of it: whole batches of columns      */
    float aspect2;        /* column links are scaled by pixel_aspect^2           */
    lens_thread *threads;
    float lo[4], hi[4];   /* the input's range per channel: the output is kept in it */
} lens_job;

/* The real conductance of a link: the smaller |CoC| squared, or 0 below the solver's floor. */
static inline float lens_link(float coc_a, float coc_b, float scale, float in_focus_px)
{
    return link_conductance(scale, in_focus_px, coc_a, coc_b, 1);
}

/* The in-focus threshold applies to CoC images only (a uniform CoC is a layer's own fill). */
static inline float in_focus_of(const adi_request *r)
{
    return r->coc ? r->in_focus_px : 0.0f;
}

/* Runs the job's component's chain of steps on the batch: y = steps(x) in acc; runs that hold
 * no heat keep x. x_im NULL: a real input. */
static void solve_chain(const lens_job *job, lens_thread *ts, uint32_t n, const float *x_re,
                        const float *x_im, size_t x_stride)
{
    const disc_kernel *k = job->k;
    const uint32_t c = job->component, C = job->r->channels;
    complex_batch batch = {n, C, ts->b, ts->gamma, x_re, x_im, x_stride, ts->acc_re,
                           ts->acc_im, ts->solver};
    for (uint32_t m = 0; m < k->steps; m++) {
        ddof_lens_solve(&batch, k->kappa[c][m][0], k->kappa[c][m][1]);
        batch.x_re = ts->acc_re; /* the next step solves in place on this one's result */
        batch.x_im = ts->acc_im;
        batch.x_stride = (size_t)L * C;
    }
    if (job->r->gamma && mark_singular_runs(ts->b, ts->gamma, n, ts->singular))
        for (uint32_t i = 0; i < n; i++)
            for (uint32_t l = 0; l < L; l++)
                if (ts->singular[(size_t)i * L + l])
                    for (uint32_t ch = 0; ch < C; ch++) {
                        const size_t at = ((size_t)i * L + l) * C + ch;
                        ts->acc_re[at] = x_re[(size_t)i * x_stride + l * C + ch];
                        ts->acc_im[at] = x_im ? x_im[(size_t)i * x_stride + l * C + ch] : 0.0f;
                    }
}

/* ---- rows: the input (real) into the component's complex image -------------------------- */

DDOF_MULTIVERSION static void lens_row_batch(void *user, uint32_t batch_index,
                                             uint32_t thread_index)
{
    const lens_job *job = user;
    const adi_request *r = job->r;
    lens_thread *ts = &job->threads[thread_index];
    const uint32_t n = r->width, C = r->channels, y0 = batch_index * L;
    const uint32_t lanes = r->height - y0 < L ? r->height - y0 : L;
    int active[L] = {0}, any_active = 0;
    float max_coc = 0.0f;
    const float in_focus = in_focus_of(r);

    if (r->coc && r->coc_channels == 1) {
        /* A one-channel CoC: its rows moved into [i][lane] order by the colour's chunked
         * gather (x is free until the colour's), so the links' loop runs on whole vectors. */
        const float *coc_rows[L];
        for (uint32_t l = 0; l < L; l++) /* padding lanes: CoC 0, no links */
            coc_rows[l] = l < lanes ? r->coc + (size_t)(y0 + l) * r->coc_stride : NULL;
        rows_in(ts->x, coc_rows, n, 1);
        float lane_max[L] = {0};
        links_from_gathered(ts->b, ts->x, n, 1.0f, in_focus, 1, active, lane_max);
        for (uint32_t l = 0; l < L; l++) {
            any_active |= active[l];
            max_coc = ddof_maxf(max_coc, lane_max[l]);
        }
    } else {
        for (uint32_t l = 0; l < L; l++) {
            const uint32_t y = y0 + (l < lanes ? l : 0);
            for (uint32_t i = 0; i < n; i++) {
                const float here = adi_request_coc(r, i, y);
                const float b = l < lanes && i + 1 < n
                                    ? lens_link(here, adi_request_coc(r, i + 1, y), 1.0f, in_focus)
                                    : 0.0f;
                ts->b[(size_t)i * L + l] = b;
                active[l] |= b > 0.0f;
                if (l < lanes)
                    max_coc = ddof_maxf(max_coc, fabsf(here));
            }
            any_active |= active[l];
        }
    }
    ts->max_coc = ddof_maxf(ts->max_coc, max_coc);
    if (r->gamma)
        gather_row_gamma(ts->gamma, r, y0, lanes, n);

    const float *src_rows[L];
    for (uint32_t l = 0; l < L; l++)
        src_rows[l] = l < lanes ? job->src + (size_t)(y0 + l) * job->src_stride : NULL;
    rows_in(ts->x, src_rows, n, C);
    if (r->gamma)
        mask_batch(ts->x, ts->gamma, n, L * C, C);
    if (job->component == 0)
        for (uint32_t i = 0; i < n; i++)
            for (uint32_t l = 0; l < lanes; l++)
                for (uint32_t c = 0; c < C; c++) {
                    const float v = ts->x[((size_t)i * L + l) * C + c];
                    ts->lo[c] = ddof_minf(ts->lo[c], v);
                    ts->hi[c] = ddof_maxf(ts->hi[c], v);
                }
    if (any_active)
        solve_chain(job, ts, n, ts->x, NULL, (size_t)L * C);

    /* Into the complex image by the chunked scatter of the heat driver (perf: a lane-by-lane
     * loop here measured a fifth of the row pass): solved lanes take the chain's result, the
     * others their input and 0. */
    float *re_solved[L], *im_solved[L], *re_idle[L];
    for (uint32_t l = 0; l < L; l++) {
        float *tr = l < lanes ? job->t_re + (size_t)(y0 + l) * job->t_stride : NULL;
        float *ti = l < lanes ? job->t_im + (size_t)(y0 + l) * job->t_stride : NULL;
        re_solved[l] = active[l] ? tr : NULL;
        im_solved[l] = active[l] ? ti : NULL;
        re_idle[l] = active[l] ? NULL : tr;
        if (ti && !active[l])
            memset(ti, 0, (size_t)n * C * sizeof(float));
        ts->lines_solved += (uint64_t)active[l] * job->k->steps;
    }
    if (any_active) {
        rows_out(re_solved, ts->acc_re, n, C);
        rows_out(im_solved, ts->acc_im, n, C);
    }
    rows_out(re_idle, ts->x, n, C);
}

/* ---- columns: in place on the complex image, then folded into the output ----------------- */

/* One row of a full block folded into the output (the loop below for a full block without heat
 * capacities): each lane's choice of chain result or row-pass value is a product with 1 or 0,
 * exact for finite values, so the loop runs over whole vectors. Both sides must be finite: a
 * block whose chain did not run hands in the row pass's values for both (its chain results
 * are whatever the scratch held). */
static DDOF_ALWAYS_INLINE void fold_row(float *restrict out, const float *restrict src,
                                        const float *restrict zr, const float *restrict zi,
                                        const float *restrict ar, const float *restrict ai,
                                        const float *restrict solved, const float *restrict lo,
                                        const float *restrict hi, uint32_t count, float mr,
                                        float mi, const int first, const int last)
{
    for (uint32_t k = 0; k < count; k++) {
        const float x = src[k];
        const float dr = solved[k] * ar[k] + (1.0f - solved[k]) * zr[k] - x;
        const float di = solved[k] * ai[k] + (1.0f - solved[k]) * zi[k];
        const float change = mr * dr - mi * di;
        const float v = first ? x + change : out[k] + change;
        out[k] = last ? ddof_minf(ddof_maxf(v, lo[k]), hi[k]) : v;
    }
}

static DDOF_ALWAYS_INLINE void fold_full_block(const lens_job *job, const lens_thread *ts,
                                               uint32_t x0, const int *active, int any_active,
                                               float mr, float mi, int first, int last)
{
    const adi_request *r = job->r;
    const uint32_t n = r->height, C = r->channels, count = L * C;
    enum { ahead = 8 };
    float solved[L * 4], lo[L * 4], hi[L * 4]; /* per value: its lane's and channel's */
    for (uint32_t k = 0; k < count; k++) {
        solved[k] = (float)active[k / C];
        lo[k] = job->lo[k % C];
        hi[k] = job->hi[k % C];
    }
    const float *t_re = job->t_re + (size_t)x0 * C, *t_im = job->t_im + (size_t)x0 * C;
    for (uint32_t i = 0; i < n; i++) {
        const float *src = job->src + (size_t)i * job->src_stride + (size_t)x0 * C;
        float *out = r->out + (size_t)i * r->out_stride + (size_t)x0 * C;
        if (i + ahead < n)
            for (uint32_t k = 0; k < count; k += 16) {
                DDOF_PREFETCH(src + (size_t)ahead * job->src_stride + k, 0);
                DDOF_PREFETCH(out + (size_t)ahead * r->out_stride + k, 1);
            }
        const float *zr = t_re + (size_t)i * job->t_stride, *zi = t_im + (size_t)i * job->t_stride;
        const float *ar = any_active ? ts->acc_re + (size_t)i * count : zr;
        const float *ai = any_active ? ts->acc_im + (size_t)i * count : zi;
        /* Four instances, so that neither choice is made per value. */
        if (first && last)
            fold_row(out, src, zr, zi, ar, ai, solved, lo, hi, count, mr, mi, 1, 1);
        else if (first)
            fold_row(out, src, zr, zi, ar, ai, solved, lo, hi, count, mr, mi, 1, 0);
        else if (last)
            fold_row(out, src, zr, zi, ar, ai, solved, lo, hi, count, mr, mi, 0, 1);
        else
            fold_row(out, src, zr, zi, ar, ai, solved, lo, hi, count, mr, mi, 0, 0);
    }
}

DDOF_MULTIVERSION static void lens_column_batch(void *user, uint32_t batch_index,
                                                uint32_t thread_index)
{
    const lens_job *job = user;
    const adi_request *r = job->r;
    lens_thread *ts = &job->threads[thread_index];
    const uint32_t n = r->height, C = r->channels, x0 = batch_index * L;
    const uint32_t lanes = r->width - x0 < L ? r->width - x0 : L;
    int active[L] = {0}, any_active = 0;
    const float in_focus = in_focus_of(r);

    /* Rows of the images are pages of their own, which the hardware prefetchers do not
     * follow down a column block (perf: these loops waited on the CoC, colour and output
     * loads); ask for them this many rows ahead. */
    enum { ahead = 8 };
    if (r->coc && r->coc_channels == 1 && lanes == L) {
        /* A full block of one-channel CoC: 16 neighbouring floats a row, vectorised. */
        for (uint32_t i = 0; i + 1 < n; i++) {
            const float *restrict coc = r->coc + (size_t)i * r->coc_stride + x0;
            const float *restrict below = coc + r->coc_stride;
            if (i + 1 + 2 * ahead < n) {
                DDOF_PREFETCH(below + (size_t)2 * ahead * r->coc_stride, 0);
                DDOF_PREFETCH(below + (size_t)2 * ahead * r->coc_stride + L - 1, 0);
            }
            float *restrict b = ts->b + (size_t)i * L;
            for (uint32_t l = 0; l < L; l++) {
                b[l] = lens_link(coc[l], below[l], job->aspect2, in_focus);
                active[l] |= b[l] > 0.0f;
            }
        }
        for (uint32_t l = 0; l < L; l++)
            ts->b[(size_t)(n - 1) * L + l] = 0.0f;
    } else {
        for (uint32_t i = 0; i < n; i++)
            for (uint32_t l = 0; l < L; l++) {
                const float b = l < lanes && i + 1 < n
                                    ? lens_link(adi_request_coc(r, x0 + l, i),
                                                adi_request_coc(r, x0 + l, i + 1), job->aspect2,
                                                in_focus)
                                    : 0.0f;
                ts->b[(size_t)i * L + l] = b;
                active[l] |= b > 0.0f;
            }
    }
    for (uint32_t l = 0; l < lanes; l++)
        any_active |= active[l];
    if (r->gamma)
        gather_column_gamma(ts->gamma, r, x0, lanes, n);

    const float *t_re = job->t_re + (size_t)x0 * C, *t_im = job->t_im + (size_t)x0 * C;
    if (any_active)
        solve_chain(job, ts, n, t_re, t_im, job->t_stride);

    const float mr = job->k->mix[job->component][0], mi = job->k->mix[job->component][1];
    const int first = job->component == 0, last = job->component + 1 == job->k->components;
    if (lanes == L && !r->gamma) {
        fold_full_block(job, ts, x0, active, any_active, mr, mi, first, last);
        for (uint32_t l = 0; l < L; l++)
            ts->lines_solved += (uint64_t)active[l] * job->k->steps;
        return;
    }
    for (uint32_t i = 0; i < n; i++) {
        if (i + ahead < n) {
            const size_t row = (size_t)(i + ahead);
            const float *src_ahead = job->src + row * job->src_stride + (size_t)x0 * C;
            float *out_ahead = r->out + row * r->out_stride + (size_t)x0 * C;
            for (uint32_t k = 0; k < lanes * C; k += 16) {
                DDOF_PREFETCH(src_ahead + k, 0);
                DDOF_PREFETCH(out_ahead + k, 1);
            }
        }
        const float *src = job->src + (size_t)i * job->src_stride + (size_t)x0 * C;
        const float *g = r->gamma ? r->gamma + (size_t)i * r->gamma_stride +
                                        (size_t)x0 * r->gamma_channels
                                  : NULL;
        float *out = r->out + (size_t)i * r->out_stride + (size_t)x0 * C;
        const float *zr = t_re + (size_t)i * job->t_stride, *zi = t_im + (size_t)i * job->t_stride;
        const float *ar = ts->acc_re + (size_t)i * L * C, *ai = ts->acc_im + (size_t)i * L * C;
        for (uint32_t l = 0; l < lanes; l++) {
            /* The input as the row pass read it: 0 where there is no heat capacity. */
            const int masked = g && !(g[(size_t)l * r->gamma_channels] > 0.0f);
            for (uint32_t c = 0; c < C; c++) {
                const uint32_t k = l * C + c;
                const float x = masked ? 0.0f : src[k];
                const float dr = (active[l] ? ar[k] : zr[k]) - x;
                const float di = active[l] ? ai[k] : zi[k];
                const float change = mr * dr - mi * di;
                const float v = first ? x + change : out[k] + change;
                out[k] = last ? ddof_minf(ddof_maxf(v, job->lo[c]), job->hi[c]) : v;
            }
        }
    }
    for (uint32_t l = 0; l < lanes; l++)
        ts->lines_solved += (uint64_t)active[l] * job->k->steps;
}

/* ---- the run ------------------------------------------------------------------------------ */

ddof_status ddof_lens_run(ddof_context *context, const adi_request *r, adi_report *report)
{
    const disc_kernel *k = r->disc;
    const uint32_t C = r->channels, W = r->width, H = r->height;
    const uint32_t n_max = W > H ? W : H;
    const uint32_t threads = thread_pool_threads(context->pool);
    const uint32_t column_batches = (W + L - 1) / L;
    const size_t t_stride = (size_t)column_batches * L * C;

    const size_t lane_floats = align16((size_t)n_max * L * C);
    const size_t coef_floats = align16((size_t)n_max * L);
    const size_t solver_floats = align16(ddof_lens_solver_scratch_floats(n_max, C));
    const size_t mark_floats = align16(((size_t)n_max * L + 3) / 4);
    const size_t per_thread = 3 * lane_floats + 2 * coef_floats + solver_floats + mark_floats;
    const size_t image_floats = align16(t_stride * H);
    const size_t copy_floats = r->out == r->color ? align16((size_t)W * C * H) : 0;
    if (per_thread > (SIZE_MAX / sizeof(float) - 2 * image_floats - copy_floats) / threads / 2)
        return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY, "scratch size overflows");
    float *memory;
    lens_thread *state = solver_scratch(context, threads * sizeof(lens_thread),
                                        per_thread * threads + 2 * image_floats + copy_floats,
                                        "disc-kernel scratch", &memory);
    if (!state)
        return DDOF_ERROR_OUT_OF_MEMORY;
    for (uint32_t t = 0; t < threads; t++) {
        float *base = memory + per_thread * t;
        float *after_coef = base + 3 * lane_floats + 2 * coef_floats;
        state[t] = (lens_thread){.x = base, .acc_re = base + lane_floats,
                                 .acc_im = base + 2 * lane_floats,
                                 .b = base + 3 * lane_floats,
                                 .gamma = base + 3 * lane_floats + coef_floats,
                                 .solver = after_coef,
                                 .singular = (unsigned char *)(after_coef + solver_floats)};
        for (uint32_t c = 0; c < 4; c++) {
            state[t].lo[c] = INFINITY;
            state[t].hi[c] = -INFINITY;
        }
        if (!r->gamma)
            for (size_t i = 0; i < (size_t)n_max * L; i++)
                state[t].gamma[i] = 1.0f;
    }
    memory += per_thread * threads;
    float *t_re = memory, *t_im = memory + image_floats;
    /* The padding columns of the complex image are solved with no links: keep them finite. */
    for (uint32_t y = 0; y < H; y++) {
        const size_t used = (size_t)W * C;
        memset(t_re + y * t_stride + used, 0, (t_stride - used) * sizeof(float));
        memset(t_im + y * t_stride + used, 0, (t_stride - used) * sizeof(float));
    }
    const float *src = r->color;
    size_t src_stride = r->color_stride;
    if (copy_floats) { /* every component reads the input; the first one writes over it */
        float *copy = memory + 2 * image_floats;
        for (uint32_t y = 0; y < H; y++)
            memcpy(copy + (size_t)y * W * C, r->color + (size_t)y * r->color_stride,
                   (size_t)W * C * sizeof(float));
        src = copy;
        src_stride = (size_t)W * C;
    }

    *report = (adi_report){.threads = threads};
    pass_progress_state progress = {r, 0, 2 * k->components};
    thread_progress_fn progress_fn = r->progress ? pass_progress : NULL;
    const uint32_t row_batches = (H + L - 1) / L;
    float range_lo[4] = {0}, range_hi[4] = {0};
    ddof_status status = DDOF_OK;
    for (uint32_t c = 0; c < k->components && status == DDOF_OK; c++) {
        lens_job job = {r, k, c, src, src_stride, t_re, t_im, t_stride,
                        r->pixel_aspect * r->pixel_aspect, state, {0}, {0}};
        const double t0 = ddof_seconds();
        progress.pass = 2 * c;
        if (thread_pool_run(context->pool, row_batches, lens_row_batch, &job, progress_fn,
                            &progress)) {
            status = DDOF_ERROR_CANCELLED;
            break;
        }
        if (c == 0) /* the input's range, which the output is clamped to */
            for (uint32_t ch = 0; ch < C; ch++) {
                range_lo[ch] = INFINITY;
                range_hi[ch] = -INFINITY;
                for (uint32_t t = 0; t < threads; t++) {
                    range_lo[ch] = ddof_minf(range_lo[ch], state[t].lo[ch]);
                    range_hi[ch] = ddof_maxf(range_hi[ch], state[t].hi[ch]);
                }
            }
        memcpy(job.lo, range_lo, sizeof range_lo);
        memcpy(job.hi, range_hi, sizeof range_hi);
        const double t1 = ddof_seconds();
        progress.pass = 2 * c + 1;
        if (thread_pool_run(context->pool, column_batches, lens_column_batch, &job, progress_fn,
                            &progress))
            status = DDOF_ERROR_CANCELLED;
        report->seconds_rows += t1 - t0;
        report->seconds_columns += ddof_seconds() - t1;
    }
    for (uint32_t t = 0; t < threads; t++) {
        report->lines_solved += state[t].lines_solved;
        report->max_coc = ddof_maxf(report->max_coc, state[t].max_coc);
    }
    report->lines_skipped =
        (uint64_t)(W + H) * k->components - report->lines_solved / k->steps;
    report->substeps_run = report->lines_solved ? 1 : 0;
    if (status == DDOF_ERROR_CANCELLED) {
        /* A cancelled frame is still a valid image: the input. */
        for (uint32_t y = 0; y < H; y++)
            memmove(r->out + (size_t)y * r->out_stride, src + (size_t)y * src_stride,
                    (size_t)W * C * sizeof(float));
        return ddof_fail(context, status, "cancelled by the progress callback");
    }
    if (r->progress)
        r->progress(r->progress_user, 1.0f);
    return DDOF_OK;
}
