/* SPDX-License-Identifier: MIT */
/* test_bad_input_images.c - the images of a call: status strings, the context, NULL pointers,
 * sizes, strides and bad pixel values each get their status and leave the output untouched
 * (bad_input_test.h). */
#include "bad_input_test.h"

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

int main(void)
{
    bad_input_test_begin();

    test_status_strings();
    test_context();
    test_null_pointers();
    test_sizes();
    test_strides();
    test_bad_values();

    return bad_input_test_end("test_bad_input_images");
}
