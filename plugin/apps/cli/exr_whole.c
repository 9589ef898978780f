/* SPDX-License-Identifier: MIT */
/* exr_whole.c - every chunk of an EXR within the file (exr_whole.h). */
#include "exr_whole.h"

#include <openexr.h>

#include <stdint.h>
#include <sys/stat.h>

/* OpenEXR's messages would go to stderr: the answer is all that is wanted. */
static void quiet(exr_const_context_t ctxt, exr_result_t code, const char *message)
{
    (void)ctxt;
    (void)code;
    (void)message;
}

/* 1 when every chunk of scanline part `p` lies within `size` bytes. */
static int part_whole(exr_const_context_t ctxt, int p, uint64_t size)
{
    exr_storage_t storage;
    exr_attr_box2i_t window;
    int32_t chunks = 0, lines = 0;
    if (exr_get_storage(ctxt, p, &storage) != EXR_ERR_SUCCESS ||
        storage != EXR_STORAGE_SCANLINE ||
        exr_get_chunk_count(ctxt, p, &chunks) != EXR_ERR_SUCCESS ||
        exr_get_scanlines_per_chunk(ctxt, p, &lines) != EXR_ERR_SUCCESS || lines < 1 ||
        exr_get_data_window(ctxt, p, &window) != EXR_ERR_SUCCESS)
        return 0;
    for (int32_t i = 0; i < chunks; i++) {
        exr_chunk_info_t chunk;
        const int64_t y = (int64_t)window.min.y + (int64_t)i * lines;
        if (y > INT32_MAX ||
            exr_read_scanline_chunk_info(ctxt, p, (int)y, &chunk) != EXR_ERR_SUCCESS ||
            chunk.data_offset > size || chunk.packed_size > size - chunk.data_offset)
            return 0;
    }
    return 1;
}

int exr_file_whole(const char *path)
{
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    exr_context_t ctxt = NULL;
    struct stat st;
    int parts = 0, whole;
    if (stat(path, &st) != 0 || !S_ISREG(st.st_mode))
        return 0;
    init.error_handler_fn = quiet;
    if (exr_start_read(&ctxt, path, &init) != EXR_ERR_SUCCESS) {
        exr_finish(&ctxt);
        return 0;
    }
    whole = exr_get_count(ctxt, &parts) == EXR_ERR_SUCCESS && parts > 0;
    for (int p = 0; whole && p < parts; p++)
        whole = part_whole(ctxt, p, (uint64_t)st.st_size);
    exr_finish(&ctxt);
    return whole;
}
