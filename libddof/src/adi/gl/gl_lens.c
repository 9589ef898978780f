/* SPDX-License-Identifier: MIT */
/* gl_lens.c - the disc kernel (libddof/src/disc/disc_kernel.h) on the GPU, with the CPU driver's
 * semantics (libddof/src/lens_adi.c): per component c, a row pass runs the component's chain of
 * complex steps from the masked colour (IMAGE_A) into the complex image T_c (IMAGE_B real,
 * IMAGE_C imaginary), then a column pass runs the chain on T_c and folds Z_c into the output,
 * out = x + sum_c Re(mix_c (Z_c - x)), accumulated in RUNNING in the CPU's order and written
 * over IMAGE_A by the last component (lens_thomas.comp), clamped to the range of the input as
 * read (gl_lens_input_range), as lens_adi.c clamps it. The colour stays on the device from the
 * upload to the read-back. Links are the disc kernel's (min |CoC|^2, columns times aspect^2, 0
 * below DDOF_LENS_MIN_LINK), so the analysis runs with those too: its conductive lines are the
 * report's and its singular runs are the ones the chain keeps. */
#include "gl_adi.h"

#include <float.h>
#include <stdio.h>

void gl_lens_input_range(const adi_request *r, float lo[4], float hi[4])
{
    for (uint32_t c = 0; c < 4; c++) {
        lo[c] = c < r->channels ? FLT_MAX : -FLT_MAX;
        hi[c] = c < r->channels ? -FLT_MAX : FLT_MAX;
    }
    for (uint32_t y = 0; y < r->height; y++)
        for (uint32_t x = 0; x < r->width; x++) {
            const int masked = r->gamma && !(r->gamma[(size_t)y * r->gamma_stride +
                                                      (size_t)x * r->gamma_channels] > 0.0f);
            for (uint32_t c = 0; c < r->channels; c++) {
                const float v =
                    masked ? 0.0f : r->color[(size_t)y * r->color_stride + (size_t)x * r->channels + c];
                lo[c] = v < lo[c] ? v : lo[c];
                hi[c] = v > hi[c] ? v : hi[c];
            }
        }
}

/* The component's chain along one direction; fold: 0 rows, else lens_thomas.comp's u_fold. */
static void chain_pass(const gl_functions *gl, GLuint prog, const gl_diffusion *d, uint32_t c,
                       const gl_pass *p, int has_gamma, uint32_t fold)
{
    const disc_kernel *k = d->disc;
    gl_pass_uniforms(gl, prog, p, has_gamma);
    for (uint32_t ch = 0; ch < 4; ch++) {
        char name[32];
        snprintf(name, sizeof name, "u_lo[%u]", ch);
        gl_uniform_f(gl, prog, name, d->lo[ch]);
        snprintf(name, sizeof name, "u_hi[%u]", ch);
        gl_uniform_f(gl, prog, name, d->hi[ch]);
    }
    gl_uniform_u(gl, prog, "u_steps", k->steps);
    for (uint32_t m = 0; m < k->steps; m++) {
        char name[32];
        snprintf(name, sizeof name, "u_kappa_re[%u]", m);
        gl_uniform_f(gl, prog, name, k->kappa[c][m][0]);
        snprintf(name, sizeof name, "u_kappa_im[%u]", m);
        gl_uniform_f(gl, prog, name, k->kappa[c][m][1]);
    }
    gl_uniform_f(gl, prog, "u_mix_re", k->mix[c][0]);
    gl_uniform_f(gl, prog, "u_mix_im", k->mix[c][1]);
    gl_uniform_u(gl, prog, "u_real_input", fold == 0);
    gl_uniform_u(gl, prog, "u_fold", fold);
    gl->UseProgram(prog);
    gl_dispatch(gl, p->lines, 64);
}

ddof_status gl_lens_diffuse(ddof_device *device, const gl_diffusion *d, adi_report *report,
                            char *message, size_t message_size)
{
    const gl_functions *gl = &device->gl;
    const disc_kernel *k = d->disc;
    const uint32_t w = d->width, h = d->height, C = k->components;
    const uint64_t pixels = (uint64_t)w * h;
    GLuint image_a = device->buffers.name[GL_BUF_IMAGE_A];
    GLuint t_re = gl_need(device, GL_BUF_IMAGE_B, pixels * 16, message, message_size);
    GLuint t_im = gl_need(device, GL_BUF_IMAGE_C, pixels * 16, message, message_size);
    GLuint weights = gl_need(device, GL_BUF_WEIGHTS, pixels * 8, message, message_size);
    GLuint running = C > 1 ? gl_need(device, GL_BUF_RUNNING, pixels * 16, message,
                                     message_size)
                           : gl_need(device, GL_BUF_DUMMY, 16, message, message_size);
    if (!t_re || !t_im || !weights || !running)
        return DDOF_ERROR_BACKEND_FAILED;

    /* The directions' buffers go unused: both bind the same ones (below). */
    gl_directions found;
    if (!gl_analyse(device, GL_PROG_LENS_ANALYSE, d, 1.0f, &found, report, message, message_size))
        return DDOF_ERROR_BACKEND_FAILED;
    if (found.active == 0) { /* nothing conducts: the (masked) input is the answer */
        report->lines_skipped = ((uint64_t)w + h) * C;
        return DDOF_OK;
    }
    GLuint prog = gl_programs_get(gl, &device->programs, GL_PROG_LENS_THOMAS, message,
                                  message_size);
    if (!prog)
        return DDOF_ERROR_BACKEND_FAILED;
    const gl_buffers *b = &device->buffers;
    gl_bind(gl, 0, b->name[GL_BUF_COC]);
    gl_bind(gl, 1, d->has_gamma ? b->name[GL_BUF_GAMMA] : b->name[GL_BUF_DUMMY]);
    gl_bind(gl, 2, d->has_gamma ? b->name[GL_BUF_FLAGS] : b->name[GL_BUF_DUMMY]);
    gl_bind(gl, 3, image_a);
    gl_bind(gl, 4, t_re);
    gl_bind(gl, 5, t_im);
    gl_bind(gl, 6, weights);
    gl_bind(gl, 7, running);

    const uint32_t passes = 2 * C;
    for (uint32_t c = 0; c < C; c++) {
        const uint32_t fold = C == 1 ? 4u : c == 0 ? 1u : c + 1 == C ? 3u : 2u;
        for (uint32_t axis = 0; axis < 2; axis++) {
            if (gl_pass_cancelled(d, 2 * c + axis, passes, message, message_size))
                return DDOF_ERROR_CANCELLED; /* IMAGE_A is written by the last pass only */
            const double t0 = gl_seconds();
            chain_pass(gl, prog, d, c, &found.along[axis], d->has_gamma,
                       axis == 0 ? 0u : fold);
            gl_pass_timed(gl, report, (int)axis, t0);
        }
    }
    report->lines_solved = found.active * C * k->steps;
    report->lines_skipped = ((uint64_t)w + h - found.active) * C;
    report->substeps_run = 1;
    return DDOF_OK;
}
