/* SPDX-License-Identifier: MIT */
/* gl_test.h - what the GL tests share: opening a backend (a missing EGL is a skip, exit 77),
 * the cases they run, and error measures. Everything static inline, as in ../test_images.h. */
#ifndef DDOF_GL_TEST_H
#define DDOF_GL_TEST_H

#include "ddof.h"
#include "test_images.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define GL_TEST_SKIP 77 /* ctest SKIP_RETURN_CODE */

static inline ddof_backend_kind backend_from_name(const char *name)
{
    if (name && strcmp(name, "egl") == 0)
        return DDOF_BACKEND_EGL;
    return DDOF_BACKEND_OSMESA;
}

/* A context on `kind` (the plugin built beside this test, DDOF_TEST_GL_PLUGIN), or NULL when
 * the backend is unavailable (the reason printed). */
static inline ddof_context *gl_context_for(ddof_backend_kind kind)
{
    ddof_context *ctx = make_context(0);
    ddof_status s = ddof_context_set_backend(ctx, kind, DDOF_TEST_GL_PLUGIN);
    if (s != DDOF_OK) {
        printf("backend %s unavailable: %s\n", ddof_backend_name(kind),
               ddof_context_last_error(ctx));
        ddof_context_free(ctx);
        return NULL;
    }
    ddof_backend_info info = {.struct_size = sizeof info};
    ddof_context_backend_info(ctx, &info);
    printf("backend %s: %s\n", ddof_backend_name(kind), info.renderer);
    return ctx;
}

/* max |a - b| over n floats, NaN counting as infinitely wrong. */
static inline double max_diff(const float *a, const float *b, size_t n)
{
    double worst = 0.0;
    for (size_t i = 0; i < n; i++) {
        const double d = fabs((double)a[i] - (double)b[i]);
        if (!(d <= worst))
            worst = isnan(d) ? INFINITY : d;
    }
    return worst;
}

/* RMS of got - want over n floats, as a share of want's mean magnitude; +inf where a value is
 * not finite. */
static inline double relative_rms(const float *got, const float *want, size_t n)
{
    double squares = 0.0, magnitude = 0.0;
    for (size_t i = 0; i < n; i++) {
        const double d = (double)got[i] - want[i];
        squares += isfinite(d) ? d * d : INFINITY;
        magnitude += fabs(want[i]);
    }
    return sqrt(squares / (double)n) / (magnitude / (double)n + 1e-6);
}

/* A device's plan without its "layers: on ..." line (where the layers ran), for comparing
 * with the CPU's, which has none; into out (size bytes). */
static inline void plan_without_device_line(const char *plan, char *out, size_t size)
{
    size_t used = 0;
    for (const char *line = plan; *line;) {
        const size_t length = strcspn(line, "\n") + (line[strcspn(line, "\n")] == '\n');
        if (strncmp(line, "layers: ", 8) != 0 && used + length < size) {
            memcpy(out + used, line, length);
            used += length;
        }
        line += length;
    }
    out[used] = '\0';
}

/* A pass that runs on the device inside the frame's one upload and one read-back: the same
 * effects as the CPU's frame, and none of the pass's host scratch (`pass_bytes`: what the CPU
 * holds for it) on the host. Uses test_util.h's checks. */
#define CHECK_PASS_ON_DEVICE(name, sc, sg, pass_bytes)                                        \
    do {                                                                                      \
        CHECK_EQ_INT((sg).effects, (sc).effects);                                             \
        CHECK_EQ_INT((sg).device_uploads, 1);                                                 \
        CHECK_EQ_INT((sg).device_readbacks, 1);                                               \
        CHECK_MSG((sg).host_bytes + (pass_bytes) <= (sc).host_bytes,                          \
                  "%s: GL host scratch %llu, the CPU's %llu", name,                           \
                  (unsigned long long)(sg).host_bytes, (unsigned long long)(sc).host_bytes); \
    } while (0)

static inline int verbose_test(void)
{
    const char *v = getenv("DDOF_TEST_VERBOSE");
    return v && v[0] && v[0] != '0';
}

#endif
