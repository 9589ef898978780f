/* SPDX-License-Identifier: MIT */
/* gather_blur.c - the naive gather blur baseline (see gather_blur.h and README.md).
 *
 * Two passes over the rows, each shared by the threads (row y goes to thread y % threads):
 *  1. per-row prefix sums in double, P[y][x] = sum of the row's first x pixels, per channel;
 *  2. per pixel, the disk of radius |CoC| / 2 is a stack of row spans [x - w_j, x + w_j] for
 *     rows y + j, w_j = floor(sqrt(r^2 - j^2)); each span clipped to the image is summed as
 *     P[y + j][b + 1] - P[y + j][a], the pixels counted, and the average written.
 * A disk that holds only its own pixel (|CoC| < 2) copies the input, bit for bit.
 * Everything the second pass reads comes from the first, so out may be the input itself. */
#include "gather_blur.h"

#include <math.h>
#include <pthread.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define MAX_CHANNELS 16u

typedef struct gather_job {
    const float *rgba, *coc;
    float *out;
    double *prefix; /* height rows of (width + 1) * channels */
    uint32_t width, height, channels, threads;
    int pass;       /* 1: prefix sums, 2: gather */
} gather_job;

typedef struct gather_task {
    const gather_job *job;
    uint32_t first; /* this task's rows: first, first + threads, ... */
} gather_task;

static void prefix_row(const gather_job *job, uint32_t y)
{
    const uint32_t W = job->width, C = job->channels;
    const float *in = job->rgba + (size_t)y * W * C;
    double *p = job->prefix + (size_t)y * (W + 1) * C;
    for (uint32_t c = 0; c < C; c++)
        p[c] = 0.0;
    for (uint32_t x = 0; x < W; x++)
        for (uint32_t c = 0; c < C; c++)
            p[(size_t)(x + 1) * C + c] = p[(size_t)x * C + c] + (double)in[(size_t)x * C + c];
}

/* The largest w >= 0 with w^2 <= v (v >= 0), exactly. */
static int64_t half_width(double v)
{
    int64_t w = (int64_t)floor(sqrt(v));
    while (w > 0 && (double)w * (double)w > v)
        w--;
    while ((double)(w + 1) * (double)(w + 1) <= v)
        w++;
    return w;
}

static void gather_row(const gather_job *job, uint32_t y)
{
    const uint32_t W = job->width, H = job->height, C = job->channels;
    const size_t row = (size_t)(W + 1) * C;
    for (uint32_t x = 0; x < W; x++) {
        const size_t i = (size_t)y * W + x;
        const double r = fabs((double)job->coc[i]) / 2.0, r2 = r * r;
        float *o = job->out + i * C;
        if (r2 < 1.0) { /* only the pixel itself */
            if (o != job->rgba + i * C)
                memcpy(o, job->rgba + i * C, C * sizeof(float));
            continue;
        }
        double sum[MAX_CHANNELS];
        for (uint32_t c = 0; c < C; c++)
            sum[c] = 0.0;
        uint64_t count = 0;
        const int64_t reach = (int64_t)floor(r); /* |j| <= r */
        const int64_t j0 = -reach > -(int64_t)y ? -reach : -(int64_t)y;
        const int64_t j1 = reach < (int64_t)(H - 1 - y) ? reach : (int64_t)(H - 1 - y);
        for (int64_t j = j0; j <= j1; j++) {
            const int64_t w = half_width(r2 - (double)j * (double)j);
            const int64_t a = (int64_t)x - w > 0 ? (int64_t)x - w : 0;
            const int64_t b = (int64_t)x + w < (int64_t)W - 1 ? (int64_t)x + w : (int64_t)W - 1;
            const double *p = job->prefix + (size_t)((int64_t)y + j) * row;
            for (uint32_t c = 0; c < C; c++)
                sum[c] += p[(size_t)(b + 1) * C + c] - p[(size_t)a * C + c];
            count += (uint64_t)(b - a + 1);
        }
        for (uint32_t c = 0; c < C; c++)
            o[c] = (float)(sum[c] / (double)count);
    }
}

static void *run_task(void *arg)
{
    const gather_task *task = arg;
    const gather_job *job = task->job;
    for (uint32_t y = task->first; y < job->height; y += job->threads) {
        if (job->pass == 1)
            prefix_row(job, y);
        else
            gather_row(job, y);
    }
    return NULL;
}

/* One pass on job->threads threads (the caller's included). */
static void run_pass(gather_job *job, int pass, pthread_t *handles, unsigned char *started,
                     gather_task *tasks)
{
    job->pass = pass;
    for (uint32_t t = 0; t < job->threads; t++)
        tasks[t] = (gather_task){job, t};
    for (uint32_t t = 1; t < job->threads; t++)
        started[t] = pthread_create(&handles[t], NULL, run_task, &tasks[t]) == 0;
    run_task(&tasks[0]);
    for (uint32_t t = 1; t < job->threads; t++) {
        if (started[t])
            pthread_join(handles[t], NULL);
        else
            run_task(&tasks[t]); /* could not start: the caller does its rows */
    }
}

int ddof_gather_blur(const float *rgba, const float *coc_px, uint32_t width, uint32_t height,
                     uint32_t channels, float *out, uint32_t threads)
{
    if (!rgba || !coc_px || !out || width == 0 || height == 0 || channels == 0 ||
        channels > MAX_CHANNELS)
        return DDOF_GATHER_BAD_ARGUMENT;
    const uint64_t pixels = (uint64_t)width * height;
    if (pixels > SIZE_MAX / sizeof(double) / (MAX_CHANNELS + 1) / 2)
        return DDOF_GATHER_BAD_ARGUMENT;
    for (size_t i = 0; i < (size_t)pixels; i++)
        if (!isfinite(coc_px[i]))
            return DDOF_GATHER_BAD_ARGUMENT;
    if (threads == 0)
        threads = 1;
    if (threads > height)
        threads = height;

    const size_t prefix_doubles = (size_t)(width + 1) * height * channels;
    double *prefix = malloc(prefix_doubles * sizeof(double));
    pthread_t *handles = malloc(threads * sizeof *handles);
    unsigned char *started = calloc(threads, 1);
    gather_task *tasks = malloc(threads * sizeof *tasks);
    if (!prefix || !handles || !started || !tasks) {
        free(prefix);
        free(handles);
        free(started);
        free(tasks);
        return DDOF_GATHER_OUT_OF_MEMORY;
    }
    gather_job job = {rgba, coc_px, out, prefix, width, height, channels, threads, 0};
    run_pass(&job, 1, handles, started, tasks);
    run_pass(&job, 2, handles, started, tasks);
    free(prefix);
    free(handles);
    free(started);
    free(tasks);
    return DDOF_GATHER_OK;
}
