/* SPDX-License-Identifier: MIT */
/* thread_pool.c - persistent pthread workers running one parallel-for at a time.
 *
 * A run publishes (task, count) under the mutex and bumps `generation`; workers wake, take task
 * indices from an atomic counter until none are left, and the last one out signals the caller.
 * The caller takes tasks too, and between its tasks reports progress, which may cancel:
 * cancelling moves the counter past `count` so no new task starts. */
#include "thread_pool.h"

#include "memory.h"

#include <pthread.h>
#include <stdatomic.h>

typedef struct worker {
    thread_pool *pool;
    uint32_t thread_index; /* 1..workers; 0 is the caller's thread */
    pthread_t thread;
} worker;

struct thread_pool {
    ddof_allocator allocator;
    pthread_mutex_t mutex;
    pthread_cond_t wake;     /* workers wait here for a new generation or shutdown */
    pthread_cond_t finished; /* the caller waits here for every worker to leave   */
    uint32_t worker_count;
    worker *workers;

    /* The current run; written under the mutex before `generation` changes. */
    uint64_t generation;
    int shutdown;
    thread_task_fn task;
    void *user;
    uint32_t count;
    uint32_t left;    /* workers done with the current run (under the mutex) */
    atomic_uint next; /* next task index to hand out                       */
    atomic_uint done; /* tasks finished, for progress                      */
};

static int run_one(thread_pool *pool, thread_task_fn task, void *user, uint32_t count,
                   uint32_t thread_index)
{
    uint32_t i = atomic_fetch_add(&pool->next, 1);
    if (i >= count)
        return 0;
    task(user, i, thread_index);
    atomic_fetch_add(&pool->done, 1);
    return 1;
}

static void *worker_main(void *arg)
{
    worker *self = arg;
    thread_pool *pool = self->pool;
    uint64_t seen = 0; /* generations are numbered from 1 */
    pthread_mutex_lock(&pool->mutex);
    for (;;) {
        while (!pool->shutdown && pool->generation == seen)
            pthread_cond_wait(&pool->wake, &pool->mutex);
        if (pool->shutdown)
            break;
        seen = pool->generation;
        thread_task_fn task = pool->task;
        void *user = pool->user;
        uint32_t count = pool->count;
        pthread_mutex_unlock(&pool->mutex);

        while (run_one(pool, task, user, count, self->thread_index)) {
        }

        pthread_mutex_lock(&pool->mutex);
        if (++pool->left == pool->worker_count)
            pthread_cond_signal(&pool->finished);
    }
    pthread_mutex_unlock(&pool->mutex);
    return NULL;
}

ddof_status thread_pool_create(const ddof_allocator *allocator, uint32_t workers,
                               thread_pool **out)
{
    *out = NULL;
    thread_pool *pool = ddof_alloc(allocator, sizeof *pool);
    if (!pool)
        return DDOF_ERROR_OUT_OF_MEMORY;
    *pool = (thread_pool){.allocator = *allocator};
    atomic_init(&pool->next, 0);
    atomic_init(&pool->done, 0);
    pool->workers = ddof_alloc(allocator, (size_t)workers * sizeof(worker));
    if (!pool->workers || pthread_mutex_init(&pool->mutex, NULL) != 0) {
        ddof_status status = pool->workers ? DDOF_ERROR_THREADS : DDOF_ERROR_OUT_OF_MEMORY;
        ddof_free(allocator, pool->workers);
        ddof_free(allocator, pool);
        return status;
    }
    pthread_cond_init(&pool->wake, NULL);
    pthread_cond_init(&pool->finished, NULL);
    for (uint32_t i = 0; i < workers; i++) {
        pool->workers[i] = (worker){.pool = pool, .thread_index = i + 1};
        if (pthread_create(&pool->workers[i].thread, NULL, worker_main, &pool->workers[i]) != 0)
            break;
        pool->worker_count++;
    }
    if (pool->worker_count != workers) {
        thread_pool_free(pool);
        return DDOF_ERROR_THREADS;
    }
    *out = pool;
    return DDOF_OK;
}

void thread_pool_free(thread_pool *pool)
{
    if (!pool)
        return;
    pthread_mutex_lock(&pool->mutex);
    pool->shutdown = 1;
    pthread_cond_broadcast(&pool->wake);
    pthread_mutex_unlock(&pool->mutex);
    for (uint32_t i = 0; i < pool->worker_count; i++)
        pthread_join(pool->workers[i].thread, NULL);
    pthread_cond_destroy(&pool->finished);
    pthread_cond_destroy(&pool->wake);
    pthread_mutex_destroy(&pool->mutex);
    ddof_allocator allocator = pool->allocator;
    ddof_free(&allocator, pool->workers);
    ddof_free(&allocator, pool);
}

uint32_t thread_pool_threads(const thread_pool *pool)
{
    return pool ? pool->worker_count + 1 : 1;
}

/* Without a pool: the same loop on the caller's thread. */
static int run_inline(uint32_t count, thread_task_fn task, void *user,
                      thread_progress_fn progress, void *progress_user)
{
    for (uint32_t i = 0; i < count; i++) {
        if (progress && progress(progress_user, i, count))
            return 1;
        task(user, i, 0);
    }
    return 0;
}

int thread_pool_run(thread_pool *pool, uint32_t count, thread_task_fn task, void *user,
                    thread_progress_fn progress, void *progress_user)
{
    if (!pool || count <= 1)
        return run_inline(count, task, user, progress, progress_user);

    pthread_mutex_lock(&pool->mutex);
    pool->task = task;
    pool->user = user;
    pool->count = count;
    pool->left = 0;
    atomic_store(&pool->next, 0);
    atomic_store(&pool->done, 0);
    pool->generation++;
    pthread_cond_broadcast(&pool->wake);
    pthread_mutex_unlock(&pool->mutex);

    int cancelled = 0;
    for (;;) {
        if (progress && !cancelled &&
            progress(progress_user, atomic_load(&pool->done), count)) {
            cancelled = 1;
            atomic_store(&pool->next, count); /* nobody starts another task */
        }
        if (!run_one(pool, task, user, count, 0))
            break;
    }

    /* Every worker takes part in every run (it may find no task left), and the next run is
     * published only after all have left this one, so no worker can mix up two runs' tasks. */
    pthread_mutex_lock(&pool->mutex);
    while (pool->left < pool->worker_count)
        pthread_cond_wait(&pool->finished, &pool->mutex);
    pthread_mutex_unlock(&pool->mutex);
    return cancelled;
}
