/* SPDX-License-Identifier: MIT */
/* ddof_output_struct.h - ddof.h's rule for an output struct (ddof_stats, ddof_backend_info,
 * ddof_kernel_info), shared by the core and the GL plugin's host calls so that both write
 * one way: the first min(struct_size, the library's own size) bytes, and struct_size then
 * says how many were written (a newer caller's larger struct learns which fields an older
 * library filled). The caller checked struct_size against the first layout beforehand. */
#ifndef DDOF_OUTPUT_STRUCT_H
#define DDOF_OUTPUT_STRUCT_H

#include <stdint.h>
#include <string.h>

static inline void ddof_write_output_struct(void *caller, const void *full, size_t full_size)
{
    uint32_t size;
    memcpy(&size, caller, sizeof size);
    const size_t n = size < full_size ? size : full_size;
    memcpy(caller, full, n);
    const uint32_t written = (uint32_t)n;
    memcpy(caller, &written, sizeof written);
}

#endif
