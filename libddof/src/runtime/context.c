/* SPDX-License-Identifier: MIT */
/* context.c - what a call does with its context: enter and leave it, its threads, its
 * scratch. Creating and freeing one is above the backends (api/context_lifetime.c): the
 * context holds a backend, and the runtime is below them. */
#include "internal.h"

int ddof_context_enter(ddof_context *context)
{
    return atomic_exchange_explicit(&context->in_use, 1, memory_order_acquire) == 0;
}

void ddof_context_leave(ddof_context *context)
{
    atomic_store_explicit(&context->in_use, 0, memory_order_release);
}

uint32_t ddof_context_thread_count(const ddof_context *context)
{
    return context ? context->thread_count : 0;
}

void *ddof_scratch_get(ddof_context *context, int slot, size_t size)
{
    ddof_scratch *scratch = &context->scratch[slot];
    if (scratch->size >= size)
        return scratch->memory;
    ddof_free(&context->allocator, scratch->memory);
    scratch->memory = ddof_alloc(&context->allocator, size);
    scratch->size = scratch->memory ? size : 0;
    return scratch->memory;
}
