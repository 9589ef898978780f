/* SPDX-License-Identifier: MIT */
/* image_check.c - validation of caller-described images and versioned structs. */
#include "internal.h"

#include <string.h>

ddof_status ddof_check_struct(ddof_context *context, const void *ptr, size_t min_size,
                              const char *what)
{
    if (!ptr)
        return ddof_fail(context, DDOF_ERROR_NULL_POINTER, "%s is NULL", what);
    uint32_t size = *(const uint32_t *)ptr;
    if (size < min_size)
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "%s.struct_size is %u, expected at least %zu (call its _init function)",
                         what, size, min_size);
    return DDOF_OK;
}

ddof_status ddof_check_stats(ddof_context *context, const ddof_stats *stats)
{
    return stats ? ddof_check_struct(context, stats, DDOF_STATS_SIZE_0_1, "stats") : DDOF_OK;
}

int ddof_struct_tail_is_zero(const void *caller, size_t known)
{
    const uint32_t size = *(const uint32_t *)caller;
    const unsigned char *bytes = caller;
    for (size_t i = known; i < size; i++)
        if (bytes[i])
            return 0;
    return 1;
}

ddof_status ddof_read_struct(ddof_context *context, const void *caller, size_t min_size,
                             void *full, size_t full_size, const char *what)
{
    ddof_status status = ddof_check_struct(context, caller, min_size, what);
    if (status != DDOF_OK)
        return status;
    const uint32_t size = *(const uint32_t *)caller;
    /* Linux's copy_struct_from_user rule: a newer caller's struct is read when the fields this
     * library does not know are zero (their defaults), refused when one is set. */
    if (!ddof_struct_tail_is_zero(caller, full_size))
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "%s.struct_size is %u, larger than this library's %zu, and a field it "
                         "does not know is set (a newer caller: update libddof)",
                         what, size, full_size);
    memcpy(full, caller, size < full_size ? size : full_size);
    *(uint32_t *)full = (uint32_t)full_size;
    return DDOF_OK;
}

ddof_status ddof_check_image(ddof_context *context, const char *what, const float *pixels,
                             uint32_t width, uint32_t height, uint32_t channels, size_t row_stride,
                             size_t *stride_floats)
{
    return ddof_check_image_up_to(context, what, pixels, width, height, channels, 4, row_stride,
                                  stride_floats);
}

ddof_status ddof_check_coc_image(ddof_context *context, const char *what, ddof_image_in coc,
                                 uint32_t width, uint32_t height, size_t *stride_floats)
{
    const ddof_status status = ddof_check_image(context, what, coc.pixels, coc.width,
                                                coc.height, coc.channels, coc.row_stride,
                                                stride_floats);
    if (status != DDOF_OK)
        return status;
    if (coc.width != width || coc.height != height || coc.channels != 1)
        return ddof_fail(context, DDOF_ERROR_SIZE_MISMATCH,
                         "%s is %ux%u with %u channels; it must be %ux%u with 1 channel", what,
                         coc.width, coc.height, coc.channels, width, height);
    return DDOF_OK;
}

ddof_status ddof_check_image_up_to(ddof_context *context, const char *what, const float *pixels,
                                   uint32_t width, uint32_t height, uint32_t channels,
                                   uint32_t most_channels, size_t row_stride,
                                   size_t *stride_floats)
{
    if (!pixels)
        return ddof_fail(context, DDOF_ERROR_NULL_POINTER, "%s.pixels is NULL", what);
    if (width == 0 || height == 0 || width > DDOF_MAX_DIMENSION || height > DDOF_MAX_DIMENSION)
        return ddof_fail(context, DDOF_ERROR_BAD_SIZE, "%s is %ux%u; each side must be 1..%u",
                         what, width, height, DDOF_MAX_DIMENSION);
    if ((uint64_t)width * height > DDOF_MAX_PIXELS)
        return ddof_fail(context, DDOF_ERROR_BAD_SIZE, "%s is %ux%u, more than %u pixels", what,
                         width, height, DDOF_MAX_PIXELS);
    if (channels < 1 || channels > most_channels)
        return ddof_fail(context, DDOF_ERROR_BAD_CHANNELS, "%s has %u channels; 1..%u allowed",
                         what, channels, most_channels);
    const size_t row_bytes = (size_t)width * channels * sizeof(float);
    const size_t stride = row_stride ? row_stride : row_bytes;
    if (stride < row_bytes)
        return ddof_fail(context, DDOF_ERROR_BAD_STRIDE,
                         "%s row stride %zu bytes is smaller than a row (%zu bytes)", what,
                         stride, row_bytes);
    if (stride % sizeof(float))
        return ddof_fail(context, DDOF_ERROR_BAD_STRIDE,
                         "%s row stride %zu bytes is not a multiple of 4", what, stride);
    if ((height - 1) > (SIZE_MAX - row_bytes) / stride)
        return ddof_fail(context, DDOF_ERROR_BAD_STRIDE,
                         "%s row stride %zu bytes times %u rows overflows the address space",
                         what, stride, height);
    *stride_floats = stride / sizeof(float);
    return DDOF_OK;
}

ddof_image_bytes ddof_image_bytes_of(const float *pixels, uint32_t width, uint32_t height,
                                     uint32_t channels, size_t row_stride)
{
    const size_t row = (size_t)width * channels * sizeof(float);
    const uintptr_t lo = (uintptr_t)pixels;
    const size_t stride = row_stride ? row_stride : row;
    return (ddof_image_bytes){lo, lo + (size_t)(height - 1) * stride + row};
}

ddof_status ddof_check_apart(ddof_context *context, const char *what, ddof_image_bytes a,
                             const char *other, ddof_image_bytes b)
{
    if (a.lo < b.hi && b.lo < a.hi)
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "%s overlaps %s in memory; an image the call writes must not share a "
                         "byte with another image of the call", what, other);
    return DDOF_OK;
}
