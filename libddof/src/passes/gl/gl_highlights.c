/* SPDX-License-Identifier: MIT */
/* gl_highlights.c - the highlight pass's take-out and drawing on the device (gl_passes.h):
 * ../highlights_find.c's base and ../highlights_draw.c's scatter, each a highlights.comp
 * program, over the list gl_highlights_find.c found and sorted into its size classes on the
 * device; per class the device counts where its light lands, weighs each highlight, draws its
 * rows' differences and sums them into the result, as the CPU does, so the host reads nothing
 * back. */
#include "gl_passes.h"

#include <math.h>
#include <stdio.h>

/* Steps of a line one invocation runs per dispatch (llvmpipe's loop limit), and the loop
 * steps a highlight's row may cost in the scatter beyond its rim pixels. */
#define SEGMENT_STEPS 4096u
#define SCATTER_STEPS 16384u
#define ROW_COST 64u
#define WEIGH_ROWS 32u

ddof_highlight_shape gl_highlight_shape(const adi_highlights *h, float aspect)
{
    return ddof_highlight_shape_of(h->blades, h->rotation_rad, h->catseye, h->centre_x,
                                   h->centre_y, h->half_width, h->half_height,
                                   h->image_sums != NULL, h->image_width, h->image_height,
                                   aspect);
}

/* A highlights.comp step with its bindings and the uniforms every step shares; 0 on failure. */
static GLuint step(ddof_device *device, gl_program_id id, const gl_highlights_request *q,
                   GLuint out, GLuint base, char *message, size_t size)
{
    const gl_functions *gl = &device->gl;
    GLuint prog = gl_programs_get(gl, &device->programs, id, message, size);
    if (!prog)
        return 0;
    const gl_buffers *b = &device->buffers;
    const GLuint dummy = b->name[GL_BUF_DUMMY];
    gl_bind_ref(gl, 0, &q->coc, dummy);
    gl_bind_ref(gl, 1, &q->color, dummy);
    gl_bind(gl, 2, out ? out : dummy);
    gl_bind(gl, 3, base ? base : dummy);
    gl_bind_ref(gl, 4, &q->items, dummy);
    gl_bind_ref(gl, 5, &q->shape, dummy);
    gl_bind_ref(gl, 6, &q->sums, dummy);
    static const gl_buffer_slot rest[4] = {GL_BUF_HL_LANDING, GL_BUF_HL_WEIGHTS, GL_BUF_HL_DIFF,
                                           GL_BUF_HL_STATE};
    for (GLuint i = 0; i < 4; i++)
        gl_bind(gl, 7 + i, b->name[rest[i]] ? b->name[rest[i]] : dummy);
    gl_uniform_u(gl, prog, "u_width", q->width);
    gl_uniform_u(gl, prog, "u_height", q->height);
    gl_uniform_u(gl, prog, "u_channels", q->channels);
    gl_uniform_ref(gl, prog, "u_coc", &q->coc);
    gl_uniform_ref(gl, prog, "u_color", &q->color);
    gl_uniform_u(gl, prog, "u_coc_signed", q->coc_signed);
    gl->UseProgram(prog);
    return prog;
}

int gl_take_out_highlights(ddof_device *device, const gl_highlights_request *q, GLuint base,
                           char *message, size_t size)
{
    const gl_functions *gl = &device->gl;
    if (!gl_need(device, GL_BUF_DUMMY, 16, message, size) ||
        !step(device, GL_PROG_HL_COPY, q, 0, base, message, size))
        return 0;
    gl_dispatch(gl, (uint64_t)q->width * q->height, 64);
    GLuint prog = step(device, GL_PROG_HL_TAKE_OUT, q, 0, base, message, size);
    if (!prog)
        return 0;
    gl_uniform_u(gl, prog, "u_count", q->count);
    gl_dispatch(gl, q->count, 64);
    return 1;
}

/* A class's uniforms on a step. */
static void class_uniforms(const gl_functions *gl, GLuint prog, const gl_highlight_class *c)
{
    gl_uniform_u(gl, prog, "u_first", c->first);
    gl_uniform_u(gl, prog, "u_count", c->count);
    gl_uniform_f(gl, prog, "u_threshold", c->threshold);
    static const char *const names[5] = {"u_reach_rows", "u_bx0", "u_bx1", "u_by0", "u_by1"};
    const int values[5] = {c->reach_rows, c->bx0, c->bx1, c->by0, c->by1};
    for (int i = 0; i < 5; i++)
        gl->ProgramUniform1i(prog, gl->GetUniformLocation(prog, names[i]), values[i]);
}

/* One step over `lines` invocations, `steps` of its loop in dispatches of `per` steps. */
static void run_segments(const gl_functions *gl, GLuint prog, uint64_t lines, uint32_t steps,
                         uint32_t per)
{
    for (uint32_t first = 0; first < steps; first += per) {
        gl_uniform_u(gl, prog, "u_seg_first", first);
        gl_uniform_u(gl, prog, "u_seg_count", steps - first < per ? steps - first : per);
        gl_dispatch(gl, lines, 64);
    }
}

/* highlights_draw.c's class: the landing counts, the weights, the differences, their sums. */
static int draw_class(ddof_device *device, const gl_highlights_request *q, GLuint out,
                      const gl_highlight_class *c, char *message, size_t size)
{
    const gl_functions *gl = &device->gl;
    const uint32_t rows = (uint32_t)(c->by1 - c->by0), columns = (uint32_t)(c->bx1 - c->bx0);
    const uint64_t state = (uint64_t)rows * 3 > c->count ? (uint64_t)rows * 3 : c->count;
    if (!gl_need(device, GL_BUF_HL_LANDING, (uint64_t)(columns + 1) * rows * 4, message, size) ||
        !gl_need(device, GL_BUF_HL_STATE, state * sizeof(double), message, size))
        return 0;
    static const gl_program_id steps[4] = {GL_PROG_HL_LANDING, GL_PROG_HL_WEIGH,
                                           GL_PROG_HL_SCATTER, GL_PROG_HL_SUM};
    /* A highlight costs its rim pixels and its row's walk in the scatter. */
    const uint32_t per_item = 2u * (uint32_t)c->reach_x + ROW_COST;
    const uint32_t items_per = SCATTER_STEPS / per_item ? SCATTER_STEPS / per_item : 1u;
    const uint32_t rows_per = WEIGH_ROWS;
    for (int i = 0; i < 4; i++) {
        GLuint prog = step(device, steps[i], q, out, 0, message, size);
        if (!prog)
            return 0;
        class_uniforms(gl, prog, c);
        if (steps[i] == GL_PROG_HL_WEIGH)
            run_segments(gl, prog, c->count, 2u * (uint32_t)c->reach_rows + 1u, rows_per);
        else if (steps[i] == GL_PROG_HL_SCATTER)
            run_segments(gl, prog, rows, c->count, items_per);
        else
            run_segments(gl, prog, rows, columns, SEGMENT_STEPS);
    }
    return 1;
}

int gl_draw_highlights(ddof_device *device, const gl_highlights_request *q, GLuint out,
                       char *message, size_t size)
{
    const uint64_t pixels = (uint64_t)q->width * q->height;
    if (!gl_need(device, GL_BUF_DUMMY, 16, message, size) ||
        !gl_need(device, GL_BUF_HL_WEIGHTS, (uint64_t)q->count * sizeof(float), message, size) ||
        !gl_need(device, GL_BUF_HL_DIFF, pixels * 3 * sizeof(float), message, size))
        return 0;
    for (int k = 0; k < GL_HIGHLIGHT_CLASSES; k++)
        if (q->classes[k].count && !draw_class(device, q, out, &q->classes[k], message, size))
            return 0;
    return 1;
}
