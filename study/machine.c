/* SPDX-License-Identifier: MIT */
/* machine.c - the machine line of results.jsonl: the CPU, memory, OS, compiler, ddof's version,
 * the options of the sweep and which GL backends could be opened. */
#include "study.h"

#include <cJSON.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/utsname.h>
#include <time.h>
#include <unistd.h>

#ifndef DDOF_STUDY_BUILD_TYPE
#define DDOF_STUDY_BUILD_TYPE "unknown"
#endif

static void first_line_value(const char *path, const char *key, char *out, size_t size)
{
    out[0] = '\0';
    FILE *f = fopen(path, "r");
    if (!f)
        return;
    char line[1024];
    const size_t n = strlen(key);
    while (fgets(line, sizeof line, f)) {
        if (strncmp(line, key, n))
            continue;
        const char *v = line + n;
        while (*v == ' ' || *v == '\t' || *v == ':' || *v == '=' || *v == '"')
            v++;
        snprintf(out, size, "%s", v);
        size_t len = strlen(out);
        while (len && (out[len - 1] == '\n' || out[len - 1] == '"' || out[len - 1] == ' '))
            out[--len] = '\0';
        break;
    }
    fclose(f);
}

cJSON *study_machine_json(const study_options *o)
{
    cJSON *m = cJSON_CreateObject();
    char buf[512];
    cJSON_AddStringToObject(m, "type", "machine");
    time_t now = time(NULL);
    struct tm tm;
    gmtime_r(&now, &tm);
    strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
    cJSON_AddStringToObject(m, "date_utc", buf);
    first_line_value("/proc/cpuinfo", "model name", buf, sizeof buf);
    cJSON_AddStringToObject(m, "cpu", buf);
    first_line_value("/proc/cpuinfo", "flags", buf, sizeof buf);
    cJSON_AddBoolToObject(m, "avx512", strstr(buf, "avx512f") != NULL);
    cJSON_AddNumberToObject(m, "cores", (double)sysconf(_SC_NPROCESSORS_ONLN));
    first_line_value("/proc/meminfo", "MemTotal", buf, sizeof buf);
    cJSON_AddNumberToObject(m, "memory_bytes", atof(buf) * 1024.0);
    first_line_value("/etc/os-release", "PRETTY_NAME", buf, sizeof buf);
    cJSON_AddStringToObject(m, "os", buf);
    struct utsname u;
    if (uname(&u) == 0) {
        snprintf(buf, sizeof buf, "%s %s %s", u.sysname, u.release, u.machine);
        cJSON_AddStringToObject(m, "kernel", buf);
    }
#ifdef __VERSION__
    cJSON_AddStringToObject(m, "compiler", "cc " __VERSION__);
#endif

    cJSON_AddStringToObject(m, "build_type", DDOF_STUDY_BUILD_TYPE);
    cJSON_AddStringToObject(m, "ddof_version", ddof_version_string());
    ddof_context *ctx;
    if (study_cpu_context(o, &ctx) == DDOF_OK) {
        cJSON_AddNumberToObject(m, "threads", ddof_context_thread_count(ctx));
        ddof_context_free(ctx);
    }
    cJSON *opts = cJSON_AddObjectToObject(m, "options");
    cJSON_AddNumberToObject(opts, "reps", o->reps_small);
    cJSON_AddNumberToObject(opts, "large_reps", o->reps_large);
    cJSON_AddNumberToObject(opts, "large_limit_s", o->large_limit);
    cJSON_AddBoolToObject(opts, "large", o->large);
    cJSON *gl = cJSON_AddObjectToObject(m, "gl");
    for (int i = 0; i < STUDY_GL_BACKEND_COUNT; i++) {
        study_gl_backend *b = study_gl_get(o, study_gl_backend_kinds[i]);
        cJSON *e = cJSON_AddObjectToObject(gl, ddof_backend_name(b->kind));
        cJSON_AddBoolToObject(e, "available", b->ctx != NULL);
        if (b->renderer[0])
            cJSON_AddStringToObject(e, "renderer", b->renderer);
        if (!b->ctx)
            cJSON_AddStringToObject(e, "why", b->why);
        if (b->renderer[0])
            cJSON_AddBoolToObject(e, "hardware", b->hardware);
    }
    return m;
}
