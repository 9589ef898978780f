/* SPDX-License-Identifier: MIT */
/* errors.c - status strings, and the context's last error and last plan (each call on the
 * context starts without them). */
#include "internal.h"

#include <stdio.h>

const char *ddof_status_string(ddof_status status)
{
    switch (status) {
    case DDOF_OK: return "success";
    case DDOF_ERROR_NULL_POINTER: return "a required pointer argument is NULL";
    case DDOF_ERROR_BAD_PARAMETER: return "a parameter is out of range or a struct is malformed";
    case DDOF_ERROR_BAD_SIZE: return "image width or height is zero or too large";
    case DDOF_ERROR_BAD_STRIDE: return "image row stride is too small, misaligned or overflows";
    case DDOF_ERROR_BAD_CHANNELS: return "image channel count is not 1 to 4";
    case DDOF_ERROR_SIZE_MISMATCH: return "images of one call differ in size or channel count";
    case DDOF_ERROR_BAD_COLOR: return "colour contains NaN, infinity or a value beyond DDOF_MAX_COLOR";
    case DDOF_ERROR_BAD_DEPTH: return "depth contains NaN, -infinity, zero or negative values";
    case DDOF_ERROR_BAD_COC: return "circle of confusion is NaN, infinite, negative or too large";
    case DDOF_ERROR_BAD_CAMERA: return "camera parameters are invalid";
    case DDOF_ERROR_OUT_OF_MEMORY: return "out of memory";
    case DDOF_ERROR_THREADS: return "a worker thread could not be started";
    case DDOF_ERROR_CANCELLED: return "cancelled by the progress callback";
    case DDOF_ERROR_BACKEND_UNAVAILABLE: return "the requested GL backend is not available";
    case DDOF_ERROR_UNSUPPORTED: return "the backend does not support this solver or precision";
    case DDOF_ERROR_BACKEND_FAILED: return "the GL backend failed during the call";
    case DDOF_ERROR_CONTEXT_BUSY:
        return "another call is running on this context (one context per thread)";
    case DDOF_STATUS_COUNT_:
    case DDOF_STATUS_FORCE_32BIT_: break;
    }
    return "unknown status code";
}

ddof_status ddof_fail(ddof_context *context, ddof_status status, const char *format, ...)
{
    if (context) {
        va_list args;
        va_start(args, format);
        vsnprintf(context->last_error, sizeof context->last_error, format, args);
        va_end(args);
    }
    return status;
}

void ddof_start_call(ddof_context *context)
{
    if (context) {
        context->last_error[0] = '\0';
        context->last_plan[0] = '\0';
    }
}

const char *ddof_context_last_error(const ddof_context *context)
{
    return context ? context->last_error : "no context";
}

const char *ddof_context_last_plan(const ddof_context *context)
{
    return context ? context->last_plan : "";
}
