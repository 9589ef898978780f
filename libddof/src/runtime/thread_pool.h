/* SPDX-License-Identifier: MIT */
/* thread_pool.h - a small pthread pool that runs a parallel-for over task indices.
 *
 * The calling thread works too, so a pool of W workers gives W + 1 threads. Tasks are taken from
 * an atomic counter (dynamic scheduling: line batches differ in cost when some are skipped). */
#ifndef DDOF_THREAD_POOL_H
#define DDOF_THREAD_POOL_H

#include "ddof.h"

#include <stdint.h>

typedef struct thread_pool thread_pool;

/* task(user, task_index, thread_index); thread_index < thread_pool_threads(), unique per
 * running thread, so it can select per-thread scratch memory. */
typedef void (*thread_task_fn)(void *user, uint32_t task_index, uint32_t thread_index);

/* Called on the caller's thread between tasks with (done, total); returns non-zero to cancel
 * the tasks not yet started. */
typedef int (*thread_progress_fn)(void *user, uint32_t done, uint32_t total);

/* workers >= 1. DDOF_ERROR_OUT_OF_MEMORY or DDOF_ERROR_THREADS (every thread that did start is
 * joined) leave *out NULL. */
ddof_status thread_pool_create(const ddof_allocator *allocator, uint32_t workers,
                               thread_pool **out);
void thread_pool_free(thread_pool *pool);
/* Threads a run uses: the workers and the caller; 1 for a NULL pool. */
uint32_t thread_pool_threads(const thread_pool *pool);

/* Runs task for every index in [0, count) and returns when all have finished. pool may be NULL
 * (runs on the caller's thread). Returns non-zero if progress cancelled the run. */
int thread_pool_run(thread_pool *pool, uint32_t count, thread_task_fn task, void *user,
                    thread_progress_fn progress, void *progress_user);

#endif
