/* SPDX-License-Identifier: MIT */
/* reference_lines.h - what the two double-precision references (reference_f64.c,
 * lens_reference_f64.c) share: how a pass walks the image's lines and reads their links and
 * heat capacities, and how a line is split at its insulating links into runs solved on their
 * own (a run that holds no heat keeps its values). Textbook loops, kept apart from the float
 * drivers (heat_adi.c, lens_adi.c) that the references measure. */
#ifndef DDOF_REFERENCE_LINES_H
#define DDOF_REFERENCE_LINES_H

#include "adi.h"

#include <math.h>

/* The heat capacity of pixel (x, y): the layers' gamma, or 1 for plain diffusion. */
static inline double reference_gamma_at(const adi_request *r, uint32_t x, uint32_t y)
{
    return r->gamma ? r->gamma[(size_t)y * r->gamma_stride + (size_t)x * r->gamma_channels] : 1.0;
}

/* The pixel (index in the image, row-major) of element i of a line: of row `line` when `rows`,
 * else of column `line`. */
static inline size_t reference_pixel(const adi_request *r, int rows, uint32_t line, uint32_t i)
{
    return rows ? (size_t)line * r->width + i : (size_t)i * r->width + line;
}

/* A kernel's link between two neighbours whose smaller |CoC| is m (px), `scale` the pass's. */
typedef double (*reference_link_fn)(const adi_request *r, double m, double scale);

/* Reads line `line` of a pass (rows when `rows`, else columns) of n elements: link[i] between
 * elements i and i + 1 (0 past the last) and gamma[i]. Returns whether any link conducts. */
static inline int reference_read_line(const adi_request *r, int rows, uint32_t line, uint32_t n,
                                      reference_link_fn link_of, double scale, double *link,
                                      double *gamma)
{
    int active = 0;
    for (uint32_t i = 0; i < n; i++) {
        const uint32_t x = rows ? i : line, y = rows ? line : i;
        double b = 0.0;
        if (i + 1 < n) {
            const double d0 = fabs((double)adi_request_coc(r, x, y));
            const double d1 = fabs((double)adi_request_coc(r, rows ? x + 1 : x, rows ? y : y + 1));
            b = link_of(r, d0 < d1 ? d0 : d1, scale);
        }
        link[i] = b;
        gamma[i] = reference_gamma_at(r, x, y);
        active |= b > 0.0;
    }
    return active;
}

/* The end (one past the last element) of the run that starts at `start` of a line of n: the
 * first link from there that does not conduct (link[i] > 0 is false), or the line's end. */
static inline uint32_t reference_run_end(const double *link, uint32_t start, uint32_t n)
{
    uint32_t i = start;
    while (i + 1 < n && link[i] > 0.0)
        i++;
    return i + 1;
}

/* Whether any element of [start, end) holds heat; a run without heat is singular. */
static inline int reference_run_holds_heat(const double *gamma, uint32_t start, uint32_t end)
{
    for (uint32_t i = start; i < end; i++)
        if (gamma[i] > 0.0)
            return 1;
    return 0;
}

#endif
