/* SPDX-License-Identifier: MIT */
/* gl_solve.h - one diffusion on the GPU: the ADI driver (gl_solve.c) and the line solvers
 * behind it (gl_solvers.c). Input and output stages are separate (gl_io.c for host memory,
 * host_api.c for a host's textures), so both share everything in between. */
#ifndef DDOF_GL_SOLVE_H
#define DDOF_GL_SOLVE_H

#include "gl_device.h"

/* What the driver needs once the images are packed: IMAGE_A holds the vec4 colour (masked
 * where gamma is 0), COC |CoC| and, with has_gamma, GAMMA. The result is left in IMAGE_A. */
typedef struct gl_diffusion {
    uint32_t width, height, channels;
    ddof_solver solver;
    ddof_precision precision;
    uint32_t substeps;
    uint32_t jacobi_iterations;
    float beta_scale;
    float pixel_aspect;
    int has_gamma;
    ddof_progress_fn progress;
    void *progress_user;
    const struct disc_kernel *disc; /* NULL: the heat kernel (gl_diffuse); else gl_lens_diffuse */
    float lo[4], hi[4]; /* disc: the masked input's range per channel, the output's clamp     */
} gl_diffusion;

/* One pass direction over the working image. */
typedef struct gl_pass {
    uint32_t n, lines, along, across;
    float scale;       /* beta scale of the pass                       */
    uint32_t flag_bit; /* 1 rows, 2 columns; 0 without heat capacities */
    GLuint src, dst;   /* vec4 images                                  */
} gl_pass;

ddof_status gl_diffuse(ddof_device *device, const gl_diffusion *d, adi_report *report,
                       char *message, size_t message_size);

/* The disc kernel (d->disc, Thomas only) on the same packed images, the result again in
 * IMAGE_A (gl_lens.c). */
/* The range per channel of the request's input as the disc reads it (0 where gamma is 0),
 * which the disc kernel clamps its result to (libddof/src/lens_adi.c); unused channels get
 * the whole float range. */
void gl_lens_input_range(const adi_request *r, float lo[4], float hi[4]);
ddof_status gl_lens_diffuse(ddof_device *device, const gl_diffusion *d, adi_report *report,
                            char *message, size_t message_size);

/* What analyse.comp finds over both directions: the conductive lines and the largest CoC; with
 * heat capacities it also marks the singular runs in FLAGS. */
typedef struct gl_analysis {
    uint32_t rows, columns;
    float max_coc;
} gl_analysis;

/* Runs program `id` (analyse.comp, heat or disc links) on rows and columns; 0 with a sentence
 * in message on failure. */
int gl_analyse(ddof_device *device, gl_program_id id, const gl_diffusion *d,
               const gl_pass *rows, const gl_pass *columns, gl_analysis *result, char *message,
               size_t message_size);

/* A monotonic clock in seconds (the report's pass times). */
double gl_seconds(void);

/* Solves every line of a pass with d->solver; 0 with a sentence in message on failure. */
int gl_solve_pass(ddof_device *device, const gl_diffusion *d, const gl_pass *pass,
                  char *message, size_t message_size);

/* Whether the GPU solvers cover this solver and precision. */
int gl_solver_supported(ddof_solver solver, ddof_precision precision);

/* Dispatch helpers shared by the stages: `invocations` threads of `local` each (2D beyond the
 * 65535-group limit), then a storage barrier. */
void gl_dispatch(const gl_functions *gl, uint64_t invocations, uint32_t local);
void gl_bind(const gl_functions *gl, GLuint index, GLuint buffer);
/* A buffer slot sized for `bytes`, checked against the renderer's SSBO size limit. */
GLuint gl_need(ddof_device *device, gl_buffer_slot slot, uint64_t bytes, char *message,
               size_t message_size);

#endif
