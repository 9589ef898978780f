/* SPDX-License-Identifier: MIT */
/* gl_functions.c - fills the GL function table from a context's get_proc. */
#include "gl_functions.h"

#include <stdio.h>

int gl_functions_load(gl_functions *gl, gl_context *context, char *message, size_t size)
{
    gl_proc proc;
#define GL_FUNCTION_LOAD(type, name)                                                       \
    proc = context->ops->get_proc(context, "gl" #name);                                    \
    if (!proc) {                                                                           \
        snprintf(message, size, "the GL library has no gl" #name);                         \
        return 0;                                                                          \
    }                                                                                      \
    gl->name = (type)proc;
    GL_FUNCTION_LIST(GL_FUNCTION_LOAD)
#undef GL_FUNCTION_LOAD
    return 1;
}
