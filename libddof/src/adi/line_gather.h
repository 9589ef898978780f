/* SPDX-License-Identifier: MIT */
/* line_gather.h - moving pixels between image lines and a solver batch's lanes, and the heat
 * capacities of the layers; shared by the heat driver (heat_adi.c) and the disc driver
 * (lens_adi.c). */
#ifndef DDOF_LINE_GATHER_H
#define DDOF_LINE_GATHER_H

#include "adi.h"
#include "solvers/solver.h"

#include <math.h>
#include <string.h>

#define L DDOF_LANES

/* Rounds a count of floats up so that every scratch array stays 64-byte aligned. */
static inline size_t align16(size_t floats)
{
    return (floats + 15) & ~(size_t)15;
}

/* A run's solver scratch: its threads' states (state_bytes) first, then `floats` floats, each
 * part 64-byte aligned. Returns the states, or NULL with the error recorded (`what` names the
 * scratch in it); *floats_start is where the floats begin. */
static inline void *solver_scratch(ddof_context *context, size_t state_bytes, size_t floats,
                                   const char *what, float **floats_start)
{
    const size_t state_floats = align16(state_bytes / sizeof(float) + 1);
    const size_t bytes = (state_floats + floats) * sizeof(float);
    float *memory = ddof_scratch_get(context, DDOF_SCRATCH_SOLVER, bytes);
    if (!memory) {
        ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY, "could not allocate %zu bytes of %s", bytes,
                  what);
        return NULL;
    }
    *floats_start = memory + state_floats;
    return memory;
}

/* One pass's progress (thread_pool's done / total) as the request's fraction of all passes. */
typedef struct pass_progress_state {
    const adi_request *request;
    uint32_t pass, passes;
} pass_progress_state;

static inline int pass_progress(void *user, uint32_t done, uint32_t total)
{
    const pass_progress_state *p = user;
    const float fraction = ((float)p->pass + (float)done / (float)total) / (float)p->passes;
    return p->request->progress(p->request->progress_user, fraction);
}

/* ---- links ------------------------------------------------------------------------------- */

/* The conductance of the link between two pixels: scale * min(|d_a|, |d_b|)^2, 0 below the
 * kernel's floor (FLT_MIN for the heat kernel, DDOF_LENS_MIN_LINK for the disc kernel: one
 * meaning of "no link" for its solver) and 0 where the smaller |CoC| is below the in-focus
 * threshold, i.e. where one of the two pixels counts as in focus. Each kernel multiplies in
 * its own order, which the GL shaders repeat (solvers/gl/line.glsl), so both sides agree bit for
 * bit. A product with 0 or 1 rather than a select: GCC does not if-convert a float select under
 * -ftrapping-math, and the links' loops would stay scalar. */
static inline float link_conductance(float scale, float in_focus_px, float coc_a, float coc_b,
                                     const int disc)
{
    const float m = ddof_minf(fabsf(coc_a), fabsf(coc_b));
    const float beta = disc ? (m * m) * scale : (scale * m) * m;
    const float least = disc ? DDOF_LENS_MIN_LINK : FLT_MIN;
    return beta * (float)((beta >= least) & (m >= in_focus_px));
}

/* The links of a row batch from its CoC gathered as coc[i][lane] (rows_in with one channel):
 * beta[i][lane] between elements i and i + 1 (0 past the last), which lanes conduct anywhere,
 * and each lane's largest |CoC|. Whole vectors: reading the sixteen rows element by element
 * would take sixteen scalar loads an element. */
static DDOF_ALWAYS_INLINE void links_from_gathered(float *restrict beta,
                                                   const float *restrict coc, uint32_t n,
                                                   float scale, float in_focus, const int disc,
                                                   int *active, float *max_coc)
{
    float conducts[L] = {0};
    for (uint32_t i = 0; i < n; i++) {
        const float *restrict here = coc + (size_t)i * L;
        float *restrict b = beta + (size_t)i * L;
        for (uint32_t l = 0; l < L; l++) {
            /* The last element's link reads its own CoC twice and is then cut to 0. */
            const float next = here[i + 1 < n ? L + l : l];
            b[l] = link_conductance(scale, in_focus, here[l], next, disc) * (float)(i + 1 < n);
            conducts[l] = ddof_maxf(conducts[l], b[l]);
            max_coc[l] = ddof_maxf(max_coc[l], fabsf(here[l]));
        }
    }
    for (uint32_t l = 0; l < L; l++)
        active[l] = conducts[l] > 0.0f;
}

/* ---- moving pixels between an image line and a batch lane -------------------------------- */

/* Row lines into the batch and back, a chunk of ROW_CHUNK pixels at a time: within a chunk
 * each lane's row is read (or written) as one contiguous burst, which the hardware prefetchers
 * follow, while the chunk's batch side (ROW_CHUNK * L * C floats, 16 KB for RGBA) stays in L1.
 * Element-by-element across the lanes would be sixteen interleaved streams, which they do not
 * follow; lane by lane over the whole row would miss L1 on every store. C is a constant in each
 * instance (a runtime-sized memcpy per pixel would be a library call). */
#define ROW_CHUNK 64u

static DDOF_ALWAYS_INLINE void rows_in_c(float *restrict x, const float *const *rows,
                                         uint32_t n, const uint32_t C)
{
    for (uint32_t i0 = 0; i0 < n; i0 += ROW_CHUNK) {
        const uint32_t i1 = n - i0 < ROW_CHUNK ? n : i0 + ROW_CHUNK;
        /* Ask for every lane's next chunk now: sixteen interleaved streams are more than the
         * hardware prefetchers follow, and the loads would otherwise wait on memory. */
        if (i1 < n)
            for (uint32_t l = 0; l < L; l++)
                if (rows[l])
                    for (uint32_t f = 0; f < ROW_CHUNK * C; f += 16)
                        DDOF_PREFETCH(rows[l] + (size_t)i1 * C + f, 0);
        for (uint32_t l = 0; l < L; l++) {
            const float *restrict row = rows[l];
            if (row) {
                for (uint32_t i = i0; i < i1; i++)
                    for (uint32_t c = 0; c < C; c++)
                        x[((size_t)i * L + l) * C + c] = row[(size_t)i * C + c];
            } else {
                for (uint32_t i = i0; i < i1; i++)
                    for (uint32_t c = 0; c < C; c++)
                        x[((size_t)i * L + l) * C + c] = 0.0f;
            }
        }
    }
}

static DDOF_ALWAYS_INLINE void rows_out_c(float *const *rows, const float *restrict x,
                                          uint32_t n, const uint32_t C)
{
    for (uint32_t i0 = 0; i0 < n; i0 += ROW_CHUNK) {
        const uint32_t i1 = n - i0 < ROW_CHUNK ? n : i0 + ROW_CHUNK;
        for (uint32_t l = 0; l < L; l++) {
            float *restrict row = rows[l];
            if (!row)
                continue;
            for (uint32_t i = i0; i < i1; i++)
                for (uint32_t c = 0; c < C; c++)
                    row[(size_t)i * C + c] = x[((size_t)i * L + l) * C + c];
        }
    }
}

/* rows[l] is lane l's image row, or NULL for a lane that is not solved (zeros in, not out). */
static DDOF_ALWAYS_INLINE void rows_in(float *x, const float *const *rows, uint32_t n, uint32_t C)
{
    switch (C) {
    case 1: rows_in_c(x, rows, n, 1); break;
    case 2: rows_in_c(x, rows, n, 2); break;
    case 3: rows_in_c(x, rows, n, 3); break;
    default: rows_in_c(x, rows, n, 4); break;
    }
}

static DDOF_ALWAYS_INLINE void rows_out(float *const *rows, const float *x, uint32_t n, uint32_t C)
{
    switch (C) {
    case 1: rows_out_c(rows, x, n, 1); break;
    case 2: rows_out_c(rows, x, n, 2); break;
    case 3: rows_out_c(rows, x, n, 3); break;
    default: rows_out_c(rows, x, n, 4); break;
    }
}

/* ---- heat capacity (layers only): gamma images and masking ----------------------------- */

/* gamma[i][l] for the row batch's lanes (padding lanes get 1: harmless, they hold zeros). */
static inline void gather_row_gamma(float *gamma, const adi_request *r, uint32_t y0, uint32_t lanes,
                             uint32_t n)
{
    for (uint32_t l = 0; l < L; l++) {
        const float *g = r->gamma + (size_t)(y0 + (l < lanes ? l : 0)) * r->gamma_stride;
        for (uint32_t i = 0; i < n; i++)
            gamma[(size_t)i * L + l] = l < lanes ? g[(size_t)i * r->gamma_channels] : 1.0f;
    }
}

static inline void gather_column_gamma(float *gamma, const adi_request *r, uint32_t x0,
                                uint32_t lanes, uint32_t n)
{
    for (uint32_t i = 0; i < n; i++) {
        const float *g = r->gamma + (size_t)i * r->gamma_stride + (size_t)x0 * r->gamma_channels;
        for (uint32_t l = 0; l < L; l++)
            gamma[(size_t)i * L + l] = l < lanes ? g[l * r->gamma_channels] : 1.0f;
    }
}

/* Where a pixel has no heat capacity its colour is never part of the answer; it may even be
 * NaN (a masked-out pixel). Zero it, so that no solver ever multiplies it by a weight. */
static inline void mask_batch(float *x, const float *gamma, uint32_t n, size_t x_stride, uint32_t C)
{
    for (uint32_t i = 0; i < n; i++)
        for (uint32_t l = 0; l < L; l++)
            if (!(gamma[(size_t)i * L + l] > 0.0f))
                for (uint32_t c = 0; c < C; c++)
                    x[(size_t)i * x_stride + l * C + c] = 0.0f;
}

/* One line with no links: y = x where gamma > 0, 0 where gamma = 0 (nothing defines it). */
static inline void copy_masked(float *dst, const float *src, const float *gamma_lane, uint32_t n,
                        uint32_t C)
{
    for (uint32_t i = 0; i < n; i++) {
        const int keep = gamma_lane[(size_t)i * L] > 0.0f;
        for (uint32_t c = 0; c < C; c++)
            dst[(size_t)i * C + c] = keep ? src[(size_t)i * C + c] : 0.0f;
    }
}

/* Marks, per lane, the runs of pixels joined by links (beta > 0) whose heat capacities are all
 * 0: nothing in them holds heat, and any constant solves them. Returns whether there is any. */
static inline int mark_singular_runs(const float *beta, const float *gamma, uint32_t n,
                                     unsigned char *singular)
{
    int any = 0;
    for (uint32_t l = 0; l < L; l++) {
        uint32_t start = 0;
        int holds_heat = 0;
        for (uint32_t i = 0; i < n; i++) {
            holds_heat |= gamma[(size_t)i * L + l] > 0.0f;
            if (i + 1 < n && beta[(size_t)i * L + l] > 0.0f)
                continue;
            for (uint32_t k = start; k <= i; k++)
                singular[(size_t)k * L + l] = (unsigned char)!holds_heat;
            any |= !holds_heat;
            start = i + 1;
            holds_heat = 0;
        }
    }
    return any;
}

#undef L

#endif
