/* adi.h - alternating-direction implicit diffusion of an image: rows, then columns, n times. */
#ifndef DDOF_ADI_H
#define DDOF_ADI_H

#include "internal.h"

#include <math.h>

/* A validated request: images are checked, strides are in floats. */
typedef struct adi_request {
    const float *color;
    size_t color_stride;
    const float *coc; /* diameters in pixels (sign ignored), first of coc_channels floats per */
    size_t coc_stride;/* pixel; NULL: every pixel has uniform_coc                          */
    uint32_t coc_channels;
    float uniform_coc;
    const float *gamma; /* heat capacity per pixel (first of gamma_channels floats), >= 0; */
    size_t gamma_stride;/* NULL: 1 everywhere. Where it is 0 the colour is not read (as 0) */
    uint32_t gamma_channels;
    float *out; /* may equal color (then out_stride == color_stride) */
    size_t out_stride;
    uint32_t width, height, channels;
    ddof_solver solver;
    ddof_precision precision; /* packed half: GL Gruen only */
    uint32_t substeps;
    uint32_t jacobi_iterations;
    float beta_scale;   /* k in beta = k d^2                          */
    float pixel_aspect; /* column links use (d * pixel_aspect)          */
    const struct disc_kernel *disc; /* NULL: the heat kernel; else the disc kernel's table */
    ddof_progress_fn progress;
    void *progress_user;
    /* |CoC| below this (read from `coc`; a uniform CoC is the layers' own fill and is never
     * cut) conducts as 0: the pixel is in focus (params.in_focus_threshold_px). Appended, so
     * the GL plugin's view of the fields before it is unchanged. */
    float in_focus_px;
} adi_request;

typedef struct adi_report {
    uint64_t lines_solved;
    uint64_t lines_skipped;
    uint32_t substeps_run; /* 0 when nothing conducted (output is a copy) */
    uint32_t threads;
    float max_coc;
    double seconds_rows;
    double seconds_columns;
    uint64_t device_bytes; /* GL: peak GPU memory of the call; 0 on the CPU */
} adi_report;

/* Conductance of the link between two pixels: k * min(|d_a|, |d_b|)^2 (a negative, near-field
 * CoC conducts by its size), flushed to 0 below FLT_MIN so that "no conductive link" has one
 * meaning everywhere (and no denormals reach a solver). */
float ddof_link_beta(float scale, float coc_a, float coc_b);

/* |CoC| as a link sees it: 0 below the in-focus threshold. A pixel cut to 0 has no link, so it
 * keeps its value exactly, as a CoC-0 pixel does. */
static inline float ddof_conducting_coc(float coc, float in_focus_px)
{
    const float d = fabsf(coc);
    return d >= in_focus_px ? d : 0.0f;
}

/* The float solvers (Thomas, CR, PCR, Jacobi), multi-threaded. */
ddof_status ddof_adi_run(ddof_context *context, const adi_request *request, adi_report *report);

/* The double-precision reference: whole image in double, textbook Thomas, one thread. */
ddof_status ddof_adi_reference(ddof_context *context, const adi_request *request,
                               adi_report *report);

/* The disc kernel (request->disc set): lens_adi.c in float on the context's threads, and its
 * double-precision reference (lens_reference_f64.c). Same contract as ddof_adi_run, except
 * that the output is no longer a convex combination of the input. */
ddof_status ddof_lens_run(ddof_context *context, const adi_request *request, adi_report *report);
ddof_status ddof_lens_reference(ddof_context *context, const adi_request *request,
                                adi_report *report);

#endif
