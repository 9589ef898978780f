/* SPDX-License-Identifier: MIT */
/* test_bad_input.c - every bad input gets its documented status, leaves the output bitwise
 * untouched (ddof.h: "every check runs before the first output pixel is written") and leaves a
 * message in ddof_context_last_error(); a success clears it to "".
 *
 * Readings of the header where it does not name one code (accepted alternatives noted inline):
 *  - the CoC is read from the first channel of a 1..4-channel image; the other channels are not
 *    read, so NaN there is no error;
 *  - camera depth_unit_m <= 0 and out-of-range camera enums: BAD_CAMERA or BAD_PARAMETER;
 *  - curve out of order / blur out of range: BAD_PARAMETER ("a value is out of range");
 *  - CoC -0.0 is not negative (it compares equal to 0): accepted. */
#include "ddof.h"
#include "test_util.h"
#include "test_images.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stddef.h>
#include <string.h>

#define W 40u
#define H 30u
#define CH 4u
#define BUF_FLOATS (W * H * CH * 2 + 64) /* big enough for every description used below */

static ddof_context *ctx;
static float color_buf[BUF_FLOATS], coc_buf[BUF_FLOATS], out_buf[BUF_FLOATS];
static float sentinel_buf[BUF_FLOATS];
static ddof_params good_params;

static void fill_sentinel(void)
{
    const uint32_t bits = 0x7FC0DEADu; /* a NaN payload nothing computes by accident */
    for (size_t i = 0; i < BUF_FLOATS; i++)
        memcpy(&sentinel_buf[i], &bits, 4);
    memcpy(out_buf, sentinel_buf, sizeof out_buf);
}

static int out_untouched(void) { return !memcmp(out_buf, sentinel_buf, sizeof out_buf); }

static void reset_inputs(void)
{
    test_rng rng = {12345};
    for (size_t i = 0; i < BUF_FLOATS; i++) {
        color_buf[i] = (float)test_uniform(&rng);
        coc_buf[i] = (float)(10.0 * test_uniform(&rng));
    }
}

/* One ddof_diffuse call, described field by field so each case changes one thing. */
typedef struct call {
    ddof_context *ctx;
    const ddof_params *params;
    ddof_image_in color, coc;
    ddof_image out;
    int null_color, null_coc, null_out;
} call;

static call good_call(void)
{
    call c;
    memset(&c, 0, sizeof c);
    c.ctx = ctx;
    c.params = &good_params;
    c.color = (ddof_image_in){color_buf, W, H, CH, 0};
    c.coc = (ddof_image_in){coc_buf, W, H, 1, 0};
    c.out = (ddof_image){out_buf, W, H, CH, 0};
    return c;
}

static ddof_status run_call(const call *c)
{
    return ddof_diffuse(c->ctx, c->params, c->null_color ? NULL : &c->color,
                        c->null_coc ? NULL : &c->coc, c->null_out ? NULL : &c->out, NULL);
}

/* A successful call first (on its own clean images), so the message checked afterwards is the
 * failure's own. */
static void clear_error_by_success(void)
{
    static float color[8 * 4], coc[8], out[8 * 4];
    for (int i = 0; i < 8; i++)
        coc[i] = (float)i;
    ddof_image_in ci = {color, 4, 2, 4, 0}, zi = {coc, 4, 2, 1, 0};
    ddof_image oi = {out, 4, 2, 4, 0};
    ddof_status s = ddof_diffuse(ctx, &good_params, &ci, &zi, &oi, NULL);
    CHECK_MSG(s == DDOF_OK, "the good call failed: %d (%s)", (int)s, ddof_context_last_error(ctx));
    CHECK_MSG(ddof_context_last_error(ctx)[0] == '\0', "last error after a success: \"%s\"",
              ddof_context_last_error(ctx));
}

static void check_failure(const char *what, ddof_status got, ddof_status want, ddof_status alt)
{
    CHECK_MSG(got == want || got == alt, "%s: status %d (%s), expected %d", what, (int)got,
              ddof_status_string(got), (int)want);
    CHECK_MSG(out_untouched(), "%s: the output was written", what);
    const char *msg = ddof_context_last_error(ctx);
    CHECK_MSG(msg && msg[0], "%s: no last-error message", what);
}

static void expect2(const char *what, const call *c, ddof_status want, ddof_status alt)
{
    clear_error_by_success();
    fill_sentinel();
    ddof_status s = run_call(c);
    check_failure(what, s, want, alt);
}

static void expect(const char *what, const call *c, ddof_status want)
{
    expect2(what, c, want, want);
}

/* The good call with one thing changed by `stmt` (which edits the call `c`) must fail with
 * `want`: one line a case, so the table of cases reads as the list of defects. */
#define BAD_CALL(what, stmt, want)                                                             \
    do {                                                                                       \
        call c = good_call();                                                                  \
        stmt;                                                                                  \
        expect(what, &c, want);                                                                \
    } while (0)

static void test_status_strings(void)
{
    for (int a = 0; a < DDOF_STATUS_COUNT_; a++) {
        const char *sa = ddof_status_string((ddof_status)a);
        CHECK_MSG(sa && sa[0], "status %d has no string", a);
        for (int b = 0; b < a; b++)
            CHECK_MSG(!sa || strcmp(sa, ddof_status_string((ddof_status)b)),
                      "status %d and %d share \"%s\"", a, b, sa);
    }
    CHECK(ddof_status_string(DDOF_STATUS_COUNT_) != NULL);
    CHECK(ddof_status_string((ddof_status)999) != NULL);
    CHECK(ddof_status_string((ddof_status)-1) != NULL);

    const char *names[] = {"thomas", "cr", "pcr", "jacobi", "reference", "gruen"};
    for (int i = 0; i < DDOF_SOLVER_COUNT_; i++) {
        const char *n = ddof_solver_name((ddof_solver)i);
        CHECK_MSG(n && !strcmp(n, names[i]), "solver %d name \"%s\"", i, n ? n : "(null)");
    }
    CHECK(ddof_solver_name(DDOF_SOLVER_COUNT_) == NULL);
    CHECK(ddof_solver_name((ddof_solver)-1) == NULL);

    CHECK_EQ_INT(ddof_version_number(), DDOF_VERSION_NUMBER);
    char expected_version[32];
    snprintf(expected_version, sizeof expected_version, "%d.%d.%d", DDOF_VERSION_MAJOR,
             DDOF_VERSION_MINOR, DDOF_VERSION_PATCH);
    CHECK(ddof_version_string() && !strcmp(ddof_version_string(), expected_version));
}

static void test_context(void)
{
    ddof_context_free(NULL); /* must be a no-op */
    CHECK(ddof_context_last_error(NULL) != NULL);

    ddof_context *c = NULL;
    CHECK_EQ_INT(ddof_context_create(NULL, &c), DDOF_OK); /* NULL options: defaults */
    CHECK(c != NULL);
    CHECK(c && ddof_context_thread_count(c) >= 1);
    CHECK(c && ddof_context_last_error(c) && ddof_context_last_error(c)[0] == '\0');
    ddof_context_free(c);

    ddof_context_options o;
    ddof_context_options_init(&o);
    CHECK_EQ_INT(o.struct_size, sizeof o);
    CHECK_EQ_INT(ddof_context_create(&o, NULL), DDOF_ERROR_NULL_POINTER);
    o.struct_size = 0;
    c = (ddof_context *)&o; /* a value the call must not leave as a context */
    CHECK_EQ_INT(ddof_context_create(&o, &c), DDOF_ERROR_BAD_PARAMETER);
    CHECK(c == NULL || c == (ddof_context *)&o);
}

static void test_null_pointers(void)
{
    /* No context: no message to check, only the status and the output. */
    {
        call c = good_call();
        c.ctx = NULL;
        fill_sentinel();
        ddof_status s = run_call(&c);
        CHECK_EQ_INT(s, DDOF_ERROR_NULL_POINTER);
        CHECK(out_untouched());
    }
    BAD_CALL("params NULL", c.params = NULL, DDOF_ERROR_NULL_POINTER);
    BAD_CALL("color NULL", c.null_color = 1, DDOF_ERROR_NULL_POINTER);
    BAD_CALL("coc NULL", c.null_coc = 1, DDOF_ERROR_NULL_POINTER);
    BAD_CALL("out NULL", c.null_out = 1, DDOF_ERROR_NULL_POINTER);
    BAD_CALL("color pixels NULL", c.color.pixels = NULL, DDOF_ERROR_NULL_POINTER);
    BAD_CALL("coc pixels NULL", c.coc.pixels = NULL, DDOF_ERROR_NULL_POINTER);
    /* No output pixels: nothing to check for writes, only the status and the message. */
    {
        call c = good_call();
        c.out.pixels = NULL;
        fill_sentinel();
        clear_error_by_success();
        CHECK_EQ_INT(run_call(&c), DDOF_ERROR_NULL_POINTER);
        CHECK(ddof_context_last_error(ctx)[0] != '\0');
    }
}

/* Sizes: all three images agree, so the size itself is the only defect. The buffers are far
 * too small for the claimed sizes: the check must come before any pixel is read. */
static void set_size(call *c, uint32_t w, uint32_t h)
{
    c->color.width = c->coc.width = c->out.width = w;
    c->color.height = c->coc.height = c->out.height = h;
}

static void test_sizes(void)
{
    static const struct {
        const char *what;
        uint32_t w, h;
    } sizes[] = {
        {"width 0", 0, H},
        {"height 0", W, 0},
        {"width > max", DDOF_MAX_DIMENSION + 1, 1},
        {"height > max", 1, DDOF_MAX_DIMENSION + 1},
        {"width * height > max pixels", DDOF_MAX_DIMENSION,
         DDOF_MAX_PIXELS / DDOF_MAX_DIMENSION + 1},
        {"width, height UINT32_MAX", UINT32_MAX, UINT32_MAX},
    };
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++)
        BAD_CALL(sizes[i].what, set_size(&c, sizes[i].w, sizes[i].h), DDOF_ERROR_BAD_SIZE);

    BAD_CALL("channels 0", c.color.channels = c.out.channels = 0, DDOF_ERROR_BAD_CHANNELS);
    BAD_CALL("channels 5", c.color.channels = c.out.channels = 5, DDOF_ERROR_BAD_CHANNELS);
    BAD_CALL("coc channels 0", c.coc.channels = 0, DDOF_ERROR_BAD_CHANNELS);
    BAD_CALL("coc channels 5", c.coc.channels = 5, DDOF_ERROR_BAD_CHANNELS);

    BAD_CALL("coc narrower", c.coc.width = W - 1, DDOF_ERROR_SIZE_MISMATCH);
    BAD_CALL("coc taller", c.coc.height = H + 1, DDOF_ERROR_SIZE_MISMATCH);
    BAD_CALL("out wider", c.out.width = W + 1, DDOF_ERROR_SIZE_MISMATCH);
    BAD_CALL("out shorter", c.out.height = H - 1, DDOF_ERROR_SIZE_MISMATCH);
    BAD_CALL("out 3 channels, colour 4", c.out.channels = 3, DDOF_ERROR_SIZE_MISMATCH);
    BAD_CALL("colour 1 channel, out 4", c.color.channels = 1, DDOF_ERROR_SIZE_MISMATCH);
}

static void test_strides(void)
{
    const size_t row = W * CH * sizeof(float), crow = W * sizeof(float);
    const size_t huge = (SIZE_MAX / 2 + 1); /* 2^63 on 64-bit: a multiple of 4 */
    for (int which = 0; which < 3; which++) {
        const char *names[] = {"colour", "coc", "out"};
        size_t r = which == 1 ? crow : row;
        const size_t strides[] = {r - 4, 4, r + 2, r + 1, huge, SIZE_MAX - 3};
        const char *what[] = {"stride one float short", "stride 4", "stride +2 bytes",
                              "stride +1 byte", "stride 2^63 x 3 rows overflows",
                              "stride SIZE_MAX-3 overflows"};
        for (int i = 0; i < 6; i++) {
            call c = good_call();
            if (i >= 4)
                set_size(&c, W, 3);
            size_t *s = which == 0 ? &c.color.row_stride
                        : which == 1 ? &c.coc.row_stride
                                     : &c.out.row_stride;
            *s = strides[i];
            char msg[96];
            snprintf(msg, sizeof msg, "%s %s", names[which], what[i]);
            expect(msg, &c, DDOF_ERROR_BAD_STRIDE);
        }
    }
    /* A valid padded stride is fine (and stride == row is fine). */
    call c = good_call();
    c.color.row_stride = row;
    c.coc.row_stride = crow + 16;
    c.out.row_stride = row;
    clear_error_by_success();
    CHECK_EQ_INT(run_call(&c), DDOF_OK);
}

/* The good call over inputs with a bad value planted (by the caller) at (27, 13) and at a later
 * pixel: `want`, and the message names the first bad pixel. */
static void expect_bad_pixel(const char *what, ddof_status want)
{
    call c = good_call();
    expect(what, &c, want);
    const char *msg = ddof_context_last_error(ctx);
    CHECK_MSG(strstr(msg, "27") && strstr(msg, "13"),
              "%s: message does not name the first bad pixel (27, 13): \"%s\"", what, msg);
}

static void test_bad_values(void)
{
    static const struct { uint32_t x, y; } at = {27, 13}, later = {30, 20};
    const float bad_color[] = {NAN, INFINITY, -INFINITY};
    const char *names[] = {"NaN", "+inf", "-inf"};
    for (int i = 0; i < 3; i++) {
        reset_inputs();
        color_buf[(at.y * W + at.x) * CH + 2] = bad_color[i];
        color_buf[(later.y * W + later.x) * CH + 0] = bad_color[i];
        char what[64];
        snprintf(what, sizeof what, "colour %s", names[i]);
        expect_bad_pixel(what, DDOF_ERROR_BAD_COLOR);
        /* In place, the colour (= output) buffer is untouched as well. */
        float saved[W * H * CH];
        memcpy(saved, color_buf, sizeof saved);
        call c = good_call();
        c.out.pixels = color_buf;
        CHECK_EQ_INT(run_call(&c), DDOF_ERROR_BAD_COLOR);
        CHECK(!memcmp(saved, color_buf, sizeof saved));
    }
    /* NaN in the padding of a strided colour image is not a pixel: accepted. */
    reset_inputs();
    {
        call c = good_call();
        c.color.row_stride = W * CH * sizeof(float) + 8;
        for (uint32_t y = 0; y < H; y++) {
            color_buf[y * (W * CH + 2) + W * CH] = NAN;
            color_buf[y * (W * CH + 2) + W * CH + 1] = INFINITY;
        }
        clear_error_by_success();
        ddof_status s = run_call(&c);
        CHECK_MSG(s == DDOF_OK, "NaN in the colour padding rejected: %d (%s)", (int)s,
                  ddof_context_last_error(ctx));
    }

    /* A 2- or 4-channel CoC image: only the first channel counts (NaN in the others is never
     * read), the result equals that of the 1-channel CoC bitwise. */
    reset_inputs();
    {
        static float ref[W * H * CH], coc_multi[W * H * 4];
        call c = good_call();
        CHECK_EQ_INT(run_call(&c), DDOF_OK);
        memcpy(ref, out_buf, sizeof ref);
        for (uint32_t cc = 2; cc <= 4; cc += 2) {
            for (size_t i = 0; i < W * H; i++) {
                coc_multi[i * cc] = coc_buf[i];
                for (uint32_t k = 1; k < cc; k++)
                    coc_multi[i * cc + k] = NAN;
            }
            c.coc = (ddof_image_in){coc_multi, W, H, cc, 0};
            fill_sentinel();
            ddof_status s = run_call(&c);
            CHECK_MSG(s == DDOF_OK, "%u-channel CoC: %d (%s)", cc, (int)s,
                      ddof_context_last_error(ctx));
            CHECK_MSG(!memcmp(ref, out_buf, sizeof ref),
                      "%u-channel CoC gives another result than its first channel alone", cc);
        }
    }

    const float bad_coc[] = {NAN, -1.0f, -FLT_MIN, INFINITY, -INFINITY,
                             nextafterf(DDOF_MAX_COC_PX, INFINITY), 2 * DDOF_MAX_COC_PX};
    const char *coc_names[] = {"NaN", "-1", "-FLT_MIN", "+inf", "-inf", "just above max",
                               "2x max"};
    for (int i = 0; i < 7; i++) {
        reset_inputs();
        coc_buf[at.y * W + at.x] = bad_coc[i];
        coc_buf[later.y * W + later.x] = bad_coc[i];
        char what[64];
        snprintf(what, sizeof what, "CoC %s", coc_names[i]);
        expect_bad_pixel(what, DDOF_ERROR_BAD_COC);
    }
    /* Edge values that are valid: exactly the maximum, 0 and -0. */
    const float ok_coc[] = {DDOF_MAX_COC_PX, 0.0f, -0.0f};
    for (int i = 0; i < 3; i++) {
        reset_inputs();
        coc_buf[at.y * W + at.x] = ok_coc[i];
        call c = good_call();
        ddof_status s = run_call(&c);
        CHECK_MSG(s == DDOF_OK, "CoC %g rejected: %d (%s)", (double)ok_coc[i], (int)s,
                  ddof_context_last_error(ctx));
    }
    reset_inputs();
}

static void test_params(void)
{
    ddof_params p;
    ddof_params_init(&p);
    CHECK_EQ_INT(p.struct_size, sizeof p);
    /* The measured default preset (docs/accuracy.md): the diffusion, with the solver, sub-steps
     * and k the study chose among those it sweeps (test_presets runs it on the CPU). */
    CHECK_EQ_INT(p.method, DDOF_METHOD_DIFFUSION);
    CHECK(p.solver != DDOF_SOLVER_GRUEN);
    CHECK(p.substeps >= 1 && p.substeps <= 8);
    CHECK(p.beta_scale >= DDOF_MOMENT_BETA_SCALE / 4 && p.beta_scale <= DDOF_MOMENT_BETA_SCALE * 4);
    CHECK(p.pixel_aspect == 1.0f);
    CHECK_EQ_INT(p.jacobi_iterations, 50);
    CHECK(p.progress == NULL);

    call c = good_call();
    c.params = &p;
#define BAD_PARAM(what, stmt)                                                                  \
    do {                                                                                       \
        ddof_params_init(&p);                                                                  \
        stmt;                                                                                  \
        expect(what, &c, DDOF_ERROR_BAD_PARAMETER);                                            \
    } while (0)
    BAD_PARAM("params struct_size 0", p.struct_size = 0);
    BAD_PARAM("params struct_size 4", p.struct_size = 4);
    /* Smaller than the first version of the struct (0.1 ended before coc_signed). */
    BAD_PARAM("params struct_size below version 0.1",
              p.struct_size = offsetof(ddof_params, coc_signed) - 1);
    BAD_PARAM("solver COUNT_", p.solver = DDOF_SOLVER_COUNT_);
    BAD_PARAM("solver -1", p.solver = (ddof_solver)-1);
    BAD_PARAM("substeps 0", p.substeps = 0);
    BAD_PARAM("beta_scale 0", p.beta_scale = 0.0f);
    BAD_PARAM("beta_scale -1", p.beta_scale = -1.0f);
    BAD_PARAM("beta_scale NaN", p.beta_scale = NAN);
    BAD_PARAM("beta_scale inf", p.beta_scale = INFINITY);
    BAD_PARAM("pixel_aspect 0", p.pixel_aspect = 0.0f);
    BAD_PARAM("pixel_aspect -1", p.pixel_aspect = -1.0f);
    BAD_PARAM("pixel_aspect NaN", p.pixel_aspect = NAN);
    BAD_PARAM("pixel_aspect inf", p.pixel_aspect = INFINITY);
    /* Finite, positive, but out of the documented ranges (issue 14: 1e20 gave NaN, DDOF_OK). */
    BAD_PARAM("pixel_aspect 1e20", p.pixel_aspect = 1e20f);
    BAD_PARAM("pixel_aspect 1e-20", p.pixel_aspect = 1e-20f);
    BAD_PARAM("pixel_aspect just above 100", p.pixel_aspect = nextafterf(100.0f, 200.0f));
    BAD_PARAM("pixel_aspect just below 0.01", p.pixel_aspect = nextafterf(0.01f, 0.0f));
    BAD_PARAM("beta_scale just above 1", p.beta_scale = nextafterf(1.0f, 2.0f));
    BAD_PARAM("beta_scale 1e30", p.beta_scale = 1e30f);
    BAD_PARAM("background_threshold_px above the largest CoC",
              p.background_threshold_px = 2.0f * DDOF_MAX_COC_PX);
    BAD_PARAM("near_spread_threshold_px above the largest CoC",
              p.near_spread_threshold_px = 2.0f * DDOF_MAX_COC_PX);
    BAD_PARAM("jacobi_iterations 0", (p.solver = DDOF_SOLVER_JACOBI, p.jacobi_iterations = 0));
    BAD_PARAM("method 2", p.method = (ddof_method)2);
    BAD_PARAM("precision 2", p.precision = (ddof_precision)2);
#undef BAD_PARAM
    /* The CPU backend has no Gruen solver and no packed half: a clear status, out untouched. */
    ddof_params_init(&p);
    p.solver = DDOF_SOLVER_GRUEN;
    expect("Gruen on the CPU", &c, DDOF_ERROR_UNSUPPORTED);
    ddof_params_init(&p);
    p.precision = DDOF_PRECISION_PACKED_HALF;
    expect("packed half on the CPU", &c, DDOF_ERROR_UNSUPPORTED);
}

/* The messages name the parameter and its range. */
static void expect_param_message(const char *what, ddof_params *p, const char *want)
{
    call c = good_call();
    c.params = p;
    fill_sentinel();
    CHECK_MSG(run_call(&c) == DDOF_ERROR_BAD_PARAMETER, "%s", what);
    CHECK_MSG(strstr(ddof_context_last_error(ctx), want) != NULL, "%s: \"%s\" lacks \"%s\"",
              what, ddof_context_last_error(ctx), want);
}

/* Every CPU solver at the bounds of the ranges (largest beta_scale, smallest and largest pixel
 * aspect, one sub-step, the largest CoC on every pixel or on alternate rows): DDOF_OK and a
 * finite output, so that the ranges are ones where the solvers stay finite. */
static void test_param_bounds(void)
{
    static const ddof_solver solvers[] = {DDOF_SOLVER_THOMAS, DDOF_SOLVER_CYCLIC_REDUCTION,
                                          DDOF_SOLVER_PCR,
                                          DDOF_SOLVER_JACOBI, DDOF_SOLVER_REFERENCE_F64};
    static const float aspects[] = {0.01f, 100.0f};
    static float coc[W * H], out[W * H * CH];
    ddof_params p;
    for (int pattern = 0; pattern < 2; pattern++) {
        for (size_t i = 0; i < W * H; i++)
            coc[i] = pattern == 0 || (i / W) % 2 ? DDOF_MAX_COC_PX : 0.5f;
        for (size_t s = 0; s < sizeof solvers / sizeof solvers[0]; s++) {
            for (size_t a = 0; a < 2; a++) {
                ddof_params_init(&p);
                p.solver = solvers[s];
                p.substeps = 1;
                p.beta_scale = 1.0f;
                p.pixel_aspect = aspects[a];
                p.jacobi_iterations = 50;
                const ddof_image_in ci = {color_buf, W, H, CH, 0}, zi = {coc, W, H, 1, 0};
                const ddof_image oi = {out, W, H, CH, 0};
                ddof_status st = ddof_diffuse(ctx, &p, &ci, &zi, &oi, NULL);
                size_t bad = 0;
                for (size_t i = 0; i < W * H * CH; i++)
                    bad += !isfinite(out[i]);
                CHECK_MSG(st == DDOF_OK && bad == 0,
                          "%s, pixel aspect %g, CoC pattern %d: status %d, %zu non-finite",
                          ddof_solver_name(solvers[s]), (double)aspects[a], pattern, (int)st, bad);
            }
        }
    }
    ddof_params_init(&p);
    p.pixel_aspect = 1e20f;
    expect_param_message("pixel_aspect 1e20", &p, "params.pixel_aspect 1.00000002e+20 must be "
                         "within 0.01..100");
    ddof_params_init(&p);
    p.beta_scale = 2.0f;
    expect_param_message("beta_scale 2", &p, "params.beta_scale 2 must be > 0 and at most 1");
}

/* Issue 14: a forced near spread with a foreground element was ignored with DDOF_OK (the same
 * force with unsigned CoC is an error); a CoC just above the limit was printed as the limit. */
static void test_forced_near_spread_and_messages(void)
{
    static float fg_color[W * H * 4], fg_coc[W * H];
    ddof_foreground fg;
    ddof_params p;
    ddof_foreground_init(&fg);
    fg.color = (ddof_image_in){fg_color, W, H, 4, 0};
    fg.coc = (ddof_image_in){fg_coc, W, H, 1, 0};
    ddof_params_init(&p);
    p.coc_signed = 1;
    const ddof_image_in ci = {color_buf, W, H, CH, 0}, zi = {coc_buf, W, H, 1, 0};
    const ddof_image oi = {out_buf, W, H, CH, 0};
    reset_inputs();
    CHECK_EQ_INT(ddof_diffuse_layers(ctx, &p, &ci, &zi, &fg, &oi, NULL), DDOF_OK);
    p.near_spread = DDOF_LAYER_ON;
    CHECK_EQ_INT(ddof_diffuse_layers(ctx, &p, &ci, &zi, NULL, &oi, NULL), DDOF_OK);
    fill_sentinel();
    check_failure("near spread forced on with a foreground element",
                  ddof_diffuse_layers(ctx, &p, &ci, &zi, &fg, &oi, NULL),
                  DDOF_ERROR_BAD_PARAMETER, DDOF_ERROR_BAD_PARAMETER);
    CHECK_MSG(strstr(ddof_context_last_error(ctx), "foreground element") != NULL, "%s",
              ddof_context_last_error(ctx));

    coc_buf[5] = 100000.01f;
    {
        call c = good_call();
        fill_sentinel();
        CHECK_EQ_INT(run_call(&c), DDOF_ERROR_BAD_COC);
        CHECK_MSG(strstr(ddof_context_last_error(ctx), "is 100000.008;") != NULL, "%s",
                  ddof_context_last_error(ctx));
    }
    reset_inputs();
}

static int same_settings(const ddof_params *a, const ddof_params *b)
{
    return a->method == b->method && a->solver == b->solver && a->substeps == b->substeps &&
           a->beta_scale == b->beta_scale && a->background == b->background &&
           a->background_levels == b->background_levels && a->near_spread == b->near_spread &&
           a->precision == b->precision && a->struct_size == b->struct_size;
}

/* Presets: known ones are valid params (the good call succeeds with each), an unknown one is
 * an error that still leaves the default preset, and ddof_params_init is the default preset. */
static void test_presets(void)
{
    ddof_params p, d;
    ddof_params_init(&d);
    for (int i = 0; i < DDOF_PRESET_COUNT_; i++) {
        CHECK_EQ_INT(ddof_params_init_preset(&p, (ddof_preset)i), DDOF_OK);
        CHECK(ddof_preset_name((ddof_preset)i) != NULL);
        call c = good_call();
        c.params = &p;
        CHECK_MSG(run_call(&c) == DDOF_OK, "preset %s: %s", ddof_preset_name((ddof_preset)i),
                  ddof_context_last_error(ctx));
    }
    CHECK_EQ_INT(ddof_params_init_preset(&p, DDOF_PRESET_DEFAULT), DDOF_OK);
    CHECK(same_settings(&p, &d));
    CHECK_EQ_INT(ddof_params_init_preset(&p, DDOF_PRESET_COUNT_), DDOF_ERROR_BAD_PARAMETER);
    CHECK(same_settings(&p, &d));
    CHECK(ddof_preset_name(DDOF_PRESET_COUNT_) == NULL);
    CHECK_EQ_INT(ddof_params_init_preset((ddof_params *)NULL, DDOF_PRESET_DEFAULT), DDOF_ERROR_NULL_POINTER);
}

/* Backends: a GL backend that cannot be loaded is a status and a sentence, the context keeps
 * working on the CPU; AUTO falls back to the CPU and says why. */
static void test_backend_selection(void)
{
    ddof_backend_info info = {.struct_size = sizeof info};
    CHECK_EQ_INT(ddof_context_backend_info(ctx, &info), DDOF_OK);
    CHECK_EQ_INT(info.kind, DDOF_BACKEND_CPU);
    CHECK(strstr(info.renderer, "CPU") != NULL);
    const char *missing = "/nonexistent/libddof_gl.so";
    for (int k = DDOF_BACKEND_EGL; k < DDOF_BACKEND_COUNT_; k++) {
        CHECK_EQ_INT(ddof_context_set_backend(ctx, (ddof_backend_kind)k, missing),
                     DDOF_ERROR_BACKEND_UNAVAILABLE);
        CHECK_MSG(strstr(ddof_context_last_error(ctx), "could not be loaded") != NULL,
                  "backend %s: \"%s\"", ddof_backend_name((ddof_backend_kind)k),
                  ddof_context_last_error(ctx));
        CHECK_EQ_INT(ddof_context_backend_info(ctx, &info), DDOF_OK);
        CHECK_EQ_INT(info.kind, DDOF_BACKEND_CPU);
    }
    /* A plugin named by the environment is the only one tried, like an explicit path. */
    CHECK_EQ_INT(setenv("DDOF_GL_PLUGIN", missing, 1), 0);
    CHECK_EQ_INT(ddof_context_set_backend(ctx, DDOF_BACKEND_OSMESA, NULL),
                 DDOF_ERROR_BACKEND_UNAVAILABLE);
    CHECK(strstr(ddof_context_last_error(ctx), missing) != NULL);
    CHECK_EQ_INT(unsetenv("DDOF_GL_PLUGIN"), 0);
    CHECK_EQ_INT(ddof_context_set_backend(ctx, DDOF_BACKEND_AUTO, missing), DDOF_OK);
    CHECK_EQ_INT(ddof_context_backend_info(ctx, &info), DDOF_OK);
    CHECK_EQ_INT(info.kind, DDOF_BACKEND_CPU);
    CHECK_MSG(strstr(info.note, "CPU") != NULL, "auto note \"%s\"", info.note);
    CHECK_EQ_INT(ddof_context_set_backend(ctx, DDOF_BACKEND_COUNT_, NULL),
                 DDOF_ERROR_BAD_PARAMETER);
    CHECK_EQ_INT(ddof_context_set_backend(NULL, DDOF_BACKEND_CPU, NULL), DDOF_ERROR_NULL_POINTER);
    CHECK_EQ_INT(ddof_context_backend_info(ctx, NULL), DDOF_ERROR_NULL_POINTER);
    info.struct_size = 4;
    CHECK_EQ_INT(ddof_context_backend_info(ctx, &info), DDOF_ERROR_BAD_PARAMETER);
    CHECK(ddof_backend_name(DDOF_BACKEND_COUNT_) == NULL);
    CHECK_EQ_INT(ddof_context_set_backend(ctx, DDOF_BACKEND_CPU, NULL), DDOF_OK);
    call c = good_call();
    ddof_stats st = {.struct_size = sizeof st};
    CHECK_EQ_INT(ddof_diffuse(ctx, c.params, &c.color, &c.coc, &c.out, &st), DDOF_OK);
    CHECK_EQ_INT(st.backend, DDOF_BACKEND_CPU);
    CHECK_EQ_INT(st.method, DDOF_METHOD_DIFFUSION);
    CHECK_EQ_INT(st.device_bytes, 0);
    /* The solver's scratch: at least one line batch of the image's rows. */
    CHECK_MSG(st.host_bytes >= (uint64_t)W * CH * sizeof(float), "host_bytes %llu",
              (unsigned long long)st.host_bytes);
}

/* Counting allocator: balance check, and failure injection (the allocation after `budget`
 * successful ones fails; budget < 0: never fails). */
typedef struct counting {
    long allocs, frees, live;
    long budget;
} counting;

static void *c_alloc(void *user, size_t size)
{
    counting *c = user;
    if (c->budget == 0)
        return NULL;
    if (c->budget > 0)
        c->budget--;
    void *p = malloc(size);
    if (p) {
        c->allocs++;
        c->live++;
    }
    return p;
}

static void c_free(void *user, void *ptr)
{
    counting *c = user;
    if (ptr) {
        c->frees++;
        c->live--;
        free(ptr);
    }
}

static void test_allocator(void)
{
    counting cnt = {0, 0, 0, -1};
    ddof_allocator a = {c_alloc, c_free, &cnt};
    ddof_context_options o;
    ddof_context_options_init(&o);
    o.allocator = &a;
    o.thread_count = 2;

    /* Context creation with the k-th allocation failing: OOM ("an allocation failed"), no leak,
     * no context. */
    for (long k = 0; k < 8; k++) {
        cnt = (counting){0, 0, 0, k};
        ddof_context *c = (ddof_context *)&cnt;
        ddof_status s = ddof_context_create(&o, &c);
        if (s == DDOF_OK) {
            ddof_context_free(c);
        } else {
            CHECK_MSG(s == DDOF_ERROR_OUT_OF_MEMORY,
                      "create, allocation %ld fails: status %d (%s)", k, (int)s,
                      ddof_status_string(s));
            CHECK(c == NULL);
        }
        CHECK_MSG(cnt.live == 0, "create, allocation %ld fails: %ld blocks leaked", k, cnt.live);
    }

    ddof_image_in ci = {color_buf, W, H, CH, 0}, zi = {coc_buf, W, H, 1, 0};
    ddof_image oi = {out_buf, W, H, CH, 0};
    ddof_params p;
    heat_params_init(&p);
    for (int solver = 0; solver < TEST_CPU_SOLVER_COUNT; solver++) {
        /* A fresh context whose allocator dies right after creation: the first call needs
         * scratch memory and must fail cleanly before writing anything. */
        cnt = (counting){0, 0, 0, -1};
        ddof_context *c = NULL;
        CHECK_EQ_INT(ddof_context_create(&o, &c), DDOF_OK);
        if (!c)
            return;
        cnt.budget = 0;
        p.solver = (ddof_solver)solver;
        fill_sentinel();
        ddof_status s = ddof_diffuse(c, &p, &ci, &zi, &oi, NULL);
        CHECK_MSG(s == DDOF_ERROR_OUT_OF_MEMORY, "%s without memory: %d",
                  ddof_solver_name(p.solver), (int)s);
        CHECK_MSG(out_untouched(), "%s: out written before the allocation failed",
                  ddof_solver_name(p.solver));
        CHECK(ddof_context_last_error(c)[0] != '\0');
        /* ... and works again once memory is back. */
        cnt.budget = -1;
        CHECK_EQ_INT(ddof_diffuse(c, &p, &ci, &zi, &oi, NULL), DDOF_OK);
        CHECK_MSG(cnt.allocs > 1, "the custom allocator was not used for the solve");
        ddof_context_free(c);
        CHECK_MSG(cnt.live == 0, "allocator: %ld allocations, %ld frees", cnt.allocs,
                  cnt.frees);
    }

    /* ddof_depth_of_field without memory. */
    cnt = (counting){0, 0, 0, -1};
    ddof_context *c = NULL;
    CHECK_EQ_INT(ddof_context_create(&o, &c), DDOF_OK);
    if (!c)
        return;
    float depth[W * H];
    for (size_t i = 0; i < W * H; i++)
        depth[i] = 1.0f + (float)(i % 17);
    ddof_image_in di = {depth, W, H, 1, 0};
    ddof_camera cam;
    ddof_camera_init(&cam);
    p.solver = DDOF_SOLVER_THOMAS;
    cnt.budget = 0;
    fill_sentinel();
    ddof_status s = ddof_depth_of_field(c, &p, &cam, &ci, &di, &oi, NULL);
    CHECK_EQ_INT(s, DDOF_ERROR_OUT_OF_MEMORY);
    CHECK(out_untouched());
    cnt.budget = 1; /* the CoC buffer, then nothing for the solver */
    s = ddof_depth_of_field(c, &p, &cam, &ci, &di, &oi, NULL);
    CHECK_MSG(s == DDOF_ERROR_OUT_OF_MEMORY, "depth_of_field, 2nd allocation fails: %d", (int)s);
    CHECK(out_untouched());
    cnt.budget = -1;
    CHECK_EQ_INT(ddof_depth_of_field(c, &p, &cam, &ci, &di, &oi, NULL), DDOF_OK);
    ddof_context_free(c);
    CHECK_MSG(cnt.live == 0, "allocator: %ld allocations, %ld frees", cnt.allocs, cnt.frees);
}

/* ---------------------------------------------------------------------------------------- */
/* CoC from camera and curve                                                                  */

static int coc_untouched(void) { return !memcmp(coc_buf, sentinel_buf, W * H * sizeof(float)); }

static void reset_depth(float v)
{
    for (size_t i = 0; i < W * H; i++)
        color_buf[i] = v + 0.01f * (float)(i % 7);
}

/* The depth image (color_buf, 5 m) with `v` at pixel (27, 13), and the CoC image (coc_buf)
 * reset to the sentinel so that any write shows. */
static void plant_depth(float v)
{
    reset_depth(5.0f);
    color_buf[13 * W + 27] = v;
    memcpy(coc_buf, sentinel_buf, sizeof coc_buf);
}

static void test_camera(void)
{
    ddof_camera cam;
    ddof_camera_init(&cam);
    ddof_image_in depth = {color_buf, W, H, 1, 0};
    ddof_image coc = {coc_buf, W, H, 1, 0};

    const float bad_depth[] = {NAN, 0.0f, -0.0f, -1.0f, -INFINITY};
    const char *names[] = {"NaN", "0", "-0", "-1", "-inf"};
    for (int i = 0; i < 5; i++) {
        plant_depth(bad_depth[i]);
        ddof_status s = ddof_coc_from_camera(ctx, &cam, &depth, &coc);
        CHECK_MSG(s == DDOF_ERROR_BAD_DEPTH, "camera, depth %s: status %d", names[i], (int)s);
        CHECK_MSG(coc_untouched(), "camera, depth %s: coc written", names[i]);
        CHECK(ddof_context_last_error(ctx)[0] != '\0');
    }
    reset_depth(5.0f);
    color_buf[13 * W + 27] = INFINITY;
    CHECK_EQ_INT(ddof_coc_from_camera(ctx, &cam, &depth, &coc), DDOF_OK);
    CHECK(ddof_context_last_error(ctx)[0] == '\0');
    CHECK(isfinite(coc_buf[13 * W + 27]) && coc_buf[13 * W + 27] > 0.0f);

#define BAD_CAM(what, stmt, alt)                                                               \
    do {                                                                                       \
        ddof_camera_init(&cam);                                                                \
        stmt;                                                                                  \
        memcpy(coc_buf, sentinel_buf, sizeof coc_buf);                                         \
        ddof_status s_ = ddof_coc_from_camera(ctx, &cam, &depth, &coc);                        \
        CHECK_MSG(s_ == DDOF_ERROR_BAD_CAMERA || s_ == (alt), "%s: status %d", what, (int)s_); \
        CHECK_MSG(coc_untouched(), "%s: coc written", what);                                   \
        CHECK(ddof_context_last_error(ctx)[0] != '\0');                                        \
    } while (0)
    reset_depth(5.0f);
    BAD_CAM("fstop 0", cam.fstop = 0, DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("fstop -2", cam.fstop = -2, DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("fstop NaN", cam.fstop = NAN, DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("focal length 0", cam.focal_length_mm = 0, DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("focal length -50", cam.focal_length_mm = -50, DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("focal length NaN", cam.focal_length_mm = NAN, DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("focus = focal length", (cam.focal_length_mm = 50, cam.focus_distance_m = 0.05),
            DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("focus < focal length", (cam.focal_length_mm = 50, cam.focus_distance_m = 0.03),
            DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("focus 0", cam.focus_distance_m = 0, DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("focus -1", cam.focus_distance_m = -1, DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("focus NaN", cam.focus_distance_m = NAN, DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("sensor 0", cam.sensor_width_mm = 0, DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("sensor -36", cam.sensor_width_mm = -36, DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("pixel_aspect 0", cam.pixel_aspect = 0, DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("pixel_aspect -1", cam.pixel_aspect = -1, DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("pixel_aspect NaN", cam.pixel_aspect = NAN, DDOF_ERROR_BAD_CAMERA);
    BAD_CAM("depth_unit_m 0", cam.depth_unit_m = 0, DDOF_ERROR_BAD_PARAMETER);
    BAD_CAM("depth_unit_m -1", cam.depth_unit_m = -1, DDOF_ERROR_BAD_PARAMETER);
    BAD_CAM("lens model 7", cam.lens_model = (ddof_lens_model)7, DDOF_ERROR_BAD_PARAMETER);
    BAD_CAM("depth kind 7", cam.depth_kind = (ddof_depth_kind)7, DDOF_ERROR_BAD_PARAMETER);
    BAD_CAM("sensor fit 7", cam.sensor_fit = (ddof_sensor_fit)7, DDOF_ERROR_BAD_PARAMETER);
#undef BAD_CAM

    /* Malformed structs and images. */
    ddof_camera_init(&cam);
    memcpy(coc_buf, sentinel_buf, sizeof coc_buf);
    CHECK_EQ_INT(ddof_coc_from_camera(ctx, NULL, &depth, &coc), DDOF_ERROR_NULL_POINTER);
    CHECK_EQ_INT(ddof_coc_from_camera(NULL, &cam, &depth, &coc), DDOF_ERROR_NULL_POINTER);
    CHECK_EQ_INT(ddof_coc_from_camera(ctx, &cam, NULL, &coc), DDOF_ERROR_NULL_POINTER);
    CHECK_EQ_INT(ddof_coc_from_camera(ctx, &cam, &depth, NULL), DDOF_ERROR_NULL_POINTER);
    cam.struct_size = 0;
    CHECK_EQ_INT(ddof_coc_from_camera(ctx, &cam, &depth, &coc), DDOF_ERROR_BAD_PARAMETER);
    ddof_camera_init(&cam);
    ddof_image coc2 = coc;
    coc2.width = W - 1;
    CHECK_EQ_INT(ddof_coc_from_camera(ctx, &cam, &depth, &coc2), DDOF_ERROR_SIZE_MISMATCH);
    coc2 = coc;
    coc2.channels = 2;
    ddof_status s = ddof_coc_from_camera(ctx, &cam, &depth, &coc2);
    CHECK_MSG(s == DDOF_ERROR_BAD_CHANNELS || s == DDOF_ERROR_SIZE_MISMATCH,
              "2-channel coc output: %d", (int)s);
    coc2 = coc;
    coc2.row_stride = W * 4 - 4;
    CHECK_EQ_INT(ddof_coc_from_camera(ctx, &cam, &depth, &coc2), DDOF_ERROR_BAD_STRIDE);
    ddof_image_in d2 = depth;
    d2.width = DDOF_MAX_DIMENSION + 1;
    coc2 = coc;
    coc2.width = DDOF_MAX_DIMENSION + 1;
    CHECK_EQ_INT(ddof_coc_from_camera(ctx, &cam, &d2, &coc2), DDOF_ERROR_BAD_SIZE);
    CHECK_MSG(coc_untouched(), "coc written by a failing ddof_coc_from_camera");
}

static void test_curve(void)
{
    ddof_curve cv;
    ddof_image_in depth = {color_buf, W, H, 1, 0};
    ddof_image coc = {coc_buf, W, H, 1, 0};
    reset_depth(5.0f);
#define BAD_CURVE(what, stmt)                                                                  \
    do {                                                                                       \
        cv = curve_of(4, 1, 2, 10, 20, 8);                                                     \
        CHECK_EQ_INT(ddof_coc_from_curve(ctx, &cv, &depth, &coc), DDOF_OK);                    \
        stmt;                                                                                  \
        memcpy(coc_buf, sentinel_buf, sizeof coc_buf);                                         \
        ddof_status s_ = ddof_coc_from_curve(ctx, &cv, &depth, &coc);                          \
        CHECK_MSG(s_ == DDOF_ERROR_BAD_PARAMETER, "curve %s: status %d", what, (int)s_);       \
        CHECK_MSG(coc_untouched(), "curve %s: coc written", what);                             \
        CHECK(ddof_context_last_error(ctx)[0] != '\0');                                       \
    } while (0)
    BAD_CURVE("near_start > near_end", cv.near_start = 3);
    BAD_CURVE("near_end > far_start", cv.near_end = 11);
    BAD_CURVE("far_start > far_end", cv.far_start = 21);
    BAD_CURVE("near_start < 0", cv.near_start = -1);
    BAD_CURVE("near_blur < 0", cv.near_blur_px = -1);
    BAD_CURVE("far_blur < 0", cv.far_blur_px = -0.5);
    BAD_CURVE("far_blur > max", cv.far_blur_px = 2.0 * DDOF_MAX_COC_PX);
    BAD_CURVE("near_blur NaN", cv.near_blur_px = NAN);
    BAD_CURVE("far_end NaN", cv.far_end = NAN);
    BAD_CURVE("struct_size 0", cv.struct_size = 0);
#undef BAD_CURVE

    ddof_curve_init(&cv);
    const float bad_depth[] = {NAN, -1.0f, -INFINITY};
    const char *names[] = {"NaN", "-1", "-inf"};
    for (int i = 0; i < 3; i++) {
        plant_depth(bad_depth[i]);
        ddof_status s = ddof_coc_from_curve(ctx, &cv, &depth, &coc);
        CHECK_MSG(s == DDOF_ERROR_BAD_DEPTH, "curve, depth %s: status %d", names[i], (int)s);
        CHECK_MSG(coc_untouched(), "curve, depth %s: coc written", names[i]);
    }
    /* 0 and +inf depth are valid for the curve. */
    reset_depth(5.0f);
    color_buf[0] = 0.0f;
    color_buf[1] = INFINITY;
    CHECK_EQ_INT(ddof_coc_from_curve(ctx, &cv, &depth, &coc), DDOF_OK);
    CHECK_EQ_INT(ddof_coc_from_curve(ctx, NULL, &depth, &coc), DDOF_ERROR_NULL_POINTER);
}

static void test_depth_of_field(void)
{
    ddof_camera cam;
    ddof_camera_init(&cam);
    ddof_params p;
    ddof_params_init(&p);
    float depth_buf[W * H];
    for (size_t i = 0; i < W * H; i++)
        depth_buf[i] = 2.0f + (float)(i % 13);
    reset_inputs();
    ddof_image_in ci = {color_buf, W, H, CH, 0}, di = {depth_buf, W, H, 1, 0};
    ddof_image oi = {out_buf, W, H, CH, 0};
    CHECK_EQ_INT(ddof_depth_of_field(ctx, &p, &cam, &ci, &di, &oi, NULL), DDOF_OK);

#define BAD_DOF(what, want, stmt, undo)                                                        \
    do {                                                                                       \
        stmt;                                                                                  \
        fill_sentinel();                                                                       \
        ddof_status s_ = ddof_depth_of_field(ctx, &p, &cam, &ci, &di, &oi, NULL);              \
        check_failure(what, s_, want, want);                                                   \
        undo;                                                                                  \
        CHECK_EQ_INT(ddof_depth_of_field(ctx, &p, &cam, &ci, &di, &oi, NULL), DDOF_OK);        \
    } while (0)
    BAD_DOF("dof: depth NaN", DDOF_ERROR_BAD_DEPTH, depth_buf[77] = NAN, depth_buf[77] = 3);
    BAD_DOF("dof: depth 0", DDOF_ERROR_BAD_DEPTH, depth_buf[77] = 0, depth_buf[77] = 3);
    BAD_DOF("dof: colour NaN", DDOF_ERROR_BAD_COLOR, color_buf[77] = NAN, color_buf[77] = 0.5f);
    BAD_DOF("dof: fstop 0", DDOF_ERROR_BAD_CAMERA, cam.fstop = 0, cam.fstop = 2.8);
    BAD_DOF("dof: depth size", DDOF_ERROR_SIZE_MISMATCH, di.width = W - 1, di.width = W);
    BAD_DOF("dof: substeps 0", DDOF_ERROR_BAD_PARAMETER, p.substeps = 0, p.substeps = 1);
    /* The camera's pixel aspect becomes params.pixel_aspect: the same range, checked on the
     * double before it is converted (1e-300 would become 0, 1e300 infinity). A bad camera, as
     * a negative one is (issue 22: it was BAD_PARAMETER for 1e20 and BAD_CAMERA for -1). */
    BAD_DOF("dof: camera pixel_aspect 1e20", DDOF_ERROR_BAD_CAMERA, cam.pixel_aspect = 1e20,
            cam.pixel_aspect = 1.0);
    BAD_DOF("dof: camera pixel_aspect 1e-300", DDOF_ERROR_BAD_CAMERA,
            cam.pixel_aspect = 1e-300, cam.pixel_aspect = 1.0);
    BAD_DOF("dof: camera pixel_aspect -1", DDOF_ERROR_BAD_CAMERA, cam.pixel_aspect = -1.0,
            cam.pixel_aspect = 1.0);
    cam.pixel_aspect = 1e-300;
    CHECK(ddof_depth_of_field(ctx, &p, &cam, &ci, &di, &oi, NULL) == DDOF_ERROR_BAD_CAMERA);
    CHECK_MSG(strstr(ddof_context_last_error(ctx), "pixel_aspect 1e-300 must be within 0.01..100"),
              "%s", ddof_context_last_error(ctx));
    cam.pixel_aspect = 100.0;
    CHECK_EQ_INT(ddof_depth_of_field(ctx, &p, &cam, &ci, &di, &oi, NULL), DDOF_OK);
    cam.pixel_aspect = 1.0;
    BAD_DOF("dof: depth NULL pixels", DDOF_ERROR_NULL_POINTER, di.pixels = NULL,
            di.pixels = depth_buf);
#undef BAD_DOF
    fill_sentinel();
    CHECK_EQ_INT(ddof_depth_of_field(ctx, &p, NULL, &ci, &di, &oi, NULL),
                 DDOF_ERROR_NULL_POINTER);
    CHECK_EQ_INT(ddof_depth_of_field(ctx, NULL, &cam, &ci, &di, &oi, NULL),
                 DDOF_ERROR_NULL_POINTER);
    CHECK_EQ_INT(ddof_depth_of_field(ctx, &p, &cam, &ci, NULL, &oi, NULL),
                 DDOF_ERROR_NULL_POINTER);
    CHECK(out_untouched());
}

int main(void)
{
    ctx = make_context(2);
    ddof_params_init(&good_params);
    reset_inputs();
    fill_sentinel();

    test_status_strings();
    test_context();
    test_null_pointers();
    test_sizes();
    test_strides();
    test_bad_values();
    test_params();
    test_param_bounds();
    test_forced_near_spread_and_messages();
    test_allocator();
    test_camera();
    test_curve();
    test_depth_of_field();
    test_presets();
    test_backend_selection();

    ddof_context_free(ctx);
    return test_report("test_bad_input");
}
