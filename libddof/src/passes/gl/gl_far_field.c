/* SPDX-License-Identifier: MIT */
/* gl_far_field.c - ../far_field.c on the device (gl_passes.h): the same steps in the same order
 * on device-resident images, each a far_field.comp program; the distance maps are
 * cone_dilate.comp's. The host takes only the decisions the CPU takes from counts
 * (ddof_far_rules.h): whether anything takes the gather, how many image levels the largest
 * radius needs, and the depth slices' cuts from the counts of pairs each bin edge separates.
 * So the frame's pixels never leave the device. */
#include "gl_passes.h"

#include "ddof_far_rules.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* far_field.comp's table: the counts, the levels' offsets, the cuts' difference array. */
enum {
    T_PIXELS = 0,
    T_LAYERED = 1,
    T_LARGEST = 2,
    T_PAIRS = 3,
    T_LO = 4,
    T_HI = 5,
    T_MEMBERS = 8,
    T_MEAN = 12,
    T_REACH = 16,
    TABLE_COUNTS = 32,
    TABLE_LEVELS = 32,
    TABLE_RUNS = 160,
    TABLE_WORDS = TABLE_RUNS + FAR_MAX_BINS + 2
};

/* Steps of a line one invocation runs per dispatch (far_field.comp: llvmpipe's loop limit),
 * and the pixels of one partial sum of the slices' radii. */
#define SEGMENT_STEPS 4096u
#define CHUNK_PIXELS 1024u

typedef struct far_run {
    ddof_device *device;
    const gl_far_field_request *q;
    uint32_t pixels;
    /* the gather under way: its level-0 image, its channels, its radius and weight maps */
    gl_image_ref src;
    uint32_t channels;
    gl_buffer_slot radius, weight;
    int sink;
    uint32_t level_count;
    char *message;
    size_t size;
} far_run;

static GLuint buffer(const far_run *f, gl_buffer_slot s)
{
    const gl_buffers *b = &f->device->buffers;
    return b->name[s] ? b->name[s] : b->name[GL_BUF_DUMMY];
}

static int need(far_run *f, gl_buffer_slot s, uint64_t bytes)
{
    return gl_need(f->device, s, bytes, f->message, f->size) != 0;
}

/* Program `id` with the bindings and the uniforms every step shares; 0 on failure. */
static GLuint step(far_run *f, gl_program_id id)
{
    const gl_far_field_request *q = f->q;
    const gl_functions *gl = &f->device->gl;
    GLuint prog = gl_programs_get(gl, &f->device->programs, id, f->message, f->size);
    if (!prog)
        return 0;
    const GLuint dummy = buffer(f, GL_BUF_DUMMY);
    gl_bind_ref(gl, 0, &q->coc, dummy);
    gl_bind_ref(gl, 1, &f->src, dummy);
    gl_bind(gl, 2, q->out);
    static const gl_buffer_slot maps[5] = {GL_BUF_FAR_RADIUS, GL_BUF_FAR_WEIGHT,
                                           GL_BUF_FAR_REACH, GL_BUF_FAR_LAYERED,
                                           GL_BUF_FAR_SHARP};
    for (GLuint i = 0; i < 5; i++)
        gl_bind(gl, 3 + i, buffer(f, maps[i]));
    gl_bind(gl, 3, buffer(f, f->radius));
    gl_bind(gl, 4, buffer(f, f->weight));
    static const gl_buffer_slot rest[5] = {GL_BUF_FAR_LEVELS, GL_BUF_FAR_TABLE, GL_BUF_FAR_SINK,
                                           GL_BUF_FAR_WORK, GL_BUF_FAR_DOUBLES};
    for (GLuint i = 0; i < 5; i++)
        gl_bind(gl, 8 + i, buffer(f, rest[i]));
    const uint32_t w = q->width, h = q->height, c = q->channels;
    gl_uniform_u(gl, prog, "u_width", w);
    gl_uniform_u(gl, prog, "u_height", h);
    gl_uniform_u(gl, prog, "u_channels", f->channels);
    gl_uniform_u(gl, prog, "u_frame_channels", c);
    gl_uniform_ref(gl, prog, "u_coc", &q->coc);
    gl_uniform_ref(gl, prog, "u_src", &f->src);
    gl_uniform_f(gl, prog, "u_in_focus", q->in_focus_px);
    gl_uniform_f(gl, prog, "u_aspect", q->pixel_aspect);
    gl_uniform_u(gl, prog, "u_slices", (GLuint)q->slices);
    gl_uniform_u(gl, prog, "u_sink", (GLuint)f->sink);
    gl_uniform_u(gl, prog, "u_level_count", f->level_count);
    gl_uniform_u(gl, prog, "u_acc_at", 0);
    gl_uniform_u(gl, prog, "u_last_at", f->pixels * c);
    gl_uniform_u(gl, prog, "u_state_at", 2 * f->pixels * c);
    gl_uniform_u(gl, prog, "u_box_at", f->pixels * (c + 1));
    gl_uniform_u(gl, prog, "u_column_at", 0);
    gl_uniform_u(gl, prog, "u_rowstate_at", 2 * w);
    gl_uniform_u(gl, prog, "u_partial_at", 2 * w + 2 * h);
    gl_uniform_u(gl, prog, "u_chunk", CHUNK_PIXELS);
    gl->UseProgram(prog);
    return prog;
}

/* A step whose uniforms are the shared ones, over `invocations`; 0 on failure. */
static int run(far_run *f, gl_program_id id, uint64_t invocations)
{
    if (!step(f, id))
        return 0;
    gl_dispatch(&f->device->gl, invocations, 256);
    return 1;
}

/* A line step over `lines` lines of `steps` steps each, SEGMENT_STEPS a dispatch. */
static void run_segments(far_run *f, GLuint prog, uint32_t lines, uint32_t steps)
{
    const gl_functions *gl = &f->device->gl;
    for (uint32_t first = 0; first < steps; first += SEGMENT_STEPS) {
        gl_uniform_u(gl, prog, "u_seg_first", first);
        gl_uniform_u(gl, prog, "u_seg_count",
                     steps - first < SEGMENT_STEPS ? steps - first : SEGMENT_STEPS);
        gl_dispatch(gl, lines, 64);
    }
}

/* The table's words [first, first + count) to or from the host (a few bytes). */
static void table_write(far_run *f, uint32_t first, uint32_t count, const GLuint *words)
{
    const gl_functions *gl = &f->device->gl;
    gl->BindBuffer(GL_SHADER_STORAGE_BUFFER, f->device->buffers.name[GL_BUF_FAR_TABLE]);
    gl->BufferSubData(GL_SHADER_STORAGE_BUFFER, (GLintptr)first * 4, (GLsizeiptr)count * 4,
                      words);
}

static void table_read(far_run *f, uint32_t first, uint32_t count, GLuint *words)
{
    const gl_functions *gl = &f->device->gl;
    gl->MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    gl->BindBuffer(GL_SHADER_STORAGE_BUFFER, f->device->buffers.name[GL_BUF_FAR_TABLE]);
    gl->GetBufferSubData(GL_SHADER_STORAGE_BUFFER, (GLintptr)first * 4, (GLsizeiptr)count * 4,
                         words);
}

static float float_of(GLuint bits)
{
    float v;
    memcpy(&v, &bits, sizeof v);
    return v;
}

/* range.comp's ordered key, back to the float. */
static float from_ordered(GLuint key)
{
    return float_of(key & 0x80000000u ? key & 0x7fffffffu : ~key);
}

/* ---- the gather ------------------------------------------------------------------------------ */

/* far_field_gather.c's build_levels and its gather, into OUT or (f->sink) the slices' sink:
 * the levels' offsets into LEVELS go to the table, each level is built on the device. */
static int gather(far_run *f, float largest, uint32_t *levels)
{
    const gl_far_field_request *q = f->q;
    const gl_functions *gl = &f->device->gl;
    const uint32_t ch = f->channels;
    const uint32_t count = ddof_far_level_count(largest, q->pixel_aspect, q->width, q->height);
    GLuint table[8 * FAR_FIELD_MAX_LEVELS] = {0};
    uint64_t floats = 0;
    uint32_t w = q->width, h = q->height;
    for (uint32_t k = 0; k < count; k++) {
        GLuint *t = table + 8 * k;
        t[0] = w;
        t[1] = h;
        t[2] = (GLuint)floats;
        floats += (uint64_t)(w + 1) * (h + 2) * ch;
        t[3] = (GLuint)floats;
        floats += (uint64_t)(h + 2) * 2 * ch;
        if (k) {
            t[4] = (GLuint)floats;
            floats += (uint64_t)w * h * ch;
            t[5] = (GLuint)floats;
            floats += (uint64_t)w * h * ch;
            t[6] = (GLuint)floats;
            floats += (uint64_t)w * h;
        }
        w = (w + 1) / 2;
        h = (h + 1) / 2;
    }
    if (floats > UINT32_MAX) {
        snprintf(f->message, f->size, "the far field's image levels need %llu floats, more "
                 "than a buffer's index reaches", (unsigned long long)floats);
        return 0;
    }
    if (!need(f, GL_BUF_FAR_LEVELS, floats * sizeof(float)))
        return 0;
    table_write(f, TABLE_LEVELS, 8 * count, table);
    f->level_count = count;
    *levels = count;
    for (uint32_t k = 0; k < count; k++) {
        const GLuint *t = table + 8 * k;
        GLuint prog;
        if (k) {
            if (!(prog = step(f, GL_PROG_FAR_DOWNSAMPLE)))
                return 0;
            gl_uniform_u(gl, prog, "u_level", k);
            gl_dispatch(gl, (uint64_t)t[0] * t[1], 256);
        }
        if (!(prog = step(f, GL_PROG_FAR_PREFIX)))
            return 0;
        gl_uniform_u(gl, prog, "u_level", k);
        gl_uniform_u(gl, prog, "u_in_place", 0);
        run_segments(f, prog, t[1], t[0]);
        if (!(prog = step(f, GL_PROG_FAR_EDGE_ROWS)))
            return 0;
        gl_uniform_u(gl, prog, "u_level", k);
        gl_dispatch(gl, 2 * (uint64_t)t[0], 256);
        if (!(prog = step(f, GL_PROG_FAR_EDGE_SIDES)))
            return 0;
        gl_uniform_u(gl, prog, "u_level", k);
        gl_dispatch(gl, t[1], 256);
        if (!(prog = step(f, GL_PROG_FAR_PREFIX)))
            return 0;
        gl_uniform_u(gl, prog, "u_level", k);
        gl_uniform_u(gl, prog, "u_in_place", 1);
        run_segments(f, prog, 2, t[0]);
    }
    if (count > 1 && !run(f, GL_PROG_FAR_MARK, f->pixels))
        return 0;
    for (uint32_t k = 1; k < count; k++) {
        GLuint prog = step(f, GL_PROG_FAR_SAMPLES);
        if (!prog)
            return 0;
        gl_uniform_u(gl, prog, "u_level", k);
        gl_dispatch(gl, (uint64_t)table[8 * k] * table[8 * k + 1], 64);
    }
    return run(f, GL_PROG_FAR_GATHER, f->pixels);
}

/* ---- the depth slices (far_layers.c) --------------------------------------------------------- */

/* The cuts (ascending) from the counts the device makes of the pairs each bin edge separates;
 * 0 cuts where no edge separates FAR_MIN_SEPARATED pairs. -1 on failure. */
static int choose_cuts(far_run *f, float *cuts)
{
    const gl_functions *gl = &f->device->gl;
    GLuint range[3];
    if (!run(f, GL_PROG_FAR_PAIRS_RANGE, f->pixels))
        return -1;
    table_read(f, T_PAIRS, 3, range);
    if (!range[0])
        return 0;
    const float lo = from_ordered(range[1]), hi = from_ordered(range[2]);
    float width;
    const uint32_t bins = ddof_far_bins(lo, hi, &width);
    /* The counters as the device keeps them, and as ddof_far_take_cut reads them (on the
     * heap: 48 KB would be a large share of a host thread's stack). */
    int64_t *runs = malloc((size_t)(bins + 2) * (sizeof(int64_t) + sizeof(GLuint)));
    if (!runs) {
        snprintf(f->message, f->size, "out of memory for the depth slices' %u counters", bins);
        return -1;
    }
    GLuint *words = (GLuint *)(void *)(runs + bins + 2);
    uint32_t n = 0;
    while (n < FAR_LAYERS_MAX_SLICES - 1) {
        memset(words, 0, (size_t)(bins + 2) * sizeof *words);
        table_write(f, TABLE_RUNS, bins + 2, words);
        GLuint prog = step(f, GL_PROG_FAR_PAIRS_RUNS);
        if (!prog) {
            free(runs);
            return -1;
        }
        gl_uniform_f(gl, prog, "u_lo", lo);
        gl_uniform_f(gl, prog, "u_bin_width", width);
        gl_uniform_u(gl, prog, "u_bins", bins);
        gl_uniform_u(gl, prog, "u_cut_count", n);
        gl_uniform_f(gl, prog, "u_cut0", cuts[0]);
        gl_uniform_f(gl, prog, "u_cut1", cuts[1]);
        gl_uniform_f(gl, prog, "u_cut2", cuts[2]);
        gl_dispatch(gl, f->pixels, 256);
        table_read(f, TABLE_RUNS, bins + 2, words);
        for (uint32_t b = 0; b < bins + 2; b++)
            runs[b] = (int32_t)words[b];
        const uint32_t more = ddof_far_take_cut(runs, bins, lo, width, cuts, n);
        if (more == n)
            break;
        n = more;
    }
    free(runs);
    return (int)n;
}

/* far_layers.c: the slices, each gathered into the sink, composited into OUT. */
static int slices(far_run *f, float largest, uint64_t taken, gl_far_field_report *report)
{
    const gl_far_field_request *q = f->q;
    const gl_functions *gl = &f->device->gl;
    const uint32_t w = q->width, h = q->height, c = q->channels;
    float cuts[FAR_LAYERS_MAX_SLICES - 1] = {0.0f, 0.0f, 0.0f};
    const int cut_count = choose_cuts(f, cuts);
    if (cut_count <= 0)
        return cut_count == 0;
    const uint64_t chunks = (f->pixels + CHUNK_PIXELS - 1) / CHUNK_PIXELS;
    if (!need(f, GL_BUF_FAR_SINK, (uint64_t)f->pixels * (2 * c + 2) * sizeof(float)) ||
        !need(f, GL_BUF_FAR_WORK, (uint64_t)f->pixels * (c + 3) * sizeof(float)) ||
        !need(f, GL_BUF_FAR_DOUBLES, (2 * (uint64_t)w + 2 * h + 8 * chunks) * sizeof(double)))
        return 0;
    GLuint prog = step(f, GL_PROG_FAR_SLICE_INDEX);
    if (!prog)
        return 0;
    gl_uniform_u(gl, prog, "u_cut_count", (GLuint)cut_count);
    gl_uniform_f(gl, prog, "u_cut0", cuts[0]);
    gl_uniform_f(gl, prog, "u_cut1", cuts[1]);
    gl_uniform_f(gl, prog, "u_cut2", cuts[2]);
    gl_dispatch(gl, chunks, 64);
    if (!run(f, GL_PROG_FAR_SLICE_MEAN, 1))
        return 0;
    GLuint members[FAR_LAYERS_MAX_SLICES];
    table_read(f, T_MEMBERS, FAR_LAYERS_MAX_SLICES, members);
    const float box = ceilf(largest) + 1.0f;
    const uint32_t reach = (uint32_t)(box < (float)DDOF_MAX_DIMENSION ? box
                                                                      : (float)DDOF_MAX_DIMENSION);
    const gl_image_ref color = f->src;
    for (uint32_t k = 0; k < (uint32_t)cut_count + 1; k++) {
        if (!members[k])
            continue;
        /* The slice's image and its radius map (REACH) from the colour and the frame's radii. */
        f->src = color;
        f->channels = c + 1;
        f->radius = GL_BUF_FAR_RADIUS;
        f->weight = GL_BUF_FAR_WEIGHT;
        f->sink = 0;
        if (!(prog = step(f, GL_PROG_FAR_SLICE_IMAGE)))
            return 0;
        gl_uniform_u(gl, prog, "u_slice", k);
        gl_dispatch(gl, f->pixels, 256);
        if (!(prog = step(f, GL_PROG_FAR_SLICE_BOX)))
            return 0;
        gl_uniform_u(gl, prog, "u_slice", k);
        gl_uniform_u(gl, prog, "u_reach", reach);
        run_segments(f, prog, h, w + reach + 1);
        const GLuint zero = 0;
        table_write(f, T_REACH, 1, &zero);
        if (!(prog = step(f, GL_PROG_FAR_SLICE_RADII)))
            return 0;
        gl_uniform_u(gl, prog, "u_slice", k);
        gl_uniform_u(gl, prog, "u_reach", reach);
        run_segments(f, prog, w, h + reach + 1);
        GLuint slice_largest;
        table_read(f, T_REACH, 1, &slice_largest);
        /* Its gather, of premultiplied colour and coverage, into the sink. */
        f->src = (gl_image_ref){f->device->buffers.name[GL_BUF_FAR_WORK], 0, w * (c + 1), c + 1,
                                0, 0};
        f->radius = GL_BUF_FAR_REACH;
        f->weight = GL_BUF_FAR_LAYERED;
        f->sink = 1;
        uint32_t levels;
        if (!gather(f, float_of(slice_largest), &levels))
            return 0;
    }
    f->src = color;
    f->channels = c;
    f->radius = GL_BUF_FAR_RADIUS;
    f->weight = GL_BUF_FAR_WEIGHT;
    f->sink = 0;
    if (!run(f, GL_PROG_FAR_SLICES_BLEND, f->pixels))
        return 0;
    report->layered_pixels = taken;
    report->slices = (uint32_t)cut_count + 1;
    return 1;
}

/* ---- the pass ------------------------------------------------------------------------------- */

int gl_far_field(ddof_device *device, const gl_far_field_request *q, gl_far_field_report *report,
                 char *message, size_t size)
{
    memset(report, 0, sizeof *report);
    far_run f = {.device = device, .q = q, .pixels = q->width * q->height, .src = q->color,
                 .channels = q->channels, .radius = GL_BUF_FAR_RADIUS,
                 .weight = GL_BUF_FAR_WEIGHT, .message = message, .size = size};
    const uint64_t map_bytes = (uint64_t)f.pixels * sizeof(float);
    static const gl_buffer_slot maps[5] = {GL_BUF_FAR_RADIUS, GL_BUF_FAR_WEIGHT,
                                           GL_BUF_FAR_REACH, GL_BUF_FAR_LAYERED,
                                           GL_BUF_FAR_SHARP};
    for (int i = 0; i < 5; i++)
        if (!need(&f, maps[i], map_bytes))
            return 0;
    if (!need(&f, GL_BUF_FAR_TABLE, TABLE_WORDS * sizeof(GLuint)) ||
        !need(&f, GL_BUF_DUMMY, 16))
        return 0;
    GLuint counts[TABLE_COUNTS] = {0};
    counts[T_LO] = UINT32_MAX;
    table_write(&f, 0, TABLE_COUNTS, counts);

    /* The radius map, the seeds, the distances to the edges (far_field.c). */
    if (!run(&f, GL_PROG_FAR_SEED, f.pixels))
        return 0;
    for (int i = 1; i < (q->slices ? 5 : 3); i++)
        if (!gl_cone_dilate(device, device->buffers.name[maps[i]], 0, q->width, q->height,
                            q->width, 1.0f, message, size))
            return 0;
    if (!run(&f, GL_PROG_FAR_WEIGHT, f.pixels))
        return 0;
    table_read(&f, 0, 3, counts);
    report->pixels = counts[T_PIXELS];
    if (!report->pixels)
        return 1;
    const float largest = float_of(counts[T_LARGEST]);
    if (counts[T_LAYERED] && !slices(&f, largest, counts[T_LAYERED], report))
        return 0;
    return gather(&f, largest, &report->levels);
}
