/* SPDX-License-Identifier: MIT */
/* bad_input_test.h - what the bad-input tests share (test_bad_input_*.c): one good
 * ddof_diffuse call described field by field, buffers filled with a sentinel so that any write
 * shows, and the check that a bad call gets its documented status, leaves the output bitwise
 * untouched (ddof.h: "every check runs before the first output pixel is written") and leaves a
 * message in ddof_context_last_error(); a success clears it to "".
 *
 * Readings of the header where it does not name one code (accepted alternatives noted inline):
 *  - the CoC is read from the first channel of a 1..4-channel image; the other channels are not
 *    read, so NaN there is no error;
 *  - camera depth_unit_m <= 0 and out-of-range camera enums: BAD_CAMERA or BAD_PARAMETER;
 *  - curve out of order / blur out of range: BAD_PARAMETER ("a value is out of range");
 *  - CoC -0.0 is not negative (it compares equal to 0): accepted. */
#ifndef DDOF_BAD_INPUT_TEST_H
#define DDOF_BAD_INPUT_TEST_H

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

static inline void fill_sentinel(void)
{
    const uint32_t bits = 0x7FC0DEADu; /* a NaN payload nothing computes by accident */
    for (size_t i = 0; i < BUF_FLOATS; i++)
        memcpy(&sentinel_buf[i], &bits, 4);
    memcpy(out_buf, sentinel_buf, sizeof out_buf);
}

static inline int out_untouched(void) { return !memcmp(out_buf, sentinel_buf, sizeof out_buf); }

static inline void reset_inputs(void)
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

static inline call good_call(void)
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

static inline ddof_status run_call(const call *c)
{
    return ddof_diffuse(c->ctx, c->params, c->null_color ? NULL : &c->color,
                        c->null_coc ? NULL : &c->coc, c->null_out ? NULL : &c->out, NULL);
}

/* A successful call first (on its own clean images), so the message checked afterwards is the
 * failure's own. */
static inline void clear_error_by_success(void)
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

static inline void check_failure(const char *what, ddof_status got, ddof_status want,
                                 ddof_status alt)
{
    CHECK_MSG(got == want || got == alt, "%s: status %d (%s), expected %d", what, (int)got,
              ddof_status_string(got), (int)want);
    CHECK_MSG(out_untouched(), "%s: the output was written", what);
    const char *msg = ddof_context_last_error(ctx);
    CHECK_MSG(msg && msg[0], "%s: no last-error message", what);
}

static inline void expect2(const char *what, const call *c, ddof_status want, ddof_status alt)
{
    clear_error_by_success();
    fill_sentinel();
    ddof_status s = run_call(c);
    check_failure(what, s, want, alt);
}

static inline void expect(const char *what, const call *c, ddof_status want)
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

/* The context, the good parameters and the buffers, before the first case. */
static inline void bad_input_test_begin(void)
{
    ctx = make_context(2);
    ddof_params_init(&good_params);
    reset_inputs();
    fill_sentinel();
}

/* Frees the context; the exit status. */
static inline int bad_input_test_end(const char *name)
{
    ddof_context_free(ctx);
    return test_report(name);
}

#endif
