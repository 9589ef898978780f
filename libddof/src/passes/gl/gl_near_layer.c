/* SPDX-License-Identifier: MIT */
/* gl_near_layer.c - ../near_layer.c's split and ../near_offsets_*.c's fill on the device
 * (gl_passes.h): near_layer.comp's steps (the matte and the fringe, the pull-push pyramid, the
 * lines across the holes, the finish and the rest's boxes) and near_offsets.comp's (the search
 * level, the search, the refinement, the scores, the copies). The images stay on the device
 * for the layers' run (gl_layers.c binds them); the host reads only counts: whether a source
 * exists, the search's and the refinement's errors (which it ranks and picks from with
 * ddof_near_rules.h, as the CPU does), and the split's figures and boxes. */
#include "gl_io.h"
#include "gl_passes.h"

#include "ddof_near_rules.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define LOCAL 64u /* the programs' local_size_x */

/* A line's walk takes about 11 loop steps a pixel (its runs, their values and channels):
 * llvmpipe ends an invocation's loops after 65,535 in all (backend_table.c), so a software
 * renderer splits frames up to this side only; a longer one is the CPU's. */
#define SOFTWARE_LINE_LIMIT 5000u

enum { FACTS = 16 };

typedef struct level {
    uint32_t w, h, values, weights; /* size, and float offsets into the pyramid */
} level;

typedef struct split_run {
    ddof_device *device;
    const adi_near_request *q;
    uint32_t w, h, c;
    gl_image_ref color, coc; /* the upload's sections */
    level levels[32];
    uint32_t level_count;
    char *message;
    size_t size;
} split_run;

static GLuint slot(const split_run *s, gl_buffer_slot b)
{
    return s->device->buffers.name[b];
}

static GLuint need(split_run *s, gl_buffer_slot b, uint64_t bytes)
{
    return gl_need(s->device, b, bytes ? bytes : 4, s->message, s->size);
}

/* The frame's colour and CoC, as they lie, in one upload into FRAME. */
static int upload(split_run *s)
{
    const adi_request *r = &s->q->base;
    const void *source[2] = {r->color, r->coc};
    const uint64_t floats[2] = {gl_span_floats(s->w, s->h, r->color_stride, s->c, s->c),
                                gl_span_floats(s->w, s->h, r->coc_stride, r->coc_channels, 1)};
    uint64_t at[2], bytes[2];
    if (!gl_io_upload_sections(s->device, GL_BUF_FRAME, 2, source, floats, at, bytes, s->message,
                               s->size))
        return 0;
    const GLuint buffer = slot(s, GL_BUF_FRAME);
    s->color = (gl_image_ref){buffer, 0, (uint32_t)r->color_stride, s->c, at[0], bytes[0]};
    s->coc = (gl_image_ref){buffer, 0, (uint32_t)r->coc_stride, r->coc_channels, at[1], bytes[1]};
    return 1;
}

/* Reads `bytes` from the start of a slot's buffer (a few counts). */
static void read_back(const split_run *s, gl_buffer_slot b, uint64_t offset, void *out,
                      uint64_t bytes)
{
    const gl_functions *gl = &s->device->gl;
    gl->MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    gl->BindBuffer(GL_SHADER_STORAGE_BUFFER, slot(s, b));
    gl->GetBufferSubData(GL_SHADER_STORAGE_BUFFER, (GLintptr)offset, (GLsizeiptr)bytes, out);
}

static void write_to(const split_run *s, gl_buffer_slot b, uint64_t offset, const void *in,
                     uint64_t bytes)
{
    const gl_functions *gl = &s->device->gl;
    gl->BindBuffer(GL_SHADER_STORAGE_BUFFER, slot(s, b));
    gl->BufferSubData(GL_SHADER_STORAGE_BUFFER, (GLintptr)offset, (GLsizeiptr)bytes, in);
}

/* A step's program with what both shaders read bound and set: the frame's CoC (binding 0) and
 * colour (1), the split's maps (2) and their sizes; 0 on failure. */
static GLuint frame_program(split_run *s, gl_program_id id)
{
    const gl_functions *gl = &s->device->gl;
    GLuint prog = gl_programs_get(gl, &s->device->programs, id, s->message, s->size);
    if (!prog)
        return 0;
    gl_bind_ref(gl, 0, &s->coc, 0);
    gl_bind_ref(gl, 1, &s->color, 0);
    gl_bind(gl, 2, slot(s, GL_BUF_NEAR_MAPS));
    gl_uniform_u(gl, prog, "u_width", s->w);
    gl_uniform_u(gl, prog, "u_height", s->h);
    gl_uniform_u(gl, prog, "u_channels", s->c);
    gl_uniform_ref(gl, prog, "u_coc", &s->coc);
    gl_uniform_ref(gl, prog, "u_color", &s->color);
    return prog;
}

/* ---- near_layer.comp ---------------------------------------------------------------------- */

/* A near_layer.comp step with the frame's bindings and uniforms, in use; 0 on failure. */
static GLuint split_step(split_run *s, gl_program_id id)
{
    const gl_functions *gl = &s->device->gl;
    GLuint prog = frame_program(s, id);
    if (!prog)
        return 0;
    gl_bind(gl, 3, slot(s, GL_BUF_NEAR_REST));
    gl_bind(gl, 4, slot(s, GL_BUF_NEAR_REST_COC));
    gl_bind(gl, 5, slot(s, GL_BUF_NEAR_ELEMENT));
    gl_bind(gl, 6, slot(s, GL_BUF_NEAR_ELEMENT_COC));
    const int facts = id == GL_PROG_NEAR_FINISH || id == GL_PROG_NEAR_ANALYSE;
    gl_bind(gl, 7, slot(s, facts ? GL_BUF_NEAR_FACTS : GL_BUF_NEAR_PYRAMID));
    gl_uniform_f(gl, prog, "u_threshold", s->q->threshold);
    gl_uniform_u(gl, prog, "u_values", s->c + 1);
    gl->UseProgram(prog);
    return prog;
}

/* The pyramid's levels 1.. (halved, rounded up, down to 1 x 1): near_layer.c's lay_out. */
static uint64_t lay_out(split_run *s)
{
    uint32_t w = s->w, h = s->h;
    uint64_t used = 0;
    s->levels[0] = (level){w, h, 0, 0};
    s->level_count = 1;
    while ((w > 1 || h > 1) && s->level_count < 32) {
        w = (w + 1) / 2;
        h = (h + 1) / 2;
        const uint64_t pixels = (uint64_t)w * h;
        s->levels[s->level_count++] =
            (level){w, h, (uint32_t)used, (uint32_t)(used + pixels * (s->c + 1))};
        used += pixels * (s->c + 2);
    }
    return used;
}

static void level_uniforms(const split_run *s, GLuint prog, const char *which, const level *l)
{
    const gl_functions *gl = &s->device->gl;
    char name[32];
    snprintf(name, sizeof name, "u_%s_w", which);
    gl_uniform_u(gl, prog, name, l->w);
    snprintf(name, sizeof name, "u_%s_h", which);
    gl_uniform_u(gl, prog, name, l->h);
    snprintf(name, sizeof name, "u_%s_values", which);
    gl_uniform_u(gl, prog, name, l->values);
    snprintf(name, sizeof name, "u_%s_weight", which);
    gl_uniform_u(gl, prog, name, l->weights);
}

/* Pulls the pyramid up and says whether any source exists (its top's weight). */
static int pull(split_run *s, int *filled)
{
    for (uint32_t from = 0; from + 1 < s->level_count; from++) {
        GLuint prog = split_step(s, GL_PROG_NEAR_PULL);
        if (!prog)
            return 0;
        gl_uniform_u(&s->device->gl, prog, "u_from", from);
        level_uniforms(s, prog, "fine", &s->levels[from]);
        level_uniforms(s, prog, "coarse", &s->levels[from + 1]);
        const level *c = &s->levels[from + 1];
        gl_dispatch(&s->device->gl, (uint64_t)c->w * c->h, LOCAL);
    }
    float top = 0.0f;
    if (s->level_count > 1)
        read_back(s, GL_BUF_NEAR_PYRAMID,
                  (uint64_t)s->levels[s->level_count - 1].weights * sizeof(float), &top,
                  sizeof top);
    *filled = s->level_count > 1 && top > 0.0f;
    return 1;
}

static int push(split_run *s)
{
    for (uint32_t from = s->level_count - 2; from >= 1 && from + 1 < s->level_count; from--) {
        GLuint prog = split_step(s, GL_PROG_NEAR_PUSH);
        if (!prog)
            return 0;
        level_uniforms(s, prog, "fine", &s->levels[from]);
        level_uniforms(s, prog, "coarse", &s->levels[from + 1]);
        gl_dispatch(&s->device->gl, (uint64_t)s->levels[from].w * s->levels[from].h, LOCAL);
    }
    return 1;
}

/* The fill across the holes: rows first (they store), then columns and both diagonals (they
 * add), then each hole settled (level 1's pull-push where no line reached). */
static int lines(split_run *s)
{
    const uint64_t counts[4] = {s->h, s->w, (uint64_t)s->w + s->h - 1,
                                (uint64_t)s->w + s->h - 1};
    for (uint32_t direction = 0; direction < 4; direction++) {
        GLuint prog = split_step(s, GL_PROG_NEAR_LINES);
        if (!prog)
            return 0;
        gl_uniform_u(&s->device->gl, prog, "u_direction", direction);
        level_uniforms(s, prog, "fine", &s->levels[DDOF_NEAR_END_LEVEL]);
        gl_dispatch(&s->device->gl, counts[direction], LOCAL);
    }
    GLuint prog = split_step(s, GL_PROG_NEAR_SETTLE);
    if (!prog)
        return 0;
    level_uniforms(s, prog, "coarse", &s->levels[1]);
    gl_dispatch(&s->device->gl, (uint64_t)s->w * s->h, LOCAL);
    return 1;
}

/* ---- near_offsets.comp -------------------------------------------------------------------- */

typedef struct offsets_run {
    split_run *s;
    ddof_near_level l;
    uint32_t gw, gh, side, refine_side, nb;
} offsets_run;

static GLuint offsets_step(offsets_run *o, gl_program_id id)
{
    split_run *s = o->s;
    const gl_functions *gl = &s->device->gl;
    GLuint prog = frame_program(s, id);
    if (!prog)
        return 0;
    const int copy = id == GL_PROG_NOFF_COPY;
    gl_bind(gl, 3, slot(s, copy ? GL_BUF_NEAR_REST : GL_BUF_NEAR_OFF_INTS));
    gl_bind(gl, 4, slot(s, GL_BUF_NEAR_REST_COC));
    gl_bind(gl, 5, slot(s, GL_BUF_NEAR_OFF_LEVEL));
    gl_bind(gl, 6, slot(s, GL_BUF_NEAR_OFF_BOX));
    gl_bind(gl, 7, slot(s, GL_BUF_NEAR_OFF_SEARCH));
    gl_uniform_u(gl, prog, "u_s", o->l.s);
    gl_uniform_u(gl, prog, "u_wl", o->l.wl);
    gl_uniform_u(gl, prog, "u_hl", o->l.hl);
    gl_uniform_u(gl, prog, "u_gw", o->gw);
    gl_uniform_u(gl, prog, "u_gh", o->gh);
    gl->ProgramUniform1i(prog, gl->GetUniformLocation(prog, "u_reach"), o->l.reach);
    gl->UseProgram(prog);
    return prog;
}

static int run_offsets_step(offsets_run *o, gl_program_id id, uint64_t invocations)
{
    if (!offsets_step(o, id))
        return 0;
    gl_dispatch(&o->s->device->gl, invocations, LOCAL);
    return 1;
}

/* Box sums of `radius` over the first `maps` box maps (near_offsets_fill.c's box_sums). */
static int box_sums(offsets_run *o, uint32_t maps, uint32_t radius)
{
    const gl_functions *gl = &o->s->device->gl;
    const gl_program_id ids[2] = {GL_PROG_NOFF_BOX_ROWS, GL_PROG_NOFF_BOX_COLUMNS};
    const uint32_t lines[2] = {o->l.hl, o->l.wl};
    for (int k = 0; k < 2; k++) {
        GLuint prog = offsets_step(o, ids[k]);
        if (!prog)
            return 0;
        gl_uniform_u(gl, prog, "u_maps", maps);
        gl_uniform_u(gl, prog, "u_radius", radius);
        gl_dispatch(gl, (uint64_t)maps * lines[k], LOCAL);
    }
    return 1;
}

static void set_offset(offsets_run *o, GLuint prog, ddof_near_offset d)
{
    const gl_functions *gl = &o->s->device->gl;
    gl->ProgramUniform1i(prog, gl->GetUniformLocation(prog, "u_dx"), d.dx);
    gl->ProgramUniform1i(prog, gl->GetUniformLocation(prog, "u_dy"), d.dy);
}

/* The search (coarse, then fine) and the candidates, chosen on the host by the CPU's rules
 * (ddof_near_rules.h) from the errors read back, each refined to the pixel: into level (blocks)
 * and full (pixels), their count in *candidates. `errors` (side^2 floats and ranks) and
 * `around` ((2 s + 1)^2 floats) are the host's room for the counts read. */
static int search(offsets_run *o, float *errors, ddof_near_ranked *rank, float *around,
                  ddof_near_offset *level, ddof_near_offset *full, uint32_t *candidates)
{
    split_run *s = o->s;
    const gl_functions *gl = &s->device->gl;
    const uint32_t grid = o->side * o->side;
    const uint64_t errors_at = (4ull * o->gw * o->gh +
                                (uint64_t)DDOF_NEAR_SAMPLE_STRIDE * 4 * o->gw * o->l.hl) *
                               sizeof(float);
    uint32_t todo[9 * DDOF_NEAR_COARSE_KEPT];
    GLuint prog = offsets_step(o, GL_PROG_NOFF_SEARCH);
    if (!prog)
        return 0;
    gl_uniform_u(gl, prog, "u_count", 0);
    gl_dispatch(gl, grid, LOCAL);
    read_back(s, GL_BUF_NEAR_OFF_SEARCH, errors_at, errors, grid * sizeof(float));
    const uint32_t best = ddof_near_rank(errors, o->side, rank);
    const uint32_t count = ddof_near_fine_offsets(rank, best, o->side, todo);
    if (count) {
        write_to(s, GL_BUF_NEAR_OFF_INTS,
                 (4ull + 2ull * o->l.hl + DDOF_NEAR_REFINE_SAMPLES) * sizeof(uint32_t), todo,
                 count * sizeof(uint32_t));
        if (!(prog = offsets_step(o, GL_PROG_NOFF_SEARCH)))
            return 0;
        gl_uniform_u(gl, prog, "u_count", count);
        gl_dispatch(gl, count, LOCAL);
        read_back(s, GL_BUF_NEAR_OFF_SEARCH, errors_at, errors, grid * sizeof(float));
    }
    const uint32_t finite = ddof_near_rank(errors, o->side, rank);
    const uint32_t chosen = ddof_near_choose(rank, finite, o->l.reach, level);

    const uint32_t n = o->refine_side * o->refine_side;
    const uint64_t refine_at = errors_at + (uint64_t)grid * sizeof(float);
    for (uint32_t c = 0; c < chosen; c++) {
        if (!(prog = offsets_step(o, GL_PROG_NOFF_REFINE)))
            return 0;
        set_offset(o, prog, (ddof_near_offset){level[c].dx * (int32_t)o->l.s,
                                               level[c].dy * (int32_t)o->l.s});
        gl_uniform_u(gl, prog, "u_current", c);
        gl_dispatch(gl, n, LOCAL);
    }
    uint32_t kept = 0;
    for (uint32_t c = 0; c < chosen; c++) {
        read_back(s, GL_BUF_NEAR_OFF_SEARCH, refine_at + (uint64_t)c * n * sizeof(float), around,
                  n * sizeof(float));
        const ddof_near_offset start = {level[c].dx * (int32_t)o->l.s,
                                        level[c].dy * (int32_t)o->l.s};
        ddof_near_refine_keep(around, start, o->l.s, full, level, &kept);
    }
    *candidates = kept;
    return 1;
}

/* The level, the band and its samples, the search's planes; 0 known samples: *searchable 0. */
static int prepare(offsets_run *o, int *searchable)
{
    split_run *s = o->s;
    const uint32_t zero[4] = {0, 0, 0, 0};
    write_to(s, GL_BUF_NEAR_OFF_INTS, 0, zero, sizeof zero);
    if (!run_offsets_step(o, GL_PROG_NOFF_REDUCE, o->nb) || !box_sums(o, 1, DDOF_NEAR_BAND) ||
        !run_offsets_step(o, GL_PROG_NOFF_BAND, o->nb) ||
        !run_offsets_step(o, GL_PROG_NOFF_PHASES,
                          (uint64_t)DDOF_NEAR_SAMPLE_STRIDE * o->gw * o->l.hl) ||
        !run_offsets_step(o, GL_PROG_NOFF_GRID, (uint64_t)o->gw * o->gh) ||
        !run_offsets_step(o, GL_PROG_NOFF_BAND_ROWS, o->l.hl) ||
        !run_offsets_step(o, GL_PROG_NOFF_BAND_TOTAL, 1) ||
        !run_offsets_step(o, GL_PROG_NOFF_BAND_SAMPLES, o->l.hl))
        return 0;
    uint32_t samples = 0;
    read_back(s, GL_BUF_NEAR_OFF_INTS, 0, &samples, sizeof samples);
    *searchable = samples > 0;
    return 1;
}

/* Each candidate's scores, kept among each hole block's best, then the copies. */
static int score_and_copy(offsets_run *o, const ddof_near_offset *level,
                          const ddof_near_offset *full, uint32_t candidates)
{
    split_run *s = o->s;
    const gl_functions *gl = &s->device->gl;
    if (!run_offsets_step(o, GL_PROG_NOFF_VARIANCE_MAPS, o->nb) ||
        !box_sums(o, 7, DDOF_NEAR_SCORE_RADIUS) ||
        !run_offsets_step(o, GL_PROG_NOFF_VARIANCE, o->nb))
        return 0;
    for (uint32_t c = 0; c < candidates; c++) {
        GLuint prog = offsets_step(o, GL_PROG_NOFF_CANDIDATE);
        if (!prog)
            return 0;
        set_offset(o, prog, level[c]);
        gl_dispatch(gl, o->nb, LOCAL);
        if (!box_sums(o, 2, DDOF_NEAR_SCORE_RADIUS) ||
            !(prog = offsets_step(o, GL_PROG_NOFF_KEEP)))
            return 0;
        set_offset(o, prog, level[c]);
        gl_uniform_u(gl, prog, "u_current", c);
        gl_dispatch(gl, o->nb, LOCAL);
    }
    GLuint prog = offsets_step(o, GL_PROG_NOFF_COPY);
    if (!prog)
        return 0;
    for (uint32_t c = 0; c < candidates; c++) {
        char name[32];
        snprintf(name, sizeof name, "u_full[%u]", c);
        gl->ProgramUniform2i(prog, gl->GetUniformLocation(prog, name), full[c].dx, full[c].dy);
    }
    gl_dispatch(gl, (uint64_t)s->w * s->h, LOCAL);
    return 1;
}

/* ../near_offsets_fill.c's ddof_fill_from_offsets on the device. */
static int fill_from_offsets(split_run *s)
{
    offsets_run o = {.s = s};
    if (!ddof_near_search_level(s->w, s->h, &o.l))
        return 1; /* too small a frame to repeat itself */
    o.gw = (o.l.wl + DDOF_NEAR_SAMPLE_STRIDE - 1) / DDOF_NEAR_SAMPLE_STRIDE;
    o.gh = (o.l.hl + DDOF_NEAR_SAMPLE_STRIDE - 1) / DDOF_NEAR_SAMPLE_STRIDE;
    o.side = ddof_near_grid_side(o.l.reach);
    o.refine_side = 2 * (uint32_t)ddof_near_refine_reach(o.l.s) + 1;
    o.nb = o.l.wl * o.l.hl;
    const uint64_t grid = (uint64_t)o.side * o.side;
    const uint64_t around = (uint64_t)o.refine_side * o.refine_side;
    const uint64_t search_floats = 4ull * o.gw * o.gh +
                                   (uint64_t)DDOF_NEAR_SAMPLE_STRIDE * 4 * o.gw * o.l.hl + grid +
                                   DDOF_NEAR_CANDIDATES * around;
    const uint64_t ints =
        4ull + 2ull * o.l.hl + DDOF_NEAR_REFINE_SAMPLES + 9 * DDOF_NEAR_COARSE_KEPT;
    if (!need(s, GL_BUF_NEAR_OFF_LEVEL, (7ull + 2 * DDOF_NEAR_KEPT) * o.nb * sizeof(float)) ||
        !need(s, GL_BUF_NEAR_OFF_BOX, 2ull * DDOF_NEAR_MAX_BOX_MAPS * o.nb * sizeof(float)) ||
        !need(s, GL_BUF_NEAR_OFF_SEARCH, search_floats * sizeof(float)) ||
        !need(s, GL_BUF_NEAR_OFF_INTS, ints * sizeof(uint32_t)))
        return 0;
    int searchable = 0;
    if (!prepare(&o, &searchable))
        return 0;
    if (!searchable)
        return 1;
    /* The host's room for what it reads: the search's errors and ranks, a candidate's. */
    float *errors = malloc(grid * sizeof(float) + around * sizeof(float));
    ddof_near_ranked *rank = malloc(grid * sizeof *rank);
    if (!errors || !rank) {
        free(errors);
        free(rank);
        snprintf(s->message, s->size, "out of memory (the near layer's search)");
        return 0;
    }
    ddof_near_offset level[DDOF_NEAR_CANDIDATES], full[DDOF_NEAR_CANDIDATES];
    uint32_t candidates = 0;
    int ok = search(&o, errors, rank, errors + grid, level, full, &candidates);
    free(errors);
    free(rank);
    if (ok && candidates)
        ok = score_and_copy(&o, level, full, candidates);
    return ok;
}

/* ---- the split ---------------------------------------------------------------------------- */

static adi_box facts_box(const uint32_t *f)
{
    return (adi_box){f[0], f[1], f[2], f[3]};
}

int gl_split_near(ddof_device *device, const adi_near_request *q, adi_near_split *split,
                  int *declined, char *message, size_t size)
{
    const adi_request *r = &q->base;
    split_run s = {.device = device, .q = q, .w = r->width, .h = r->height, .c = r->channels,
                   .message = message, .size = size};
    *declined = 0;
    const uint32_t longest = s.w > s.h ? s.w : s.h;
    if (!device->info.hardware && longest > SOFTWARE_LINE_LIMIT) {
        snprintf(message, size, "lines of %u pixels are longer than this software renderer "
                 "walks (at most %u)", longest, SOFTWARE_LINE_LIMIT);
        *declined = 1;
        return 0;
    }
    const uint64_t n = (uint64_t)s.w * s.h;
    const uint64_t pyramid = lay_out(&s);
    if (!upload(&s) || !need(&s, GL_BUF_NEAR_REST, n * s.c * 4) ||
        !need(&s, GL_BUF_NEAR_REST_COC, n * 4) || !need(&s, GL_BUF_NEAR_ELEMENT, n * 16) ||
        !need(&s, GL_BUF_NEAR_ELEMENT_COC, n * 4) || !need(&s, GL_BUF_NEAR_MAPS, n * 5 * 4) ||
        !need(&s, GL_BUF_NEAR_PYRAMID, pyramid * 4) ||
        !need(&s, GL_BUF_NEAR_FACTS, FACTS * 4))
        return 0;
    int filled = 0;
    if (!split_step(&s, GL_PROG_NEAR_MATTE))
        return 0;
    gl_dispatch(&device->gl, n, LOCAL);
    if (!pull(&s, &filled))
        return 0;
    if (filled && (!push(&s) || !lines(&s) || !fill_from_offsets(&s)))
        return 0;
    uint32_t facts[FACTS] = {UINT32_MAX, UINT32_MAX, 0, 0, 0, 0, 0, 0,
                             UINT32_MAX, UINT32_MAX, 0, 0, UINT32_MAX, UINT32_MAX, 0, 0};
    write_to(&s, GL_BUF_NEAR_FACTS, 0, facts, sizeof facts);
    GLuint prog = split_step(&s, GL_PROG_NEAR_FINISH);
    if (!prog)
        return 0;
    gl_uniform_u(&device->gl, prog, "u_filled", (GLuint)filled);
    gl_dispatch(&device->gl, n, LOCAL);
    if (!(prog = split_step(&s, GL_PROG_NEAR_ANALYSE)))
        return 0;
    gl_uniform_f(&device->gl, prog, "u_bg_threshold", q->background_threshold_px);
    gl_uniform_f(&device->gl, prog, "u_bg_insulator", q->background_ramp_start_px);
    gl_dispatch(&device->gl, n, LOCAL);
    read_back(&s, GL_BUF_NEAR_FACTS, 0, facts, sizeof facts);
    float max_coc;
    memcpy(&max_coc, &facts[4], sizeof max_coc);
    *split = (adi_near_split){.rest = ADI_ON_DEVICE, .rest_coc = ADI_ON_DEVICE,
                              .element = ADI_ON_DEVICE, .element_coc = ADI_ON_DEVICE,
                              .carried_alpha = facts[7] ? ADI_ON_DEVICE : NULL,
                              .box = facts_box(facts), .max_coc = max_coc,
                              .element_pixels = facts[5], .holes = facts[6],
                              .filled = (uint32_t)filled,
                              .rest_background_box = facts_box(facts + 8),
                              .rest_near_box = facts_box(facts + 12)};
    return 1;
}
