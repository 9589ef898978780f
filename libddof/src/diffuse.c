/* diffuse.c - the public diffusion calls: validate everything, plan, then hand over.
 * Every check happens before the first output pixel is written, so a failed call leaves the
 * output as it was. */
#include "adi.h"
#include "backend.h"
#include "coc.h"
#include "disc_kernel.h"
#include "layers.h"
#include "parallel_rows.h"
#include "planner.h"
#include "preview_cod4.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#define DDOF_MAX_SUBSTEPS 4096u
#define DDOF_MAX_JACOBI_ITERATIONS 1000000u
#define DDOF_MAX_BACKGROUND_LEVELS 8u

/* The float parameters' ranges (ddof.h). At the largest CoC (DDOF_MAX_COC_PX) and one
 * sub-step, beta_scale 1 and pixel aspect 100 make the column links' beta 1e14; the reference
 * solver's overflows near 1e16, the others' later (tests/test_bad_input.c runs every CPU
 * solver at the bounds and checks the output is finite). */
#define DDOF_MAX_BETA_SCALE 1.0f
#define DDOF_MIN_PIXEL_ASPECT 0.01
#define DDOF_MAX_PIXEL_ASPECT 100.0

/* Compared as float for params (0.01f is below the double 0.01) and as double for a camera. */
static int pixel_aspect_ok(double v, int is_float)
{
    return is_float ? v >= (float)DDOF_MIN_PIXEL_ASPECT && v <= (float)DDOF_MAX_PIXEL_ASPECT
                    : v >= DDOF_MIN_PIXEL_ASPECT && v <= DDOF_MAX_PIXEL_ASPECT;
}

/* A CoC-sized threshold: > 0 (or >= 0) and at most DDOF_MAX_COC_PX. */
static int coc_size_ok(float v, int zero_ok)
{
    return (zero_ok ? v >= 0.0f : v > 0.0f) && v <= DDOF_MAX_COC_PX;
}

/* The caller's params over the defaults (an older caller's struct lacks the layer fields),
 * then every value checked. */
static ddof_status read_params(ddof_context *context, const ddof_params *caller, ddof_params *p)
{
    ddof_params_init(p);
    ddof_status status = ddof_read_struct(context, caller, offsetof(ddof_params, coc_signed), p,
                                          sizeof *p, "params");
    if (status != DDOF_OK)
        return status;
    if ((unsigned)p->solver >= DDOF_SOLVER_COUNT_)
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER, "params.solver %u is not a solver",
                         (unsigned)p->solver);
    if (p->substeps < 1 || p->substeps > DDOF_MAX_SUBSTEPS)
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.substeps %u must be within 1..%u", p->substeps,
                         DDOF_MAX_SUBSTEPS);
    if (!(p->beta_scale > 0.0f && p->beta_scale <= DDOF_MAX_BETA_SCALE))
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.beta_scale %.9g must be > 0 and at most %g",
                         (double)p->beta_scale, (double)DDOF_MAX_BETA_SCALE);
    if (!pixel_aspect_ok(p->pixel_aspect, 1))
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.pixel_aspect %.9g must be within %g..%g", (double)p->pixel_aspect,
                         DDOF_MIN_PIXEL_ASPECT, DDOF_MAX_PIXEL_ASPECT);
    if (p->solver == DDOF_SOLVER_JACOBI &&
        (p->jacobi_iterations < 1 || p->jacobi_iterations > DDOF_MAX_JACOBI_ITERATIONS))
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.jacobi_iterations %u must be within 1..%u",
                         p->jacobi_iterations, DDOF_MAX_JACOBI_ITERATIONS);
    if (p->coc_signed > 1 || (unsigned)p->background > DDOF_LAYER_ON ||
        (unsigned)p->near_spread > DDOF_LAYER_ON)
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.coc_signed, background or near_spread is not a known value");
    if (!(coc_size_ok(p->background_ramp_start_px, 1) &&
          coc_size_ok(p->background_threshold_px, 0) &&
          p->background_threshold_px > p->background_ramp_start_px))
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.background_threshold_px (%.9g) must exceed "
                         "background_ramp_start_px (%.9g) >= 0, both at most %g px",
                         (double)p->background_threshold_px,
                         (double)p->background_ramp_start_px, (double)DDOF_MAX_COC_PX);
    if (p->background_levels < 1 || p->background_levels > DDOF_MAX_BACKGROUND_LEVELS)
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.background_levels %u must be within 1..%u",
                         p->background_levels, DDOF_MAX_BACKGROUND_LEVELS);
    if (!coc_size_ok(p->near_spread_threshold_px, 0))
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.near_spread_threshold_px %.9g must be > 0 and at most %g px",
                         (double)p->near_spread_threshold_px, (double)DDOF_MAX_COC_PX);
    if ((unsigned)p->method > DDOF_METHOD_COD4_PREVIEW ||
        (unsigned)p->precision > DDOF_PRECISION_PACKED_HALF)
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.method %u or params.precision %u is not a known value",
                         (unsigned)p->method, (unsigned)p->precision);
    if (!coc_size_ok(p->in_focus_threshold_px, 1))
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.in_focus_threshold_px %.9g must be >= 0 and at most %g px",
                         (double)p->in_focus_threshold_px, (double)DDOF_MAX_COC_PX);
    if ((unsigned)p->kernel >= DDOF_KERNEL_COUNT_)
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER, "params.kernel %u is not a kernel",
                         (unsigned)p->kernel);
    /* The disc kernel has a complex form of the Thomas solver only (on the CPU and on a
     * device that runs it) and the double reference; anything else runs the heat kernel, and
     * ddof_stats.kernel says which ran. */
    if (p->kernel != DDOF_KERNEL_HEAT && !ddof_backend_runs_disc(context, p->solver))
        p->kernel = DDOF_KERNEL_HEAT;
    if (p->method == DDOF_METHOD_DIFFUSION) {
        ddof_status supported = ddof_check_backend_supports(context, p->solver, p->precision);
        if (supported != DDOF_OK)
            return supported;
    }
    if (p->near_spread == DDOF_LAYER_ON && !p->coc_signed)
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.near_spread is forced on, but the CoC is unsigned: without "
                         "coc_signed = 1 the near field is unknown");
    return DDOF_OK;
}

static ddof_status check_same_size(ddof_context *context, const char *what, uint32_t width,
                                   uint32_t height, uint32_t w, uint32_t h)
{
    if (width != w || height != h)
        return ddof_fail(context, DDOF_ERROR_SIZE_MISMATCH, "%s is %ux%u but colour is %ux%u",
                         what, width, height, w, h);
    return DDOF_OK;
}

/* Checks one more image of the call: valid, the colour's size; *stride in floats. */
static ddof_status check_map(ddof_context *context, const char *what, const ddof_image_in *map,
                             const adi_request *r, size_t *stride)
{
    if (!map)
        return ddof_fail(context, DDOF_ERROR_NULL_POINTER, "%s image is NULL", what);
    ddof_status status = ddof_check_image(context, what, map->pixels, map->width, map->height,
                                          map->channels, map->row_stride, stride);
    if (status == DDOF_OK)
        status = check_same_size(context, what, map->width, map->height, r->width, r->height);
    return status;
}

/* Checks colour, the per-pixel input (CoC or depth) and out, and fills the request's images. */
static ddof_status check_images(ddof_context *context, const ddof_image_in *color,
                                const ddof_image_in *map, const char *map_name,
                                const ddof_image *out, adi_request *r, size_t *map_stride)
{
    if (!color || !out)
        return ddof_fail(context, DDOF_ERROR_NULL_POINTER, "%s image is NULL",
                         !color ? "colour" : "output");
    ddof_status status = ddof_check_image(context, "colour", color->pixels, color->width,
                                          color->height, color->channels, color->row_stride,
                                          &r->color_stride);
    if (status != DDOF_OK)
        return status;
    r->width = color->width;
    r->height = color->height;
    r->channels = color->channels;
    status = check_map(context, map_name, map, r, map_stride);
    if (status == DDOF_OK)
        status = ddof_check_image(context, "output", out->pixels, out->width, out->height,
                                  out->channels, out->row_stride, &r->out_stride);
    if (status == DDOF_OK)
        status = check_same_size(context, "output", out->width, out->height, color->width,
                                 color->height);
    if (status != DDOF_OK)
        return status;
    if (out->channels != color->channels)
        return ddof_fail(context, DDOF_ERROR_SIZE_MISMATCH,
                         "output has %u channels but colour has %u", out->channels,
                         color->channels);
    if (out->pixels == color->pixels && r->out_stride != r->color_stride)
        return ddof_fail(context, DDOF_ERROR_BAD_STRIDE,
                         "in-place diffusion needs the same stride for colour and output");
    r->color = color->pixels;
    r->out = out->pixels;

    bad_value bad;
    if (ddof_find_bad_value(context, color->pixels, color->width, color->height,
                            color->channels, color->channels, r->color_stride, VALUE_FINITE,
                            &bad, NULL))
        return ddof_fail(context, DDOF_ERROR_BAD_COLOR,
                         "colour at pixel (%u, %u) channel %u is %g", bad.x, bad.y,
                         bad.channel, (double)bad.value);
    return DDOF_OK;
}

/* Validates the CoC; *max_abs is its largest |CoC|, found by the same read. */
static ddof_status check_coc_values(ddof_context *context, const ddof_image_in *coc,
                                    size_t stride, int coc_signed, float *max_abs)
{
    bad_value bad;
    if (ddof_find_bad_value(context, coc->pixels, coc->width, coc->height, coc->channels, 1,
                            stride, coc_signed ? VALUE_COC_SIGNED : VALUE_COC, &bad, max_abs))
        return ddof_fail(context, DDOF_ERROR_BAD_COC,
                         "CoC at pixel (%u, %u) is %.9g; it must be finite, within %s0..%g px",
                         bad.x, bad.y, (double)bad.value, coc_signed ? "+-" : "",
                         (double)DDOF_MAX_COC_PX);
    return DDOF_OK;
}

static void fill_request_params(adi_request *r, const ddof_params *p)
{
    r->solver = p->solver;
    r->precision = p->precision;
    r->substeps = p->substeps;
    r->jacobi_iterations = p->jacobi_iterations;
    r->beta_scale = p->beta_scale;
    r->pixel_aspect = p->pixel_aspect;
    r->disc = p->method == DDOF_METHOD_DIFFUSION ? ddof_disc_kernel(p->kernel) : NULL;
    r->progress = p->progress;
    r->progress_user = p->progress_user;
    r->in_focus_px = p->in_focus_threshold_px;
}

/* Whether a frame whose largest |CoC| is max_coc has nothing out of focus. */
static int all_in_focus(float max_coc, const ddof_params *p)
{
    return max_coc <= 0.0f || max_coc < p->in_focus_threshold_px;
}

/* Copies the fields the caller's struct has room for. */
static void write_stats(ddof_stats *stats, const ddof_stats *full)
{
    if (!stats || stats->struct_size < sizeof(uint32_t))
        return;
    size_t size = stats->struct_size < sizeof *full ? stats->struct_size : sizeof *full;
    uint32_t caller_size = stats->struct_size;
    memcpy(stats, full, size);
    stats->struct_size = caller_size;
}

/* Working memory the context holds for its calls (grown, reused). */
static uint64_t host_bytes(const ddof_context *context)
{
    uint64_t sum = 0;
    for (int i = 0; i < DDOF_SCRATCH_COUNT; i++)
        sum += context->scratch[i].size;
    return sum;
}

static ddof_stats stats_from(const ddof_context *context, const adi_report *report,
                             const adi_request *r, double t_start, double seconds_coc)
{
    const ddof_solver solver = r->solver;
    const ddof_kernel kernel = r->disc ? r->disc->id : DDOF_KERNEL_HEAT;
    return (ddof_stats){
        .struct_size = sizeof(ddof_stats),
        .solver = (uint32_t)solver,
        .threads = report->threads,
        .substeps = report->substeps_run,
        .lines_solved = report->lines_solved,
        .lines_skipped = report->lines_skipped,
        .max_coc_px = report->max_coc,
        .copied_only = report->substeps_run == 0,
        .seconds_total = ddof_seconds() - t_start,
        .seconds_coc = seconds_coc,
        .seconds_rows = report->seconds_rows,
        .seconds_columns = report->seconds_columns,
        .effects = report->substeps_run ? DDOF_EFFECT_MIDGROUND : 0u,
        .backend = (uint32_t)context->backend.kind,
        .method = (uint32_t)DDOF_METHOD_DIFFUSION,
        .kernel = (uint32_t)kernel,
        .device_bytes = report->device_bytes,
        .host_bytes = host_bytes(context),
    };
}

/* ---- the foreground element ------------------------------------------------------------- */

typedef struct foreground_scan {
    const float *color, *coc;
    size_t color_stride, coc_stride;
    uint32_t coc_channels, width;
    bad_value *first_bad; /* per chunk; channel 4 marks a bad CoC */
    unsigned char *found, *has_alpha;
    pixel_box *box;       /* per chunk: where alpha > 0 */
    float *max_coc;       /* per chunk: largest |CoC| where alpha > 0 */
} foreground_scan;

/* Alpha must be finite everywhere; colour and CoC only matter (and are only read) where
 * alpha > 0, so NaN under alpha 0 is accepted. */
static void scan_foreground_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    const foreground_scan *s = user;
    s->found[chunk] = 0;
    s->has_alpha[chunk] = 0;
    s->box[chunk] = box_empty();
    s->max_coc[chunk] = 0.0f;
    for (uint32_t y = y0; y < y1; y++) {
        const float *px = s->color + (size_t)y * s->color_stride;
        const float *coc = s->coc + (size_t)y * s->coc_stride;
        for (uint32_t x = 0; x < s->width; x++) {
            const float alpha = px[x * 4 + 3];
            const float d = fabsf(coc[(size_t)x * s->coc_channels]);
            int bad_channel = -1;
            if (!isfinite(alpha))
                bad_channel = 3;
            else if (alpha > 0.0f) {
                for (int c = 0; c < 3 && bad_channel < 0; c++)
                    if (!isfinite(px[x * 4 + c]))
                        bad_channel = c;
                if (bad_channel < 0 && !(d <= DDOF_MAX_COC_PX))
                    bad_channel = 4;
                s->has_alpha[chunk] = 1;
                box_add(&s->box[chunk], x, y);
                if (d > s->max_coc[chunk])
                    s->max_coc[chunk] = d;
            }
            if (bad_channel >= 0 && !s->found[chunk]) {
                s->first_bad[chunk] =
                    (bad_value){x, y, (uint32_t)bad_channel,
                                bad_channel == 4 ? coc[(size_t)x * s->coc_channels]
                                                 : px[x * 4 + bad_channel]};
                s->found[chunk] = 1;
            }
        }
    }
}

/* Validates the element and fills the request's foreground fields; *visible says whether any
 * alpha > 0 (an element with none changes nothing and is skipped). */
static ddof_status read_foreground(ddof_context *context, const ddof_foreground *caller,
                                   layers_request *q, int *visible)
{
    ddof_foreground fg;
    ddof_foreground_init(&fg);
    ddof_status status = ddof_read_struct(context, caller, sizeof fg, &fg, sizeof fg,
                                          "foreground");
    if (status != DDOF_OK)
        return status;
    const adi_request *r = &q->base;
    if (r->channels < 3)
        return ddof_fail(context, DDOF_ERROR_BAD_CHANNELS,
                         "a foreground element needs colour with 3 or 4 channels, not %u",
                         r->channels);
    size_t color_stride, coc_stride;
    status = check_map(context, "foreground colour", &fg.color, r, &color_stride);
    if (status == DDOF_OK)
        status = check_map(context, "foreground coc", &fg.coc, r, &coc_stride);
    if (status != DDOF_OK)
        return status;
    if (fg.color.channels != 4)
        return ddof_fail(context, DDOF_ERROR_BAD_CHANNELS,
                         "foreground colour has %u channels; it must be RGBA (4)",
                         fg.color.channels);

    enum { max_chunks = (DDOF_MAX_DIMENSION + DDOF_ROWS_PER_CHUNK - 1) / DDOF_ROWS_PER_CHUNK };
    bad_value first_bad[max_chunks];
    unsigned char found[max_chunks], has_alpha[max_chunks];
    pixel_box box[max_chunks];
    float max_coc[max_chunks];
    foreground_scan scan = {fg.color.pixels, fg.coc.pixels, color_stride, coc_stride,
                            fg.coc.channels, r->width, first_bad, found, has_alpha, box, max_coc};
    ddof_parallel_rows(context, r->height, scan_foreground_rows, &scan);
    *visible = 0;
    q->fg_box = box_empty();
    q->fg_max_coc = 0.0f;
    for (uint32_t c = 0; c < ddof_row_chunks(r->height); c++) {
        q->fg_box = box_union(q->fg_box, box[c]);
        q->fg_max_coc = ddof_maxf(q->fg_max_coc, max_coc[c]);
        if (found[c]) {
            const bad_value b = first_bad[c];
            return b.channel == 4
                       ? ddof_fail(context, DDOF_ERROR_BAD_COC,
                                   "foreground CoC at pixel (%u, %u) is %g", b.x, b.y,
                                   (double)b.value)
                       : ddof_fail(context, DDOF_ERROR_BAD_COLOR,
                                   "foreground colour at pixel (%u, %u) channel %u is %g", b.x,
                                   b.y, b.channel, (double)b.value);
        }
        *visible |= has_alpha[c];
    }
    q->fg_color = fg.color.pixels;
    q->fg_color_stride = color_stride;
    q->fg_coc = fg.coc.pixels;
    q->fg_coc_stride = coc_stride;
    q->fg_coc_channels = fg.coc.channels;
    q->fg_premultiplied = fg.premultiplied != 0;
    return DDOF_OK;
}

/* ---- running ------------------------------------------------------------------------------ */

/* The CoD4 preview instead of the diffusion. */
static ddof_status run_preview(ddof_context *context, const adi_request *r, int coc_signed,
                               ddof_stats *stats, double t_start, double seconds_coc)
{
    adi_report report = {.threads = context->thread_count};
    ddof_status status = ddof_cod4_preview(context, r, coc_signed, &report);
    if (status != DDOF_OK)
        return status;
    ddof_stats full = stats_from(context, &report, r, t_start, seconds_coc);
    full.backend = (uint32_t)DDOF_BACKEND_CPU;
    full.method = (uint32_t)DDOF_METHOD_COD4_PREVIEW;
    full.substeps = 0;
    full.copied_only = 0;
    full.effects = 0;
    snprintf(full.plan, sizeof full.plan, "preview: the CoD4 post-process (GPU Gems 3 ch. 28)");
    write_stats(stats, &full);
    return DDOF_OK;
}

/* Nothing out of focus: the output is the input, on every backend (no device is involved). */
static void copy_frame(ddof_context *context, const adi_request *r, adi_report *report,
                       float max_coc)
{
    ddof_parallel_copy(context, r->color, r->color_stride, r->out, r->out_stride,
                       (size_t)r->width * r->channels, r->height);
    /* Every line skipped, counted as the run would have: a disc kernel per component. */
    const uint64_t passes = r->disc ? r->disc->components : 1u;
    *report = (adi_report){.threads = context->thread_count,
                           .lines_skipped = ((uint64_t)r->width + r->height) * passes,
                           .max_coc = max_coc};
    if (r->progress)
        r->progress(r->progress_user, 1.0f);
}

static ddof_status run_single(ddof_context *context, const adi_request *r, const ddof_params *p,
                              float max_coc, ddof_stats *stats, double t_start,
                              double seconds_coc)
{
    adi_report report;
    /* On a device the call stays there (it is the backend's frame to run, and it reports
     * what it ran); its CoC is cut to the threshold by ddof_run_adi. */
    if (all_in_focus(max_coc, p) && !context->backend.device) {
        copy_frame(context, r, &report, max_coc);
    } else {
        ddof_status status = ddof_run_adi(context, r, &report);
        if (status != DDOF_OK)
            return status;
    }
    ddof_stats full = stats_from(context, &report, r, t_start, seconds_coc);
    write_stats(stats, &full);
    return DDOF_OK;
}

/* Plans the frame, runs what the plan says, reports it. known_max_coc: the largest |CoC| when
 * the validation found it (a frame below the in-focus threshold then needs no analysis), or
 * negative. */
static ddof_status run_layered(ddof_context *context, layers_request *q, int fg_given,
                               int fg_visible, float known_max_coc, ddof_stats *stats,
                               double t_start, double seconds_coc)
{
    const adi_request *r = &q->base;
    if (q->params->method == DDOF_METHOD_COD4_PREVIEW)
        return run_preview(context, r, (int)q->params->coc_signed, stats, t_start, seconds_coc);
    const double t_plan = ddof_seconds();
    coc_analysis analysis = {.max_coc = known_max_coc};
    if (known_max_coc < 0.0f || !all_in_focus(known_max_coc, q->params) ||
        (fg_given && fg_visible))
        ddof_analyse_coc(context, r->coc, r->coc_stride, r->coc_channels, r->width, r->height,
                         q->params, &analysis);
    frame_plan plan;
    ddof_plan_frame(&analysis, q->params, fg_given, fg_visible, &plan);
    const double seconds_plan = ddof_seconds() - t_plan;

    layers_report report = {.adi = {.threads = context->thread_count,
                                    .lines_skipped = (uint64_t)r->width + r->height}};
    if (plan.copy_only) {
        copy_frame(context, r, &report.adi, analysis.max_coc);
    } else {
        q->fg_color = fg_visible ? q->fg_color : NULL;
        q->background_box = analysis.background_box;
        q->near_box = analysis.near_box;
        ddof_status status = ddof_run_layers(context, q, &plan, analysis.max_near_coc, &report);
        if (status != DDOF_OK)
            return status;
    }
    ddof_stats full = stats_from(context, &report.adi, r, t_start, seconds_coc);
    full.max_coc_px = analysis.max_coc;
    full.copied_only = plan.copy_only;
    full.effects = report.effects;
    full.seconds_plan = seconds_plan;
    full.seconds_background = report.seconds_background;
    full.seconds_foreground = report.seconds_foreground;
    memcpy(full.plan, plan.text, sizeof full.plan);
    write_stats(stats, &full);
    return DDOF_OK;
}

/* The checks every diffusion call shares: params, colour, CoC, output. */
static ddof_status prepare(ddof_context *context, const ddof_params *caller_params,
                           const ddof_image_in *color, const ddof_image_in *coc,
                           const ddof_image *out, ddof_params *params, adi_request *r,
                           float *max_coc)
{
    size_t coc_stride = 0;
    ddof_status status = read_params(context, caller_params, params);
    if (status == DDOF_OK)
        status = check_images(context, color, coc, "coc", out, r, &coc_stride);
    if (status == DDOF_OK)
        status = check_coc_values(context, coc, coc_stride, (int)params->coc_signed, max_coc);
    if (status != DDOF_OK)
        return status;
    r->coc = coc->pixels;
    r->coc_stride = coc_stride;
    r->coc_channels = coc->channels;
    fill_request_params(r, params);
    return DDOF_OK;
}

ddof_status ddof_diffuse(ddof_context *context, const ddof_params *params,
                         const ddof_image_in *color, const ddof_image_in *coc,
                         const ddof_image *out, ddof_stats *stats)
{
    const double t_start = ddof_seconds();
    if (!context)
        return DDOF_ERROR_NULL_POINTER;
    ddof_clear_error(context);
    ddof_params p;
    adi_request r = {0};
    float max_coc = 0.0f;
    ddof_status status = prepare(context, params, color, coc, out, &p, &r, &max_coc);
    if (status != DDOF_OK)
        return status;
    if (p.method == DDOF_METHOD_COD4_PREVIEW)
        return run_preview(context, &r, (int)p.coc_signed, stats, t_start,
                           ddof_seconds() - t_start);
    return run_single(context, &r, &p, max_coc, stats, t_start, ddof_seconds() - t_start);
}

ddof_status ddof_diffuse_layers(ddof_context *context, const ddof_params *params,
                                const ddof_image_in *color, const ddof_image_in *coc,
                                const ddof_foreground *foreground, const ddof_image *out,
                                ddof_stats *stats)
{
    const double t_start = ddof_seconds();
    if (!context)
        return DDOF_ERROR_NULL_POINTER;
    ddof_clear_error(context);
    ddof_params p;
    layers_request q = {.params = &p};
    int fg_visible = 0;
    float max_coc = 0.0f;
    ddof_status status = prepare(context, params, color, coc, out, &p, &q.base, &max_coc);
    if (status == DDOF_OK && foreground && p.method == DDOF_METHOD_COD4_PREVIEW)
        status = ddof_fail(context, DDOF_ERROR_UNSUPPORTED,
                           "the CoD4 preview takes no foreground element");
    if (status == DDOF_OK && foreground && p.near_spread == DDOF_LAYER_ON)
        status = ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                           "params.near_spread is forced on, but a foreground element is given: "
                           "the element is the near field, and the near spread works on one "
                           "image only");
    if (status == DDOF_OK && foreground)
        status = read_foreground(context, foreground, &q, &fg_visible);
    if (status != DDOF_OK)
        return status;
    return run_layered(context, &q, foreground != NULL, fg_visible, max_coc, stats, t_start,
                       ddof_seconds() - t_start);
}

ddof_status ddof_depth_of_field(ddof_context *context, const ddof_params *params,
                                const ddof_camera *camera, const ddof_image_in *color,
                                const ddof_image_in *depth, const ddof_image *out,
                                ddof_stats *stats)
{
    const double t_start = ddof_seconds();
    if (!context)
        return DDOF_ERROR_NULL_POINTER;
    ddof_clear_error(context);
    ddof_params p;
    ddof_camera cam;
    layers_request q = {.params = &p};
    adi_request *r = &q.base;
    size_t depth_stride = 0;
    ddof_status status = read_params(context, params, &p);
    if (status == DDOF_OK)
        status = ddof_read_camera(context, camera, &cam);
    if (status == DDOF_OK && !pixel_aspect_ok(cam.pixel_aspect, 0))
        status = ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                           "camera pixel_aspect %.9g must be within %g..%g for the diffusion",
                           cam.pixel_aspect, DDOF_MIN_PIXEL_ASPECT, DDOF_MAX_PIXEL_ASPECT);
    if (status == DDOF_OK)
        status = check_images(context, color, depth, "depth", out, r, &depth_stride);
    if (status != DDOF_OK)
        return status;

    /* Signed, so the planner knows the near field from the far. */
    cam.signed_coc = 1;
    p.coc_signed = 1;
    p.pixel_aspect = (float)cam.pixel_aspect;
    float *coc = ddof_scratch_get(context, DDOF_SCRATCH_COC,
                                  (size_t)r->width * r->height * sizeof(float));
    if (!coc)
        return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                         "could not allocate the %ux%u CoC buffer", r->width, r->height);
    status = ddof_compute_coc_camera(context, &cam, depth, depth_stride, coc, r->width);
    if (status != DDOF_OK)
        return status;
    r->coc = coc;
    r->coc_stride = r->width;
    r->coc_channels = 1;
    fill_request_params(r, &p);
    return run_layered(context, &q, 0, 0, -1.0f, stats, t_start, ddof_seconds() - t_start);
}
