/* SPDX-License-Identifier: MIT */
/* gl_library.h - loading GL libraries at run time without letting their symbols leak. */
#ifndef DDOF_GL_LIBRARY_H
#define DDOF_GL_LIBRARY_H

#include <stddef.h>

/* Any function pointer: what *GetProcAddress return. Casting between function pointer types
 * is valid C; from dlsym's void * it is not, so gl_library_symbol copies the bits instead. */
typedef void (*gl_proc)(void);

/* dlopen(RTLD_NOW | RTLD_LOCAL) of the file the environment variable `env_var` names when it is
 * set (so a test or a user can point at another build, or at nothing to simulate missing GL),
 * else of the first of `names` (NULL-terminated) that loads. The handle is never closed: Mesa
 * does not support being unloaded and loaded again in one process. NULL with a sentence in
 * message on failure. */
void *gl_library_open(const char *env_var, const char *const *names, char *message,
                      size_t message_size);

/* The library among `names` that is already loaded in the process (RTLD_NOLOAD), or NULL. */
void *gl_library_find_loaded(const char *const *names);

/* dlsym as a function pointer; NULL when absent. */
gl_proc gl_library_symbol(void *library, const char *name);

#endif
