/* SPDX-License-Identifier: MIT */
/* call.c - one call of a configuration on one frame (the diffusion, the CoD4 preview or a
 * baseline), and its timing. */
#include "study.h"

#ifdef DDOF_STUDY_HAVE_GATHER
#include "gather_blur.h"
#endif

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

ddof_status study_run_call(study_call *c)
{
    const study_frame *f = c->frame;
    const size_t pixels = (size_t)f->width * f->height;
    c->stats = (ddof_stats){.struct_size = sizeof c->stats};
    switch (c->cfg->kind) {
    case STUDY_PINHOLE:
        memcpy(c->out, f->rgba, pixels * 4 * sizeof(float));
        return DDOF_OK;
    case STUDY_DEFOCUS:
        return DDOF_ERROR_UNSUPPORTED;
    case STUDY_GATHER:
#ifdef DDOF_STUDY_HAVE_GATHER
        if (ddof_gather_blur(f->rgba, c->abs_coc, f->width, f->height, 4, c->out,
                             ddof_context_thread_count(c->ctx)) != 0) {
            snprintf(c->error, sizeof c->error, "ddof_gather_blur failed");
            return DDOF_ERROR_BAD_PARAMETER;
        }
        return DDOF_OK;
#else
        snprintf(c->error, sizeof c->error, "study/baselines/gather_blur.c is not built");
        return DDOF_ERROR_UNSUPPORTED;
#endif

    case STUDY_COD4:
    case STUDY_DIFFUSION:
        break;
    }
    const int fg = study_config_uses_fg(c->cfg, f->fg_rgba != NULL);
    /* The paper's layers: the element over the rest of the scene rendered without it. */
    const int rest = fg && c->cfg->layers == LAYERS_FG && f->rest_rgba != NULL;
    ddof_params p;
    study_config_params(c->cfg, fg, &p);
    p.pixel_aspect = (float)c->scene->camera.pixel_aspect;
    ddof_image_in color = {rest ? f->rest_rgba : f->rgba, f->width, f->height, 4, 0};
    ddof_image_in coc = {rest ? f->rest_coc : f->coc, f->width, f->height, 1, 0};
    ddof_image out = {c->out, f->width, f->height, 4, 0};
    ddof_foreground element;
    ddof_foreground_init(&element);
    if (fg) {
        element.color = (ddof_image_in){f->fg_rgba, f->width, f->height, 4, 0};
        element.coc = (ddof_image_in){f->fg_coc, f->width, f->height, 1, 0};
        element.premultiplied = 1;
    }
    ddof_status st;
    if (c->cfg->matte) {
        /* The scene's object matte for the split: the frame call that takes one. */
        if (!f->matte_ranks) {
            snprintf(c->error, sizeof c->error, "%s has no matte.exr (per scene: the tables "
                     "of the presets against the baselines)", c->scene->name);
            return DDOF_ERROR_UNSUPPORTED;
        }
        ddof_frame frame;
        ddof_frame_init(&frame);
        frame.color = color;
        frame.coc = coc;
        if (fg) {
            frame.foreground_color = element.color;
            frame.foreground_coc = element.coc;
            frame.foreground_premultiplied = 1;
        }
        const ddof_image_in matte = {f->matte, f->width, f->height, 2 * f->matte_ranks, 0};
        st = ddof_render_frame_with_matte(c->ctx, &p, &frame, &matte, &out, &c->stats);
    } else {
        st = ddof_diffuse_layers(c->ctx, &p, &color, &coc, fg ? &element : NULL, &out,
                                 &c->stats);
    }
    if (st != DDOF_OK)
        snprintf(c->error, sizeof c->error, "%s: %s", ddof_status_string(st),
                 ddof_context_last_error(c->ctx));
    return st;
}

/* A warm-up call, then up to `reps` timed calls while the budget lasts (at least one). A
 * warm-up longer than a second is itself the measurement (its allocations are noise then). */
ddof_status study_time_calls(study_call *c, int reps, double budget, double *runs, int *count)
{
    *count = 0;
    double t0 = study_now();
    ddof_status st = study_run_call(c);
    double first = study_now() - t0;
    if (st != DDOF_OK)
        return st;
    if (first > 1.0) {
        runs[(*count)++] = first;
        return DDOF_OK;
    }
    double spent = 0.0;
    for (int i = 0; i < reps && (i == 0 || spent < budget); i++) {
        t0 = study_now();
        st = study_run_call(c);
        const double t = study_now() - t0;
        if (st != DDOF_OK)
            return st;
        runs[(*count)++] = t;
        spent += t;
    }
    return DDOF_OK;
}

float *study_abs_of(const float *coc, size_t n)
{
    float *a = malloc(n * sizeof *a);
    if (a)
        for (size_t i = 0; i < n; i++)
            a[i] = fabsf(coc[i]);
    return a;
}
