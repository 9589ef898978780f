/* SPDX-License-Identifier: MIT */
/* lens_reference_f64.c - the disc kernel in double precision: what lens_adi.c is measured
 * against. Deliberately independent of it: complex doubles, the whole image per component, the
 * textbook Thomas algorithm on the unnormalised system of each step, the components summed as
 * sum_c Re(mix_c Z_c) (not as changes), no batching, skipping or threading. Links, singular runs,
 * masked input and the clamp to the input's range mean what they mean in lens_adi.c. */
#include "adi.h"
#include "reference_lines.h"

#include "disc/disc_kernel.h"
#include "solvers/lens_solver.h"

#include <complex.h>
#include <math.h>

typedef struct lens_lines {
    double *b, *gamma;                    /* [n] link i -> i+1, heat capacity */
    double complex *cprime, *value;       /* [n]                              */
} lens_lines;

static void thomas_complex(uint32_t n, const double *b, const double *gamma, double complex kappa,
                           double complex *cprime, double complex *value)
{
    double complex denominator = gamma[0] + kappa * b[0];
    cprime[0] = -kappa * b[0] / denominator;
    value[0] = gamma[0] * value[0] / denominator;
    for (uint32_t i = 1; i < n; i++) {
        const double complex a = -kappa * b[i - 1];
        denominator = gamma[i] + kappa * (b[i - 1] + b[i]) - a * cprime[i - 1];
        cprime[i] = -kappa * b[i] / denominator;
        value[i] = (gamma[i] * value[i] - a * value[i - 1]) / denominator;
    }
    for (uint32_t i = n - 1; i-- > 0;)
        value[i] -= cprime[i] * value[i + 1];
}

/* value = the component's chain of steps applied to the line in value; runs without heat keep
 * their values. */
static void solve_line(const disc_kernel *k, uint32_t c, uint32_t n, lens_lines *buf)
{
    for (uint32_t m = 0; m < k->steps; m++) {
        const double complex kappa = k->kappa[c][m][0] + I * (double)k->kappa[c][m][1];
        for (uint32_t start = 0, end; start < n; start = end) {
            end = reference_run_end(buf->b, start, n);
            if (reference_run_holds_heat(buf->gamma, start, end))
                thomas_complex(end - start, buf->b + start, buf->gamma + start, kappa,
                               buf->cprime + start, buf->value + start);
        }
    }
}

static double coc_abs(const adi_request *r, uint32_t x, uint32_t y)
{
    return fabs((double)adi_request_coc(r, x, y));
}

/* The disc kernel's link: the float path's floor, applied to the same float value. */
static double disc_link(const adi_request *r, double m, double scale)
{
    const float bf = (float)(m * m) * (float)scale;
    const int in_focus = r->coc && (float)m < r->in_focus_px;
    return bf >= DDOF_LENS_MIN_LINK && !in_focus ? (double)bf : 0.0;
}

/* One pass of component c over the complex image (w * h * C). */
static uint64_t lens_pass(const adi_request *r, const disc_kernel *k, uint32_t c,
                          double complex *image, int rows, lens_lines *buf)
{
    const uint32_t C = r->channels, n = rows ? r->width : r->height;
    const uint32_t lines = rows ? r->height : r->width;
    const double scale = rows ? 1.0 : (double)r->pixel_aspect * r->pixel_aspect;
    uint64_t solved = 0;
    for (uint32_t line = 0; line < lines; line++) {
        if (!reference_read_line(r, rows, line, n, disc_link, scale, buf->b, buf->gamma))
            continue;
        solved += k->steps;
        for (uint32_t ch = 0; ch < C; ch++) {
            for (uint32_t i = 0; i < n; i++)
                buf->value[i] = image[reference_pixel(r, rows, line, i) * C + ch];
            solve_line(k, c, n, buf);
            for (uint32_t i = 0; i < n; i++)
                image[reference_pixel(r, rows, line, i) * C + ch] = buf->value[i];
        }
    }
    return solved;
}

ddof_status ddof_lens_reference(ddof_context *context, const adi_request *r, adi_report *report)
{
    const disc_kernel *k = r->disc;
    const uint32_t w = r->width, h = r->height, C = r->channels;
    const uint32_t n_max = w > h ? w : h;
    const size_t elements = (size_t)w * h * C;
    double complex *image = ddof_alloc(&context->allocator, elements * sizeof *image);
    double *sum = ddof_alloc(&context->allocator, elements * sizeof *sum);
    double *line_reals = ddof_alloc(&context->allocator, 2 * (size_t)n_max * sizeof(double));
    double complex *line_complex =
        ddof_alloc(&context->allocator, 2 * (size_t)n_max * sizeof(double complex));
    ddof_status status = DDOF_OK;
    if (!image || !sum || !line_reals || !line_complex) {
        status = ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                           "could not allocate the double-precision disc reference");
        goto done;
    }
    lens_lines buf = {line_reals, line_reals + n_max, line_complex, line_complex + n_max};
    for (size_t i = 0; i < elements; i++)
        sum[i] = 0.0;
    *report = (adi_report){.threads = 1};
    for (uint32_t c = 0; c < k->components; c++) {
        if (r->progress && r->progress(r->progress_user, (float)c / (float)k->components)) {
            status = ddof_fail(context, DDOF_ERROR_CANCELLED, "cancelled by the progress callback");
            break;
        }
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++)
                for (uint32_t ch = 0; ch < C; ch++)
                    image[((size_t)y * w + x) * C + ch] =
                        reference_gamma_at(r, x, y) > 0.0
                            ? r->color[(size_t)y * r->color_stride + (size_t)x * C + ch]
                            : 0.0;
        const double t0 = ddof_seconds();
        report->lines_solved += lens_pass(r, k, c, image, 1, &buf);
        const double t1 = ddof_seconds();
        report->lines_solved += lens_pass(r, k, c, image, 0, &buf);
        report->seconds_rows += t1 - t0;
        report->seconds_columns += ddof_seconds() - t1;
        const double complex mix = k->mix[c][0] + I * (double)k->mix[c][1];
        for (size_t i = 0; i < elements; i++)
            sum[i] += creal(mix * image[i]);
    }
    report->substeps_run = report->lines_solved ? 1 : 0;
    report->lines_skipped = (uint64_t)(w + h) * k->components - report->lines_solved / k->steps;
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++)
            report->max_coc = fmaxf(report->max_coc, (float)coc_abs(r, x, y));
    if (status == DDOF_OK) {
        /* Clamped to the range of the input as read (masked), per channel, as lens_adi.c does. */
        double lo[4] = {INFINITY, INFINITY, INFINITY, INFINITY};
        double hi[4] = {-INFINITY, -INFINITY, -INFINITY, -INFINITY};
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++)
                for (uint32_t ch = 0; ch < C; ch++) {
                    const double v =
                        reference_gamma_at(r, x, y) > 0.0
                            ? r->color[(size_t)y * r->color_stride + (size_t)x * C + ch]
                            : 0.0;
                    lo[ch] = fmin(lo[ch], v);
                    hi[ch] = fmax(hi[ch], v);
                }
        for (uint32_t y = 0; y < h; y++)
            for (size_t i = 0; i < (size_t)w * C; i++)
                r->out[(size_t)y * r->out_stride + i] =
                    (float)fmin(fmax(sum[(size_t)y * w * C + i], lo[i % C]), hi[i % C]);
        if (r->progress)
            r->progress(r->progress_user, 1.0f);
    } else if (r->out != r->color) {
        for (uint32_t y = 0; y < h; y++)
            for (size_t i = 0; i < (size_t)w * C; i++)
                r->out[(size_t)y * r->out_stride + i] = r->color[(size_t)y * r->color_stride + i];
    }
done:
    ddof_free(&context->allocator, line_complex);
    ddof_free(&context->allocator, line_reals);
    ddof_free(&context->allocator, sum);
    ddof_free(&context->allocator, image);
    return status;
}
