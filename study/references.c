/* SPDX-License-Identifier: MIT */
/* references.c - the double-precision solve of a diffusion configuration's settings, the
 * reference its solver and precision error is measured against, cached per scene. */
#include "study.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The double-precision reference of a diffusion configuration, cached by its settings. */
typedef struct ref_entry {
    char key[96];
    char scene[128];
    float *image;
    uint64_t used;
} ref_entry;

#define REF_CACHE 24
static ref_entry ref_cache[REF_CACHE];
static uint64_t ref_clock;
static double ref_seconds; /* spent computing references (the sweep's overhead) */

void study_references_clear(void)
{
    for (int i = 0; i < REF_CACHE; i++) {
        free(ref_cache[i].image);
        memset(&ref_cache[i], 0, sizeof ref_cache[i]);
    }
}

const float *study_reference_image(ddof_context *ctx, const study_scene *scene,
                                   const study_config *cfg, char *error, size_t size)
{
    study_config r = *cfg;
    r.backend = DDOF_BACKEND_CPU;
    r.solver = DDOF_SOLVER_REFERENCE_F64;
    r.precision = DDOF_PRECISION_FLOAT;
    r.jacobi_iterations = 50;
    study_config_make_id(&r);
    ref_entry *slot = &ref_cache[0];
    for (int i = 0; i < REF_CACHE; i++) {
        ref_entry *e = &ref_cache[i];
        if (e->image && !strcmp(e->key, r.id) && !strcmp(e->scene, scene->name)) {
            e->used = ++ref_clock;
            return e->image;
        }
        if (!e->image || e->used < slot->used)
            slot = e;
        if (!e->image)
            break;
    }
    const size_t pixels = (size_t)scene->small.width * scene->small.height;
    if (!slot->image)
        slot->image = malloc(pixels * 4 * sizeof(float));
    if (!slot->image) {
        snprintf(error, size, "out of memory");
        return NULL;
    }
    study_call c = {.cfg = &r, .scene = scene, .frame = &scene->small, .ctx = ctx,
                    .out = slot->image};
    const double t0 = study_now();
    ddof_status st = study_run_call(&c);
    ref_seconds += study_now() - t0;
    if (st != DDOF_OK) {
        snprintf(error, size, "reference: %s", c.error);
        free(slot->image);
        memset(slot, 0, sizeof *slot);
        return NULL;
    }
    snprintf(slot->key, sizeof slot->key, "%s", r.id);
    snprintf(slot->scene, sizeof slot->scene, "%s", scene->name);
    slot->used = ++ref_clock;
    return slot->image;
}

double study_references_seconds(void)
{
    return ref_seconds;
}
