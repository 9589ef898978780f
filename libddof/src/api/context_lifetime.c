/* SPDX-License-Identifier: MIT */
/* context_lifetime.c - a context's options, creation and teardown: its allocator, worker
 * threads and (at teardown) the backend it loaded. */
#include "backends/backend.h"
#include "cpu/backend_cpu.h"

#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void *default_alloc(void *user, size_t size)
{
    (void)user;
    return malloc(size);
}

static void default_free(void *user, void *ptr)
{
    (void)user;
    free(ptr);
}

void ddof_context_options_init_sized(ddof_context_options *options, size_t size)
{
    if (!options || size < sizeof(uint32_t))
        return;
    const ddof_context_options full = {.struct_size = sizeof full};
    const size_t n = size < sizeof full ? size : sizeof full;
    memcpy(options, &full, n);
    options->struct_size = (uint32_t)n;
}

/* For binaries built against 0.5, whose struct has the 0.5 layout (ddof.h, Conventions). */
void (ddof_context_options_init)(ddof_context_options *options)
{
    ddof_context_options_init_sized(options, DDOF_CONTEXT_OPTIONS_SIZE_0_5);
}

static uint32_t online_cores(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1u : n > 256 ? 256u : (uint32_t)n;
}

ddof_status ddof_context_create(const ddof_context_options *options, ddof_context **out_context)
{
    if (!out_context)
        return DDOF_ERROR_NULL_POINTER;
    *out_context = NULL;
    ddof_context_options given;
    ddof_context_options_init(&given);
    if (options) {
        /* The 0.5 layout or newer; a newer caller's unknown trailing bytes must be zero. */
        if (options->struct_size < DDOF_CONTEXT_OPTIONS_SIZE_0_5 ||
            !ddof_struct_tail_is_zero(options, sizeof given))
            return DDOF_ERROR_BAD_PARAMETER;
        memcpy(&given, options, sizeof given < options->struct_size ? sizeof given
                                                                     : options->struct_size);
        given.struct_size = sizeof given;
    }
    options = &given;
    if (options->allocator && (!options->allocator->alloc || !options->allocator->free))
        return DDOF_ERROR_NULL_POINTER;
    if (options->thread_count > 1024)
        return DDOF_ERROR_BAD_PARAMETER;

    ddof_allocator allocator = {default_alloc, default_free, NULL};
    if (options->allocator)
        allocator = *options->allocator;
    ddof_context *context = ddof_alloc(&allocator, sizeof *context);
    if (!context)
        return DDOF_ERROR_OUT_OF_MEMORY;
    *context = (ddof_context){.allocator = allocator, .thread_count = 1, .cpu = &ddof_cpu_backend};
    ddof_backend_start(context);
    atomic_init(&context->in_use, 0);

    uint32_t threads = options->thread_count ? options->thread_count : online_cores();
    if (threads > 1) {
        ddof_status status = thread_pool_create(&allocator, threads - 1, &context->pool);
        if (status != DDOF_OK) {
            ddof_free(&allocator, context);
            return status;
        }
        context->thread_count = threads;
    }
    *out_context = context;
    return DDOF_OK;
}

void ddof_context_free(ddof_context *context)
{
    if (!context)
        return;
    ddof_backend_release(context);
    thread_pool_free(context->pool);
    ddof_allocator allocator = context->allocator;
    for (int i = 0; i < DDOF_SCRATCH_COUNT; i++)
        ddof_free(&allocator, context->scratch[i].memory);
    ddof_free(&allocator, context);
}
