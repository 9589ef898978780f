/* SPDX-License-Identifier: MIT */
/* progress.c - the terminal progress bar. */
#include "progress.h"

#include "cli_clock.h"
#include "output_file.h"

#include <errno.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define BAR_WIDTH 30

struct progress {
    pthread_mutex_t lock;
    int enabled;
    int total;
    int done;
    int slots;
    float *fraction; /* per slot: how far its current frame is */
    double start;
    double last_draw;
    int drawn;
};

progress *progress_create(int enabled, int total_frames, int slots)
{
    progress *p = calloc(1, sizeof *p);
    if (!p)
        return NULL;
    p->fraction = calloc((size_t)(slots > 0 ? slots : 1), sizeof *p->fraction);
    if (!p->fraction) {
        free(p);
        return NULL;
    }
    pthread_mutex_init(&p->lock, NULL);
    p->enabled = enabled;
    p->total = total_frames > 0 ? total_frames : 1;
    p->slots = slots > 0 ? slots : 1;
    p->start = cli_now();
    return p;
}

void progress_free(progress *p)
{
    if (!p)
        return;
    pthread_mutex_destroy(&p->lock);
    free(p->fraction);
    free(p);
}

/* Called with the lock held. */
static void draw(progress *p)
{
    double work = p->done;
    double elapsed = cli_now() - p->start;
    char bar[BAR_WIDTH + 1];
    int i, filled;
    for (i = 0; i < p->slots; i++)
        work += p->fraction[i];
    if (work > p->total)
        work = p->total;
    filled = (int)(BAR_WIDTH * work / p->total);
    for (i = 0; i < BAR_WIDTH; i++)
        bar[i] = i < filled ? '#' : '.';
    bar[BAR_WIDTH] = '\0';
    fprintf(stderr, "\r\033[K[%s] %d/%d frames %5.1f%%", bar, p->done, p->total,
            100.0 * work / p->total);
    if (work > 0.05 && p->done < p->total) {
        double left = elapsed * (p->total - work) / work;
        fprintf(stderr, "  %dm%02ds left", (int)(left / 60), (int)left % 60);
    }
    fflush(stderr);
    p->drawn = 1;
    p->last_draw = cli_now();
}

static void clear(progress *p)
{
    if (p->drawn) {
        fputs("\r\033[K", stderr);
        fflush(stderr);
        p->drawn = 0;
    }
}

void progress_update(progress *p, int slot, float fraction)
{
    if (!p)
        return;
    pthread_mutex_lock(&p->lock);
    if (slot >= 0 && slot < p->slots)
        p->fraction[slot] = fraction < 0.0f ? 0.0f : fraction > 1.0f ? 1.0f : fraction;
    if (p->enabled && cli_now() - p->last_draw > 0.1)
        draw(p);
    pthread_mutex_unlock(&p->lock);
}

void progress_frame_done(progress *p, int slot)
{
    if (!p)
        return;
    pthread_mutex_lock(&p->lock);
    if (slot >= 0 && slot < p->slots)
        p->fraction[slot] = 0.0f;
    p->done++;
    if (p->enabled)
        draw(p);
    pthread_mutex_unlock(&p->lock);
}

/* A summary nobody reads any more (`ddof ... | head -1`) ends the run like SIGTERM: the rest
 * of the batch would run unwatched and its report would be lost. */
static void flush_or_stop(FILE *to)
{
    if (fflush(to) != 0 && errno == EPIPE)
        output_broken_pipe(to == stderr ? "standard error" : "standard output");
}

void progress_print(progress *p, FILE *to, const char *text)
{
    if (!p) {
        fputs(text, to);
        flush_or_stop(to);
        return;
    }
    pthread_mutex_lock(&p->lock);
    if (p->enabled)
        clear(p);
    fputs(text, to);
    flush_or_stop(to);
    if (p->enabled && p->done < p->total)
        draw(p);
    pthread_mutex_unlock(&p->lock);
}

void progress_finish(progress *p)
{
    if (!p)
        return;
    pthread_mutex_lock(&p->lock);
    if (p->enabled)
        clear(p);
    pthread_mutex_unlock(&p->lock);
}
