/* SPDX-License-Identifier: MIT */
/* memory.c - aligned allocation on top of the caller's allocator, and a monotonic clock. */
#include "memory.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>

#define DDOF_ALIGNMENT 64u /* a cache line; also covers every SIMD width the solvers use */

/* The allocator hooks promise no alignment, so over-allocate and keep the original pointer
 * just below the aligned block. */
void *ddof_alloc(const ddof_allocator *allocator, size_t size)
{
    const size_t extra = DDOF_ALIGNMENT + sizeof(void *);
    if (size > SIZE_MAX - extra)
        return NULL;
    void *raw = allocator->alloc(allocator->user, size + extra);
    if (!raw)
        return NULL;
    uintptr_t aligned = ((uintptr_t)raw + extra) & ~(uintptr_t)(DDOF_ALIGNMENT - 1);
    memcpy((void *)(aligned - sizeof(void *)), &raw, sizeof raw);
    return (void *)aligned;
}

void ddof_free(const ddof_allocator *allocator, void *ptr)
{
    if (!ptr)
        return;
    void *raw;
    memcpy(&raw, (char *)ptr - sizeof(void *), sizeof raw);
    allocator->free(allocator->user, raw);
}

double ddof_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}
