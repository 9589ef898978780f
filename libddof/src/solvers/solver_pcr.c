/* SPDX-License-Identifier: MIT */
/* solver_pcr.c - parallel cyclic reduction (Zhang, Cohen, Owens 2010).
 *
 * At step k every equation eliminates its neighbours at distance s = 2^k, which couples it to the
 * unknowns at distance 2s instead. After ceil(log2 n) steps the distance exceeds the line and
 * every equation stands alone: y = u. O(n log n) work against cyclic reduction's O(n), but no
 * back-substitution and every step is one independent pass over all equations (what a GPU
 * wants); here it mainly exists to be compared. Steps are double-buffered: an equation must see
 * its neighbours as they were before the step.
 *
 * The rows and how they are combined are shared with solver_cr.c (reduction_rows.h): per
 * equation, for all lanes, links A and C, excess E (diagonal = E + A + C, never formed by
 * subtraction) and the source value u (right-hand side = E u), updated as u + w * (v - u).
 */
#include "reduction_rows.h"

static size_t pcr_scratch_floats(uint32_t n, uint32_t channels)
{
    return 2 * (size_t)n * row_floats(channels);
}

static DDOF_ALWAYS_INLINE void pcr_solve_channels(const line_batch *batch, const uint32_t ch)
{
    const size_t rf = row_floats(ch);
    const uint32_t n = batch->n;
    float *src = batch->scratch, *dst = batch->scratch + n * rf;

    for (uint32_t i = 0; i < n; i++) load_row(src + i * rf, batch, i, ch);

    for (uint64_t s = 1; s < n; s *= 2) {
        for (uint32_t i = 0; i < n; i++) {
            const float *lo = i >= s ? src + (i - s) * rf : zero_row;
            const float *hi = i + s < n ? src + (i + s) * rf : zero_row;
            eliminate(dst + i * rf, src + i * rf, lo, hi, ch);
        }
        float *t = src;
        src = dst;
        dst = t;
    }

    /* Every row is decoupled now (A = C = 0: its neighbours at distance >= n do not exist), so
     * its source value is its solution. */
    for (uint32_t i = 0; i < n; i++) store_values(batch, i, src + i * rf, ch);
}

DDOF_MULTIVERSION static void pcr_solve(const line_batch *batch)
{
    DDOF_SOLVE_PER_CHANNEL_COUNT(pcr_solve_channels, batch);
}

const solver_ops ddof_solver_pcr = {"pcr", pcr_scratch_floats, pcr_solve};
