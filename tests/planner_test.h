/* SPDX-License-Identifier: MIT */
/* planner_test.h - what the planner's tests share (test_planner_*.c): what
 * ddof_diffuse_layers decides to simulate (issue 4: "simulate only what the scene calls for")
 * and what it reports in ddof_stats, on scenes built in code that each call for exactly one
 * effect, with every layer left at DDOF_LAYER_AUTO, then the same scenes with the layers forced
 * on and off. Here: the frame and its buffers, the plan text's readers, the scenes.
 *
 *
 * Readings of ddof.h this test relies on (tell the header's owner if one is wrong):
 *  - effects holds the bits of what was *simulated*: a call with nothing out of focus simulates
 *    nothing (copied_only 1, 0 solves), so its effects are 0; a call whose main image has no CoC
 *    but a foreground element may or may not set MIDGROUND (not asserted).
 *  - ddof_diffuse (the single-layer call) reports effects == DDOF_EFFECT_MIDGROUND.
 *  - "on when a CoC >= threshold borders an in-focus pixel" (background AUTO) is about the far
 *    field: a near (negative, coc_signed = 1) object over an in-focus background calls for the
 *    near spread only, not the background layer.
 *  - plan: "one line per decision": every layered call that solves anything has a line naming
 *    "background" and one naming "near" or "foreground"; a layer that did not run says "off" on
 *    its line, one that ran says "on". Nothing else of the wording is assumed.
 *  - seconds_background is 0 when the background layer did not run, seconds_foreground 0 when
 *    neither the foreground element nor the near spread ran; plan, background and foreground
 *    are disjoint stages of seconds_total.
 *  - "older callers get the defaults": a ddof_params whose struct_size ends before coc_signed
 *    behaves as the defaults; a ddof_stats whose struct_size ends before effects is written only
 *    up to its size. */
#ifndef DDOF_PLANNER_TEST_H
#define DDOF_PLANNER_TEST_H

#include "ddof.h"
#include "test_images.h"
#include "test_util.h"

#include <ctype.h>
#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static uint32_t W = 128, H = 96;
#define CH 4u
#define ALL_LAYER_BITS \
    (DDOF_EFFECT_MIDGROUND | DDOF_EFFECT_BACKGROUND | DDOF_EFFECT_FOREGROUND | DDOF_EFFECT_NEAR_SPREAD)

static ddof_context *ctx;
static int verbose;

#include "test_frame_calls.h"

/* ddof_diffuse on the frame (one layer); st (may be NULL) is reset first. */
static inline ddof_status single(const ddof_params *p, const float *color, const float *coc,
                                 float *out, uint32_t ch, ddof_stats *st)
{
    if (st)
        *st = stats_init();
    return diffuse(ctx, p, color, coc, out, W, H, ch, st);
}

/* ---------------------------------------------------------------------------------------- */
/* The plan text                                                                              */

static inline int ci_find(const char *hay, size_t hay_len, const char *needle)
{
    size_t n = strlen(needle);
    for (size_t i = 0; i + n <= hay_len; i++) {
        size_t k = 0;
        while (k < n && tolower((unsigned char)hay[i + k]) == tolower((unsigned char)needle[k]))
            k++;
        if (k == n)
            return 1;
    }
    return 0;
}

/* The word `word` (letters only, case-insensitive) as a whole token of the line. */
static inline int has_token(const char *line, size_t len, const char *word)
{
    size_t n = strlen(word);
    for (size_t i = 0; i + n <= len; i++) {
        if (i > 0 && isalpha((unsigned char)line[i - 1]))
            continue;
        if (i + n < len && isalpha((unsigned char)line[i + n]))
            continue;
        size_t k = 0;
        while (k < n && tolower((unsigned char)line[i + k]) == tolower((unsigned char)word[k]))
            k++;
        if (k == n)
            return 1;
    }
    return 0;
}

/* The first line of the plan that contains `key` (case-insensitive); *len its length. */
static inline const char *plan_line(const ddof_stats *st, const char *key, size_t *len)
{
    const char *p = st->plan;
    if (!memchr(p, '\0', sizeof st->plan))
        return NULL;
    while (*p) {
        const char *e = strchr(p, '\n');
        size_t l = e ? (size_t)(e - p) : strlen(p);
        if (ci_find(p, l, key)) {
            *len = l;
            return p;
        }
        if (!e)
            break;
        p = e + 1;
    }
    return NULL;
}

/* The plan is a NUL-terminated, non-empty text of non-empty lines. */
static inline int plan_well_formed(const ddof_stats *st)
{
    if (!memchr(st->plan, '\0', sizeof st->plan))
        return 0;
    size_t n = strlen(st->plan);
    if (n == 0 || st->plan[0] == '\n')
        return 0;
    for (size_t i = 0; i + 1 < n; i++)
        if (st->plan[i] == '\n' && st->plan[i + 1] == '\n')
            return 0;
    return 1;
}

/* A line containing `key` exists and says `word` (a token), e.g. ("background", "off"). */
static inline int plan_says(const ddof_stats *st, const char *key, const char *word)
{
    size_t len = 0;
    const char *line = plan_line(st, key, &len);
    return line && has_token(line, len, word);
}

/* The near-field decision line (the header names it "near spread"; the foreground element's
 * line names "foreground"). */
static inline int plan_has_near_or_foreground(const ddof_stats *st)
{
    size_t len;
    return plan_line(st, "near", &len) || plan_line(st, "foreground", &len);
}

static inline void dump_plan(const char *name, const ddof_stats *st)
{
    if (verbose)
        printf("--- %s: effects 0x%x lines %llu/%llu skipped, plan:\n%s\n", name, st->effects,
               (unsigned long long)st->lines_solved, (unsigned long long)st->lines_skipped,
               memchr(st->plan, '\0', sizeof st->plan) ? st->plan : "(not terminated)");
}

/* Timings: finite, >= 0, each stage within the total, and plan + background + foreground (the
 * disjoint layer stages) within the total. `bg_ran` / `fg_ran` say whether the stage ran. */
static inline void check_timings(const char *name, const ddof_stats *st, int bg_ran, int fg_ran)
{
    const double eps = 1e-3;
    CHECK_MSG(isfinite(st->seconds_total) && st->seconds_total >= 0, "%s: total %g", name,
              st->seconds_total);
    CHECK_MSG(isfinite(st->seconds_plan) && st->seconds_plan >= 0, "%s: plan %g", name,
              st->seconds_plan);
    CHECK_MSG(isfinite(st->seconds_background) && st->seconds_background >= 0,
              "%s: background %g", name, st->seconds_background);
    CHECK_MSG(isfinite(st->seconds_foreground) && st->seconds_foreground >= 0,
              "%s: foreground %g", name, st->seconds_foreground);
    CHECK_MSG(st->seconds_plan + st->seconds_background + st->seconds_foreground <=
                  st->seconds_total + eps,
              "%s: plan %g + background %g + foreground %g > total %g", name, st->seconds_plan,
              st->seconds_background, st->seconds_foreground, st->seconds_total);
    if (bg_ran)
        CHECK_MSG(st->seconds_background > 0, "%s: background ran in 0 s", name);
    else
        CHECK_MSG(st->seconds_background == 0, "%s: background did not run but took %g s",
                  name, st->seconds_background);
    if (fg_ran)
        CHECK_MSG(st->seconds_foreground > 0, "%s: foreground/near ran in 0 s", name);
    else
        CHECK_MSG(st->seconds_foreground == 0, "%s: no foreground/near but %g s", name,
                  st->seconds_foreground);
}

/* ---------------------------------------------------------------------------------------- */
/* Scenes                                                                                     */

/* Blocky random texture (8x8 blocks) in [0.1, 0.9]; alpha (channel 3) 1. */
static inline void texture(float *color, uint32_t ch, unsigned long long seed)
{
    block_texture(color, W, H, ch, seed, 0.1, 0.9);
}

/* Thin sharp vertical bars (2 or 3 px, every 16 px; CoC 0) over a blurred background (CoC 20). */
static inline void bars_coc(float *coc)
{
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            uint32_t k = x / 16, off = x % 16, width = (k & 1) ? 3 : 2;
            coc[(size_t)y * W + x] = (off >= 8 && off < 8 + width) ? 0.0f : 20.0f;
        }
}

/* A disc of radius H/4 in the middle: value `in` inside, `out` outside. */
static inline int in_disc(uint32_t x, uint32_t y)
{
    double dx = x + 0.5 - W / 2.0, dy = y + 0.5 - H / 2.0, r = H / 4.0;
    return dx * dx + dy * dy <= r * r;
}

static inline void disc_coc(float *coc, float in, float out)
{
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++)
            coc[(size_t)y * W + x] = in_disc(x, y) ? in : out;
}

/* A foreground element: a disc of premultiplied colour (0.9, 0.6, 0.2) with alpha 1, CoC 20;
 * outside: zeros (alpha 0, CoC 0). */
static inline void disc_foreground(float *fg_color, float *fg_coc)
{
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            size_t i = (size_t)y * W + x;
            int in = in_disc(x, y);
            fg_color[i * 4 + 0] = in ? 0.9f : 0.0f;
            fg_color[i * 4 + 1] = in ? 0.6f : 0.0f;
            fg_color[i * 4 + 2] = in ? 0.2f : 0.0f;
            fg_color[i * 4 + 3] = in ? 1.0f : 0.0f;
            fg_coc[i] = in ? 20.0f : 0.0f;
        }
}

/* The frame's buffers (npx pixels, n colour values). */
static float *color, *coc, *out, *out2, *fg_color, *fg_coc;
static size_t npx, n;

/* The frame's size, DDOF_TEST_VERBOSE, the context and the buffers. */
static inline void planner_test_begin(void)
{
    verbose = getenv("DDOF_TEST_VERBOSE") && atoi(getenv("DDOF_TEST_VERBOSE"));
    if (test_quick()) {
        W = 64;
        H = 48;
    }
    ctx = make_context(2);
    npx = (size_t)W * H;
    n = npx * CH;
    color = alloc_f(n);
    coc = alloc_f(npx);
    out = alloc_f(n);
    out2 = alloc_f(n);
    fg_color = alloc_f(npx * 4);
    fg_coc = alloc_f(npx);
}

/* Frees the buffers and the context; the exit status. */
static inline int planner_test_end(const char *name)
{
    free(color);
    free(coc);
    free(out);
    free(out2);
    free(fg_color);
    free(fg_coc);
    ddof_context_free(ctx);
    return test_report(name);
}

#endif
