/* SPDX-License-Identifier: MIT */
/* frame.c - how a frame fails: one message in its result. */
#include "frame.h"

#include <stdarg.h>
#include <stdio.h>

int frame_fail(frame_result *result, const char *format, ...)
{
    va_list args;
    va_start(args, format);
    vsnprintf(result->error, sizeof result->error, format, args);
    va_end(args);
    result->ok = 0;
    return -1;
}

