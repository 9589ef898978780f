/* SPDX-License-Identifier: MIT */
/* reference_f64.c - the double-precision reference path: what the float solvers are measured
 * against. Deliberately independent of them: the whole image is kept in double between passes,
 * each line is solved with the textbook Thomas algorithm on the unnormalised system
 *   a_i = -beta_{i-1}, b_i = gamma_i + beta_{i-1} + beta_i, c_i = -beta_i, rhs_i = gamma_i x_i,
 * and there is no batching, skipping or threading. In double, 1 + 2e10 keeps the 1 to ~1e-6
 * relative, so the cancellation that rules out this form in float is harmless here.
 * A run of pixels joined by links whose gamma are all 0 is singular (nothing holds heat): it is
 * found explicitly and keeps its values, as heat_adi.c makes the float solvers do. The input's
 * values without heat capacity are never read (they are taken as 0). */
#include "adi.h"
#include "reference_lines.h"

#include <string.h>

typedef struct line_buffers {
    double *beta;   /* [n] link i -> i+1 */
    double *gamma;  /* [n] heat capacity */
    double *cprime; /* [n] modified super-diagonal */
    double *value;  /* [n] one channel's values */
} line_buffers;

/* Solves one run [0, n) in place (no link leaves it); value[] holds x on entry, y on return. */
static void thomas_f64(uint32_t n, const double *beta, const double *gamma, double *cprime,
                       double *value)
{
    double b = gamma[0] + beta[0];
    cprime[0] = -beta[0] / b;
    value[0] = gamma[0] * value[0] / b;
    for (uint32_t i = 1; i < n; i++) {
        const double a = -beta[i - 1];
        const double denominator = gamma[i] + beta[i - 1] + beta[i] - a * cprime[i - 1];
        cprime[i] = -beta[i] / denominator;
        value[i] = (gamma[i] * value[i] - a * value[i - 1]) / denominator;
    }
    for (uint32_t i = n - 1; i-- > 0;)
        value[i] -= cprime[i] * value[i + 1];
}

/* Splits a line at its insulating links and solves each run; singular runs keep their values. */
static void solve_line_f64(uint32_t n, line_buffers *buf)
{
    for (uint32_t start = 0, end; start < n; start = end) {
        end = reference_run_end(buf->beta, start, n);
        if (reference_run_holds_heat(buf->gamma, start, end))
            thomas_f64(end - start, buf->beta + start, buf->gamma + start, buf->cprime + start,
                       buf->value + start);
    }
}

static float coc_at(const adi_request *r, uint32_t x, uint32_t y)
{
    const float d = adi_request_coc(r, x, y);
    return d < 0.0f ? -d : d;
}

/* The heat kernel's link: beta_scale m^2, 0 below the in-focus threshold (compared in float as
 * the float solvers do). */
static double heat_link(const adi_request *r, double m, double beta_scale)
{
    return r->coc && (float)m < r->in_focus_px ? 0.0 : beta_scale * m * m;
}

/* One pass over all lines of one direction (rows, or columns). */
static uint64_t pass_f64(const adi_request *r, double *image, int rows, double beta_scale,
                         line_buffers *buf)
{
    const uint32_t C = r->channels;
    const uint32_t n = rows ? r->width : r->height;
    const uint32_t lines = rows ? r->height : r->width;
    uint64_t solved = 0;
    for (uint32_t line = 0; line < lines; line++) {
        const int active =
            reference_read_line(r, rows, line, n, heat_link, beta_scale, buf->beta, buf->gamma);
        if (!active && !r->gamma)
            continue;
        solved += active;
        for (uint32_t c = 0; c < C; c++) {
            for (uint32_t i = 0; i < n; i++)
                buf->value[i] = image[reference_pixel(r, rows, line, i) * C + c];
            solve_line_f64(n, buf);
            for (uint32_t i = 0; i < n; i++)
                image[reference_pixel(r, rows, line, i) * C + c] = buf->value[i];
        }
    }
    return solved;
}

ddof_status ddof_adi_reference(ddof_context *context, const adi_request *r, adi_report *report)
{
    const uint32_t w = r->width, h = r->height, C = r->channels;
    const uint32_t n_max = w > h ? w : h;
    const size_t image_doubles = (size_t)w * h * C;
    double *image = ddof_alloc(&context->allocator, image_doubles * sizeof(double));
    double *lines = ddof_alloc(&context->allocator, 4 * (size_t)n_max * sizeof(double));
    if (!image || !lines) {
        ddof_free(&context->allocator, image);
        ddof_free(&context->allocator, lines);
        return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                         "could not allocate the double-precision reference image");
    }
    line_buffers buf = {lines, lines + n_max, lines + 2 * (size_t)n_max,
                        lines + 3 * (size_t)n_max};
    /* Without heat capacity a pixel's colour is not read (it may be NaN): 0 instead. */
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++)
            for (uint32_t c = 0; c < C; c++)
                image[((size_t)y * w + x) * C + c] =
                    reference_gamma_at(r, x, y) > 0.0
                        ? r->color[(size_t)y * r->color_stride + x * C + c]
                        : 0.0;

    *report = (adi_report){.threads = 1};
    const double row_scale = (double)r->beta_scale / r->substeps;
    const double column_scale = row_scale * r->pixel_aspect * r->pixel_aspect;
    ddof_status status = DDOF_OK;
    for (uint32_t step = 0; step < r->substeps; step++) {
        if (r->progress && r->progress(r->progress_user, (float)step / (float)r->substeps)) {
            status = ddof_fail(context, DDOF_ERROR_CANCELLED, "cancelled by the progress callback");
            break;
        }
        double t0 = ddof_seconds();
        uint64_t rows = pass_f64(r, image, 1, row_scale, &buf);
        double t1 = ddof_seconds();
        uint64_t columns = pass_f64(r, image, 0, column_scale, &buf);
        report->seconds_rows += t1 - t0;
        report->seconds_columns += ddof_seconds() - t1;
        if (rows + columns == 0)
            break;
        report->lines_solved += rows + columns;
        report->lines_skipped += (uint64_t)w + h - rows - columns;
        report->substeps_run++;
    }
    if (report->substeps_run == 0)
        report->lines_skipped = (uint64_t)w + h;
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            const float d = coc_at(r, x, y);
            report->max_coc = d > report->max_coc ? d : report->max_coc;
        }
    /* On cancel the image still holds the input or a finished pass: finite either way. */
    {
        for (uint32_t y = 0; y < h; y++)
            for (size_t i = 0; i < (size_t)w * C; i++)
                r->out[(size_t)y * r->out_stride + i] = (float)image[(size_t)y * w * C + i];
        if (r->progress && status == DDOF_OK)
            r->progress(r->progress_user, 1.0f);
    }
    ddof_free(&context->allocator, lines);
    ddof_free(&context->allocator, image);
    return status;
}
