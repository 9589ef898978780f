/* SPDX-License-Identifier: MIT */
/* gl_device.h - an opened GL backend: its context, function table, compiled programs and
 * working buffers. The core sees it as the opaque ddof_device of ddof_backend_seam.h. */
#ifndef DDOF_GL_DEVICE_H
#define DDOF_GL_DEVICE_H

#include "ddof_backend_seam.h"
#include "gl_buffers.h"
#include "gl_functions.h"
#include "gl_programs.h"

struct ddof_device {
    ddof_backend_kind kind;
    gl_context *context;
    gl_functions gl;
    gl_programs programs;
    gl_buffers buffers;
    ddof_device_info info;
    uint64_t max_buffer_bytes; /* GL_MAX_SHADER_STORAGE_BLOCK_SIZE */
    uint64_t buffer_alignment; /* GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT: bound ranges */
    /* Host <-> device image transfers of the current call (adi_report's uploads and
     * readbacks): counted where they happen (gl_io.c), so no path can transfer uncounted. */
    uint32_t uploads, readbacks;
    GLuint cards_program; /* gl_cards.c's vertex and fragment program, built on first use */
};

/* Opens a device on a new (or, for HOST_GL, the current) context; the context is released
 * again on return. NULL with a sentence in message on failure. */
ddof_device *gl_device_open(ddof_backend_kind kind, int require_hardware, char *message,
                            size_t message_size);
void gl_device_close(ddof_device *device);

/* Makes the device's context current (1) or says why not (0, message). */
int gl_device_begin(ddof_device *device, char *message, size_t message_size);
void gl_device_end(ddof_device *device);

#endif
