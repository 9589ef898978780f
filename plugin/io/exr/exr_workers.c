/* SPDX-License-Identifier: MIT */
/* exr_workers.c - the threads that encode and decode chunks: started per file and joined at its
 * end. A file's chunks take milliseconds each, so starting a thread (tens of microseconds) costs
 * nothing worth a pool, and exrio keeps no state between calls. */
#include "exr_internal.h"

#include <pthread.h>
#include <stdlib.h>

typedef struct worker {
    void (*work)(void *arg, unsigned index);
    void *arg;
    unsigned index;
    pthread_t thread;
    int started;
} worker;

static void *worker_main(void *p)
{
    worker *w = p;
    w->work(w->arg, w->index);
    return NULL;
}

void exrio_run_workers(unsigned count, void (*work)(void *arg, unsigned index), void *arg)
{
    worker *workers = count > 1 ? calloc(count, sizeof *workers) : NULL;
    unsigned i;
    if (workers) {
        for (i = 1; i < count; i++) {
            workers[i].work = work;
            workers[i].arg = arg;
            workers[i].index = i;
            workers[i].started =
                pthread_create(&workers[i].thread, NULL, worker_main, &workers[i]) == 0;
        }
    }
    work(arg, 0);
    if (workers) {
        for (i = 1; i < count; i++)
            if (workers[i].started)
                pthread_join(workers[i].thread, NULL);
        free(workers);
    }
}
