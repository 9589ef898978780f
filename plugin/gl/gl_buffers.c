/* SPDX-License-Identifier: MIT */
/* gl_buffers.c - grow-only GPU buffers per slot (see gl_buffers.h). */
#include "gl_buffers.h"

#include <string.h>

void gl_buffers_begin(gl_buffers *buffers)
{
    memset(buffers->used, 0, sizeof buffers->used);
}

GLuint gl_buffers_get(const gl_functions *gl, gl_buffers *buffers, gl_buffer_slot slot,
                      uint64_t bytes)
{
    if (bytes < 16)
        bytes = 16; /* an empty buffer cannot be bound */
    if (buffers->used[slot] < bytes)
        buffers->used[slot] = bytes;
    if (buffers->name[slot] && buffers->capacity[slot] >= bytes)
        return buffers->name[slot];
    if (buffers->name[slot])
        gl->DeleteBuffers(1, &buffers->name[slot]);
    buffers->name[slot] = 0;
    buffers->capacity[slot] = 0;
    while (gl->GetError() != GL_NO_ERROR) {
    }
    GLuint name = 0;
    gl->GenBuffers(1, &name);
    gl->BindBuffer(GL_SHADER_STORAGE_BUFFER, name);
    gl->BufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)bytes, NULL, GL_DYNAMIC_COPY);
    gl->BindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    if (gl->GetError() != GL_NO_ERROR) {
        gl->DeleteBuffers(1, &name);
        return 0;
    }
    buffers->name[slot] = name;
    buffers->capacity[slot] = bytes;
    return name;
}

uint64_t gl_buffers_used(const gl_buffers *buffers)
{
    uint64_t sum = 0;
    for (int i = 0; i < GL_BUF_COUNT; i++)
        sum += buffers->used[i];
    return sum;
}

void gl_buffers_free(const gl_functions *gl, gl_buffers *buffers)
{
    for (int i = 0; i < GL_BUF_COUNT; i++)
        if (buffers->name[i])
            gl->DeleteBuffers(1, &buffers->name[i]);
    memset(buffers, 0, sizeof *buffers);
}
