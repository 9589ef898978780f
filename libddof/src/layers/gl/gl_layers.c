/* SPDX-License-Identifier: MIT */
/* gl_layers.c - the seam's run_layers: ../layers.c's pipeline with every step on the device.
 * The colour, the CoC, the foreground element, an object matte and the highlights' aperture go
 * up in one mapped write (FRAME, in the caller's layouts), the result comes back in one mapped
 * read (OUT), and in between each step is the CPU's: the per-pixel steps are layers.comp, the
 * cone dilation cone_dilate.comp, the diffusions gl_resident.c's on the device's maps, the
 * highlights' find, take-out and discs, the silhouettes' clean and split and the far field
 * (its gather of the element too) the passes' GL code (gl_passes.h), in the CPU's order and on
 * the CPU's areas (the crops are offsets into the maps), so that the device's frame differs
 * from the CPU's only by float rounding. */
#include "gl_layers.h"

#include "gl_io.h"
#include "gl_passes.h"

#include "ddof_layer_rules.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* ---- the frame's state -------------------------------------------------------------------- */

/* The images of the one upload, each a section of FRAME. */
enum {
    IN_COLOR,
    IN_COC,
    IN_FG,
    IN_FG_COC,
    IN_FG_CARRIED, /* the part of the frame's alpha the element carries */
    IN_MATTE,
    IN_HL_SHAPE, /* the aperture the highlights are drawn with */
    IN_HL_SUMS,  /* an aperture image's table                  */
    IN_FG_HL_SHAPE, /* the element's own highlights' aperture and its table */
    IN_FG_HL_SUMS,
    IN_COUNT
};

typedef struct frame {
    ddof_device *device;
    const adi_layers_request *q;
    uint32_t w, h, c;
    uint64_t at[IN_COUNT], bytes[IN_COUNT]; /* each image's section of FRAME */
    adi_layers_report *report;
    gl_found lights, fg_lights;         /* the highlights found, the element's own      */
    gl_silhouettes_request silhouettes; /* the passes' requests, on the upload's sections */
    gl_highlights_request highlights;
    uint32_t stage, stages;            /* progress: the diffusion running, of how many */
    char *message;
    size_t size;
} frame;

static GLuint slot(const frame *f, gl_buffer_slot s)
{
    const gl_buffers *b = &f->device->buffers;
    return b->name[s] ? b->name[s] : b->name[GL_BUF_DUMMY];
}

/* The images a near split left on the device (gl_near_layer.c) in place of the colour, the
 * CoC and the element's three (near_resident), each in its slot, the carried alpha a plane
 * of the split's maps. */
static const gl_buffer_slot resident[IN_FG_CARRIED + 1] = {
    GL_BUF_NEAR_REST, GL_BUF_NEAR_REST_COC, GL_BUF_NEAR_ELEMENT, GL_BUF_NEAR_ELEMENT_COC,
    GL_BUF_NEAR_MAPS};

static int is_resident(const frame *f, int in)
{
    return f->q->near_resident && in <= IN_FG_CARRIED;
}

/* Image `offset` floats into section `in` of the upload (or its resident slot). */
static gl_image_ref input(const frame *f, int in, uint32_t offset, size_t stride, uint32_t step)
{
    if (is_resident(f, in)) {
        const uint32_t plane = in == IN_FG_CARRIED ? gl_near_carried_at(f->w, f->h) : 0;
        return (gl_image_ref){f->device->buffers.name[resident[in]], plane + offset,
                              (uint32_t)stride, step, 0, 0};
    }
    return (gl_image_ref){f->device->buffers.name[GL_BUF_FRAME], offset, (uint32_t)stride, step,
                          f->at[in], f->bytes[in]};
}

/* The colour with the highlights taken out (HL_BASE, width x channels floats a row), or the
 * upload's without them: what the silhouettes' split reads. */
static gl_image_ref passes_color(const frame *f)
{
    const adi_request *r = &f->q->base;
    if (f->lights.count)
        return (gl_image_ref){f->device->buffers.name[GL_BUF_HL_BASE], 0, f->w * f->c, f->c, 0,
                              0};
    return input(f, IN_COLOR, 0, r->color_stride, f->c);
}

/* What the layers diffuse, from frame pixel (x, y): that colour, or with the silhouettes its
 * cleaned copy (SIL_CLEAN, width x channels floats a row). */
static gl_image_ref diffused(const frame *f, uint32_t x, uint32_t y)
{
    gl_image_ref ref = f->q->silhouettes
                           ? (gl_image_ref){f->device->buffers.name[GL_BUF_SIL_CLEAN], 0,
                                            f->w * f->c, f->c, 0, 0}
                           : passes_color(f);
    ref.offset += (uint32_t)(y * ref.stride) + x * f->c;
    return ref;
}

static GLuint need(frame *f, gl_buffer_slot s, uint64_t floats)
{
    return gl_need(f->device, s, floats * sizeof(float), f->message, f->size);
}

/* The floats of a highlight pass's two sections: the aperture's shape and its image's table
 * (none without the pass). */
static void highlight_sections(const adi_highlights *h, uint64_t floats[2])
{
    if (!h->find)
        return;
    floats[0] = sizeof(ddof_highlight_shape) / sizeof(float);
    if (h->image_sums)
        floats[1] = (uint64_t)(h->image_width + 1) * (h->image_height + 1) *
                    (sizeof(double) / sizeof(float));
}

/* The one upload: every image the frame reads, each as it lies, into its section of FRAME
 * (sections start at the renderer's binding alignment and are bound one at a time, so each
 * must fit the storage-block limit, not the whole). */
static int upload(frame *f)
{
    const adi_layers_request *q = f->q;
    const adi_request *r = &q->base;
    const adi_highlights *hl = &q->highlights;
    const adi_highlights *fg_hl = &q->fg_highlights;
    const void *source[IN_COUNT] = {r->color, r->coc, q->fg_color, q->fg_coc,
                                    q->fg_carried_alpha, q->matte,
                                    NULL, hl->image_sums, NULL, fg_hl->image_sums};
    uint64_t floats[IN_COUNT] = {gl_span_floats(f->w, f->h, r->color_stride, f->c, f->c),
                                 gl_span_floats(f->w, f->h, r->coc_stride, r->coc_channels, 1)};
    highlight_sections(hl, floats + IN_HL_SHAPE);
    if (q->fg_color)
        highlight_sections(fg_hl, floats + IN_FG_HL_SHAPE);
    if (q->silhouettes && q->matte && q->matte_ranks)
        floats[IN_MATTE] = gl_span_floats(f->w, f->h, q->matte_stride, 2 * q->matte_ranks,
                                          2 * q->matte_ranks);
    if (q->fg_color) {
        floats[IN_FG] = gl_span_floats(f->w, f->h, q->fg_color_stride, 4, 4);
        floats[IN_FG_COC] = gl_span_floats(f->w, f->h, q->fg_coc_stride, q->fg_coc_channels, 1);
        if (q->fg_carried_alpha && f->c == 4)
            floats[IN_FG_CARRIED] = gl_span_floats(f->w, f->h, q->fg_carried_stride, 1, 1);
    }
    for (int i = 0; i <= IN_FG_CARRIED; i++) /* already on the device: no section */
        floats[i] = is_resident(f, i) ? 0 : floats[i];
    /* The apertures' shapes (the lists are found on the device). */
    ddof_highlight_shape shapes[2];
    memset(shapes, 0, sizeof shapes);
    if (floats[IN_HL_SHAPE])
        shapes[0] = gl_highlight_shape(hl, r->pixel_aspect);
    if (floats[IN_FG_HL_SHAPE])
        shapes[1] = gl_highlight_shape(fg_hl, r->pixel_aspect);
    source[IN_HL_SHAPE] = &shapes[0];
    source[IN_FG_HL_SHAPE] = &shapes[1];
    return gl_io_upload_sections(f->device, GL_BUF_FRAME, IN_COUNT, source, floats, f->at,
                                 f->bytes, f->message, f->size);
}

/* The one read-back: OUT (w x c floats a row) into the caller's out. */
static int download(frame *f)
{
    const adi_request *r = &f->q->base;
    const gl_functions *gl = &f->device->gl;
    const size_t row = (size_t)f->w * f->c;
    gl->MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_CLIENT_MAPPED_BUFFER_BARRIER_BIT);
    gl->BindBuffer(GL_SHADER_STORAGE_BUFFER, f->device->buffers.name[GL_BUF_OUT]);
    const float *mapped = gl->MapBufferRange(GL_SHADER_STORAGE_BUFFER, 0,
                                             (GLsizeiptr)(row * f->h * sizeof(float)),
                                             GL_MAP_READ_BIT);
    if (!mapped) {
        snprintf(f->message, f->size, "the result buffer could not be mapped for reading");
        return 0;
    }
    f->device->readbacks++;
    for (uint32_t y = 0; y < f->h; y++)
        memcpy(r->out + (size_t)y * r->out_stride, mapped + (size_t)y * row,
               row * sizeof(float));
    gl->UnmapBuffer(GL_SHADER_STORAGE_BUFFER);
    return 1;
}

/* ---- per-pixel steps ---------------------------------------------------------------------- */

/* A layers.comp program over `area` (frame pixels) with the uniforms every step shares set;
 * the caller sets its own and calls run_step. 0 with a sentence on failure. */
static GLuint step_program(frame *f, gl_program_id id, adi_box area)
{
    const adi_layers_request *q = f->q;
    const adi_request *r = &q->base;
    const gl_functions *gl = &f->device->gl;
    GLuint prog = gl_programs_get(gl, &f->device->programs, id, f->message, f->size);
    if (!prog)
        return 0;
    static const gl_buffer_slot bound[8] = {GL_BUF_FRAME, GL_BUF_OUT,      GL_BUF_MAP_A,
                                            GL_BUF_MAP_B, GL_BUF_MAP_C,    GL_BUF_CAPACITY,
                                            GL_BUF_SPREAD, GL_BUF_LAYER};
    for (GLuint i = 0; i < 8; i++)
        gl_bind(gl, i, slot(f, bound[i]));
    /* Binding 0: the CoC's section; the element's step reads the element's sections at 1 and
     * 6 instead of OUT and SPREAD (layers.comp). */
    const gl_image_ref coc = input(f, IN_COC, 0, 0, 0);
    gl_bind_ref(gl, 0, &coc, 0);
    if (id == GL_PROG_LAYER_FG_PREPARE) {
        const gl_image_ref fg = input(f, IN_FG, 0, 0, 0), fg_coc = input(f, IN_FG_COC, 0, 0, 0);
        gl_bind_ref(gl, 1, &fg, 0);
        gl_bind_ref(gl, 6, &fg_coc, 0);
    }
    const uint32_t x0 = area.x0, y0 = area.y0;
    gl_uniform_u(gl, prog, "u_width", area.x1 - x0);
    gl_uniform_u(gl, prog, "u_height", area.y1 - y0);
    gl_uniform_u(gl, prog, "u_channels", f->c);
    gl_uniform_u(gl, prog, "u_coc_base", (GLuint)(y0 * r->coc_stride + x0 * r->coc_channels));
    gl_uniform_u(gl, prog, "u_coc_stride", (GLuint)r->coc_stride);
    gl_uniform_u(gl, prog, "u_coc_step", r->coc_channels);
    gl_uniform_u(gl, prog, "u_out_base", (y0 * f->w + x0) * f->c);
    gl_uniform_u(gl, prog, "u_out_stride", f->w * f->c);
    gl_uniform_u(gl, prog, "u_spread_base", y0 * f->w + x0);
    gl_uniform_u(gl, prog, "u_spread_stride", f->w);
    gl_uniform_u(gl, prog, "u_has_spread", q->near_spread);
    if (q->fg_color) {
        gl_uniform_u(gl, prog, "u_fg_base", (GLuint)(y0 * q->fg_color_stride + x0 * 4));
        gl_uniform_u(gl, prog, "u_fg_stride", (GLuint)q->fg_color_stride);
        gl_uniform_u(gl, prog, "u_fg_coc_base",
                     (GLuint)(y0 * q->fg_coc_stride + x0 * q->fg_coc_channels));
        gl_uniform_u(gl, prog, "u_fg_coc_stride", (GLuint)q->fg_coc_stride);
        gl_uniform_u(gl, prog, "u_fg_coc_step", q->fg_coc_channels);
        gl_uniform_u(gl, prog, "u_premultiplied", q->fg_premultiplied);
    }
    return prog;
}

static void run_step(frame *f, GLuint prog, adi_box area)
{
    f->device->gl.UseProgram(prog);
    gl_dispatch(&f->device->gl, (uint64_t)(area.x1 - area.x0) * (area.y1 - area.y0), 256);
}

/* One of the simple steps (no uniforms of its own); 0 on failure. */
static int simple_step(frame *f, gl_program_id id, adi_box area)
{
    GLuint prog = step_program(f, id, area);
    if (prog)
        run_step(f, prog, area);
    return prog != 0;
}

/* cone_dilate.c on one of the frame's maps (gl_passes.h). */
static int cone_dilate(frame *f, gl_buffer_slot map, uint32_t base, uint32_t width,
                       uint32_t height, uint32_t stride, float slope)
{
    return gl_cone_dilate(f->device, slot(f, map), base, width, height, stride, slope,
                          f->message, f->size);
}

/* ---- diffusions --------------------------------------------------------------------------- */

/* Maps one diffusion's progress into the frame's (layers.c's stage_progress). */
static int stage_progress(void *user, float fraction)
{
    const frame *f = user;
    const adi_request *r = &f->q->base;
    return r->progress(r->progress_user, ((float)f->stage + fraction) / (float)f->stages);
}

static gl_image_ref map_ref(const frame *f, gl_buffer_slot s, uint32_t width, uint32_t step)
{
    return (gl_image_ref){f->device->buffers.name[s], 0, width * step, step, 0, 0};
}

/* One diffusion; its figures are added to the report as layers.c's diffuse() adds them. */
static ddof_status diffuse(frame *f, gl_resident *d)
{
    const adi_request *r = &f->q->base;
    if (r->progress) {
        d->progress = stage_progress;
        d->progress_user = f;
    }
    adi_report a = {0};
    ddof_status status = gl_resident_diffuse(f->device, r, d, &a, f->message, f->size);
    f->stage++;
    if (status != DDOF_OK)
        return status;
    adi_report *sum = &f->report->adi;
    sum->lines_solved += a.lines_solved;
    sum->lines_skipped += a.lines_skipped;
    sum->seconds_rows += a.seconds_rows;
    sum->seconds_columns += a.seconds_columns;
    sum->threads = a.threads;
    sum->max_coc = a.max_coc > sum->max_coc ? a.max_coc : sum->max_coc;
    if (a.substeps_run > sum->substeps_run)
        sum->substeps_run = a.substeps_run;
    return DDOF_OK;
}

/* A request for an area-sized image with the frame's solver settings (layers.c's derived). */
static gl_resident derived(const frame *f, adi_box area, gl_image_ref color, uint32_t channels,
                           gl_image_ref out)
{
    const adi_request *r = &f->q->base;
    return (gl_resident){.width = area.x1 - area.x0, .height = area.y1 - area.y0,
                         .channels = channels, .color = color, .out = out,
                         .uniform_coc = r->uniform_coc, .substeps = r->substeps,
                         .disc = r->disc};
}

/* ---- the effects -------------------------------------------------------------------------- */

static adi_box whole(const frame *f)
{
    return (adi_box){0, 0, f->w, f->h};
}

/* SPREAD = max(|CoC|, the cone-dilated near CoC). */
static int near_spread(frame *f)
{
    const adi_layers_request *q = f->q;
    if (!need(f, GL_BUF_SPREAD, (uint64_t)f->w * f->h))
        return 0;
    /* layers.comp's map_a is binding 2; the spread map takes its place for these steps. */
    GLuint prog = step_program(f, GL_PROG_LAYER_NEAR_MAP, whole(f));
    if (!prog)
        return 0;
    gl_bind(&f->device->gl, 2, slot(f, GL_BUF_SPREAD));
    run_step(f, prog, whole(f));
    const adi_box b = q->near_dilate;
    if (!ddof_box_is_empty(b) && !cone_dilate(f, GL_BUF_SPREAD, b.y0 * f->w + b.x0, b.x1 - b.x0,
                                      b.y1 - b.y0, f->w, q->near_slope))
        return 0;
    if (!(prog = step_program(f, GL_PROG_LAYER_SPREAD, whole(f))))
        return 0;
    gl_bind(&f->device->gl, 2, slot(f, GL_BUF_SPREAD));
    run_step(f, prog, whole(f));
    return 1;
}

static ddof_status midground(frame *f)
{
    const adi_layers_request *q = f->q;
    const adi_request *r = &q->base;
    gl_resident mid = derived(f, whole(f), diffused(f, 0, 0), f->c,
                              map_ref(f, GL_BUF_OUT, f->w, f->c));
    mid.coc = q->near_spread ? map_ref(f, GL_BUF_SPREAD, f->w, 1)
                             : input(f, IN_COC, 0, r->coc_stride, r->coc_channels);
    return diffuse(f, &mid);
}

/* One background level with matte ramp [ramp_start, threshold] over `area`, blended into OUT
 * within `blend` (frame pixels). */
static ddof_status background_level(frame *f, adi_box area, adi_box blend, float ramp_start,
                                    float threshold, float blend_from)
{
    const gl_functions *gl = &f->device->gl;
    const uint32_t aw = area.x1 - area.x0, ah = area.y1 - area.y0;
    const uint64_t pixels = (uint64_t)aw * ah;
    if (!need(f, GL_BUF_MAP_A, pixels) || !need(f, GL_BUF_MAP_B, pixels) ||
        !need(f, GL_BUF_MAP_C, pixels) || !need(f, GL_BUF_CAPACITY, pixels) ||
        !need(f, GL_BUF_LAYER, pixels * f->c))
        return DDOF_ERROR_BACKEND_FAILED;
    GLuint prog = step_program(f, GL_PROG_LAYER_MATTE, area);
    if (!prog)
        return DDOF_ERROR_BACKEND_FAILED;
    gl_uniform_f(gl, prog, "u_t0", ramp_start);
    gl_uniform_f(gl, prog, "u_inv_ramp", 1.0f / (threshold - ramp_start));
    run_step(f, prog, area);

    /* The CoC flows into the holes, every link at the threshold, by plain heat. */
    gl_resident fill = derived(f, area, map_ref(f, GL_BUF_MAP_B, aw, 1), 1,
                               map_ref(f, GL_BUF_MAP_C, aw, 1));
    fill.uniform_coc = threshold;
    fill.substeps = 1;
    fill.disc = NULL;
    fill.gamma = map_ref(f, GL_BUF_CAPACITY, aw, 1);
    ddof_status status = diffuse(f, &fill);
    if (status != DDOF_OK)
        return status;

    /* The colour, with the holes holding no heat of their own. */
    gl_resident bg = derived(f, area, diffused(f, area.x0, area.y0), f->c,
                             map_ref(f, GL_BUF_LAYER, aw, f->c));
    bg.coc = map_ref(f, GL_BUF_MAP_C, aw, 1);
    bg.gamma = map_ref(f, GL_BUF_CAPACITY, aw, 1);
    if ((status = diffuse(f, &bg)) != DDOF_OK)
        return status;

    /* The filled CoC is spent: its buffer becomes the proximity map. */
    if (!(prog = step_program(f, GL_PROG_LAYER_INSULATOR, area)))
        return DDOF_ERROR_BACKEND_FAILED;
    gl_uniform_f(gl, prog, "u_t0", ramp_start);
    run_step(f, prog, area);
    if (!cone_dilate(f, GL_BUF_MAP_C, 0, aw, ah, aw, 1.0f))
        return DDOF_ERROR_BACKEND_FAILED;
    if (!(prog = step_program(f, GL_PROG_LAYER_BLEND, area)))
        return DDOF_ERROR_BACKEND_FAILED;
    gl_uniform_f(gl, prog, "u_blend_from", blend_from);
    gl_uniform_u(gl, prog, "u_blend_x0", blend.x0 - area.x0);
    gl_uniform_u(gl, prog, "u_blend_y0", blend.y0 - area.y0);
    gl_uniform_u(gl, prog, "u_blend_x1", blend.x1 - area.x0);
    gl_uniform_u(gl, prog, "u_blend_y1", blend.y1 - area.y0);
    run_step(f, prog, area);
    return DDOF_OK;
}

/* layers.c's background: the area around the edges the layer can change, level by level. */
static ddof_status background(frame *f)
{
    const adi_layers_request *q = f->q;
    const adi_request *r = &q->base;
    const uint32_t reach =
        ddof_background_reach_px(r->disc, r->beta_scale, f->report->adi.max_coc,
                                 q->background_threshold_px, q->background_levels);
    const adi_box area = ddof_box_grow(q->background_edges, 2 * reach, f->w, f->h);
    const adi_box blend = ddof_box_grow(q->background_edges, reach, f->w, f->h);
    for (uint32_t level = 0; level < q->background_levels; level++) {
        const float threshold = ddof_background_threshold(q->background_threshold_px, level);
        const float ramp_start =
            ddof_background_ramp_start(threshold, level, q->background_ramp_start_px);
        const ddof_status status = background_level(f, area, blend, ramp_start, threshold,
                                                    ddof_background_blend_from(threshold, level));
        if (status != DDOF_OK)
            return status;
    }
    return DDOF_OK;
}

/* layers.c's gather_element: the far field over the element's blur (`blurred`) within its
 * area, from the element before its blur (`sharp`) and its CoC filled outwards (MAP_C), no
 * slices. */
static ddof_status gather_element(frame *f, adi_box area, gl_buffer_slot sharp,
                                  gl_buffer_slot blurred)
{
    const adi_request *r = &f->q->base;
    const uint32_t aw = area.x1 - area.x0;
    const gl_far_field_request far = {
        .width = aw, .height = area.y1 - area.y0, .channels = 4,
        .color = map_ref(f, sharp, aw, 4), .coc = map_ref(f, GL_BUF_MAP_C, aw, 1),
        .out = f->device->buffers.name[blurred], .in_focus_px = r->in_focus_px,
        .pixel_aspect = r->pixel_aspect, .slices = 0};
    gl_far_field_report found;
    if (!gl_far_field(f->device, &far, &found, f->message, f->size))
        return DDOF_ERROR_BACKEND_FAILED;
    if (found.pixels)
        f->report->element_effects |= DDOF_EFFECT_FAR_FIELD;
    return DDOF_OK;
}

/* The element's own highlights' request over its area: taken out of LAYER, drawn with the
 * CoC filled outwards (MAP_C, unsigned). */
static gl_highlights_request element_lights(const frame *f, adi_box area)
{
    const uint32_t aw = area.x1 - area.x0;
    gl_highlights_request h = {
        .width = aw, .height = area.y1 - area.y0, .channels = 4,
        .color = map_ref(f, GL_BUF_LAYER, aw, 4), .coc = map_ref(f, GL_BUF_MAP_C, aw, 1),
        .items = map_ref(f, GL_BUF_HL_FG_ITEMS, 0, 0), .shape = input(f, IN_FG_HL_SHAPE, 0, 0, 0),
        .count = f->fg_lights.count, .coc_signed = 0, .classes = f->fg_lights.classes};
    if (f->bytes[IN_FG_HL_SUMS])
        h.sums = input(f, IN_FG_HL_SUMS, 0, 0, 0);
    return h;
}

/* layers.c's foreground: the element's CoC filled outwards in two steps, its premultiplied
 * colour and alpha diffused with it (its own highlights taken out first and drawn into its
 * blur after, the far field's gather between), composited over. */
static ddof_status foreground(frame *f)
{
    const adi_layers_request *q = f->q;
    const adi_box area = q->fg_area;
    const uint32_t aw = area.x1 - area.x0;
    const uint64_t pixels = (uint64_t)aw * (area.y1 - area.y0);
    const int lights = f->fg_lights.count > 0;
    if (!need(f, GL_BUF_LAYER, pixels * 4) || !need(f, GL_BUF_MAP_B, pixels) ||
        !need(f, GL_BUF_MAP_C, pixels) || (lights && !need(f, GL_BUF_FG_BASE, pixels * 4)))
        return DDOF_ERROR_BACKEND_FAILED;
    if (!simple_step(f, GL_PROG_LAYER_FG_PREPARE, area))
        return DDOF_ERROR_BACKEND_FAILED;
    if (lights) {
        const gl_highlights_request h = element_lights(f, area);
        if (!gl_take_out_highlights(f->device, &h, slot(f, GL_BUF_FG_BASE), f->message,
                                    f->size))
            return DDOF_ERROR_BACKEND_FAILED;
    }

    gl_resident fill = derived(f, area, map_ref(f, GL_BUF_MAP_B, aw, 1), 1,
                               map_ref(f, GL_BUF_MAP_C, aw, 1));
    fill.uniform_coc = q->fg_max_coc; /* the CPU's map_max of b: the same value */
    fill.substeps = 1;
    fill.disc = NULL;
    fill.gamma = (gl_image_ref){slot(f, GL_BUF_LAYER), 3, aw * 4, 4, 0, 0};
    ddof_status status = diffuse(f, &fill);
    if (status != DDOF_OK)
        return status;
    if (!simple_step(f, GL_PROG_LAYER_HOLDS_VALUE, area))
        return DDOF_ERROR_BACKEND_FAILED;
    gl_resident spread = fill;
    spread.color = map_ref(f, GL_BUF_MAP_C, aw, 1);
    spread.out = spread.color; /* in place */
    spread.gamma = map_ref(f, GL_BUF_MAP_B, aw, 1);
    if ((status = diffuse(f, &spread)) != DDOF_OK)
        return status;

    /* Its blur: from the element without its highlights (FG_BASE) into LAYER, or in place, or
     * beside the element (BLUR) when the far field gathers from it. */
    const gl_buffer_slot sharp = lights ? GL_BUF_FG_BASE : GL_BUF_LAYER;
    const gl_buffer_slot blurred = lights || !q->fg_gather ? GL_BUF_LAYER : GL_BUF_LAYER_BLUR;
    if (blurred == GL_BUF_LAYER_BLUR && !need(f, GL_BUF_LAYER_BLUR, pixels * 4))
        return DDOF_ERROR_BACKEND_FAILED;
    gl_resident blur = derived(f, area, map_ref(f, sharp, aw, 4), 4, map_ref(f, blurred, aw, 4));
    blur.coc = map_ref(f, GL_BUF_MAP_C, aw, 1);
    if ((status = diffuse(f, &blur)) != DDOF_OK)
        return status;
    if (q->fg_gather && (status = gather_element(f, area, sharp, blurred)) != DDOF_OK)
        return status;
    if (lights) {
        const gl_highlights_request h = element_lights(f, area);
        if (!gl_draw_highlights(f->device, &h, slot(f, blurred), f->message, f->size))
            return DDOF_ERROR_BACKEND_FAILED;
        f->report->element_effects |= DDOF_EFFECT_HIGHLIGHTS;
    }
    /* The part of the frame's alpha the element carries, blurred as its colour is (into MAP_B,
     * free since the spread), is the output's alpha where the element lies. */
    const int carried = q->fg_carried_alpha && f->c == 4;
    if (carried) {
        const gl_image_ref alpha_in =
            input(f, IN_FG_CARRIED, (uint32_t)(area.y0 * q->fg_carried_stride + area.x0),
                  q->fg_carried_stride, 1);
        gl_resident alpha = derived(f, area, alpha_in, 1, map_ref(f, GL_BUF_MAP_B, aw, 1));
        alpha.coc = map_ref(f, GL_BUF_MAP_C, aw, 1);
        if ((status = diffuse(f, &alpha)) != DDOF_OK)
            return status;
    }
    GLuint prog = step_program(f, GL_PROG_LAYER_COMPOSITE, area);
    if (!prog)
        return DDOF_ERROR_BACKEND_FAILED;
    gl_bind(&f->device->gl, 7, slot(f, blurred));
    gl_bind(&f->device->gl, 6, slot(f, carried ? GL_BUF_MAP_B : GL_BUF_DUMMY));
    gl_uniform_u(&f->device->gl, prog, "u_has_carried", (GLuint)carried);
    run_step(f, prog, area);
    return DDOF_OK;
}

/* The passes' requests (gl_passes.h) on the upload's sections: the silhouettes' from the colour
 * the passes read, the CoC and the matte; the highlights' from the colour, the CoC and their
 * list, shape and aperture image. */
static void describe_passes(frame *f)
{
    const adi_layers_request *q = f->q;
    const adi_request *r = &q->base;
    const gl_image_ref coc = input(f, IN_COC, 0, r->coc_stride, r->coc_channels);
    f->silhouettes = (gl_silhouettes_request){.width = f->w, .height = f->h, .channels = f->c,
                                              .color = passes_color(f), .coc = coc,
                                              .in_focus_px = r->in_focus_px};
    if (f->bytes[IN_MATTE]) {
        f->silhouettes.matte = input(f, IN_MATTE, 0, q->matte_stride, 2 * q->matte_ranks);
        f->silhouettes.ranks = q->matte_ranks;
    }
    f->highlights = (gl_highlights_request){
        .width = f->w, .height = f->h, .channels = f->c,
        .color = input(f, IN_COLOR, 0, r->color_stride, f->c), .coc = coc,
        .items = map_ref(f, GL_BUF_HL_ITEMS, 0, 0), .shape = input(f, IN_HL_SHAPE, 0, 0, 0),
        .count = f->lights.count, .coc_signed = q->highlights.coc_signed,
        .classes = f->lights.classes};
    if (f->bytes[IN_HL_SUMS])
        f->highlights.sums = input(f, IN_HL_SUMS, 0, 0, 0);
}

/* The run's first stage: the highlights found on the device, the frame's in the uploaded
 * colour and the element's own in its area (gl_highlights_find.c); the host reads counts. */
static int find_highlights(frame *f)
{
    const adi_layers_request *q = f->q;
    const adi_request *r = &q->base;
    const double t0 = gl_seconds();
    if (q->highlights.find) {
        const gl_find_request find = {
            .width = f->w, .height = f->h,
            .color = input(f, IN_COLOR, 0, r->color_stride, f->c),
            .coc = input(f, IN_COC, 0, r->coc_stride, r->coc_channels), .owner = 1,
            .coc_signed = q->highlights.coc_signed, .area = q->highlights.image_sums != NULL,
            .threshold = q->highlights.threshold, .aspect = r->pixel_aspect,
            .sorted = GL_BUF_HL_ITEMS};
        if (!gl_find_highlights(f->device, &find, &f->lights, f->message, f->size))
            return 0;
        adi_layers_report *report = f->report;
        report->highlights_count = f->lights.count;
        report->highlights_hidden = f->lights.hidden;
        report->highlights_over_budget = f->lights.over_budget;
        report->highlights_threshold = f->lights.threshold;
        report->highlights_cost = f->lights.cost;
    }
    if (q->fg_color && q->fg_highlights.find) {
        const adi_box a = q->fg_area;
        const gl_find_request find = {
            .width = a.x1 - a.x0, .height = a.y1 - a.y0,
            .color = input(f, IN_FG, (uint32_t)(a.y0 * q->fg_color_stride + a.x0 * 4),
                           q->fg_color_stride, 4),
            .coc = input(f, IN_FG_COC,
                         (uint32_t)(a.y0 * q->fg_coc_stride + a.x0 * q->fg_coc_channels),
                         q->fg_coc_stride, q->fg_coc_channels),
            .owner = q->fg_premultiplied ? 0u : 2u, .coc_signed = 0,
            .area = q->fg_highlights.image_sums != NULL,
            .threshold = q->fg_highlights.threshold, .aspect = r->pixel_aspect,
            .sorted = GL_BUF_HL_FG_ITEMS};
        if (!gl_find_highlights(f->device, &find, &f->fg_lights, f->message, f->size))
            return 0;
    }
    f->report->seconds_highlights += gl_seconds() - t0;
    return 1;
}

/* The colour the passes read, with the highlights' excess taken out (HL_BASE), then the
 * colour the layers diffuse, with the silhouettes' objects taken out too (SIL_CLEAN); the
 * passes' requests once those buffers exist. */
static int take_out(frame *f)
{
    const adi_layers_request *q = f->q;
    const uint64_t floats = (uint64_t)f->w * f->h * f->c;
    const GLuint base = f->lights.count ? need(f, GL_BUF_HL_BASE, floats) : 1;
    const GLuint cleaned = q->silhouettes ? need(f, GL_BUF_SIL_CLEAN, floats) : 1;
    if (!base || !cleaned)
        return 0;
    describe_passes(f);
    double t0 = gl_seconds();
    if (f->lights.count &&
        !gl_take_out_highlights(f->device, &f->highlights, base, f->message, f->size))
        return 0;
    f->report->seconds_highlights += gl_seconds() - t0;
    t0 = gl_seconds();
    if (q->silhouettes &&
        !gl_clean_silhouettes(f->device, &f->silhouettes, cleaned, f->message, f->size))
        return 0;
    f->report->seconds_silhouettes += gl_seconds() - t0;
    return 1;
}

/* The highlights drawn into OUT. */
static int draw_highlights(frame *f)
{
    const double t0 = gl_seconds();
    const int ok = gl_draw_highlights(f->device, &f->highlights,
                                      f->device->buffers.name[GL_BUF_OUT], f->message, f->size);
    f->device->gl.Finish();
    f->report->seconds_highlights += gl_seconds() - t0;
    return ok;
}

/* The silhouettes' split and the highlights' discs over OUT, in layers.c's order: with an
 * object matte the discs first. */
static ddof_status split_and_draw(frame *f)
{
    const adi_layers_request *q = f->q;
    const int discs_first = f->lights.count && f->bytes[IN_MATTE];
    if (discs_first && !draw_highlights(f))
        return DDOF_ERROR_BACKEND_FAILED;
    if (q->silhouettes) {
        const double t0 = gl_seconds();
        if (!gl_split_silhouettes(f->device, &f->silhouettes,
                                  f->device->buffers.name[GL_BUF_OUT],
                                  &f->report->silhouette_pixels, f->message, f->size))
            return DDOF_ERROR_BACKEND_FAILED;
        f->report->seconds_silhouettes += gl_seconds() - t0;
    }
    if (f->lights.count && !discs_first && !draw_highlights(f))
        return DDOF_ERROR_BACKEND_FAILED;
    return DDOF_OK;
}

/* The far field over OUT (gl_passes.h), from the colour the layers diffused. */
static ddof_status far_field(frame *f)
{
    const adi_layers_request *q = f->q;
    const adi_request *r = &q->base;
    const gl_far_field_request far = {
        .width = f->w, .height = f->h, .channels = f->c,
        .color = diffused(f, 0, 0),
        .coc = input(f, IN_COC, 0, r->coc_stride, r->coc_channels),
        .out = f->device->buffers.name[GL_BUF_OUT], .in_focus_px = r->in_focus_px,
        .pixel_aspect = r->pixel_aspect, .slices = (int)q->far_slices};
    gl_far_field_report found;
    if (!gl_far_field(f->device, &far, &found, f->message, f->size))
        return DDOF_ERROR_BACKEND_FAILED;
    adi_layers_report *report = f->report;
    report->far_pixels = found.pixels;
    report->far_layered_pixels = found.layered_pixels;
    report->far_slices = found.slices;
    report->far_levels = found.levels;
    return DDOF_OK;
}

ddof_status gl_layers_run(ddof_device *device, const adi_layers_request *q,
                          adi_layers_report *report, char *message, size_t size)
{
    const adi_request *r = &q->base;
    frame f = {.device = device, .q = q, .w = r->width, .h = r->height, .c = r->channels,
               .report = report, .message = message, .size = size};
    f.stages = 1 + 2 * q->background_levels +
               (q->fg_color ? 3u + (q->fg_carried_alpha && f.c == 4) : 0u);
    if (!need(&f, GL_BUF_DUMMY, 4) || !upload(&f) ||
        !need(&f, GL_BUF_OUT, (uint64_t)f.w * f.h * f.c))
        return DDOF_ERROR_BACKEND_FAILED;
    ddof_status status = DDOF_OK;
    if (!find_highlights(&f) || !take_out(&f))
        return DDOF_ERROR_BACKEND_FAILED;
    double t0 = gl_seconds();
    if (q->near_spread && !near_spread(&f))
        return DDOF_ERROR_BACKEND_FAILED;
    report->seconds_foreground += gl_seconds() - t0;
    status = midground(&f);
    if (status == DDOF_OK && q->background_levels) {
        t0 = gl_seconds();
        status = background(&f);
        device->gl.Finish();
        report->seconds_background = gl_seconds() - t0;
    }
    if (status == DDOF_OK && q->far_field) {
        t0 = gl_seconds();
        status = far_field(&f);
        device->gl.Finish();
        report->seconds_far_field = gl_seconds() - t0;
    }
    if (status == DDOF_OK)
        status = split_and_draw(&f);
    if (status == DDOF_OK && q->fg_color) {
        t0 = gl_seconds();
        status = foreground(&f);
        device->gl.Finish();
        report->seconds_foreground += gl_seconds() - t0;
    }
    /* Cancelled: OUT holds the midground (or its last finished substep) and what was blended
     * into it so far, all finite. */
    if ((status == DDOF_OK || status == DDOF_ERROR_CANCELLED) && !download(&f))
        status = DDOF_ERROR_BACKEND_FAILED;
    return status;
}
