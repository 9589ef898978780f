/* SPDX-License-Identifier: MIT */
/* sequence.c - the frame-sequence driver: a shared queue of frames and worker threads. */
#include "sequence.h"

#include "stats_json.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static uint32_t online_cores(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (uint32_t)n : 1u;
}

sequence_plan sequence_plan_for(const cli_options *o, int frames, uint64_t pixels)
{
    sequence_plan plan;
    const uint32_t cores = online_cores();
    plan.jobs = 1;
    plan.threads_per_frame = o->threads;
    plan.reason = "one frame at a time, every core on each frame";
    if (o->jobs > 0) {
        plan.jobs = o->jobs;
        plan.threads_per_frame = o->threads ? o->threads : (o->jobs > 1 ? 1 : 0);
        plan.reason = "--jobs";
    } else if (frames >= 2 && cores >= 2 && pixels <= SEQUENCE_PARALLEL_MAX_PIXELS) {
        plan.jobs = cores;
        plan.threads_per_frame = o->threads ? o->threads : 1;
        plan.reason = "small frames: whole frames in parallel, one thread each";
    } else if (frames >= 2 && cores >= 2) {
        plan.reason = "large frames: one at a time, every core on each frame";
    }
    if (plan.jobs > (uint32_t)frames)
        plan.jobs = (uint32_t)(frames > 0 ? frames : 1);
    return plan;
}

typedef struct shared_queue {
    const frame_setup *setup;
    const frame_paths *paths;
    frame_result *results;
    int count;
    int next;
    int failed;
    pthread_mutex_t lock;
    progress *bar;
    uint32_t threads_per_frame;
    char start_error[512];
} shared_queue;

typedef struct worker {
    shared_queue *queue;
    int slot;
    pthread_t thread;
} worker;

static void ms(char *out, size_t size, const char *label, double seconds)
{
    snprintf(out, size, "%s %.1f ms", label, seconds * 1e3);
}

static void report(shared_queue *q, int index)
{
    const frame_paths *p = &q->paths[index];
    const frame_result *r = &q->results[index];
    char prefix[64], line[2 * PATH_MAX + 1024], read[48], dof[48], write[48], effects[128];
    char how[160];
    if (p->frame >= 0)
        snprintf(prefix, sizeof prefix, "frame %d: ", p->frame);
    else
        prefix[0] = '\0';
    if (!r->ok) {
        snprintf(line, sizeof line, "ddof: %sFAILED: %s\n", prefix, r->error);
        progress_print(q->bar, stderr, line);
        return;
    }
    if (r->skipped) {
        if (!q->setup->options->quiet) {
            snprintf(line, sizeof line, "%s%s -> %s  skipped: complete and newer than its "
                     "inputs (--skip-existing)\n", prefix, p->input, p->output);
            progress_print(q->bar, stdout, line);
        }
        return;
    }
    if (!q->setup->options->quiet) {
        stats_effects(&r->stats, effects, sizeof effects);
        ms(read, sizeof read, "read", r->seconds_read);
        ms(dof, sizeof dof, "dof", r->seconds_dof + r->seconds_coc);
        ms(write, sizeof write, "write", r->seconds_write + r->seconds_preview);
        if (r->stats.method == DDOF_METHOD_COD4_PREVIEW) {
            /* No diffusion, so no effects and no lines: the preview's own words. */
            snprintf(effects, sizeof effects, "CoD4 preview");
            snprintf(how, sizeof how, "%u thread%s", r->stats.threads,
                     r->stats.threads == 1 ? "" : "s");
        } else if (r->stats.kernel != DDOF_KERNEL_HEAT)
            snprintf(how, sizeof how, "%s %s, %u thread%s: %llu lines solved, %llu skipped%s",
                     ddof_solver_name((ddof_solver)r->stats.solver),
                     ddof_kernel_name((ddof_kernel)r->stats.kernel), r->stats.threads,
                     r->stats.threads == 1 ? "" : "s",
                     (unsigned long long)r->stats.lines_solved,
                     (unsigned long long)r->stats.lines_skipped,
                     r->stats.copied_only ? " (nothing out of focus: copied)" : "");
        else
            snprintf(how, sizeof how, "%s x%u, %u thread%s: %llu lines solved, %llu skipped%s",
                     ddof_solver_name((ddof_solver)r->stats.solver), r->stats.substeps,
                     r->stats.threads, r->stats.threads == 1 ? "" : "s",
                     (unsigned long long)r->stats.lines_solved,
                     (unsigned long long)r->stats.lines_skipped,
                     r->stats.copied_only ? " (nothing out of focus: copied)" : "");
        snprintf(line, sizeof line, "%s%s -> %s  %ux%u %s  max CoC %.1f px  %s  %s  (%s, %s, %s)\n",
                 prefix, p->input, p->output, r->width, r->height,
                 r->channels == 4 ? "RGBA" : "RGB", (double)r->stats.max_coc_px, effects, how,
                 read, dof, write);
        progress_print(q->bar, stdout, line);
    }
    if (q->setup->options->verbose) {
        char backend[768];
        stats_backend_line(r, backend, sizeof backend);
        snprintf(line, sizeof line, "%s  %s\n", prefix, backend);
        progress_print(q->bar, stdout, line);
        if (r->plan[0]) {
            char copy[sizeof r->plan], *plan_line, *save = NULL;
            memcpy(copy, r->plan, sizeof r->plan);
            for (plan_line = strtok_r(copy, "\n", &save); plan_line;
                 plan_line = strtok_r(NULL, "\n", &save)) {
                snprintf(line, sizeof line, "%s  plan: %s\n", prefix, plan_line);
                progress_print(q->bar, stdout, line);
            }
        }
    }
}

static void *worker_main(void *arg)
{
    worker *w = arg;
    shared_queue *q = w->queue;
    char error[sizeof q->start_error];
    ddof_context *context = frame_context_create(q->setup->options, q->threads_per_frame, error,
                                                 sizeof error);
    if (!context) {
        pthread_mutex_lock(&q->lock);
        snprintf(q->start_error, sizeof q->start_error, "%s", error);
        pthread_mutex_unlock(&q->lock);
        return NULL;
    }
    for (;;) {
        int index;
        pthread_mutex_lock(&q->lock);
        index = q->next < q->count ? q->next++ : -1;
        pthread_mutex_unlock(&q->lock);
        if (index < 0)
            break;
        if (frame_run(context, q->setup, &q->paths[index], &q->results[index], q->bar,
                      w->slot) != 0) {
            pthread_mutex_lock(&q->lock);
            q->failed++;
            pthread_mutex_unlock(&q->lock);
        }
        report(q, index);
        progress_frame_done(q->bar, w->slot);
    }
    ddof_context_free(context);
    return NULL;
}

int sequence_run(const frame_setup *setup, const frame_paths *paths, frame_result *results,
                 int count, const sequence_plan *plan, progress *bar, char *error,
                 size_t error_size)
{
    shared_queue q;
    worker *workers;
    uint32_t i, started = 0;

    memset(&q, 0, sizeof q);
    q.setup = setup;
    q.paths = paths;
    q.results = results;
    q.count = count;
    q.bar = bar;
    q.threads_per_frame = plan->threads_per_frame;
    pthread_mutex_init(&q.lock, NULL);

    workers = calloc(plan->jobs ? plan->jobs : 1, sizeof *workers);
    if (!workers) {
        snprintf(error, error_size, "out of memory");
        pthread_mutex_destroy(&q.lock);
        return -1;
    }
    if (plan->jobs <= 1) {
        /* No extra thread for the common case of one frame at a time. */
        workers[0].queue = &q;
        worker_main(&workers[0]);
        started = 1;
    } else {
        for (i = 0; i < plan->jobs; i++) {
            workers[i].queue = &q;
            workers[i].slot = (int)i;
            if (pthread_create(&workers[i].thread, NULL, worker_main, &workers[i]) != 0)
                break;
            started++;
        }
        for (i = 0; i < started; i++)
            pthread_join(workers[i].thread, NULL);
    }
    free(workers);
    pthread_mutex_destroy(&q.lock);
    if (q.next < count) {
        /* No worker got going (no thread, no context): nothing ran at all. */
        snprintf(error, error_size, "%s", q.start_error[0] ? q.start_error
                                                            : "cannot start a worker thread");
        return -1;
    }
    return q.failed;
}
