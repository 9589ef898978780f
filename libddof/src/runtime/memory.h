/* SPDX-License-Identifier: MIT */
/* memory.h - the library's allocations (through the caller's allocator) and its clock: the
 * bottom of the runtime, which the thread pool and the context both use. */
#ifndef DDOF_MEMORY_H
#define DDOF_MEMORY_H

#include "ddof.h"

#include <stddef.h>

/* 64-byte aligned memory from the context's allocator; NULL on failure or on size overflow. */
void *ddof_alloc(const ddof_allocator *allocator, size_t size);
void ddof_free(const ddof_allocator *allocator, void *ptr);

/* Monotonic seconds. */
double ddof_seconds(void);

#endif
