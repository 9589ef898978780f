/* SPDX-License-Identifier: MIT */
/* exr_common.c - names of compressions and pixel types, the file-descriptor stream given to
 * OpenEXR's C core, error formatting, channel look-up and freeing an image. */
#include "exr_internal.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

static const char *const compression_names[EXRIO_COMPRESSION_COUNT_] = {
    "none", "rle", "zips", "zip", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab"};

const char *exrio_compression_name(exrio_compression compression)
{
    if ((unsigned)compression >= EXRIO_COMPRESSION_COUNT_)
        return "?";
    return compression_names[compression];
}

int exrio_compression_parse(const char *name, exrio_compression *out)
{
    int i;
    for (i = 0; i < EXRIO_COMPRESSION_COUNT_; i++) {
        if (strcasecmp(name, compression_names[i]) == 0) {
            *out = (exrio_compression)i;
            return 0;
        }
    }
    return -1;
}

/* OpenEXR 3.1's C core implements every method but DWAA/DWAB, in both directions (its
 * internal_dwa.c returns "not yet implemented in C"); those go through the C++ library
 * (exr_dwa.cpp). */
int exrio_compression_can_decode(exrio_compression compression)
{
    return (unsigned)compression < EXRIO_COMPRESSION_COUNT_;
}

int exrio_compression_can_encode(exrio_compression compression)
{
    return exrio_compression_can_decode(compression);
}

int exrio_compression_is_dwa(exrio_compression compression)
{
    return compression == EXRIO_COMPRESSION_DWAA || compression == EXRIO_COMPRESSION_DWAB;
}

const char *exrio_pixel_type_name(exrio_pixel_type type)
{
    switch (type) {
    case EXRIO_UINT:
        return "uint";
    case EXRIO_HALF:
        return "half";
    case EXRIO_FLOAT:
        return "float";
    }
    return "?";
}

/* ---- the stream ------------------------------------------------------------------------- */

/* While writing, the core calls the error handler with the context's lock held, and
 * exr_get_user_data takes that lock again: the thread would deadlock. A write context's errors
 * therefore go to this thread's sink (set by exrio_set_error_sink around the write and in each
 * of its worker threads). Reading takes no lock there, so a read's errors go to the context's
 * stream, unless the thread has a sink of its own: the workers of a parallel decode do, so that
 * two failing chunks never write one message at once. */
static _Thread_local exrio_stream *error_sink;

static void record_error(exrio_stream *stream, exr_result_t code, const char *msg)
{
    stream->last_code = code;
    snprintf(stream->message, sizeof stream->message, "%s", msg ? msg : "");
}

static void stream_error_handler(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    void *user = NULL;
    if (error_sink) {
        record_error(error_sink, code, msg);
        return;
    }
    if (exr_get_user_data(ctxt, &user) != EXR_ERR_SUCCESS || !user)
        return;
    record_error(user, code, msg);
}

static void write_error_handler(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    (void)ctxt;
    if (error_sink)
        record_error(error_sink, code, msg);
}

void exrio_set_error_sink(exrio_stream *sink)
{
    error_sink = sink;
}

/* Where an I/O error's errno goes: the thread's sink when it has one (a worker's own record). */
static void save_errno(exrio_stream *stream, int e)
{
    (error_sink ? error_sink : stream)->saved_errno = e;
}

/* pread into `into` (reading) or pwrite from `from` until `size` bytes are done, again after
 * EINTR; a read also stops at the end of the file (the core treats a short count as
 * truncation). The bytes done, or -1 with errno saved. */
static int64_t transfer(exrio_stream *stream, int reading, uint8_t *into, const uint8_t *from,
                        uint64_t size, uint64_t offset)
{
    uint64_t done = 0;
    while (done < size) {
        const size_t count = (size_t)(size - done);
        const off_t at = (off_t)(offset + done);
        const ssize_t n = reading ? pread(stream->fd, into + done, count, at)
                                  : pwrite(stream->fd, from + done, count, at);
        if (n < 0) {
            if (errno == EINTR)
                continue;
            save_errno(stream, errno);
            return -1;
        }
        if (n == 0 && reading)
            break;
        done += (uint64_t)n;
    }
    return (int64_t)done;
}

static int64_t stream_read(exr_const_context_t ctxt, void *user, void *buffer, uint64_t size,
                           uint64_t offset, exr_stream_error_func_ptr_t error_cb)
{
    (void)ctxt;
    (void)error_cb;
    return transfer(user, 1, buffer, NULL, size, offset);
}

static int64_t stream_size(exr_const_context_t ctxt, void *user)
{
    (void)ctxt;
    return ((exrio_stream *)user)->size;
}

static int64_t stream_write(exr_const_context_t ctxt, void *user, const void *buffer,
                            uint64_t size, uint64_t offset, exr_stream_error_func_ptr_t error_cb)
{
    (void)ctxt;
    (void)error_cb;
    return transfer(user, 0, NULL, buffer, size, offset);
}

exr_context_initializer_t exrio_stream_initializer(exrio_stream *stream, int for_write)
{
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = for_write ? write_error_handler : stream_error_handler;
    init.user_data = stream;
    if (for_write) {
        init.write_fn = stream_write;
    } else {
        init.read_fn = stream_read;
        init.size_fn = stream_size;
    }
    /* 0 disables the core's size limits: ddof checks image sizes itself, with its own limits. */
    init.max_image_width = 0;
    init.max_image_height = 0;
    init.max_tile_width = 0;
    init.max_tile_height = 0;
    return init;
}

exrio_status exrio_fail(exrio_status status, const exrio_stream *stream, char *error,
                        size_t error_size, const char *name, const char *what, exr_result_t rv)
{
    const char *detail;
    if (stream && stream->saved_errno != 0)
        detail = strerror(stream->saved_errno);
    else if (stream && stream->message[0] != '\0')
        detail = stream->message;
    else
        detail = exr_get_default_error_message(rv);
    snprintf(error, error_size, "%s: %s: %s", name, what, detail);
    return status;
}

/* ---- images ----------------------------------------------------------------------------- */

int exrio_find_channel(const exrio_image *image, const char *name, int part)
{
    int i;
    for (i = 0; i < image->channel_count; i++)
        if ((part < 0 || image->channels[i].part == part) &&
            strcmp(image->channels[i].name, name) == 0)
            return i;
    return -1;
}

void exrio_close(exrio_image *image)
{
    int i;
    if (!image)
        return;
    if (image->source_) {
        exr_context_t ctxt = image->source_;
        exrio_stream *stream = NULL;
        void *user = NULL;
        if (exr_get_user_data(ctxt, &user) == EXR_ERR_SUCCESS)
            stream = user;
        exr_finish(&ctxt);
        if (stream) {
            close(stream->fd);
            free(stream);
        }
    }
    for (i = 0; i < image->channel_count; i++) {
        free(image->channels[i].name);
        free(image->channels[i].pixels);
    }
    for (i = 0; i < image->part_count; i++)
        free(image->parts[i].name);
    free(image->channels);
    free(image->parts);
    free(image->path);
    memset(image, 0, sizeof *image);
}
