/* SPDX-License-Identifier: MIT */
/* gl_highlights_find.c - ../highlights_find.c's find on the device (gl_passes.h), each step a
 * highlights_find.comp program: the classes' counts and costs in the CPU's order, the budget
 * applied on the host to their 128 totals (ddof_highlight_choose, the CPU's rule), the items in
 * row order, for the frame the parts sharp occluders hide, and the items sorted into their size
 * classes for highlights.comp's drawing. The host reads only counts (the totals, the entries,
 * the parts kept and their cost, the classes' table): never the colour or the list. */
#include "gl_passes.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

/* Pixels of a chunk one invocation takes per dispatch, chunks or blocks per dispatch of a
 * step that one invocation runs alone (llvmpipe's loop limit), and the scan's block (as the
 * shader's). */
#define PIXEL_STEPS 2048u
#define SERIAL_STEPS 256u
#define SPEND_STEPS 4096u
#define SCAN_BLOCK 1024u
#define SORT_BLOCK 256u
#define CLASSES DDOF_HIGHLIGHT_CLASSES
#define SIZE_CLASSES GL_HIGHLIGHT_CLASSES
#define HIGHLIGHT_FLOATS (sizeof(adi_highlight) / sizeof(float))

typedef struct find_run {
    ddof_device *device;
    const gl_find_request *q;
    uint32_t chunks;
    char *message;
    size_t size;
} find_run;

/* The smallest positive float whose class by `class_of` is at least k (+inf when none): the
 * class functions are non-decreasing, so a bisection over the floats' bit patterns finds it. */
static float least_of_class(int (*class_of)(float, float), float arg, float from, int k)
{
    uint32_t lo, hi = 0x7f800000u; /* +inf */
    memcpy(&lo, &from, sizeof lo);
    while (lo < hi) {
        const uint32_t mid = lo + (hi - lo) / 2;
        float v;
        memcpy(&v, &mid, sizeof v);
        if (class_of(v, arg) >= k)
            hi = mid;
        else
            lo = mid + 1;
    }
    float v;
    memcpy(&v, &lo, sizeof v);
    return v;
}

static int size_class_of(float coc, float unused)
{
    (void)unused;
    return ddof_highlight_size_class(coc, 0);
}

/* The shader's tables: each brightness class's least brightness over the threshold, each size
 * class's least |CoC|, each size class's landing threshold (std430 floats). */
static int upload_bounds(find_run *f)
{
    float bounds[CLASSES + 32 + 32] = {0};
    const float above = nextafterf(f->q->threshold, INFINITY);
    bounds[0] = above;
    for (int k = 1; k < CLASSES; k++)
        bounds[k] = least_of_class(ddof_highlight_brightness_class, f->q->threshold, above, k);
    for (int k = 1; k < DDOF_HIGHLIGHT_SIZE_CLASSES; k++)
        bounds[CLASSES + k] =
            least_of_class(size_class_of, 0.0f, DDOF_HIGHLIGHT_MIN_COC_PX, k);
    for (int k = 0; k < SIZE_CLASSES; k++)
        bounds[CLASSES + 32 + k] = ddof_highlight_landing_threshold(k);
    const GLuint b = gl_need(f->device, GL_BUF_HLF_BOUNDS, sizeof bounds, f->message, f->size);
    if (!b)
        return 0;
    const gl_functions *gl = &f->device->gl;
    gl->BindBuffer(GL_SHADER_STORAGE_BUFFER, b);
    gl->BufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof bounds, bounds);
    return 1;
}

static GLuint slot(const find_run *f, gl_buffer_slot s)
{
    const gl_buffers *b = &f->device->buffers;
    return b->name[s] ? b->name[s] : b->name[GL_BUF_DUMMY];
}

/* A find step with every binding and the uniforms every step shares; 0 on failure. */
static GLuint step(find_run *f, gl_program_id id, gl_buffer_slot all)
{
    const gl_functions *gl = &f->device->gl;
    const gl_find_request *q = f->q;
    GLuint prog = gl_programs_get(gl, &f->device->programs, id, f->message, f->size);
    if (!prog)
        return 0;
    const GLuint dummy = f->device->buffers.name[GL_BUF_DUMMY];
    gl_bind_ref(gl, 0, &q->coc, dummy);
    gl_bind_ref(gl, 1, &q->color, dummy);
    /* Bindings 2..12 (highlights_find.comp): ALL is the list the sort reads (FOUND where no
     * hidden part joined it), SORTED the request's. */
    const gl_buffer_slot bound[11] = {
        GL_BUF_HLF_COUNTS, GL_BUF_HLF_COSTS, GL_BUF_HLF_FOUND, GL_BUF_HLF_PIXELS,
        GL_BUF_HLF_SCAN,   GL_BUF_HLF_MERGED, GL_BUF_HLF_KEPT, all,
        q->sorted,         GL_BUF_HLF_CLASSES, GL_BUF_HLF_BOUNDS};
    for (GLuint i = 0; i < 11; i++)
        gl_bind(gl, 2 + i, slot(f, bound[i]));
    gl_uniform_u(gl, prog, "u_width", q->width);
    gl_uniform_u(gl, prog, "u_height", q->height);
    gl_uniform_ref(gl, prog, "u_color", &q->color);
    gl_uniform_ref(gl, prog, "u_coc", &q->coc);
    gl_uniform_u(gl, prog, "u_owner", q->owner);
    gl_uniform_u(gl, prog, "u_coc_signed", q->coc_signed);
    gl_uniform_f(gl, prog, "u_threshold", q->threshold);
    gl_uniform_u(gl, prog, "u_area", q->area);
    gl_uniform_f(gl, prog, "u_aspect", q->aspect);
    gl_uniform_u(gl, prog, "u_chunks", f->chunks);
    gl->UseProgram(prog);
    return prog;
}

/* `steps` of a step's loop over `invocations`, `per` a dispatch; at least one dispatch, whose
 * first segment sets the step's running state even when there are no steps. */
static void segments(const gl_functions *gl, GLuint prog, uint64_t invocations, uint32_t steps,
                     uint32_t per)
{
    uint32_t first = 0;
    do {
        gl_uniform_u(gl, prog, "u_seg_first", first);
        gl_uniform_u(gl, prog, "u_seg_count", steps - first < per ? steps - first : per);
        gl_dispatch(gl, invocations, 64);
        first += per;
    } while (first < steps);
}

/* `count` words of a buffer from word `first` (a few bytes: counts, never an image). */
static void read_words(const find_run *f, gl_buffer_slot s, uint64_t first, uint64_t count,
                       size_t word, void *out)
{
    const gl_functions *gl = &f->device->gl;
    gl->MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    gl->BindBuffer(GL_SHADER_STORAGE_BUFFER, f->device->buffers.name[s]);
    gl->GetBufferSubData(GL_SHADER_STORAGE_BUFFER, (GLintptr)(first * word),
                         (GLsizeiptr)(count * word), out);
}

/* Where Counts' sections start (highlights_find.comp). */
static uint64_t totals_at(const find_run *f)
{
    return (uint64_t)f->chunks * CLASSES;
}

static uint64_t scalars_at(const find_run *f)
{
    return totals_at(f) + CLASSES + 2u * (uint64_t)f->chunks;
}

/* The classes' counts and costs, their totals read back, the budget's choice. */
static int count_classes(find_run *f, ddof_highlight_choice *choice)
{
    const gl_find_request *q = f->q;
    const gl_functions *gl = &f->device->gl;
    if (!gl_need(f->device, GL_BUF_HLF_COUNTS, (scalars_at(f) + 8) * sizeof(GLuint), f->message,
                 f->size) ||
        !gl_need(f->device, GL_BUF_HLF_COSTS, (totals_at(f) + CLASSES + 1) * sizeof(double),
                 f->message, f->size))
        return 0;
    GLuint prog = step(f, GL_PROG_HLF_COUNT, GL_BUF_HLF_FOUND);
    if (!prog)
        return 0;
    segments(gl, prog, f->chunks, DDOF_HIGHLIGHT_CHUNK_ROWS * q->width, PIXEL_STEPS);
    if (!(prog = step(f, GL_PROG_HLF_TOTALS, GL_BUF_HLF_FOUND)))
        return 0;
    gl_dispatch(gl, CLASSES, 64);
    GLuint counts[CLASSES];
    double costs[CLASSES];
    read_words(f, GL_BUF_HLF_COUNTS, totals_at(f), CLASSES, sizeof(GLuint), counts);
    read_words(f, GL_BUF_HLF_COSTS, totals_at(f), CLASSES, sizeof(double), costs);
    uint64_t count[CLASSES];
    for (int k = 0; k < CLASSES; k++)
        count[k] = counts[k];
    const double budget = DDOF_HIGHLIGHT_BUDGET * (double)q->width * q->height;
    *choice = ddof_highlight_choose(count, costs, budget, q->threshold);
    return 1;
}

/* The kept items in row order into FOUND. */
static int fill_items(find_run *f, const ddof_highlight_choice *choice)
{
    const gl_find_request *q = f->q;
    const gl_functions *gl = &f->device->gl;
    if (!gl_need(f->device, GL_BUF_HLF_FOUND, choice->kept * sizeof(adi_highlight), f->message,
                 f->size))
        return 0;
    GLuint prog = step(f, GL_PROG_HLF_OFFSETS, GL_BUF_HLF_FOUND);
    if (!prog)
        return 0;
    gl_uniform_u(gl, prog, "u_first", choice->first);
    segments(gl, prog, 1, f->chunks, SERIAL_STEPS);
    if (!(prog = step(f, GL_PROG_HLF_FILL, GL_BUF_HLF_FOUND)))
        return 0;
    gl_uniform_u(gl, prog, "u_first", choice->first);
    gl_uniform_f(gl, prog, "u_kept", choice->threshold);
    segments(gl, prog, f->chunks, DDOF_HIGHLIGHT_CHUNK_ROWS * q->width, PIXEL_STEPS);
    return 1;
}

/* A step of the hidden parts with the choice's uniforms. */
static GLuint hidden_step(find_run *f, gl_program_id id, const ddof_highlight_choice *choice,
                          uint32_t count)
{
    GLuint prog = step(f, id, GL_BUF_HLF_ALL);
    if (prog) {
        const gl_functions *gl = &f->device->gl;
        gl_uniform_u(gl, prog, "u_first", choice->first);
        gl_uniform_f(gl, prog, "u_kept", choice->threshold);
        gl_uniform_u(gl, prog, "u_count", count);
    }
    return prog;
}

/* highlights_find.c's add_hidden_parts: the parts kept merged with the visible items into ALL
 * (*total of them, *hidden of those the parts), *cost grown by theirs; *total stays the
 * visible count where there are none (ALL then unused). */
static int hidden_parts(find_run *f, const ddof_highlight_choice *choice, uint32_t *total,
                        uint32_t *hidden, double *cost)
{
    const gl_find_request *q = f->q;
    const gl_functions *gl = &f->device->gl;
    const uint64_t pixels = (uint64_t)q->width * q->height;
    const uint32_t visible = (uint32_t)choice->kept;
    *total = visible;
    *hidden = 0;
    if (!gl_need(f->device, GL_BUF_HLF_PIXELS, pixels * sizeof(GLuint), f->message, f->size))
        return 0;
    GLuint prog = hidden_step(f, GL_PROG_HLF_CLEAR, choice, visible);
    if (!prog)
        return 0;
    gl_dispatch(gl, pixels, 64);
    if (!(prog = hidden_step(f, GL_PROG_HLF_MARK, choice, visible)))
        return 0;
    gl_dispatch(gl, visible, 64);
    GLuint entries = 0;
    read_words(f, GL_BUF_HLF_COUNTS, scalars_at(f) + 1, 1, sizeof(GLuint), &entries);
    /* As the CPU: a frame with more than that keeps its memory bounded and draws the visible
     * parts alone. */
    if (!entries || entries > pixels / 4)
        return 1;
    const uint64_t blocks = (pixels + SCAN_BLOCK - 1) / SCAN_BLOCK;
    if (!gl_need(f->device, GL_BUF_HLF_SCAN, blocks * sizeof(GLuint), f->message, f->size))
        return 0;
    static const gl_program_id scan[3] = {GL_PROG_HLF_SCAN_BLOCKS, GL_PROG_HLF_SCAN_TOP,
                                          GL_PROG_HLF_SCAN_NUMBER};
    for (int i = 0; i < 3; i++) {
        if (!(prog = hidden_step(f, scan[i], choice, visible)))
            return 0;
        if (i == 1)
            segments(gl, prog, 1, (uint32_t)blocks, SERIAL_STEPS * 16u);
        else
            gl_dispatch(gl, blocks, 64);
    }
    GLuint marked = 0;
    read_words(f, GL_BUF_HLF_COUNTS, scalars_at(f) + 3, 1, sizeof(GLuint), &marked);
    if (!gl_need(f->device, GL_BUF_HLF_MERGED, (uint64_t)marked * sizeof(adi_highlight),
                 f->message, f->size) ||
        !gl_need(f->device, GL_BUF_HLF_KEPT, (uint64_t)marked * sizeof(adi_highlight),
                 f->message, f->size) ||
        !(prog = hidden_step(f, GL_PROG_HLF_GATHER, choice, visible)))
        return 0;
    gl_dispatch(gl, pixels, 64);
    if (!(prog = hidden_step(f, GL_PROG_HLF_SPEND, choice, marked)))
        return 0;
    const double budget = DDOF_HIGHLIGHT_BUDGET * (double)q->width * q->height;
    gl->ProgramUniform4d(prog, gl->GetUniformLocation(prog, "u_money"), budget, *cost, 0.0, 0.0);
    segments(gl, prog, 1, marked, SPEND_STEPS);
    GLuint kept = 0;
    read_words(f, GL_BUF_HLF_COUNTS, scalars_at(f) + 2, 1, sizeof(GLuint), &kept);
    read_words(f, GL_BUF_HLF_COSTS, totals_at(f) + CLASSES, 1, sizeof(double), cost);
    if (!kept)
        return 1;
    if (!gl_need(f->device, GL_BUF_HLF_ALL, ((uint64_t)visible + kept) * sizeof(adi_highlight),
                 f->message, f->size) ||
        !(prog = hidden_step(f, GL_PROG_HLF_MERGE, choice, visible)))
        return 0;
    gl_uniform_u(gl, prog, "u_other", kept);
    gl_dispatch(gl, (uint64_t)visible + kept, 64);
    *total = visible + kept;
    *hidden = kept;
    return 1;
}

/* The items of `all` sorted into their size classes into the request's buffer, and the
 * classes' table (gl_highlights.c's prepare, on the device; boxes clipped to the frame here). */
static int sort_classes(find_run *f, gl_buffer_slot all, uint32_t count, gl_found *found)
{
    const gl_find_request *q = f->q;
    const gl_functions *gl = &f->device->gl;
    const uint64_t blocks = (count + SORT_BLOCK - 1) / SORT_BLOCK;
    if (!gl_need(f->device, q->sorted, (uint64_t)count * sizeof(adi_highlight), f->message,
                 f->size) ||
        !gl_need(f->device, GL_BUF_HLF_CLASSES, (SIZE_CLASSES * 8 + blocks * SIZE_CLASSES) * 4,
                 f->message, f->size))
        return 0;
    /* Per block, per class, once, per block, per item. */
    static const gl_program_id steps[5] = {GL_PROG_HLF_SORT_COUNT, GL_PROG_HLF_SORT_TOP,
                                           GL_PROG_HLF_SORT_FIRST, GL_PROG_HLF_SORT_PLACE,
                                           GL_PROG_HLF_SORT_BOXES};
    const uint64_t invocations[5] = {blocks, SIZE_CLASSES, 1, blocks, count};
    for (int i = 0; i < 5; i++) {
        GLuint prog = step(f, steps[i], all);
        if (!prog)
            return 0;
        gl_uniform_u(gl, prog, "u_count", count);
        gl_dispatch(gl, invocations[i], 64);
    }
    GLint table[SIZE_CLASSES * 8];
    read_words(f, GL_BUF_HLF_CLASSES, 0, SIZE_CLASSES * 8, sizeof(GLint), table);
    for (int k = 0; k < SIZE_CLASSES; k++) {
        const GLint *t = table + 8 * k;
        gl_highlight_class *c = &found->classes[k];
        *c = (gl_highlight_class){.first = (uint32_t)t[1], .count = (uint32_t)t[0],
                                  .threshold = ddof_highlight_landing_threshold(k),
                                  .reach_rows = t[2], .reach_x = t[3],
                                  .bx0 = t[4] < 0 ? 0 : t[4],
                                  .bx1 = t[5] > (int)q->width ? (int)q->width : t[5],
                                  .by0 = t[6] < 0 ? 0 : t[6],
                                  .by1 = t[7] > (int)q->height ? (int)q->height : t[7]};
        if (!c->count)
            *c = (gl_highlight_class){.first = c->first, .threshold = c->threshold,
                                      .bx0 = 0, .by0 = 0, .bx1 = 0, .by1 = 0};
    }
    return 1;
}

int gl_find_highlights(ddof_device *device, const gl_find_request *q, gl_found *found,
                       char *message, size_t size)
{
    memset(found, 0, sizeof *found);
    found->threshold = q->threshold;
    find_run f = {.device = device, .q = q,
                  .chunks = (q->height + DDOF_HIGHLIGHT_CHUNK_ROWS - 1) / DDOF_HIGHLIGHT_CHUNK_ROWS,
                  .message = message, .size = size};
    if (!q->width || !q->height)
        return 1;
    if (!gl_need(device, GL_BUF_DUMMY, 16, message, size) || !upload_bounds(&f))
        return 0;
    ddof_highlight_choice choice;
    if (!count_classes(&f, &choice))
        return 0;
    found->threshold = choice.threshold;
    found->over_budget = (uint32_t)choice.over_budget;
    if (!choice.kept)
        return 1;
    if (!fill_items(&f, &choice))
        return 0;
    uint32_t total = (uint32_t)choice.kept, hidden = 0;
    double cost = choice.kept_cost;
    if (q->owner == 1u && !hidden_parts(&f, &choice, &total, &hidden, &cost))
        return 0;
    if (!sort_classes(&f, hidden ? GL_BUF_HLF_ALL : GL_BUF_HLF_FOUND, total, found))
        return 0;
    found->count = total;
    found->hidden = hidden;
    found->cost = (uint64_t)cost;
    return 1;
}
