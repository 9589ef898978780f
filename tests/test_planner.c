/* SPDX-License-Identifier: MIT */
/* test_planner.c - what ddof_diffuse_layers decides to simulate (issue 4: "simulate only what the
 * scene calls for") and what it reports in ddof_stats: scenes built in code that each call for
 * exactly one effect, with every layer left at DDOF_LAYER_AUTO, then the same scenes with the
 * layers forced on and off.
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

static ddof_status single(const ddof_params *p, const float *color, const float *coc, float *out,
                          uint32_t ch, ddof_stats *st)
{
    if (st)
        *st = stats_init();
    return diffuse(ctx, p, color, coc, out, W, H, ch, st);
}

/* ---------------------------------------------------------------------------------------- */
/* The plan text                                                                              */

static int ci_find(const char *hay, size_t hay_len, const char *needle)
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
static int has_token(const char *line, size_t len, const char *word)
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
static const char *plan_line(const ddof_stats *st, const char *key, size_t *len)
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
static int plan_well_formed(const ddof_stats *st)
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
static int plan_says(const ddof_stats *st, const char *key, const char *word)
{
    size_t len = 0;
    const char *line = plan_line(st, key, &len);
    return line && has_token(line, len, word);
}

/* The near-field decision line (the header names it "near spread"; the foreground element's
 * line names "foreground"). */
static int plan_has_near_or_foreground(const ddof_stats *st)
{
    size_t len;
    return plan_line(st, "near", &len) || plan_line(st, "foreground", &len);
}

static void dump_plan(const char *name, const ddof_stats *st)
{
    if (verbose)
        printf("--- %s: effects 0x%x lines %llu/%llu skipped, plan:\n%s\n", name, st->effects,
               (unsigned long long)st->lines_solved, (unsigned long long)st->lines_skipped,
               memchr(st->plan, '\0', sizeof st->plan) ? st->plan : "(not terminated)");
}

/* Timings: finite, >= 0, each stage within the total, and plan + background + foreground (the
 * disjoint layer stages) within the total. `bg_ran` / `fg_ran` say whether the stage ran. */
static void check_timings(const char *name, const ddof_stats *st, int bg_ran, int fg_ran)
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
static void texture(float *color, uint32_t ch, unsigned long long seed)
{
    block_texture(color, W, H, ch, seed, 0.1, 0.9);
}

/* Thin sharp vertical bars (2 or 3 px, every 16 px; CoC 0) over a blurred background (CoC 20). */
static void bars_coc(float *coc)
{
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            uint32_t k = x / 16, off = x % 16, width = (k & 1) ? 3 : 2;
            coc[(size_t)y * W + x] = (off >= 8 && off < 8 + width) ? 0.0f : 20.0f;
        }
}

/* A disc of radius H/4 in the middle: value `in` inside, `out` outside. */
static int in_disc(uint32_t x, uint32_t y)
{
    double dx = x + 0.5 - W / 2.0, dy = y + 0.5 - H / 2.0, r = H / 4.0;
    return dx * dx + dy * dy <= r * r;
}

static void disc_coc(float *coc, float in, float out)
{
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++)
            coc[(size_t)y * W + x] = in_disc(x, y) ? in : out;
}

/* A foreground element: a disc of premultiplied colour (0.9, 0.6, 0.2) with alpha 1, CoC 20;
 * outside: zeros (alpha 0, CoC 0). */
static void disc_foreground(float *fg_color, float *fg_coc)
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

/* ---------------------------------------------------------------------------------------- */

static float *color, *coc, *out, *out2, *fg_color, *fg_coc;
static size_t npx, n;

static void test_defaults(void)
{
    ddof_params p;
    memset(&p, 0x5A, sizeof p);
    heat_params_init(&p);
    CHECK_EQ_INT(p.struct_size, sizeof p);
    CHECK_EQ_INT(p.coc_signed, 0);
    CHECK_EQ_INT(p.background, DDOF_LAYER_AUTO);
    CHECK_EQ_INT(p.near_spread, DDOF_LAYER_AUTO);
    CHECK_NEAR(p.background_threshold_px, 8.0, 0);
    CHECK_NEAR(p.background_ramp_start_px, 2.0, 0);
    CHECK_EQ_INT(p.background_levels, 1);
    CHECK_NEAR(p.near_spread_threshold_px, 4.0, 0);

    ddof_foreground fg;
    memset(&fg, 0x5A, sizeof fg);
    ddof_foreground_init(&fg);
    CHECK_EQ_INT(fg.struct_size, sizeof fg);
    CHECK_EQ_INT(fg.premultiplied, 1);
    CHECK(fg.color.pixels == NULL && fg.coc.pixels == NULL);

    ddof_camera cam;
    memset(&cam, 0x5A, sizeof cam);
    ddof_camera_init(&cam);
    CHECK_EQ_INT(cam.signed_coc, 0);
    ddof_curve curve;
    memset(&curve, 0x5A, sizeof curve);
    ddof_curve_init(&curve);
    CHECK_EQ_INT(curve.signed_coc, 0);
}

/* Nothing out of focus: zero solves, a bitwise copy, no effect. */
static void test_all_sharp(void)
{
    texture(color, CH, 1);
    fill_const(coc, npx, 0.0f);
    for (int variant = 0; variant < 2; variant++) {
        ddof_params p;
        heat_params_init(&p);
        p.coc_signed = (uint32_t)variant;
        ddof_stats st;
        fill_const(out, n, -7.0f);
        ddof_status s = layers(&p, color, coc, NULL, out, CH, &st);
        CHECK_EQ_INT(s, DDOF_OK);
        dump_plan("all sharp", &st);
        CHECK_EQ_INT(st.lines_solved, 0);
        CHECK_EQ_INT(st.copied_only, 1);
        CHECK_EQ_INT(st.substeps, 0);
        CHECK_MSG(st.effects == 0, "all sharp: effects 0x%x, nothing was simulated", st.effects);
        CHECK(!memcmp(out, color, n * sizeof(float)));
        CHECK_MSG(plan_well_formed(&st), "all sharp: plan \"%.*s\"", 511, st.plan);
        CHECK_NEAR(st.max_coc_px, 0.0, 0.0);
        check_timings("all sharp", &st, 0, 0);
    }
}

/* The in-focus threshold (params.in_focus_threshold_px, default 0.5 px). A frame whose largest
 * |CoC| is below it is a copy: no line solved, copied_only 1, the output bit for bit the input,
 * through ddof_diffuse and ddof_diffuse_layers, both kernels, signed or not, in place or not.
 * The same frame with the threshold 0 does blur: the threshold is what made it a copy. Inside
 * a blurred frame a pixel below the threshold conducts as CoC 0 and keeps its value. */
static void sub_pixel_coc(float *coc, float max, int with_near, unsigned long long seed)
{
    test_rng rng = {seed};
    for (size_t i = 0; i < npx; i++) {
        const float v = (float)(max * test_uniform(&rng));
        coc[i] = with_near && (i / W + i % W) % 3 == 0 ? -v : v;
    }
    /* The largest |CoC| is exactly `max`, on two neighbours: a link of that size. */
    coc[npx / 2 + W / 2] = coc[npx / 2 + W / 2 + 1] = with_near ? -max : max;
}

/* How many values of pixels with |CoC| below t differ from the input, bit for bit. */
static size_t in_focus_changed(const float *out, const float *in, const float *coc, float t)
{
    size_t changed = 0;
    for (size_t i = 0; i < npx; i++)
        if (fabsf(coc[i]) < t)
            changed += memcmp(out + i * CH, in + i * CH, CH * sizeof(float)) != 0;
    return changed;
}

static void check_copy(const char *name, const ddof_stats *st, const float *result, float max)
{
    CHECK_MSG(st->lines_solved == 0, "%s: %llu lines solved", name,
              (unsigned long long)st->lines_solved);
    CHECK_MSG(st->copied_only == 1, "%s: copied_only %u", name, st->copied_only);
    CHECK_EQ_INT(st->substeps, 0);
    CHECK_MSG(st->effects == 0, "%s: effects 0x%x", name, st->effects);
    CHECK_MSG(st->max_coc_px == max, "%s: max_coc_px %.9g, the frame's is %.9g", name,
              (double)st->max_coc_px, (double)max);
    CHECK_MSG(!memcmp(result, color, n * sizeof(float)), "%s: output is not the input", name);
}

static void test_in_focus_threshold(void)
{
    texture(color, CH, 11);
    ddof_params defaults;
    for (int preset = 0; preset < DDOF_PRESET_COUNT_; preset++) {
        CHECK_EQ_INT(ddof_params_init_preset(&defaults, (ddof_preset)preset), DDOF_OK);
        CHECK_NEAR(defaults.in_focus_threshold_px, 0.5, 0.0);
    }

    static const float below = 0.45f; /* the frame's largest |CoC|, under the default */
    for (int variant = 0; variant < 8; variant++) {
        const int layered = variant & 1, disc = (variant >> 1) & 1, in_place = variant >> 2;
        char name[96];
        snprintf(name, sizeof name, "sub-pixel %s %s%s", layered ? "layers" : "single",
                 disc ? "disc" : "heat", in_place ? " in place" : "");
        ddof_params p;
        ddof_params_init(&p); /* the default preset: disc-2x2 */
        if (!disc)
            p.kernel = DDOF_KERNEL_HEAT;
        p.coc_signed = 1;
        sub_pixel_coc(coc, below, 1, 100 + (unsigned)variant);
        ddof_stats st;
        float *result = in_place ? out2 : out;
        if (in_place)
            memcpy(out2, color, n * sizeof(float));
        else
            fill_const(out, n, -7.0f);
        const float *input = in_place ? out2 : color;
        CHECK_EQ_INT(layered ? layers(&p, input, coc, NULL, result, CH, &st)
                             : single(&p, input, coc, result, CH, &st),
                     DDOF_OK);
        check_copy(name, &st, result, below);
        if (layered) {
            CHECK_MSG(plan_says(&st, "midground", "off"), "%s: plan \"%.*s\"", name, 511,
                      st.plan);
            check_timings(name, &st, 0, 0);
        }

        /* Without the threshold the same frame is blurred: lines solved, output changed. */
        p.in_focus_threshold_px = 0.0f;
        if (in_place)
            memcpy(out2, color, n * sizeof(float));
        CHECK_EQ_INT(layered ? layers(&p, input, coc, NULL, result, CH, &st)
                             : single(&p, input, coc, result, CH, &st),
                     DDOF_OK);
        CHECK_MSG(st.lines_solved > 0 && st.copied_only == 0, "%s, threshold 0: %llu lines",
                  name, (unsigned long long)st.lines_solved);
        CHECK_MSG(max_abs_diff_ff(result, color, n) > 1e-4,
                  "%s, threshold 0: the output is the input", name);
    }

    /* ddof_depth_of_field computes its CoC (no validation pass finds the largest): a scene
     * just behind the focus plane has a CoC far below a pixel, and is a copy too. */
    {
        ddof_camera cam;
        ddof_camera_init(&cam); /* 50 mm f/2.8 focused at 10 m */
        float *depth = alloc_f(npx);
        for (size_t i = 0; i < npx; i++)
            depth[i] = 10.0f + 0.01f * (float)(i % 7);
        ddof_params p;
        ddof_params_init(&p);
        ddof_image_in ci = {color, W, H, CH, 0}, di = {depth, W, H, 1, 0};
        ddof_image oi = {out, W, H, CH, 0};
        ddof_stats st = stats_init();
        fill_const(out, n, -7.0f);
        CHECK_EQ_INT(ddof_depth_of_field(ctx, &p, &cam, &ci, &di, &oi, &st), DDOF_OK);
        CHECK_MSG(st.max_coc_px > 0.0f && st.max_coc_px < 0.5f, "camera: largest CoC %g",
                  (double)st.max_coc_px);
        check_copy("camera, sub-pixel", &st, out, st.max_coc_px);
        /* The heat kernel: a disc kernel drops links below DDOF_LENS_MIN_LINK, which CoCs this
         * small (the quick run's smaller frame has larger pixels) do not reach. */
        p.in_focus_threshold_px = 0.0f;
        p.kernel = DDOF_KERNEL_HEAT;
        CHECK_EQ_INT(ddof_depth_of_field(ctx, &p, &cam, &ci, &di, &oi, &st), DDOF_OK);
        CHECK_MSG(st.lines_solved > 0, "camera, threshold 0: %llu lines",
                  (unsigned long long)st.lines_solved);
        free(depth);
    }

    /* The bound: a largest |CoC| equal to the threshold conducts (|CoC| < t is in focus), one
     * a hair below it does not. */
    ddof_params p;
    heat_params_init(&p);
    ddof_stats st;
    sub_pixel_coc(coc, 0.8f, 0, 7);
    p.in_focus_threshold_px = 0.8f;
    CHECK_EQ_INT(single(&p, color, coc, out, CH, &st), DDOF_OK);
    CHECK_MSG(st.lines_solved > 0 && st.copied_only == 0,
              "largest CoC = threshold: %llu lines, copied_only %u",
              (unsigned long long)st.lines_solved, st.copied_only);
    p.in_focus_threshold_px = nextafterf(0.8f, 1.0f);
    CHECK_EQ_INT(single(&p, color, coc, out, CH, &st), DDOF_OK);
    check_copy("largest CoC just below the threshold", &st, out, 0.8f);

    /* A blurred frame: its sub-pixel pixels conduct as CoC 0 and keep their values exactly,
     * with either kernel; the others blur. */
    for (int disc = 0; disc < 2; disc++) {
        ddof_params_init(&p);
        if (!disc)
            p.kernel = DDOF_KERNEL_HEAT;
        test_rng rng = {31};
        for (size_t i = 0; i < npx; i++)
            coc[i] = test_uniform(&rng) < 0.3 ? (float)(0.49 * test_uniform(&rng)) : 10.0f;
        CHECK_EQ_INT(single(&p, color, coc, out, CH, &st), DDOF_OK);
        CHECK(st.lines_solved > 0 && st.copied_only == 0);
        size_t changed = in_focus_changed(out, color, coc, 0.5f);
        CHECK_MSG(changed == 0, "%s: %zu sub-pixel pixels changed", disc ? "disc" : "heat",
                  changed);
        CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, &st), DDOF_OK);
        CHECK(st.lines_solved > 0);
        /* Without the threshold they blur like any other. */
        p.in_focus_threshold_px = 0.0f;
        CHECK_EQ_INT(single(&p, color, coc, out, CH, &st), DDOF_OK);
        changed = in_focus_changed(out, color, coc, 0.5f);
        CHECK_MSG(changed > npx / 10, "%s, threshold 0: only %zu sub-pixel pixels changed",
                  disc ? "disc" : "heat", changed);
    }

    /* The range: >= 0, at most DDOF_MAX_COC_PX; outside it a status and out untouched. */
    sub_pixel_coc(coc, below, 0, 5);
    const float bad[] = {-0.25f, -FLT_MIN, NAN, INFINITY, 2.0f * DDOF_MAX_COC_PX,
                         nextafterf(DDOF_MAX_COC_PX, INFINITY)};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        heat_params_init(&p);
        p.in_focus_threshold_px = bad[i];
        fill_const(out, n, -7.0f);
        CHECK_MSG(single(&p, color, coc, out, CH, NULL) == DDOF_ERROR_BAD_PARAMETER,
                  "threshold %g accepted by ddof_diffuse", (double)bad[i]);
        CHECK_MSG(layers(&p, color, coc, NULL, out, CH, NULL) == DDOF_ERROR_BAD_PARAMETER,
                  "threshold %g accepted by ddof_diffuse_layers", (double)bad[i]);
        CHECK_MSG(ci_find(ddof_context_last_error(ctx), strlen(ddof_context_last_error(ctx)),
                          "in_focus_threshold_px"),
                  "threshold %g: error \"%s\"", (double)bad[i], ddof_context_last_error(ctx));
        size_t touched = 0;
        for (size_t k = 0; k < n; k++)
            touched += out[k] != -7.0f;
        CHECK_MSG(touched == 0, "threshold %g: %zu output values written", (double)bad[i],
                  touched);
    }
    const float good[] = {0.0f, DDOF_MAX_COC_PX};
    for (size_t i = 0; i < 2; i++) {
        heat_params_init(&p);
        p.in_focus_threshold_px = good[i];
        CHECK_EQ_INT(single(&p, color, coc, out, CH, &st), DDOF_OK);
        CHECK_EQ_INT(st.copied_only, good[i] > 0.0f);
    }

    /* Bad colour in a frame that would be a copy is still found, and out stays untouched. */
    heat_params_init(&p);
    color[n / 3] = NAN;
    fill_const(out, n, -7.0f);
    CHECK_EQ_INT(single(&p, color, coc, out, CH, NULL), DDOF_ERROR_BAD_COLOR);
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, NULL), DDOF_ERROR_BAD_COLOR);
    size_t touched = 0;
    for (size_t k = 0; k < n; k++)
        touched += out[k] != -7.0f;
    CHECK_MSG(touched == 0, "bad colour, sub-pixel frame: %zu output values written", touched);
    texture(color, CH, 11);

    /* An older caller (params up to kernel, garbage after) gets the default threshold. */
    ddof_params_init(&p);
    p.kernel = DDOF_KERNEL_HEAT;
    unsigned char pbuf[sizeof(ddof_params)];
    memset(pbuf, 0xA7, sizeof pbuf);
    const size_t v04 = offsetof(ddof_params, in_focus_threshold_px);
    memcpy(pbuf, &p, v04);
    ((ddof_params *)(void *)pbuf)->struct_size = (uint32_t)v04;
    ddof_params old;
    memcpy(&old, pbuf, sizeof old);
    CHECK_MSG(!(old.in_focus_threshold_px >= 0.0f && old.in_focus_threshold_px <= 1.0f),
              "the garbage must not itself be a plausible threshold");
    for (int layered = 0; layered < 2; layered++) {
        fill_const(out, n, -7.0f);
        CHECK_EQ_INT(layered ? layers(&old, color, coc, NULL, out, CH, &st)
                             : single(&old, color, coc, out, CH, &st),
                     DDOF_OK);
        check_copy(layered ? "v0.4 params, layers" : "v0.4 params, single", &st, out, below);
    }
}

/* Uniform blur, no in-focus pixel: the midground only; equal to ddof_diffuse. */
static void test_uniform_blur(void)
{
    texture(color, CH, 2);
    fill_const(coc, npx, 10.0f);
    ddof_params p;
    heat_params_init(&p);
    ddof_stats st, st1;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, &st), DDOF_OK);
    dump_plan("uniform", &st);
    CHECK_MSG(st.effects == DDOF_EFFECT_MIDGROUND, "uniform blur: effects 0x%x, want 0x%x",
              st.effects, DDOF_EFFECT_MIDGROUND);
    CHECK_EQ_INT(st.copied_only, 0);
    CHECK(st.lines_solved >= (uint64_t)W + H);
    CHECK_MSG(plan_well_formed(&st), "uniform: plan \"%.*s\"", 511, st.plan);
    CHECK_MSG(plan_says(&st, "background", "off"), "uniform: plan \"%.*s\"", 511, st.plan);
    CHECK_MSG(plan_has_near_or_foreground(&st), "uniform: no near/foreground line in \"%.*s\"",
              511, st.plan);
    check_timings("uniform", &st, 0, 0);

    CHECK_EQ_INT(single(&p, color, coc, out2, CH, &st1), DDOF_OK);
    double d = max_abs_diff_ff(out, out2, n);
    CHECK_MSG(d <= 1e-6, "uniform: layered vs ddof_diffuse differ by %g", d);
    CHECK_EQ_INT(st.lines_solved, st1.lines_solved);
    CHECK_MSG(st1.effects == DDOF_EFFECT_MIDGROUND, "ddof_diffuse effects 0x%x", st1.effects);

    /* Signed CoC with nothing near: the same. */
    p.coc_signed = 1;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out2, CH, &st), DDOF_OK);
    CHECK_MSG(st.effects == DDOF_EFFECT_MIDGROUND, "uniform signed: effects 0x%x", st.effects);
    CHECK(max_abs_diff_ff(out, out2, n) <= 1e-6);
}

/* Half the image sharp (top), the other half mildly blurred (CoC 6 < threshold 8): the sharp
 * rows are skipped, the background layer is not called for. */
static void test_half_sharp(void)
{
    texture(color, CH, 3);
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++)
            coc[(size_t)y * W + x] = y < H / 2 ? 0.0f : 6.0f;
    ddof_params p;
    heat_params_init(&p);
    p.highlights = DDOF_LAYER_OFF; /* the texture is above the highlight threshold */
    ddof_stats st;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, &st), DDOF_OK);
    dump_plan("half sharp", &st);
    CHECK_MSG(st.effects == DDOF_EFFECT_MIDGROUND, "half sharp: effects 0x%x", st.effects);
    CHECK_MSG(st.lines_skipped >= H / 2, "half sharp: %llu lines skipped, want >= %u",
              (unsigned long long)st.lines_skipped, H / 2);
    CHECK(!memcmp(out, color, (size_t)(H / 2) * W * CH * sizeof(float)));
    check_timings("half sharp", &st, 0, 0);
}

/* Thin sharp bars over a blurred background: the background layer, nothing else. */
static void test_bars(void)
{
    texture(color, CH, 4);
    bars_coc(coc);
    ddof_params p;
    heat_params_init(&p);
    ddof_stats st_auto, st_off, st_on, st2;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, &st_auto), DDOF_OK);
    dump_plan("bars auto", &st_auto);
    CHECK_MSG(st_auto.effects == (DDOF_EFFECT_MIDGROUND | DDOF_EFFECT_BACKGROUND),
              "bars: effects 0x%x, want midground + background", st_auto.effects);
    CHECK_MSG(plan_well_formed(&st_auto), "bars: plan \"%.*s\"", 511, st_auto.plan);
    CHECK_MSG(plan_says(&st_auto, "background", "on"), "bars: plan \"%.*s\"", 511, st_auto.plan);
    CHECK_MSG(plan_has_near_or_foreground(&st_auto), "bars: no near line in \"%.*s\"", 511,
              st_auto.plan);
    check_timings("bars auto", &st_auto, 1, 0);

    /* Signed CoC, nothing near: still only the background. */
    p.coc_signed = 1;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out2, CH, &st2), DDOF_OK);
    CHECK_MSG(st2.effects == (DDOF_EFFECT_MIDGROUND | DDOF_EFFECT_BACKGROUND),
              "bars signed: effects 0x%x", st2.effects);
    CHECK(max_abs_diff_ff(out, out2, n) <= 1e-6);
    p.coc_signed = 0;

    /* Forced on: the same as AUTO here. */
    p.background = DDOF_LAYER_ON;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out2, CH, &st_on), DDOF_OK);
    CHECK(st_on.effects & DDOF_EFFECT_BACKGROUND);
    CHECK(max_abs_diff_ff(out, out2, n) <= 1e-6);

    /* Forced off: skipped, says so, and the result is the single-layer diffusion. */
    p.background = DDOF_LAYER_OFF;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, &st_off), DDOF_OK);
    dump_plan("bars off", &st_off);
    CHECK_MSG(st_off.effects == DDOF_EFFECT_MIDGROUND, "bars, background off: effects 0x%x",
              st_off.effects);
    CHECK_MSG(plan_says(&st_off, "background", "off"), "bars off: plan \"%.*s\"", 511,
              st_off.plan);
    check_timings("bars off", &st_off, 0, 0);
    CHECK_EQ_INT(single(&p, color, coc, out2, CH, NULL), DDOF_OK);
    double d = max_abs_diff_ff(out, out2, n);
    CHECK_MSG(d <= 1e-6, "bars, background off vs ddof_diffuse: %g", d);

    /* The background layer solves at least one more row and column pass (CoC fill + colour). */
    CHECK_MSG(st_auto.lines_solved >= st_off.lines_solved + W + H,
              "bars: %llu lines with background, %llu without",
              (unsigned long long)st_auto.lines_solved, (unsigned long long)st_off.lines_solved);

    /* A second level (threshold 16 <= CoC 20) solves more lines still. */
    p.background = DDOF_LAYER_AUTO;
    p.background_levels = 2;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out2, CH, &st2), DDOF_OK);
    CHECK(st2.effects == (DDOF_EFFECT_MIDGROUND | DDOF_EFFECT_BACKGROUND));
    CHECK_MSG(st2.lines_solved > st_auto.lines_solved, "bars: 2 levels %llu lines, 1 level %llu",
              (unsigned long long)st2.lines_solved, (unsigned long long)st_auto.lines_solved);

    /* A higher threshold (25 > every CoC) leaves nothing to put underneath. */
    p.background_levels = 1;
    p.background_threshold_px = 25.0f;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out2, CH, &st2), DDOF_OK);
    dump_plan("bars threshold 25", &st2);
    CHECK_MSG(st2.effects == DDOF_EFFECT_MIDGROUND, "bars, threshold 25: effects 0x%x",
              st2.effects);
}

/* Forcing the background on where AUTO would not run it. */
static void test_force_background_on(void)
{
    texture(color, CH, 5);
    fill_const(coc, npx, 10.0f);
    ddof_params p;
    heat_params_init(&p);
    p.background = DDOF_LAYER_ON;
    ddof_stats st;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, &st), DDOF_OK);
    dump_plan("uniform, background on", &st);
    CHECK_MSG(st.effects == (DDOF_EFFECT_MIDGROUND | DDOF_EFFECT_BACKGROUND),
              "uniform, background forced on: effects 0x%x", st.effects);
    size_t len = 0;
    const char *line = plan_line(&st, "background", &len);
    CHECK_MSG(line && has_token(line, len, "on"), "plan \"%.*s\"", 511, st.plan);
    CHECK_MSG(line && (ci_find(line, len, "forc") || ci_find(line, len, "param") ||
                       ci_find(line, len, "request") || ci_find(line, len, "caller")),
              "forced background: the line does not say it was forced: \"%.*s\"", (int)len,
              line ? line : "");
    check_timings("uniform, background on", &st, 1, 0);
    /* Every pixel is wholly background (matte 1 at CoC 10 >= 8): finite, within the input. */
    int ok = 1;
    for (size_t i = 0; i < n; i++)
        if (!(out[i] >= 0.1f - 1e-5f && out[i] <= 1.0f + 1e-5f))
            ok = 0;
    CHECK(ok);
}

/* A near blurred object over an in-focus background: the near spread, nothing else. With the
 * object as a separate foreground element instead: the foreground, not the near spread. */
static void test_near(void)
{
    texture(color, CH, 6);
    disc_coc(coc, -20.0f, 0.0f);
    ddof_params p;
    heat_params_init(&p);
    p.highlights = DDOF_LAYER_OFF; /* the texture is above the highlight threshold */
    p.coc_signed = 1;
    p.near_layer = DDOF_LAYER_OFF; /* the near spread's plan (the near layer's: below) */
    ddof_stats st, st_off;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, &st), DDOF_OK);
    dump_plan("near auto", &st);
    CHECK_MSG(st.effects == (DDOF_EFFECT_MIDGROUND | DDOF_EFFECT_NEAR_SPREAD),
              "near object: effects 0x%x, want midground + near spread", st.effects);
    CHECK_MSG(plan_says(&st, "near spread", "on"), "near: plan \"%.*s\"", 511, st.plan);
    CHECK_MSG(plan_says(&st, "near layer", "off"), "near: plan \"%.*s\"", 511, st.plan);
    CHECK_MSG(plan_line(&st, "background", &(size_t){0}) != NULL, "near: plan \"%.*s\"", 511,
              st.plan);
    CHECK_NEAR(st.max_coc_px, 20.0, 0);
    check_timings("near auto", &st, 0, 1);

    /* Near spread forced off: skipped, says so; the result is ddof_diffuse of |CoC| (with the
     * background off too, so that this does not depend on how |CoC| counts for it). */
    p.near_spread = DDOF_LAYER_OFF;
    p.background = DDOF_LAYER_OFF;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, &st_off), DDOF_OK);
    dump_plan("near off", &st_off);
    CHECK_MSG(st_off.effects == DDOF_EFFECT_MIDGROUND, "near spread off: effects 0x%x",
              st_off.effects);
    CHECK_MSG(plan_says(&st_off, "near spread", "off"), "near off: plan \"%.*s\"", 511,
              st_off.plan);
    check_timings("near off", &st_off, 0, 0);
    float *abs_coc = alloc_f(npx);
    for (size_t i = 0; i < npx; i++)
        abs_coc[i] = fabsf(coc[i]);
    ddof_params p1;
    heat_params_init(&p1);
    CHECK_EQ_INT(single(&p1, color, abs_coc, out2, CH, NULL), DDOF_OK);
    double d = max_abs_diff_ff(out, out2, n);
    CHECK_MSG(d <= 1e-6, "near spread off vs ddof_diffuse(|CoC|): %g", d);
    CHECK_MSG(st.lines_solved >= st_off.lines_solved, "near: %llu lines with spread, %llu without",
              (unsigned long long)st.lines_solved, (unsigned long long)st_off.lines_solved);

    /* The spread changes the result (it is what gives the silhouette its soft edge). */
    p.near_spread = DDOF_LAYER_AUTO;
    p.background = DDOF_LAYER_AUTO;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, NULL), DDOF_OK);
    d = max_abs_diff_ff(out, out2, n);
    CHECK_MSG(d > 0.05, "near spread on changes the result by only %g", d);

    /* The same object, unsigned (a far object over an in-focus background): the background
     * layer's case, not the near spread. */
    heat_params_init(&p);
    p.highlights = DDOF_LAYER_OFF; /* the texture is above the highlight threshold */
    CHECK_EQ_INT(layers(&p, color, abs_coc, NULL, out, CH, &st), DDOF_OK);
    dump_plan("far disc", &st);
    CHECK_MSG(st.effects == (DDOF_EFFECT_MIDGROUND | DDOF_EFFECT_BACKGROUND),
              "far disc over in-focus: effects 0x%x", st.effects);

    /* A small near CoC (3 < threshold 4): no spread. */
    disc_coc(coc, -3.0f, 0.0f);
    heat_params_init(&p);
    p.coc_signed = 1;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, &st), DDOF_OK);
    dump_plan("near small", &st);
    CHECK_MSG(st.effects == DDOF_EFFECT_MIDGROUND, "near CoC 3: effects 0x%x", st.effects);

    /* Near spread forced on in a scene with nothing near: it runs. */
    fill_const(coc, npx, 10.0f);
    p.near_spread = DDOF_LAYER_ON;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, &st), DDOF_OK);
    dump_plan("near forced on", &st);
    CHECK_MSG(st.effects == (DDOF_EFFECT_MIDGROUND | DDOF_EFFECT_NEAR_SPREAD),
              "near spread forced on: effects 0x%x", st.effects);
    CHECK_MSG(plan_says(&st, "near spread", "on"), "near forced: plan \"%.*s\"", 511, st.plan);
    free(abs_coc);
}

/* The near layer: AUTO runs it for a blurred near silhouette (and then the element path, not
 * the spread), with its own plan line and time; forced on it runs on a frame with nothing near
 * (an empty element: no foreground), forced off it says so. */
static void test_near_layer(void)
{
    texture(color, CH, 6);
    disc_coc(coc, -20.0f, 0.0f);
    ddof_params p;
    heat_params_init(&p);
    p.highlights = DDOF_LAYER_OFF;
    p.coc_signed = 1;
    ddof_stats st;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, &st), DDOF_OK);
    dump_plan("near layer auto", &st);
    CHECK_MSG(st.effects ==
                  (DDOF_EFFECT_MIDGROUND | DDOF_EFFECT_NEAR_LAYER | DDOF_EFFECT_FOREGROUND),
              "near layer: effects 0x%x", st.effects);
    CHECK_MSG(plan_says(&st, "near layer", "on") && plan_says(&st, "foreground", "on") &&
                  plan_says(&st, "near spread", "off"),
              "near layer: plan \"%.*s\"", 511, st.plan);
    CHECK_MSG(st.seconds_near_layer > 0 && st.seconds_near_layer <= st.seconds_total,
              "near layer: %g s of %g", st.seconds_near_layer, st.seconds_total);
    check_timings("near layer auto", &st, 0, 1);
    CHECK(plan_well_formed(&st));

    /* A threshold above every near CoC: AUTO finds no silhouette to split. */
    p.near_layer_threshold_px = 25.0f;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, &st), DDOF_OK);
    CHECK_MSG(!(st.effects & DDOF_EFFECT_NEAR_LAYER) && plan_says(&st, "near layer", "off") &&
                  plan_says(&st, "near spread", "on"),
              "near layer threshold 25: effects 0x%x, plan \"%.*s\"", st.effects, 511, st.plan);
    CHECK(st.seconds_near_layer == 0.0);
    p.near_layer_threshold_px = 8.0f;

    /* Forced on with nothing near: it looks, finds no element, the midground alone runs. */
    fill_const(coc, npx, 10.0f);
    p.near_layer = DDOF_LAYER_ON;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, &st), DDOF_OK);
    dump_plan("near layer forced on, nothing near", &st);
    CHECK_MSG(st.effects == (DDOF_EFFECT_MIDGROUND | DDOF_EFFECT_NEAR_LAYER),
              "near layer forced on, nothing near: effects 0x%x", st.effects);
    float *plain = alloc_f(n);
    ddof_params p1;
    heat_params_init(&p1);
    CHECK_EQ_INT(single(&p1, color, coc, plain, CH, NULL), DDOF_OK);
    CHECK_MSG(max_abs_diff_ff(out, plain, n) == 0.0, "empty near layer changes the result by %g",
              max_abs_diff_ff(out, plain, n));
    free(plain);

    /* Forced off: said. */
    disc_coc(coc, -20.0f, 0.0f);
    p.near_layer = DDOF_LAYER_OFF;
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out, CH, &st), DDOF_OK);
    CHECK_MSG(plan_says(&st, "near layer", "forced") && !(st.effects & DDOF_EFFECT_NEAR_LAYER),
              "near layer off: plan \"%.*s\"", 511, st.plan);
}

static void test_foreground(void)
{
    texture(color, CH, 7);
    disc_foreground(fg_color, fg_coc);
    ddof_foreground fg = make_fg(fg_color, fg_coc, 1);
    ddof_params p;
    heat_params_init(&p);
    p.coc_signed = 1;
    ddof_stats st, st_none;

    /* Sharp main image + the object as a foreground element. */
    fill_const(coc, npx, 0.0f);
    CHECK_EQ_INT(layers(&p, color, coc, &fg, out, CH, &st), DDOF_OK);
    dump_plan("foreground, sharp main", &st);
    CHECK_MSG((st.effects & ~DDOF_EFFECT_MIDGROUND) == DDOF_EFFECT_FOREGROUND,
              "foreground over a sharp image: effects 0x%x", st.effects);
    CHECK_EQ_INT(st.copied_only, 0);
    CHECK(st.lines_solved >= (uint64_t)W + H);
    CHECK_MSG(plan_says(&st, "foreground", "on"), "foreground: plan \"%.*s\"", 511, st.plan);
    {
        size_t len;
        const char *line = plan_line(&st, "near", &len);
        if (line)
            CHECK_MSG(has_token(line, len, "off"), "foreground given, near line \"%.*s\"",
                      (int)len, line);
    }
    check_timings("foreground, sharp main", &st, 0, 1);
    /* The element shows. */
    CHECK(max_abs_diff_ff(out, color, n) > 0.1);

    /* The same scene without the element: nothing to do. */
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out2, CH, &st_none), DDOF_OK);
    CHECK(st_none.effects == 0 && st_none.lines_solved == 0);
    CHECK_MSG(st.lines_solved > st_none.lines_solved, "foreground adds no lines");

    /* Uniformly (mildly) blurred main image + foreground: midground + foreground exactly. */
    fill_const(coc, npx, 6.0f);
    CHECK_EQ_INT(layers(&p, color, coc, &fg, out, CH, &st), DDOF_OK);
    dump_plan("foreground, blurred main", &st);
    CHECK_MSG(st.effects == (DDOF_EFFECT_MIDGROUND | DDOF_EFFECT_FOREGROUND),
              "foreground over a blurred image: effects 0x%x", st.effects);
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out2, CH, &st_none), DDOF_OK);
    CHECK_MSG(st.lines_solved >= st_none.lines_solved + W + H,
              "foreground: %llu lines, without %llu", (unsigned long long)st.lines_solved,
              (unsigned long long)st_none.lines_solved);

    /* The near object also in the main image's signed CoC, and the element given: the element
     * is used, the near spread is not (it needs no foreground element). */
    disc_coc(coc, -20.0f, 0.0f);
    CHECK_EQ_INT(layers(&p, color, coc, &fg, out, CH, &st), DDOF_OK);
    dump_plan("foreground + near CoC", &st);
    CHECK(st.effects & DDOF_EFFECT_FOREGROUND);
    CHECK_MSG(!(st.effects & DDOF_EFFECT_NEAR_SPREAD),
              "foreground given but near spread ran: effects 0x%x", st.effects);
}

/* Older callers: a v0.1 ddof_params gets the layer defaults, a v0.1 ddof_stats is not written
 * past its size. */
static void test_old_structs(void)
{
    texture(color, CH, 8);
    bars_coc(coc);
    ddof_params p;
    ddof_params_init(&p); /* the whole default, disc kernel included */
    CHECK_EQ_INT(layers(&p, color, coc, NULL, out2, CH, NULL), DDOF_OK);

    unsigned char pbuf[sizeof(ddof_params)];
    memset(pbuf, 0xA7, sizeof pbuf); /* garbage in the fields an old caller does not have */
    memcpy(pbuf, &p, offsetof(ddof_params, coc_signed));
    ((ddof_params *)(void *)pbuf)->struct_size = (uint32_t)offsetof(ddof_params, coc_signed);
    ddof_params old;
    memcpy(&old, pbuf, sizeof old);
    CHECK_EQ_INT(layers(&old, color, coc, NULL, out, CH, NULL), DDOF_OK);
    double d = max_abs_diff_ff(out, out2, n);
    CHECK_MSG(d <= 1e-6, "v0.1 params: result differs from the defaults by %g", d);

    /* ddof_diffuse with v0.1 params works as before. */
    CHECK_EQ_INT(single(&old, color, coc, out, CH, NULL), DDOF_OK);

    unsigned char sbuf[sizeof(ddof_stats)];
    memset(sbuf, 0xC3, sizeof sbuf);
    const size_t old_size = offsetof(ddof_stats, effects);
    ddof_stats *st = (ddof_stats *)(void *)sbuf;
    st->struct_size = (uint32_t)old_size;
    ddof_image_in ci = {color, W, H, CH, 0};
    ddof_image_in zi = {coc, W, H, 1, 0};
    ddof_image oi = {out, W, H, CH, 0};
    CHECK_EQ_INT(ddof_diffuse_layers(ctx, &p, &ci, &zi, NULL, &oi, st), DDOF_OK);
    size_t changed = 0;
    for (size_t i = old_size; i < sizeof sbuf; i++)
        if (sbuf[i] != 0xC3)
            changed++;
    CHECK_MSG(changed == 0, "v0.1 stats: %zu bytes past struct_size written", changed);
    CHECK_EQ_INT(st->struct_size, old_size);
    CHECK(st->lines_solved > 0);
}

int main(void)
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

    test_defaults();
    test_all_sharp();
    test_in_focus_threshold();
    test_uniform_blur();
    test_half_sharp();
    test_bars();
    test_force_background_on();
    test_near();
    test_near_layer();
    test_foreground();
    test_old_structs();

    free(color);
    free(coc);
    free(out);
    free(out2);
    free(fg_color);
    free(fg_coc);
    ddof_context_free(ctx);
    return test_report("test_planner");
}
