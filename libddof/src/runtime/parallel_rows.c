/* SPDX-License-Identifier: MIT */
/* parallel_rows.c - row-chunk parallelism and value validation scans. */
#include "parallel_rows.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

#if defined(__SSE2__)
#  include <emmintrin.h>
#endif

typedef struct rows_job {
    row_chunk_fn fn;
    void *user;
    uint32_t height;
} rows_job;

static void rows_task(void *user, uint32_t chunk, uint32_t thread_index)
{
    (void)thread_index;
    const rows_job *job = user;
    uint32_t y0 = chunk * DDOF_ROWS_PER_CHUNK;
    uint32_t y1 = y0 + DDOF_ROWS_PER_CHUNK < job->height ? y0 + DDOF_ROWS_PER_CHUNK : job->height;
    job->fn(job->user, y0, y1, chunk);
}

void ddof_parallel_rows(ddof_context *context, uint32_t height, row_chunk_fn fn, void *user)
{
    rows_job job = {fn, user, height};
    thread_pool_run(context->pool, ddof_row_chunks(height), rows_task, &job, NULL, NULL);
}

static DDOF_ALWAYS_INLINE int value_ok(float v, const value_rule rule)
{
    switch (rule) {
    case VALUE_FINITE: return v - v == 0.0f; /* NaN and +-inf give NaN; isfinite may not vectorise */
    case VALUE_COLOR: return (v >= -DDOF_MAX_COLOR) & (v <= DDOF_MAX_COLOR);
    case VALUE_DEPTH: return v > 0.0f;       /* false for NaN; true for +inf */
    case VALUE_DEPTH_ZERO: return v >= 0.0f;
    /* & rather than &&: both compares are cheap, and a short-circuit keeps the loop scalar. */
    case VALUE_COC: return (v >= 0.0f) & (v <= DDOF_MAX_COC_PX);
    case VALUE_COC_SIGNED: return (v >= -DDOF_MAX_COC_PX) & (v <= DDOF_MAX_COC_PX);
    }
    return 0;
}

/* |v| as its bits: for values that are not NaN they order as the values do, and an integer max
 * reduction vectorises where a float one (which must order NaN) does not. */
static inline uint32_t abs_bits(float v)
{
    uint32_t u;
    memcpy(&u, &v, sizeof u);
    return u & 0x7fffffffu;
}

/* Failures among n values `step` floats apart, counted branch-free so that it vectorises;
 * with `track_max`, the largest |value| of the same read goes into *max_abs (meaningful only
 * when nothing failed). */
static DDOF_ALWAYS_INLINE unsigned count_bad_rule(const float *v, size_t n, size_t step,
                                                  const value_rule rule, const int track_max,
                                                  float *max_abs)
{
    unsigned bad = 0;
    uint32_t m = abs_bits(*max_abs);
    if (step == 1) {
        for (size_t i = 0; i < n; i++) {
            bad += !value_ok(v[i], rule);
            if (track_max) {
                const uint32_t a = abs_bits(v[i]);
                m = a > m ? a : m;
            }
        }
    } else {
        for (size_t i = 0; i < n; i++) {
            bad += !value_ok(v[i * step], rule);
            if (track_max) {
                const uint32_t a = abs_bits(v[i * step]);
                m = a > m ? a : m;
            }
        }
    }
    memcpy(max_abs, &m, sizeof m);
    return bad;
}

#define COUNT_BAD_CASE(RULE)                                                                   \
    case RULE:                                                                                 \
        return track_max ? count_bad_rule(v, n, step, RULE, 1, max_abs)                        \
                         : count_bad_rule(v, n, step, RULE, 0, max_abs);

static DDOF_ALWAYS_INLINE unsigned count_bad(const float *v, size_t n, size_t step,
                                             value_rule rule, int track_max, float *max_abs)
{
    switch (rule) {
        COUNT_BAD_CASE(VALUE_FINITE)
        COUNT_BAD_CASE(VALUE_COLOR)
        COUNT_BAD_CASE(VALUE_DEPTH)
        COUNT_BAD_CASE(VALUE_DEPTH_ZERO)
        COUNT_BAD_CASE(VALUE_COC)
        COUNT_BAD_CASE(VALUE_COC_SIGNED)
    }
    return 0;
}
#undef COUNT_BAD_CASE

typedef struct scan_job {
    const float *pixels;
    uint32_t width, channels, channels_read;
    size_t stride;
    value_rule rule;
    bad_value *first_bad; /* one per chunk */
    unsigned char *found; /* one per chunk */
    float *max_abs;       /* one per chunk, or NULL when not asked for */
} scan_job;

/* Multi-versioned: the max of the CoC scan needs SSE4.1's integer max to vectorise. */
DDOF_MULTIVERSION static void scan_chunk(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    const scan_job *job = user;
    job->found[chunk] = 0;
    float max_abs = 0.0f;
    for (uint32_t y = y0; y < y1; y++) {
        const float *row = job->pixels + (size_t)y * job->stride;
        /* Count failures fast; only a row that has one is scanned again to locate it. Either
         * every channel is read (one contiguous run) or only the first (a strided one). */
        const int all = job->channels_read == job->channels;
        const size_t n = all ? (size_t)job->width * job->channels : job->width;
        if (!count_bad(row, n, all ? 1 : job->channels, job->rule, job->max_abs != NULL,
                       &max_abs))
            continue;
        for (uint32_t x = 0; x < job->width; x++)
            for (uint32_t c = 0; c < job->channels_read; c++) {
                float v = row[(size_t)x * job->channels + c];
                if (!value_ok(v, job->rule)) {
                    job->first_bad[chunk] = (bad_value){x, y, c, v};
                    job->found[chunk] = 1;
                    return;
                }
            }
    }
    if (job->max_abs)
        job->max_abs[chunk] = max_abs;
}

int ddof_find_bad_value(ddof_context *context, const float *pixels, uint32_t width,
                        uint32_t height, uint32_t channels, uint32_t channels_read,
                        size_t stride_floats, value_rule rule, bad_value *bad, float *max_abs)
{
    uint32_t chunks = ddof_row_chunks(height);
    /* One result per chunk, on the stack: at most 4096 chunks (86 KB) for the tallest image. */
    enum { max_chunks = (DDOF_MAX_DIMENSION + DDOF_ROWS_PER_CHUNK - 1) / DDOF_ROWS_PER_CHUNK };
    bad_value first_bad[max_chunks];
    unsigned char found[max_chunks];
    float chunk_max[max_chunks];
    scan_job job = {pixels, width, channels, channels_read, stride_floats, rule, first_bad, found,
                    max_abs ? chunk_max : NULL};
    ddof_parallel_rows(context, height, scan_chunk, &job);
    float m = 0.0f;
    for (uint32_t c = 0; c < chunks; c++) {
        if (found[c]) {
            *bad = first_bad[c];
            return 1;
        }
        if (max_abs)
            m = ddof_maxf(m, chunk_max[c]);
    }
    if (max_abs)
        *max_abs = m;
    return 0;
}

typedef struct copy_job {
    const float *src;
    size_t src_stride;
    float *dst;
    size_t dst_stride, row_floats;
} copy_job;

/* One row copied with non-temporal stores where the CPU has them: an image is larger than the
 * caches and is not read again by this call, and a plain store first reads the line it writes
 * (a copy of many rows through row-sized memcpys moves 3 bytes for each one copied, against
 * the 2 of the streaming memcpy a whole-image copy gets). */
static void copy_row(float *restrict dst, const float *restrict src, size_t n)
{
#if defined(__SSE2__)
    size_t i = 0;
    for (; i < n && ((uintptr_t)(dst + i) & 15u); i++)
        dst[i] = src[i];
    for (; i + 16 <= n; i += 16) {
        const __m128 a = _mm_loadu_ps(src + i), b = _mm_loadu_ps(src + i + 4);
        const __m128 c = _mm_loadu_ps(src + i + 8), d = _mm_loadu_ps(src + i + 12);
        _mm_stream_ps(dst + i, a);
        _mm_stream_ps(dst + i + 4, b);
        _mm_stream_ps(dst + i + 8, c);
        _mm_stream_ps(dst + i + 12, d);
    }
    for (; i < n; i++)
        dst[i] = src[i];
#else
    memcpy(dst, src, n * sizeof(float));
#endif
}

static void copy_chunk(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const copy_job *job = user;
    for (uint32_t y = y0; y < y1; y++)
        copy_row(job->dst + (size_t)y * job->dst_stride, job->src + (size_t)y * job->src_stride,
                 job->row_floats);
#if defined(__SSE2__)
    _mm_sfence(); /* streaming stores are weakly ordered: visible before the pool's join */
#endif
}

void ddof_parallel_copy(ddof_context *context, const float *src, size_t src_stride, float *dst,
                        size_t dst_stride, size_t row_floats, uint32_t height)
{
    if (src == dst)
        return;
    copy_job job = {src, src_stride, dst, dst_stride, row_floats};
    ddof_parallel_rows(context, height, copy_chunk, &job);
}
