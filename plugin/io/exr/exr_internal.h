/* SPDX-License-Identifier: MIT */
/* exr_internal.h - what the files of plugin/io/exr/ share: the stream that connects OpenEXR's C
 * core to a file descriptor, and how its error messages are caught instead of printed. */
#ifndef DDOF_EXR_INTERNAL_H
#define DDOF_EXR_INTERNAL_H

#include "exrio.h"

#include <openexr.h>

#include <stddef.h>
#include <stdint.h>

/* The user data of every OpenEXR context made here. We give the core our own read/write
 * functions on a file descriptor (rather than letting it open the file by name) so that
 * (a) the error callback can find this struct through exr_get_user_data(), (b) writing goes to
 * the temporary file the caller created and registered for clean-up, and (c) I/O errors keep
 * their errno. */
typedef struct exrio_stream {
    int fd;
    int64_t size;              /* of the file being read; -1 when writing                   */
    int saved_errno;           /* errno of the last failed read or write, 0 if none           */
    exr_result_t last_code;    /* code of the last error the core reported                  */
    char message[512];         /* and its message                                            */
} exrio_stream;

/* An initializer for a context that reads or writes through `stream`, reports errors into it
 * (never to stderr), and allows any image size (ddof checks sizes itself). */
exr_context_initializer_t exrio_stream_initializer(exrio_stream *stream, int for_write);
/* Where the core's errors raised on this thread are recorded, NULL to stop: the write
 * context's handler needs it (see exr_common.c), and a thread that decodes or encodes chunks of
 * a context shared with other threads records into its own stream rather than the shared one. */
void exrio_set_error_sink(exrio_stream *sink);

/* The most threads one file's chunks are shared among: beyond, a thread's start costs more than
 * its share of a frame's chunks saves. */
#define EXRIO_MAX_WORKERS 64u

/* Runs work(arg, i) for i = 0 .. count-1, i > 0 on new threads and 0 on the calling thread,
 * and waits for all. A thread that cannot be started is not run: each worker takes chunks from
 * a shared counter, so fewer workers do the same work. */
void exrio_run_workers(unsigned count, void (*work)(void *arg, unsigned index), void *arg);

/* Formats "NAME: WHAT: core message" into error, preferring the core's own message when it
 * has one. Returns `status` so that callers can `return exrio_fail(...)`. */
exrio_status exrio_fail(exrio_status status, const exrio_stream *stream, char *error,
                        size_t error_size, const char *name, const char *what, exr_result_t rv);

/* Copies the header attributes of source part `part` into output part 0 of `out`, except the
 * attributes that describe the pixel layout (those the writer sets itself). */
exr_result_t exrio_copy_metadata(exr_context_t out, exr_const_context_t source, int part);

#endif
