/* diffuse.c - the public diffusion calls: validate everything, then hand over to a solver path.
 * Every check happens before the first output pixel is written, so a failed call leaves the
 * output as it was. */
#include "adi.h"
#include "coc.h"
#include "parallel_rows.h"

#include <math.h>
#include <string.h>

#define DDOF_MAX_SUBSTEPS 4096u
#define DDOF_MAX_JACOBI_ITERATIONS 1000000u

static ddof_status check_params(ddof_context *context, const ddof_params *p)
{
    ddof_status status = ddof_check_struct(context, p, sizeof *p, "params");
    if (status != DDOF_OK)
        return status;
    if ((unsigned)p->solver >= DDOF_SOLVER_COUNT_)
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER, "params.solver %u is not a solver",
                         (unsigned)p->solver);
    if (p->substeps < 1 || p->substeps > DDOF_MAX_SUBSTEPS)
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.substeps %u must be within 1..%u", p->substeps,
                         DDOF_MAX_SUBSTEPS);
    if (!(isfinite(p->beta_scale) && p->beta_scale > 0.0f))
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER, "params.beta_scale %g must be > 0",
                         (double)p->beta_scale);
    if (!(isfinite(p->pixel_aspect) && p->pixel_aspect > 0.0f))
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.pixel_aspect %g must be > 0", (double)p->pixel_aspect);
    if (p->solver == DDOF_SOLVER_JACOBI &&
        (p->jacobi_iterations < 1 || p->jacobi_iterations > DDOF_MAX_JACOBI_ITERATIONS))
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "params.jacobi_iterations %u must be within 1..%u",
                         p->jacobi_iterations, DDOF_MAX_JACOBI_ITERATIONS);
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

/* Checks colour, the per-pixel input (CoC or depth) and out, and fills the request's images. */
static ddof_status check_images(ddof_context *context, const ddof_image_in *color,
                                const ddof_image_in *map, const char *map_name,
                                const ddof_image *out, adi_request *r, size_t *map_stride)
{
    if (!color || !map || !out)
        return ddof_fail(context, DDOF_ERROR_NULL_POINTER, "%s image is NULL",
                         !color ? "colour" : !map ? map_name : "output");
    ddof_status status = ddof_check_image(context, "colour", color->pixels, color->width,
                                          color->height, color->channels, color->row_stride,
                                          &r->color_stride);
    if (status == DDOF_OK)
        status = ddof_check_image(context, map_name, map->pixels, map->width, map->height,
                                  map->channels, map->row_stride, map_stride);
    if (status == DDOF_OK)
        status = ddof_check_image(context, "output", out->pixels, out->width, out->height,
                                  out->channels, out->row_stride, &r->out_stride);
    if (status == DDOF_OK)
        status = check_same_size(context, map_name, map->width, map->height, color->width,
                                 color->height);
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
    r->width = color->width;
    r->height = color->height;
    r->channels = color->channels;

    bad_value bad;
    if (ddof_find_bad_value(context, color->pixels, color->width, color->height,
                            color->channels, color->channels, r->color_stride, VALUE_FINITE,
                            &bad))
        return ddof_fail(context, DDOF_ERROR_BAD_COLOR,
                         "colour at pixel (%u, %u) channel %u is %g", bad.x, bad.y,
                         bad.channel, (double)bad.value);
    return DDOF_OK;
}

static void fill_request_params(adi_request *r, const ddof_params *p)
{
    r->solver = p->solver;
    r->substeps = p->substeps;
    r->jacobi_iterations = p->jacobi_iterations;
    r->beta_scale = p->beta_scale;
    r->pixel_aspect = p->pixel_aspect;
    r->progress = p->progress;
    r->progress_user = p->progress_user;
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

static ddof_status run(ddof_context *context, const adi_request *r, ddof_stats *stats,
                       double t_start, double seconds_coc)
{
    adi_report report;
    ddof_status status = r->solver == DDOF_SOLVER_REFERENCE_F64
                             ? ddof_adi_reference(context, r, &report)
                             : ddof_adi_run(context, r, &report);
    if (status != DDOF_OK)
        return status;
    ddof_stats full = {
        .struct_size = sizeof full,
        .solver = (uint32_t)r->solver,
        .threads = report.threads,
        .substeps = report.substeps_run,
        .lines_solved = report.lines_solved,
        .lines_skipped = report.lines_skipped,
        .max_coc_px = report.max_coc,
        .copied_only = report.substeps_run == 0,
        .seconds_total = ddof_seconds() - t_start,
        .seconds_coc = seconds_coc,
        .seconds_rows = report.seconds_rows,
        .seconds_columns = report.seconds_columns,
    };
    write_stats(stats, &full);
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
    adi_request r = {0};
    size_t coc_stride = 0;
    ddof_status status = check_params(context, params);
    if (status == DDOF_OK)
        status = check_images(context, color, coc, "coc", out, &r, &coc_stride);
    if (status != DDOF_OK)
        return status;
    bad_value bad;
    if (ddof_find_bad_value(context, coc->pixels, coc->width, coc->height, coc->channels, 1,
                            coc_stride, VALUE_COC, &bad))
        return ddof_fail(context, DDOF_ERROR_BAD_COC,
                         "CoC at pixel (%u, %u) is %g; it must be finite, within 0..%g px",
                         bad.x, bad.y, (double)bad.value, (double)DDOF_MAX_COC_PX);
    r.coc = coc->pixels;
    r.coc_stride = coc_stride;
    r.coc_channels = coc->channels;
    fill_request_params(&r, params);
    return run(context, &r, stats, t_start, ddof_seconds() - t_start);
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
    adi_request r = {0};
    size_t depth_stride = 0;
    ddof_status status = check_params(context, params);
    if (status == DDOF_OK)
        status = ddof_check_camera(context, camera);
    if (status == DDOF_OK)
        status = check_images(context, color, depth, "depth", out, &r, &depth_stride);
    if (status != DDOF_OK)
        return status;

    const size_t coc_floats = (size_t)r.width * r.height;
    float *coc = ddof_scratch_get(context, DDOF_SCRATCH_COC, coc_floats * sizeof(float));
    if (!coc)
        return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                         "could not allocate the %ux%u CoC buffer", r.width, r.height);
    status = ddof_compute_coc_camera(context, camera, depth, depth_stride, coc, r.width);
    if (status == DDOF_OK) {
        r.coc = coc;
        r.coc_stride = r.width;
        r.coc_channels = 1;
        fill_request_params(&r, params);
        r.pixel_aspect = (float)camera->pixel_aspect;
        status = run(context, &r, stats, t_start, ddof_seconds() - t_start);
    }
    return status;
}
