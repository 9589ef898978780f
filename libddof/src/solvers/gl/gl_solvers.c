/* SPDX-License-Identifier: MIT */
/* gl_solvers.c - the line solvers of one ADI pass on the GPU, one function per solver:
 *
 *  THOMAS  thomas.comp, one invocation per line.
 *  CR      Kass-style cyclic reduction: cr_reduce.comp once per level up the pyramid (level 0
 *          read from the image with its coefficients computed on the fly), cr_back.comp once
 *          per level down, the last one writing the image.
 *  PCR     pcr_shared.comp, the whole line in shared memory, when it has at most
 *          PCR_CAPACITY unknowns; longer lines are reduced by CR in global memory until a
 *          level fits, solved by PCR there and substituted back (the CR+PCR hybrid of Zhang,
 *          Cohen and Owens 2010). Every length up to 65536 works.
 *  GRUEN   Gruen's solver (Game Engine Gems 2, ch. 8): four-to-one reduction straight from the
 *          image, CR levels until 2 or 3 unknowns remain, Cramer's rule, back-substitution, and
 *          a last pass that finishes four pixels per invocation from level 2. PACKED_HALF keeps
 *          the levels as one RGBA32UI texel per row and channel group (4 channels: 2 groups).
 *  JACOBI  jacobi_init.comp (the CPU's first guess, per segment of a line: no invocation loops
 *          over a whole line) and jacobi_sweep.comp k times.
 *
 * The pyramid of reduced levels is laid out [row][line]; when a whole pass's pyramid would
 * exceed the renderer's storage-block limit, the lines are solved in batches. */
#include "gl_solvers.h"

#include <stdio.h>

#define PCR_CAPACITY 1024u /* pcr_shared.comp */
#define JACOBI_SEGMENT 1024u /* jacobi_init.comp */
#define MAX_LEVELS 40

int gl_solver_supported(ddof_solver solver, ddof_precision precision)
{
    switch (solver) {
    case DDOF_SOLVER_THOMAS:
    case DDOF_SOLVER_CYCLIC_REDUCTION:
    case DDOF_SOLVER_PCR:
    case DDOF_SOLVER_JACOBI:
        return precision == DDOF_PRECISION_FLOAT;
    case DDOF_SOLVER_GRUEN:
        return precision == DDOF_PRECISION_FLOAT || precision == DDOF_PRECISION_PACKED_HALF;
    default:
        return 0;
    }
}

typedef struct pass_context {
    ddof_device *device;
    const gl_functions *gl;
    const gl_diffusion *d;
    const gl_pass *pass;
    char *message;
    size_t message_size;
} pass_context;

static GLuint program(const pass_context *c, gl_program_id id)
{
    return gl_programs_get(c->gl, &c->device->programs, id, c->message, c->message_size);
}

/* Binds the line buffers and sets line.glsl's uniforms for a whole-pass dispatch. */
static void use_line_program(const pass_context *c, GLuint prog)
{
    const gl_functions *gl = c->gl;
    const gl_pass *p = c->pass;
    const gl_buffers *b = &c->device->buffers;
    gl_bind(gl, 0, b->name[GL_BUF_COC]);
    gl_bind(gl, 1, c->d->has_gamma ? b->name[GL_BUF_GAMMA] : b->name[GL_BUF_DUMMY]);
    gl_bind(gl, 2, c->d->has_gamma ? b->name[GL_BUF_FLAGS] : b->name[GL_BUF_DUMMY]);
    gl_bind(gl, 3, p->src);
    gl_bind(gl, 4, p->dst);
    gl_pass_uniforms(gl, prog, p, c->d->has_gamma);
    gl_uniform_u(gl, prog, "u_line0", 0);
    gl_uniform_u(gl, prog, "u_batch_lines", p->lines);
    gl_uniform_u(gl, prog, "u_write_mask", 15);
    gl_uniform_u(gl, prog, "u_group", 0);
    gl_uniform_u(gl, prog, "u_level0", 0);
    gl->UseProgram(prog);
}

static int solve_copy(const pass_context *c)
{
    GLuint prog = program(c, GL_PROG_COPY);
    if (!prog)
        return 0;
    use_line_program(c, prog);
    gl_dispatch(c->gl, (uint64_t)c->pass->n * c->pass->lines, 256);
    return 1;
}

static int solve_thomas(const pass_context *c)
{
    const uint64_t pixels = (uint64_t)c->pass->n * c->pass->lines;
    GLuint prog = program(c, GL_PROG_THOMAS);
    GLuint weights = gl_need(c->device, GL_BUF_WEIGHTS, pixels * 4, c->message,
                             c->message_size);
    if (!prog || !weights)
        return 0;
    use_line_program(c, prog);
    gl_bind(c->gl, 6, weights);
    gl_dispatch(c->gl, c->pass->lines, 64);
    return 1;
}

static int solve_jacobi(const pass_context *c)
{
    const gl_functions *gl = c->gl;
    const uint64_t pixels = (uint64_t)c->pass->n * c->pass->lines;
    const uint32_t k = c->d->jacobi_iterations;
    GLuint init = program(c, GL_PROG_JACOBI_INIT), sweep = program(c, GL_PROG_JACOBI_SWEEP);
    GLuint other = gl_need(c->device, GL_BUF_IMAGE_C, pixels * 16, c->message,
                           c->message_size);
    /* jacobi_init.comp's segments: one invocation each, their (first, last) heat marks. */
    const uint64_t segments = (uint64_t)c->pass->lines *
                              ((c->pass->n + JACOBI_SEGMENT - 1) / JACOBI_SEGMENT);
    GLuint marks = c->d->has_gamma ? gl_need(c->device, GL_BUF_WEIGHTS, segments * 8,
                                             c->message, c->message_size)
                                   : c->device->buffers.name[GL_BUF_DUMMY];
    if (!init || !sweep || !other || !marks)
        return 0;
    /* Sweep t reads X_t and writes X_t+1; X_0 is chosen so that X_k is the pass's output. */
    GLuint x[2] = {k % 2 ? other : c->pass->dst, k % 2 ? c->pass->dst : other};
    use_line_program(c, init);
    gl_bind(gl, 6, x[0]);
    gl_bind(gl, 7, marks);
    for (GLuint stage = c->d->has_gamma ? 0 : 1; stage < 2; stage++) {
        gl_uniform_u(gl, init, "u_stage", stage);
        gl_dispatch(gl, segments, 64);
    }
    use_line_program(c, sweep);
    for (uint32_t t = 0; t < k; t++) {
        gl_bind(gl, 6, x[t % 2]);
        gl_bind(gl, 7, x[(t + 1) % 2]);
        gl_uniform_u(gl, sweep, "u_last", t + 1 == k);
        gl_dispatch(gl, pixels, 256);
    }
    return 1;
}

/* A pyramid of levels: counts and first rows (per line), level 0 being the image. */
typedef struct pyramid {
    uint32_t count[MAX_LEVELS];
    uint32_t offset[MAX_LEVELS];
    int top;
    uint64_t rows; /* stored rows per line */
} pyramid;

/* Levels count[first..] halving from `start` until a level has at most `stop` rows. */
static void plan_levels(pyramid *p, uint32_t n, int first, uint32_t start, uint32_t stop)
{
    p->count[0] = n;
    p->offset[0] = 0;
    p->count[first] = start;
    p->offset[first] = 0;
    int k = first;
    while (p->count[k] > stop && k + 1 < MAX_LEVELS) {
        p->count[k + 1] = p->count[k] / 2;
        p->offset[k + 1] = p->offset[k] + p->count[k];
        k++;
    }
    p->top = k;
    p->rows = (uint64_t)p->offset[k] + p->count[k];
}

/* Lines per batch so that the pyramid buffer stays within the storage-block limit. */
static uint32_t batch_lines(const pass_context *c, uint64_t row_bytes_per_line)
{
    if (row_bytes_per_line == 0)
        return c->pass->lines;
    uint64_t fit = c->device->max_buffer_bytes / row_bytes_per_line;
    if (fit == 0)
        fit = 1;
    return fit < c->pass->lines ? (uint32_t)fit : c->pass->lines;
}

static void set_level(const gl_functions *gl, GLuint prog, const pyramid *p, int src, int dst,
                      int level0)
{
    gl_uniform_u(gl, prog, "u_level0", (GLuint)level0);
    gl_uniform_u(gl, prog, "u_src_off", p->offset[src]);
    gl_uniform_u(gl, prog, "u_src_count", p->count[src]);
    if (dst >= 0) {
        gl_uniform_u(gl, prog, "u_dst_off", p->offset[dst]);
        gl_uniform_u(gl, prog, "u_dst_count", p->count[dst]);
        gl_uniform_u(gl, prog, "u_up_off", p->offset[dst]);
        gl_uniform_u(gl, prog, "u_up_count", p->count[dst]);
    }
}

static void set_batch(const pass_context *c, GLuint prog, uint32_t line0, uint32_t lines,
                      uint32_t group, uint32_t mask)
{
    gl_uniform_u(c->gl, prog, "u_line0", line0);
    gl_uniform_u(c->gl, prog, "u_batch_lines", lines);
    gl_uniform_u(c->gl, prog, "u_group", group);
    gl_uniform_u(c->gl, prog, "u_write_mask", mask);
}

/* Reduction from level `from` up to p->top with cr_reduce (level 0: the image). */
static void reduce_levels(const pass_context *c, GLuint prog, const pyramid *p, int from,
                          uint32_t line0, uint32_t lines, uint32_t group, uint32_t mask)
{
    use_line_program(c, prog);
    set_batch(c, prog, line0, lines, group, mask);
    for (int k = from; k < p->top; k++) {
        set_level(c->gl, prog, p, k, k == 0 ? 1 : k + 1, k == 0);
        gl_dispatch(c->gl, (uint64_t)p->count[k == 0 ? 1 : k + 1] * lines, 64);
    }
}

/* Back-substitution from p->top - 1 down to level `to` (level 0 writes the image). */
static void back_levels(const pass_context *c, GLuint prog, const pyramid *p, int to,
                        uint32_t line0, uint32_t lines, uint32_t group, uint32_t mask)
{
    use_line_program(c, prog);
    set_batch(c, prog, line0, lines, group, mask);
    for (int k = p->top - 1; k >= to; k--) {
        set_level(c->gl, prog, p, k, k == 0 ? 1 : k + 1, k == 0);
        gl_dispatch(c->gl, (uint64_t)p->count[k] * lines, 64);
    }
}

static GLuint pyramid_buffer(const pass_context *c, uint64_t bytes)
{
    return gl_need(c->device, GL_BUF_PYRAMID, bytes, c->message, c->message_size);
}

/* The lines of the next batch from line0 on: `batch`, or what is left of the pass. */
static uint32_t lines_from(const pass_context *c, uint32_t line0, uint32_t batch)
{
    return c->pass->lines - line0 < batch ? c->pass->lines - line0 : batch;
}

/* Cyclic reduction in global memory, batch by batch, up to a level of at most `top_rows`
 * unknowns, then back-substitution down to the image. top_solver, when not 0, solves that top
 * level in between (PCR in shared memory); CR alone reduces to a single unknown instead. */
static int solve_by_reduction(const pass_context *c, uint32_t top_rows, GLuint top_solver)
{
    const uint32_t n = c->pass->n;
    pyramid p;
    plan_levels(&p, n, 1, n / 2, top_rows);
    GLuint reduce = program(c, GL_PROG_CR_REDUCE), back = program(c, GL_PROG_CR_BACK);
    const uint32_t batch = batch_lines(c, p.rows * 32);
    GLuint pyr = pyramid_buffer(c, p.rows * 32 * batch);
    if (!reduce || !back || !pyr)
        return 0;
    gl_bind(c->gl, 5, pyr);
    for (uint32_t line0 = 0; line0 < c->pass->lines; line0 += batch) {
        const uint32_t lines = lines_from(c, line0, batch);
        reduce_levels(c, reduce, &p, 0, line0, lines, 0, 15);
        if (top_solver) {
            use_line_program(c, top_solver);
            set_batch(c, top_solver, line0, lines, 0, 15);
            set_level(c->gl, top_solver, &p, p.top, -1, 0);
            gl_dispatch(c->gl, lines, 1);
        }
        back_levels(c, back, &p, 0, line0, lines, 0, 15);
    }
    return 1;
}

static int solve_cr(const pass_context *c)
{
    return c->pass->n == 1 ? solve_copy(c) : solve_by_reduction(c, 1, 0);
}

static int solve_pcr(const pass_context *c)
{
    GLuint shared = program(c, GL_PROG_PCR_SHARED);
    if (!shared)
        return 0;
    if (c->pass->n > PCR_CAPACITY)
        return solve_by_reduction(c, PCR_CAPACITY, shared);
    /* the whole line in shared memory */
    use_line_program(c, shared);
    gl_bind(c->gl, 5, c->device->buffers.name[GL_BUF_DUMMY]);
    gl_uniform_u(c->gl, shared, "u_level0", 1);
    gl_dispatch(c->gl, c->pass->lines, 1);
    return 1;
}

static int solve_gruen(const pass_context *c)
{
    const uint32_t n = c->pass->n;
    const int packed = c->d->precision == DDOF_PRECISION_PACKED_HALF;
    if (n <= 3) { /* nothing to reduce: Cramer's rule on the image's own rows */
        GLuint cramer = program(c, GL_PROG_GRUEN_CRAMER);
        if (!cramer)
            return 0;
        use_line_program(c, cramer);
        gl_bind(c->gl, 5, c->device->buffers.name[GL_BUF_DUMMY]);
        gl_uniform_u(c->gl, cramer, "u_level0", 1);
        gl_dispatch(c->gl, c->pass->lines, 64);
        return 1;
    }
    GLuint reduce4 = program(c, packed ? GL_PROG_GRUEN_REDUCE4_PACKED : GL_PROG_GRUEN_REDUCE4);
    GLuint reduce = program(c, packed ? GL_PROG_CR_REDUCE_PACKED : GL_PROG_CR_REDUCE);
    GLuint cramer = program(c, packed ? GL_PROG_GRUEN_CRAMER_PACKED : GL_PROG_GRUEN_CRAMER);
    GLuint back = program(c, packed ? GL_PROG_CR_BACK_PACKED : GL_PROG_CR_BACK);
    GLuint back4 = program(c, packed ? GL_PROG_GRUEN_BACK4_PACKED : GL_PROG_GRUEN_BACK4);
    /* Level 2 is the first stored level; p's level numbers start there (first = 1 below). */
    pyramid p;
    plan_levels(&p, n, 1, (n / 2) / 2, 3);
    const uint64_t row_bytes = packed ? 16 : 32;
    const uint32_t batch = batch_lines(c, p.rows * row_bytes);
    GLuint pyr = pyramid_buffer(c, p.rows * row_bytes * batch);
    if (!reduce4 || !reduce || !cramer || !back || !back4 || !pyr)
        return 0;
    gl_bind(c->gl, 5, pyr);
    /* Packed rows carry three channels: a fourth is a second solve of its own. */
    const uint32_t groups = packed && c->d->channels == 4 ? 2 : 1;
    for (uint32_t group = 0; group < groups; group++) {
        const uint32_t mask = groups == 1 ? 15u : group == 0 ? 7u : 8u;
        for (uint32_t line0 = 0; line0 < c->pass->lines; line0 += batch) {
            const uint32_t lines = lines_from(c, line0, batch);
            use_line_program(c, reduce4);
            set_batch(c, reduce4, line0, lines, group, mask);
            set_level(c->gl, reduce4, &p, 1, 1, 1);
            gl_dispatch(c->gl, (uint64_t)p.count[1] * lines, 64);
            reduce_levels(c, reduce, &p, 1, line0, lines, group, mask);
            use_line_program(c, cramer);
            set_batch(c, cramer, line0, lines, group, mask);
            set_level(c->gl, cramer, &p, p.top, -1, 0);
            gl_dispatch(c->gl, lines, 64);
            back_levels(c, back, &p, 1, line0, lines, group, mask);
            use_line_program(c, back4);
            set_batch(c, back4, line0, lines, group, mask);
            set_level(c->gl, back4, &p, 1, -1, 0);
            gl_dispatch(c->gl, (uint64_t)((n + 3) / 4) * lines, 64);
        }
    }
    return 1;
}

int gl_solve_pass(ddof_device *device, const gl_diffusion *d, const gl_pass *pass,
                  char *message, size_t message_size)
{
    const pass_context c = {device, &device->gl, d, pass, message, message_size};
    switch (d->solver) {
    case DDOF_SOLVER_THOMAS: return solve_thomas(&c);
    case DDOF_SOLVER_CYCLIC_REDUCTION: return solve_cr(&c);
    case DDOF_SOLVER_PCR: return solve_pcr(&c);
    case DDOF_SOLVER_GRUEN: return solve_gruen(&c);
    case DDOF_SOLVER_JACOBI: return solve_jacobi(&c);
    default:
        snprintf(message, message_size, "solver %d is not available on the GPU", (int)d->solver);
        return 0;
    }
}
