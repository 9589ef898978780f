/* SPDX-License-Identifier: MIT */
/* gl_library.c - dlopen/dlsym for the GL libraries (see gl_library.h). */
#define _GNU_SOURCE /* RTLD_NOLOAD */
#include "gl_library.h"

#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void *gl_library_open(const char *env_var, const char *const *names, char *message,
                      size_t message_size)
{
    const char *chosen = env_var ? getenv(env_var) : NULL;
    if (chosen && chosen[0]) {
        void *handle = dlopen(chosen, RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            const char *why = dlerror();
            snprintf(message, message_size, "%s=%s could not be loaded (%s)", env_var, chosen,
                     why ? why : "unknown error");
        }
        return handle;
    }
    char first_error[256] = "";
    for (size_t i = 0; names[i]; i++) {
        void *handle = dlopen(names[i], RTLD_NOW | RTLD_LOCAL);
        if (handle)
            return handle;
        const char *why = dlerror();
        if (!first_error[0])
            snprintf(first_error, sizeof first_error, "%s", why ? why : names[i]);
    }
    snprintf(message, message_size, "%s is not installed (%s)", names[0], first_error);
    return NULL;
}

void *gl_library_find_loaded(const char *const *names)
{
    for (size_t i = 0; names[i]; i++) {
        void *handle = dlopen(names[i], RTLD_NOW | RTLD_LOCAL | RTLD_NOLOAD);
        if (handle)
            return handle;
    }
    return NULL;
}

gl_proc gl_library_symbol(void *library, const char *name)
{
    void *symbol = dlsym(library, name);
    gl_proc proc = NULL;
    memcpy(&proc, &symbol, sizeof proc); /* ISO C has no object-to-function pointer cast */
    return proc;
}
