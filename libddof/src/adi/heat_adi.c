/* SPDX-License-Identifier: MIT */
/* heat_adi.c - the ADI driver for the float solvers: batches of lines, gathered, solved, scattered.
 *
 * A pass (all rows, or all columns) is cut into batches of DDOF_LANES consecutive lines. Each
 * batch first computes its links' beta from the CoC alone; lines without a conductive link are
 * not solved (a row is copied from source to destination; a column pass works in place, so an
 * idle column needs nothing). Active row batches are gathered into the solver's
 * [i][lane][channel] layout, solved, and scattered back; a full block of columns is already in
 * that layout in the image and is solved where it lies. Batches run on the context's threads,
 * each thread with its own scratch, so no two threads ever touch the same line.
 * For the layers a request may carry a heat capacity per pixel: the input is then read as 0
 * where it is 0, and runs that hold no heat keep their values (see save_singular). */
#include "adi.h"

#include "line_gather.h"
#include "solvers/solver.h"

#include <float.h>
#include <math.h>
#include <string.h>

#define L DDOF_LANES

/* The heat kernel's link (line_gather.h): k * min(|d_a|, |d_b|)^2, a negative, near-field CoC
 * conducting by its size, flushed to 0 below FLT_MIN so that "no conductive link" has one
 * meaning everywhere, and 0 where the smaller |CoC| is below the in-focus threshold, i.e. where
 * one of the two pixels counts as in focus (ddof_conducting_coc). */
static inline float link_beta(float scale, float in_focus_px, float coc_a, float coc_b)
{
    return link_conductance(scale, in_focus_px, coc_a, coc_b, 0);
}

static const solver_ops *float_solver(ddof_solver solver)
{
    switch (solver) {
    case DDOF_SOLVER_CYCLIC_REDUCTION: return &ddof_solver_cr;
    case DDOF_SOLVER_PCR: return &ddof_solver_pcr;
    case DDOF_SOLVER_JACOBI: return &ddof_solver_jacobi;
    default: return &ddof_solver_thomas;
    }
}

/* Per-thread working memory and tallies. */
typedef struct thread_state {
    float *x;        /* [n_max][L][C] */
    float *beta;     /* [n_max][L]    */
    float *gamma;    /* [n_max][L]: all 1 (plain diffusion) or gathered per batch */
    float *scratch;  /* the solver's  */
    float *saved;    /* [n_max][L][C] values of singular runs (layers only) */
    unsigned char *singular; /* [n_max][L] (layers only) */
    uint64_t lines_solved;
    float max_coc;
    float gamma_min;  /* smallest positive heat capacity the row pass read (layers) */
} thread_state;

typedef struct pass_job {
    const adi_request *request;
    const solver_ops *solver;
    const float *src;
    size_t src_stride;
    float *dst;
    size_t dst_stride;
    float beta_scale;
    thread_state *threads;
    uint32_t first_block; /* columns: the width of block 0 (L, or less to align the rest) */
    line_running running; /* Thomas's precision: by batch (rows), for the pass (columns) */
} pass_job;

/* A run of pixels joined by links whose heat capacities are all 0 is singular: nothing in it
 * holds heat, and any constant solves it. Such a run keeps the values it had before the pass
 * (0 from the input, which is masked; what an earlier pass gave it otherwise). The solvers only
 * promise finite values there, so the driver puts the values back. Marks the runs per lane and
 * saves their values; returns whether there is any. */
static int save_singular(const float *beta, const float *gamma, const float *x, size_t x_stride,
                         uint32_t n, uint32_t C, unsigned char *singular, float *saved)
{
    const int any = mark_singular_runs(beta, gamma, n, singular);
    if (any)
        for (uint32_t i = 0; i < n; i++)
            for (uint32_t l = 0; l < L; l++)
                if (singular[(size_t)i * L + l])
                    memcpy(saved + ((size_t)i * L + l) * C, x + (size_t)i * x_stride + l * C,
                           C * sizeof(float));
    return any;
}

static void restore_singular(float *x, size_t x_stride, uint32_t n, uint32_t C,
                             const unsigned char *singular, const float *saved)
{
    for (uint32_t i = 0; i < n; i++)
        for (uint32_t l = 0; l < L; l++)
            if (singular[(size_t)i * L + l])
                memcpy(x + (size_t)i * x_stride + l * C, saved + ((size_t)i * L + l) * C,
                       C * sizeof(float));
}

/* Solves a batch; with heat capacities, singular runs keep their values. */
static void solve_batch(const pass_job *job, thread_state *ts, const line_batch *batch)
{
    const size_t xs = batch_x_stride(batch);
    const int singular = job->request->gamma &&
                         save_singular(batch->beta, batch->gamma, batch->x, xs, batch->n,
                                       batch->channels, ts->singular, ts->saved);
    job->solver->solve(batch);
    if (singular)
        restore_singular(batch->x, xs, batch->n, batch->channels, ts->singular, ts->saved);
}

/* ---- rows: lanes are neighbouring rows, unknowns run along x ---------------------------- */

/* The smallest positive value of count floats (FLT_MAX when none): element-wise per lane so
 * that it vectorises. */
static DDOF_ALWAYS_INLINE float smallest_positive(const float *restrict v, size_t count)
{
    float lane_min[L];
    for (uint32_t l = 0; l < L; l++)
        lane_min[l] = FLT_MAX;
    for (size_t i = 0; i + L <= count; i += L)
        for (uint32_t l = 0; l < L; l++)
            lane_min[l] = ddof_minf(lane_min[l], ddof_positive_or_lifted(v[i + l]));
    float m = FLT_MAX;
    for (uint32_t l = 0; l < L; l++)
        m = ddof_minf(m, lane_min[l]);
    return m;
}

DDOF_MULTIVERSION static void row_batch(void *user, uint32_t batch_index, uint32_t thread_index)
{
    const pass_job *job = user;
    const adi_request *r = job->request;
    thread_state *ts = &job->threads[thread_index];
    const uint32_t n = r->width, C = r->channels, y0 = batch_index * L;
    const uint32_t lanes = r->height - y0 < L ? r->height - y0 : L;
    int active[L] = {0};
    int any_active = 0;

    /* Links element by element across the lanes (contiguous writes, in-order reads). A
     * uniform CoC is read from a one-pixel "image" with stride 0. */
    const uint32_t cc = r->coc ? r->coc_channels : 0;
    const float in_focus = r->coc ? r->in_focus_px : 0.0f;
    const float *coc[L];
    for (uint32_t l = 0; l < L; l++)
        coc[l] = r->coc ? r->coc + (size_t)(y0 + (l < lanes ? l : 0)) * r->coc_stride
                        : &r->uniform_coc;
    float max_coc[L] = {0};
    if (cc == 1) {
        /* A one-channel CoC: its rows are first moved into the [i][lane] order the links are
         * stored in, by the colour's chunked gather (x is free until the colour's gather), so
         * that the links' loop reads and writes whole vectors instead of sixteen scalars. */
        const float *coc_rows[L];
        for (uint32_t l = 0; l < L; l++)
            coc_rows[l] = l < lanes ? coc[l] : NULL; /* padding lanes: CoC 0, no links */
        rows_in(ts->x, coc_rows, n, 1);
        links_from_gathered(ts->beta, ts->x, n, job->beta_scale, in_focus, 0, active, max_coc);
    } else {
        for (uint32_t i = 0; i < n; i++) {
            float *beta = ts->beta + (size_t)i * L;
            for (uint32_t l = 0; l < L; l++) {
                const float here = coc[l][(size_t)i * cc];
                const float next = i + 1 < n ? coc[l][(size_t)(i + 1) * cc] : 0.0f;
                beta[l] = l < lanes ? link_beta(job->beta_scale, in_focus, here, next) : 0.0f;
                active[l] |= beta[l] > 0.0f;
                max_coc[l] = ddof_maxf(max_coc[l], fabsf(here));
            }
        }
    }
    if (r->gamma) {
        gather_row_gamma(ts->gamma, r, y0, lanes, n);
        ts->gamma_min = ddof_minf(ts->gamma_min, smallest_positive(ts->gamma, (size_t)n * L));
    }
    for (uint32_t l = 0; l < lanes; l++) {
        ts->max_coc = ddof_maxf(ts->max_coc, max_coc[l]);
        any_active |= active[l];
    }

    const size_t row_floats = (size_t)n * C;
    for (uint32_t l = 0; l < lanes; l++) {
        const float *src = job->src + (size_t)(y0 + l) * job->src_stride;
        float *dst = job->dst + (size_t)(y0 + l) * job->dst_stride;
        if (active[l])
            continue;
        if (r->gamma && src == r->color) /* no links: x where it has capacity, else 0 */
            copy_masked(dst, src, ts->gamma + l, n, C);
        else if (src != dst)
            memcpy(dst, src, row_floats * sizeof(float));
    }
    if (!any_active)
        return;

    const float *src_rows[L];
    float *dst_rows[L];
    for (uint32_t l = 0; l < L; l++) {
        const int used = l < lanes && active[l];
        src_rows[l] = used ? job->src + (size_t)(y0 + l) * job->src_stride : NULL;
        dst_rows[l] = used ? job->dst + (size_t)(y0 + l) * job->dst_stride : NULL;
        ts->lines_solved += (uint64_t)used;
    }
    rows_in(ts->x, src_rows, n, C);
    if (r->gamma && job->src == r->color) /* the input: values without capacity are unread */
        mask_batch(ts->x, ts->gamma, n, L * C, C);
    line_batch batch = {n, C, ts->beta, ts->gamma, ts->x, ts->scratch, r->jacobi_iterations, 0,
                        job->running};
    solve_batch(job, ts, &batch);
    rows_out(dst_rows, ts->x, n, C);
}

/* ---- columns: lanes are neighbouring columns, unknowns run along y; in place on dst ------ */

DDOF_MULTIVERSION static void column_batch(void *user, uint32_t batch_index, uint32_t thread_index)
{
    const pass_job *job = user;
    const adi_request *r = job->request;
    thread_state *ts = &job->threads[thread_index];
    const uint32_t n = r->height, C = r->channels;
    const uint32_t x0 = batch_index ? job->first_block + (batch_index - 1) * L : 0;
    const uint32_t width = batch_index ? L : job->first_block;
    const uint32_t lanes = r->width - x0 < width ? r->width - x0 : width;
    const uint32_t cc = r->coc ? r->coc_channels : 0;
    const size_t coc_stride = r->coc ? r->coc_stride : 0;
    const float in_focus = r->coc ? r->in_focus_px : 0.0f;
    int active[L] = {0};
    int any_active = 0;

    /* A full block of a one-channel CoC (the common case) reads 16 neighbouring floats a row:
     * a loop the compiler vectorises, with the rows asked for ahead (each is in a page of its
     * own, which the prefetchers do not follow; perf showed the scalar loop waiting on them). */
    if (r->coc && cc == 1 && lanes == L) {
        enum { ahead = 16 };
        for (uint32_t i = 0; i + 1 < n; i++) {
            const float *restrict coc = r->coc + (size_t)i * coc_stride + x0;
            const float *restrict below = coc + coc_stride;
            if (i + 1 + ahead < n)
                DDOF_PREFETCH(below + (size_t)ahead * coc_stride, 0);
            float *restrict beta = ts->beta + (size_t)i * L;
            for (uint32_t l = 0; l < L; l++) {
                beta[l] = link_beta(job->beta_scale, in_focus, coc[l], below[l]);
                active[l] |= beta[l] > 0.0f;
            }
        }
    } else {
        for (uint32_t i = 0; i + 1 < n; i++) {
            const float *coc = r->coc ? r->coc + (size_t)i * coc_stride + (size_t)x0 * cc
                                      : &r->uniform_coc;
            const float *below = coc + coc_stride;
            float *beta = ts->beta + (size_t)i * L;
            for (uint32_t l = 0; l < L; l++) {
                beta[l] = l < lanes ? link_beta(job->beta_scale, in_focus, coc[l * cc],
                                                below[l * cc])
                                    : 0.0f;
                active[l] |= beta[l] > 0.0f;
            }
        }
    }
    for (uint32_t l = 0; l < L; l++) {
        ts->beta[(size_t)(n - 1) * L + l] = 0.0f;
        any_active |= active[l];
    }
    /* The column pass reads the row pass's output, which is already masked and finite, so
     * only the heat capacities are needed here; idle columns were settled by the row pass. */
    if (!any_active)
        return;
    if (r->gamma)
        gather_column_gamma(ts->gamma, r, x0, lanes, n);

    line_batch batch = {n, C, ts->beta, ts->gamma, ts->x, ts->scratch, r->jacobi_iterations, 0,
                        job->running};
    if (lanes == L) {
        /* A full block is solved where it lies: element i is row i of the image, and idle lanes
         * come back bit-identical (beta 0 leaves x exact). The column pass works in place, so
         * src is dst. */
        batch.x = job->dst + (size_t)x0 * C;
        batch.x_stride = job->dst_stride;
        solve_batch(job, ts, &batch);
    } else {
        /* The image's last, narrower block: through the scratch, padded with idle lanes. */
        const size_t lane_floats = (size_t)lanes * C;
        for (uint32_t i = 0; i < n; i++) {
            float *x = ts->x + (size_t)i * L * C;
            memcpy(x, job->src + (size_t)i * job->src_stride + (size_t)x0 * C,
                   lane_floats * sizeof(float));
            memset(x + lane_floats, 0, ((size_t)L * C - lane_floats) * sizeof(float));
        }
        solve_batch(job, ts, &batch);
        for (uint32_t i = 0; i < n; i++)
            memcpy(job->dst + (size_t)i * job->dst_stride + (size_t)x0 * C,
                   ts->x + (size_t)i * L * C, lane_floats * sizeof(float));
    }
    for (uint32_t l = 0; l < lanes; l++)
        ts->lines_solved += (uint64_t)active[l];
}

/* ---- the run ------------------------------------------------------------------------------ */

/* The width of the first column block: fewer than L columns when that puts every other block's
 * rows on 64-byte boundaries. A block solved in place reads and writes L * C floats a row;
 * unaligned (malloc gives 16-byte alignment) each of its vector loads and stores spans two
 * cache lines and each row touches one line more (at 1080p the column pass took 5.7 ms with
 * malloc's offset, 3.6 ms aligned). */
static uint32_t first_column_block(const adi_request *r)
{
    const size_t pixel_bytes = (size_t)r->channels * sizeof(float);
    const uintptr_t address = (uintptr_t)r->out;
    if ((r->out_stride * sizeof(float)) % 64 || r->width <= L)
        return L; /* rows differently aligned, or one block anyway */
    for (uint32_t shift = 0; shift < L; shift++)
        if ((address + shift * pixel_bytes) % 64 == 0)
            return shift ? shift : L;
    return L;
}

/* Thomas's precision for a whole column pass, from what the row pass saw of the image: the
 * largest |CoC| bounds every column link's beta, and the smallest positive heat capacity is
 * the image's. Float where the memory is short everywhere, as a row batch decides for itself
 * (the row batches are the same lines in every call; the column blocks are not). */
static line_running column_running(const thread_state *threads, uint32_t count, float scale)
{
    float max_coc = 0.0f, gamma_min = FLT_MAX;
    for (uint32_t t = 0; t < count; t++) {
        max_coc = ddof_maxf(max_coc, threads[t].max_coc);
        gamma_min = ddof_minf(gamma_min, threads[t].gamma_min);
    }
    const float beta_max = scale * max_coc * max_coc;
    const float gamma = gamma_min < FLT_MAX ? gamma_min : 1.0f; /* none read: plain diffusion */
    return ddof_float_running_suffices(beta_max, gamma) ? LINE_RUNNING_FLOAT
                                                        : LINE_RUNNING_DOUBLE;
}

static uint64_t total_solved(const thread_state *threads, uint32_t count)
{
    uint64_t sum = 0;
    for (uint32_t t = 0; t < count; t++)
        sum += threads[t].lines_solved;
    return sum;
}

ddof_status ddof_adi_run(ddof_context *context, const adi_request *r, adi_report *report)
{
    const solver_ops *solver = float_solver(r->solver);
    const uint32_t C = r->channels;
    const uint32_t n_max = r->width > r->height ? r->width : r->height;
    const uint32_t thread_count = thread_pool_threads(context->pool);

    const size_t x_floats = align16((size_t)n_max * L * C);
    const size_t coef_floats = align16((size_t)n_max * L);
    const size_t scratch_floats = align16(solver->scratch_floats(n_max, C));
    /* Layers (heat capacities) also keep singular runs' values and a mark per element. */
    const size_t saved_floats = r->gamma ? x_floats : 0;
    const size_t mark_floats = r->gamma ? align16(((size_t)n_max * L + 3) / 4) : 0;
    const size_t per_thread = x_floats + 2 * coef_floats + scratch_floats + saved_floats +
                              mark_floats;
    if (per_thread > SIZE_MAX / sizeof(float) / thread_count)
        return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY, "scratch size overflows");
    float *memory;
    thread_state *threads = solver_scratch(context, thread_count * sizeof(thread_state),
                                           per_thread * thread_count, "solver scratch", &memory);
    if (!threads)
        return DDOF_ERROR_OUT_OF_MEMORY;
    for (uint32_t t = 0; t < thread_count; t++) {
        float *base = memory + per_thread * t;
        float *after_scratch = base + x_floats + 2 * coef_floats + scratch_floats;
        threads[t] = (thread_state){.x = base, .beta = base + x_floats,
                                    .gamma = base + x_floats + coef_floats,
                                    .scratch = base + x_floats + 2 * coef_floats,
                                    .saved = after_scratch, .gamma_min = FLT_MAX,
                                    .singular = (unsigned char *)(after_scratch + saved_floats)};
        if (!r->gamma) /* plain diffusion; layers gather theirs per batch */
            for (size_t i = 0; i < (size_t)n_max * L; i++)
                threads[t].gamma[i] = 1.0f;
    }

    *report = (adi_report){.threads = thread_count};
    const float row_scale = r->beta_scale / (float)r->substeps;
    const float column_scale = row_scale * r->pixel_aspect * r->pixel_aspect;
    const uint32_t row_batches = (r->height + L - 1) / L;
    const uint32_t aligned_block = first_column_block(r);
    const uint32_t first_block = aligned_block < r->width ? aligned_block : r->width;
    const uint32_t column_batches = 1 + (r->width - first_block + L - 1) / L;
    pass_progress_state progress = {r, 0, 2 * r->substeps};
    thread_progress_fn progress_fn = r->progress ? pass_progress : NULL;
    ddof_status status = DDOF_OK;

    for (uint32_t step = 0; step < r->substeps; step++) {
        double t0 = ddof_seconds();
        uint64_t solved_before = total_solved(threads, thread_count);
        pass_job rows = {r, solver, step == 0 ? r->color : r->out,
                         step == 0 ? r->color_stride : r->out_stride,
                         r->out, r->out_stride, row_scale, threads, L,
                         LINE_RUNNING_BY_BATCH};
        progress.pass = 2 * step;
        if (thread_pool_run(context->pool, row_batches, row_batch, &rows, progress_fn,
                            &progress)) {
            status = DDOF_ERROR_CANCELLED;
            break;
        }
        uint64_t rows_solved = total_solved(threads, thread_count) - solved_before;
        double t1 = ddof_seconds();
        pass_job columns = {r, solver, r->out, r->out_stride, r->out, r->out_stride,
                            column_scale, threads, first_block,
                            column_running(threads, thread_count, column_scale)};
        progress.pass = 2 * step + 1;
        if (thread_pool_run(context->pool, column_batches, column_batch, &columns, progress_fn,
                            &progress)) {
            status = DDOF_ERROR_CANCELLED;
            break;
        }
        uint64_t columns_solved =
            total_solved(threads, thread_count) - solved_before - rows_solved;
        double t2 = ddof_seconds();
        report->seconds_rows += t1 - t0;
        report->seconds_columns += t2 - t1;
        report->lines_solved += rows_solved + columns_solved;
        report->lines_skipped += (uint64_t)r->height + r->width - rows_solved - columns_solved;
        report->substeps_run++;
        /* The CoC is the same for every substep: if nothing conducted, nothing ever will. */
        if (rows_solved + columns_solved == 0) {
            report->substeps_run = 0;
            break;
        }
    }
    for (uint32_t t = 0; t < thread_count; t++)
        report->max_coc = ddof_maxf(report->max_coc, threads[t].max_coc);
    if (status == DDOF_ERROR_CANCELLED) {
        /* Rows the first pass never reached hold whatever the caller's buffer held; give back
         * the input instead, so a cancelled frame is still a valid image. */
        if (r->out != r->color)
            for (uint32_t y = 0; y < r->height; y++)
                memcpy(r->out + (size_t)y * r->out_stride, r->color + (size_t)y * r->color_stride,
                       (size_t)r->width * C * sizeof(float));
        ddof_fail(context, status, "cancelled by the progress callback");
    }
    else if (r->progress)
        r->progress(r->progress_user, 1.0f);
    return status;
}
