/* SPDX-License-Identifier: MIT */
/* parallel_rows.c - row-chunk parallelism and value validation scans. */
#include "parallel_rows.h"

#include <math.h>

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
    case VALUE_DEPTH: return v > 0.0f;       /* false for NaN; true for +inf */
    case VALUE_DEPTH_ZERO: return v >= 0.0f;
    case VALUE_COC: return v >= 0.0f && v <= DDOF_MAX_COC_PX;
    case VALUE_COC_SIGNED: return v >= -DDOF_MAX_COC_PX && v <= DDOF_MAX_COC_PX;
    }
    return 0;
}

/* Failures among n values `step` floats apart, counted branch-free so that it vectorises. */
static DDOF_ALWAYS_INLINE unsigned count_bad_rule(const float *v, size_t n, size_t step,
                                                  const value_rule rule)
{
    unsigned bad = 0;
    if (step == 1) {
        for (size_t i = 0; i < n; i++)
            bad += !value_ok(v[i], rule);
    } else {
        for (size_t i = 0; i < n; i++)
            bad += !value_ok(v[i * step], rule);
    }
    return bad;
}

static unsigned count_bad(const float *v, size_t n, size_t step, value_rule rule)
{
    switch (rule) {
    case VALUE_FINITE: return count_bad_rule(v, n, step, VALUE_FINITE);
    case VALUE_DEPTH: return count_bad_rule(v, n, step, VALUE_DEPTH);
    case VALUE_DEPTH_ZERO: return count_bad_rule(v, n, step, VALUE_DEPTH_ZERO);
    case VALUE_COC: return count_bad_rule(v, n, step, VALUE_COC);
    case VALUE_COC_SIGNED: return count_bad_rule(v, n, step, VALUE_COC_SIGNED);
    }
    return 0;
}

typedef struct scan_job {
    const float *pixels;
    uint32_t width, channels, channels_read;
    size_t stride;
    value_rule rule;
    bad_value *first_bad; /* one per chunk */
    unsigned char *found; /* one per chunk */
} scan_job;

static void scan_chunk(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    const scan_job *job = user;
    job->found[chunk] = 0;
    for (uint32_t y = y0; y < y1; y++) {
        const float *row = job->pixels + (size_t)y * job->stride;
        /* Count failures fast; only a row that has one is scanned again to locate it. Either
         * every channel is read (one contiguous run) or only the first (a strided one). */
        const int all = job->channels_read == job->channels;
        const size_t n = all ? (size_t)job->width * job->channels : job->width;
        if (!count_bad(row, n, all ? 1 : job->channels, job->rule))
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
}

int ddof_find_bad_value(ddof_context *context, const float *pixels, uint32_t width,
                        uint32_t height, uint32_t channels, uint32_t channels_read,
                        size_t stride_floats, value_rule rule, bad_value *bad)
{
    uint32_t chunks = ddof_row_chunks(height);
    /* One result per chunk, on the stack: at most 4096 chunks (69 KB) for the tallest image. */
    enum { max_chunks = (DDOF_MAX_DIMENSION + DDOF_ROWS_PER_CHUNK - 1) / DDOF_ROWS_PER_CHUNK };
    bad_value first_bad[max_chunks];
    unsigned char found[max_chunks];
    scan_job job = {pixels, width, channels, channels_read, stride_floats, rule, first_bad, found};
    ddof_parallel_rows(context, height, scan_chunk, &job);
    for (uint32_t c = 0; c < chunks; c++)
        if (found[c]) {
            *bad = first_bad[c];
            return 1;
        }
    return 0;
}
