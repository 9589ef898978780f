/* SPDX-License-Identifier: MIT */
/* gl_solve.h - what one diffusion on the GPU is made of and what its stages share (gl_solve.c):
 * the packed images' description, a pass, the analysis up front, binding and dispatch. The ADI
 * drivers are libddof/src/adi/gl (gl_adi.h), the line solvers behind them
 * libddof/src/solvers/gl (gl_solvers.h). Input and output stages are separate (gl_io.c for
 * host memory, host_api.c for a host's textures), so both share everything in between. */
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

/* The two directions of a diffusion over d's images: the rows (IMAGE_A to IMAGE_B), then the
 * columns (back), beta scaled by the row scale along the rows and by pixel_aspect^2 more along
 * the columns; and how many lines of both conduct. */
typedef struct gl_directions {
    gl_pass along[2];
    uint64_t active;
} gl_directions;

/* Zeroes the largest |CoC| that the packing stage (pack.comp, host_pack.comp) then measures,
 * and binds it where they write it (binding 3): call before each packing. 0 with a sentence in
 * message on failure. */
int gl_largest_reset(ddof_device *device, char *message, size_t message_size);

/* Lays out d's directions with row_scale and runs program `id` (analyse.comp, heat or disc
 * links) on them, which with heat capacities also marks the singular runs in FLAGS; starts the
 * report with what it finds (one thread, the largest |CoC| the packing measured). IMAGE_B must be allocated. 0 with a
 * sentence in message on failure. */
int gl_analyse(ddof_device *device, gl_program_id id, const gl_diffusion *d, float row_scale,
               gl_directions *directions, adi_report *report, char *message,
               size_t message_size);

/* Sets line.glsl's uniforms that describe the pass (its size, direction, scale and flags). */
void gl_pass_uniforms(const gl_functions *gl, GLuint program, const gl_pass *pass,
                      int has_gamma);

/* Asks d's progress callback, before pass `done` of `passes`, whether to go on: 1 when it
 * cancels, with a sentence in message. */
int gl_pass_cancelled(const gl_diffusion *d, uint32_t done, uint32_t passes, char *message,
                      size_t message_size);

/* Waits for the pass begun at t0, so that its time is its own, and adds that time to the
 * report's rows (axis 0) or columns. */
void gl_pass_timed(const gl_functions *gl, adi_report *report, int axis, double t0);

/* A monotonic clock in seconds (the report's pass times). */
double gl_seconds(void);

/* Dispatch helpers shared by the stages: `invocations` threads of `local` each (2D beyond the
 * 65535-group limit), then a storage barrier. */
void gl_dispatch(const gl_functions *gl, uint64_t invocations, uint32_t local);
void gl_bind(const gl_functions *gl, GLuint index, GLuint buffer);

/* An image in a device buffer: the float index of its first pixel, floats between rows and
 * between pixels (the CoC and gamma may be the first of several channels). buffer 0: none.
 * With `bytes` > 0 only the section [at, at + bytes) of the buffer is bound and offset counts
 * from its start: one buffer holds a frame's several images, each within the renderer's
 * storage-block limit while the whole may not be. */
typedef struct gl_image_ref {
    GLuint buffer;
    uint32_t offset, stride, step;
    uint64_t at, bytes;
} gl_image_ref;

/* Binds ref's buffer (or its section) to storage binding `index`, else `fallback`. */
void gl_bind_ref(const gl_functions *gl, GLuint index, const gl_image_ref *ref, GLuint fallback);

/* Sets a program's uniforms PREFIX_base, PREFIX_stride and PREFIX_step to ref's offset, stride
 * and step (those the program does not use are ignored). */
void gl_uniform_ref(const gl_functions *gl, GLuint program, const char *prefix,
                    const gl_image_ref *ref);

/* A buffer slot sized for `bytes`, checked against the renderer's SSBO size limit. */
GLuint gl_need(ddof_device *device, gl_buffer_slot slot, uint64_t bytes, char *message,
               size_t message_size);

#endif
