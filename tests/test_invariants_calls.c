/* SPDX-License-Identifier: MIT */
/* test_invariants_calls.c - what holds of a ddof_diffuse call whatever its form: in-place
 * operation, thread counts, stats, row strides and channel counts, the output's alignment,
 * progress and cancel. */
#include "ddof.h"
#include "test_util.h"
#include "test_images.h"

#include <float.h>
#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <string.h>

static void test_in_place(ddof_context *ctx)
{
    test_rng rng = {5};
    for (uint32_t ch = 1; ch <= 4; ch++) {
        test_image im = image_alloc(70, 37, ch);
        const size_t bytes = im.n * sizeof(float);
        float *inplace = alloc_f(im.n);
        fill_uniform(im.color, im.n, &rng, 0.0, 2.0);
        fill_coc(im.coc, im.px, &rng, 30.0, 0.2);
        for (int solver = 0; solver < TEST_CPU_SOLVER_COUNT; solver++) {
            ddof_params p = params_for((ddof_solver)solver, 2);
            memcpy(inplace, im.color, bytes);
            CHECK_EQ_INT(image_diffuse(ctx, &p, &im, NULL), DDOF_OK);
            CHECK_EQ_INT(diffuse(ctx, &p, inplace, im.coc, inplace, im.w, im.h, ch, NULL),
                         DDOF_OK);
            CHECK_MSG(!memcmp(im.out, inplace, bytes),
                      "solver %s, %u channels: in place differs from out of place by %.3g",
                      ddof_solver_name((ddof_solver)solver), ch,
                      max_abs_diff_ff(im.out, inplace, im.n));
        }
        image_free(&im);
        free(inplace);
    }
}

/* Every solver gives the same bits on 1, 2 and the default number of threads. */
static void test_thread_counts(void)
{
    test_rng rng = {31337};
    test_image im = image_alloc(test_quick() ? 90 : 300, test_quick() ? 70 : 200, 4);
    const size_t n = im.n;
    float *o1 = im.out, *o2 = alloc_f(n);
    fill_uniform(im.color, n, &rng, 0.0, 1.0);
    fill_coc(im.coc, im.px, &rng, 60.0, 0.2);
    ddof_context *c1 = make_context(1), *c2 = make_context(2), *c0 = make_context(0);
    CHECK_EQ_INT(ddof_context_thread_count(c1), 1);
    CHECK_EQ_INT(ddof_context_thread_count(c2), 2);
    CHECK(ddof_context_thread_count(c0) >= 1);
    for (int solver = 0; solver < TEST_CPU_SOLVER_COUNT; solver++) {
        ddof_params p = params_for((ddof_solver)solver, 2);
        ddof_stats st = stats_init();
        CHECK_EQ_INT(image_diffuse(c1, &p, &im, &st), DDOF_OK); /* into o1 */
        CHECK_EQ_INT(st.threads, 1);
        st.struct_size = sizeof st;
        CHECK_EQ_INT(diffuse(c2, &p, im.color, im.coc, o2, im.w, im.h, im.ch, &st), DDOF_OK);
        CHECK(st.threads >= 1 && st.threads <= 2);
        CHECK_MSG(!memcmp(o1, o2, n * sizeof(float)), "solver %s: 1 vs 2 threads differ by %.3g",
                  ddof_solver_name((ddof_solver)solver), max_abs_diff_ff(o1, o2, n));
        CHECK_EQ_INT(diffuse(c0, &p, im.color, im.coc, o2, im.w, im.h, im.ch, NULL), DDOF_OK);
        CHECK_MSG(!memcmp(o1, o2, n * sizeof(float)),
                  "solver %s: 1 vs default threads differ by %.3g",
                  ddof_solver_name((ddof_solver)solver), max_abs_diff_ff(o1, o2, n));
    }
    ddof_context_free(c1);
    ddof_context_free(c2);
    ddof_context_free(c0);
    image_free(&im);
    free(o2);
}

static void test_stats(ddof_context *ctx)
{
    test_rng rng = {11};
    const uint32_t w = 64, h = 64;
    const size_t px = (size_t)w * h;
    /* RGBA buffers; the line counts below are taken on their first channel alone (ch = 1). */
    test_image im = image_alloc(w, h, 4);
    float *color = im.color, *coc = im.coc, *out = im.out;
    fill_uniform(color, px * 4, &rng, 0.0, 1.0);
    ddof_stats st;

    /* Nothing out of focus: a copy, no solves. */
    fill_const(coc, px, 0.0f);
    fill_const(out, px * 4, -7.0f);
    memset(&st, 0xAB, sizeof st);
    st.struct_size = sizeof st;
    ddof_params p = params_for(DDOF_SOLVER_THOMAS, 3);
    CHECK_EQ_INT(diffuse(ctx, &p, color, coc, out, w, h, 4, &st), DDOF_OK);
    CHECK_MSG(!memcmp(color, out, px * 4 * sizeof(float)), "CoC 0 everywhere changed the image");
    CHECK_EQ_INT(st.copied_only, 1);
    CHECK_EQ_INT(st.lines_solved, 0);
    /* ... without a pass over the lines: the CPU's run copies a frame it is told is in focus. */
    CHECK_MSG(st.seconds_rows == 0.0 && st.seconds_columns == 0.0,
              "a frame in focus took row passes of %g s, column passes of %g s", st.seconds_rows,
              st.seconds_columns);
    CHECK_EQ_INT(st.substeps, 0);
    CHECK(st.max_coc_px == 0.0f);
    CHECK(st.seconds_total >= 0 && isfinite(st.seconds_total));
    CHECK_EQ_INT(st.solver, DDOF_SOLVER_THOMAS);
    /* ... also in place. */
    memcpy(out, color, px * 4 * sizeof(float));
    CHECK_EQ_INT(diffuse(ctx, &p, out, coc, out, w, h, 4, NULL), DDOF_OK);
    CHECK(!memcmp(color, out, px * 4 * sizeof(float)));

    /* Top half in focus, bottom half CoC 5, one channel (so a "line" is one system):
     * per substep 32 rows have no link (skipped), 32 rows and all 64 columns are solved. */
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++)
            coc[y * w + x] = y < h / 2 ? 0.0f : 5.0f;
    coc[(h - 1) * w + 3] = 6.5f;
    memset(&st, 0xAB, sizeof st);
    st.struct_size = sizeof st;
    p = params_for(DDOF_SOLVER_THOMAS, 2);
    CHECK_EQ_INT(diffuse(ctx, &p, color, coc, out, w, h, 1, &st), DDOF_OK);
    CHECK_EQ_INT(st.copied_only, 0);
    CHECK_EQ_INT(st.substeps, 2);
    CHECK_EQ_INT(st.solver, DDOF_SOLVER_THOMAS);
    CHECK_EQ_INT(st.lines_solved + st.lines_skipped, (uint64_t)(w + h) * 2);
    CHECK_EQ_INT(st.lines_skipped, (uint64_t)(h / 2) * 2);
    CHECK(st.max_coc_px == 6.5f);
    CHECK(st.threads >= 1 && st.threads <= ddof_context_thread_count(ctx));
    CHECK(st.seconds_total >= 0 && isfinite(st.seconds_total));
    CHECK(st.seconds_rows >= 0 && st.seconds_columns >= 0 && st.seconds_coc >= 0);
    CHECK(st.seconds_rows + st.seconds_columns <= st.seconds_total + 1e-3);
    /* The in-focus half is a copy. */
    CHECK(!memcmp(color, out, (size_t)(h / 2) * w * sizeof(float)));

    /* Out of focus only in the block [16, 48) x [8, 40): 32 rows and 32 columns conduct, the
     * other 32 rows and 32 columns are skipped, per substep. */
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++)
            coc[y * w + x] = (x >= 16 && x < 48 && y >= 8 && y < 40) ? 4.0f : 0.0f;
    memset(&st, 0xAB, sizeof st);
    st.struct_size = sizeof st;
    for (int solver = 0; solver < TEST_CPU_SOLVER_COUNT; solver++) {
        p = params_for((ddof_solver)solver, 3);
        CHECK_EQ_INT(diffuse(ctx, &p, color, coc, out, w, h, 1, &st), DDOF_OK);
        CHECK_EQ_INT(st.substeps, 3);
        CHECK_EQ_INT(st.lines_solved, 64 * 3);
        CHECK_EQ_INT(st.lines_skipped, 64 * 3);
        CHECK(st.max_coc_px == 4.0f);
    }

    /* Uniform CoC: every line solved. */
    fill_const(coc, px, 3.0f);
    st.struct_size = sizeof st;
    p = params_for(DDOF_SOLVER_THOMAS, 1);
    CHECK_EQ_INT(diffuse(ctx, &p, color, coc, out, w, h, 1, &st), DDOF_OK);
    CHECK_EQ_INT(st.lines_solved, (uint64_t)(w + h));
    CHECK_EQ_INT(st.lines_skipped, 0);
    CHECK(st.max_coc_px == 3.0f);
    image_free(&im);
}

/* Padded strides (colour, CoC and output each with their own padding) give the same pixels as
 * tight packing, leave the output's padding alone and never read the colour's padding (it holds
 * NaN, which would be a BAD_COLOR if read as a pixel). */
static void test_strides_and_channels(ddof_context *ctx)
{
    test_rng rng = {77};
    const uint32_t w = 29, h = 19;
    const size_t px = (size_t)w * h;
    const uint32_t sentinel_bits = 0x7FA5A5A5u; /* a signalling-NaN pattern, easy to spot */
    float sentinel;
    memcpy(&sentinel, &sentinel_bits, sizeof sentinel);
    float *coc = alloc_f(px);
    fill_coc(coc, px, &rng, 20.0, 0.2);

    for (uint32_t ch = 1; ch <= 4; ch++) {
        const size_t n = px * ch;
        float *color = alloc_f(n), *tight = alloc_f(n);
        fill_uniform(color, n, &rng, 0.0, 1.0);
        ddof_params p = params_for(DDOF_SOLVER_THOMAS, 2);
        CHECK_EQ_INT(diffuse(ctx, &p, color, coc, tight, w, h, ch, NULL), DDOF_OK);

        const size_t cstride = (size_t)w * ch * 4 + 12, zstride = (size_t)w * 4 + 8;
        const size_t ostride = (size_t)w * ch * 4 + 12;
        float *pc = alloc_f(cstride / 4 * h), *pz = alloc_f(zstride / 4 * h);
        float *po = alloc_f(ostride / 4 * h);
        fill_const(pc, cstride / 4 * h, NAN);
        fill_const(pz, zstride / 4 * h, NAN);
        fill_const(po, ostride / 4 * h, sentinel);
        for (uint32_t y = 0; y < h; y++) {
            memcpy(pc + y * cstride / 4, color + (size_t)y * w * ch, (size_t)w * ch * 4);
            memcpy(pz + y * zstride / 4, coc + (size_t)y * w, (size_t)w * 4);
        }
        ddof_image_in ci = {pc, w, h, ch, cstride};
        ddof_image_in zi = {pz, w, h, 1, zstride};
        ddof_image oi = {po, w, h, ch, ostride};
        CHECK_EQ_INT(ddof_diffuse(ctx, &p, &ci, &zi, &oi, NULL), DDOF_OK);
        size_t pix_diff = padded_rows_differ(po, ostride / 4, tight, (size_t)w * ch, h);
        size_t pad_touched = padding_changed(po, ostride / 4, (size_t)w * ch, h, sentinel);
        CHECK_MSG(pix_diff == 0, "%u channels: %zu padded rows differ from tight packing", ch,
                  pix_diff);
        CHECK_MSG(pad_touched == 0, "%u channels: %zu padding floats overwritten", ch,
                  pad_touched);

        /* In place on the padded buffer too (padding of NaN must stay NaN, unread). */
        CHECK_EQ_INT(ddof_diffuse(ctx, &p, &ci, &zi, &(ddof_image){pc, w, h, ch, cstride}, NULL),
                     DDOF_OK);
        pix_diff = padded_rows_differ(pc, cstride / 4, tight, (size_t)w * ch, h);
        CHECK_MSG(pix_diff == 0, "%u channels: padded in-place rows differ: %zu", ch, pix_diff);

        /* Channels are independent: each equals the 1-channel diffusion of that channel
         * (compared with a tolerance: vector code may round differently per layout). */
        if (ch == 4) {
            for (uint32_t c = 0; c < 4; c++) {
                float *one = alloc_f(px), *oo = alloc_f(px);
                for (size_t i = 0; i < px; i++)
                    one[i] = color[i * 4 + c];
                CHECK_EQ_INT(diffuse(ctx, &p, one, coc, oo, w, h, 1, NULL), DDOF_OK);
                double e = 0;
                for (size_t i = 0; i < px; i++)
                    e = fmax(e, fabs((double)oo[i] - tight[i * 4 + c]));
                CHECK_MSG(e <= 1e-6, "channel %u of RGBA vs 1-channel run: %.3g", c, e);
                free(one);
                free(oo);
            }
        }
        free(color);
        free(tight);
        free(pc);
        free(pz);
        free(po);
    }
    free(coc);
}

/* One call (ddof_diffuse, or ddof_diffuse_layers when `layered`) with the output tightly packed,
 * then at every float offset within a cache line with rows 64-byte multiples apart (the case
 * that moves the column blocks): the most rows of any offset that differ from the packed
 * result, bit for bit. */
static size_t rows_differing_when_moved(ddof_context *ctx, const ddof_params *p, int layered,
                                        const float *color, const float *coc, uint32_t w,
                                        uint32_t h, uint32_t ch)
{
    const size_t row = (size_t)w * ch, stride = (row * sizeof(float) + 63) / 64 * 64;
    float *tight = alloc_f(row * h), *block = aligned_alloc(64, stride * h + 64);
    const ddof_image_in ci = {color, w, h, ch, 0}, zi = {coc, w, h, 1, 0};
    size_t worst = 0;
    for (int offset = -1; offset < 16; offset++) {
        const ddof_image oi = offset < 0 ? (ddof_image){tight, w, h, ch, 0}
                                         : (ddof_image){block + offset, w, h, ch, stride};
        const ddof_status s = layered ? ddof_diffuse_layers(ctx, p, &ci, &zi, NULL, &oi, NULL)
                                      : ddof_diffuse(ctx, p, &ci, &zi, &oi, NULL);
        CHECK_EQ_INT(s, DDOF_OK);
        if (offset >= 0) {
            const size_t differ =
                padded_rows_differ(block + offset, stride / sizeof(float), tight, row, h);
            worst = differ > worst ? differ : worst;
        }
    }
    free(tight);
    free(block);
    return worst;
}

/* The column pass moves its block boundaries so that every full block's rows start on a 64-byte
 * boundary of the output (a narrower first block takes the columns before it). Lines are
 * solved independently, so the result must not depend on where the output lies, for every CPU
 * solver, the disc kernel and every channel count, on a width that spans several blocks and
 * narrow ends. */
static void test_output_alignment(ddof_context *ctx)
{
    test_rng rng = {91};
    const uint32_t w = 70, h = 13, tall = 64;
    float *coc = alloc_f((size_t)w * h), *wide_coc = alloc_f((size_t)w * h);
    float *ramp_coc = alloc_f((size_t)w * tall), *color = alloc_f((size_t)w * tall * 4);
    fill_coc(coc, (size_t)w * h, &rng, 20.0, 0.2);
    /* 0 to 4000 px across the width: Thomas's switch to double (CoC 1254 px at the default k)
     * falls inside a block; the wide CoC also has in-focus bars for the background to fill. */
    for (uint32_t y = 0; y < tall; y++)
        for (uint32_t x = 0; x < w; x++) {
            const float ramp = 4000.0f * (float)x / (float)w;
            ramp_coc[(size_t)y * w + x] = ramp;
            if (y < h)
                wide_coc[(size_t)y * w + x] = (x % 9 == 4) ? 0.0f : ramp;
        }
    for (uint32_t ch = 1; ch <= 4; ch++) {
        fill_uniform(color, (size_t)w * tall * ch, &rng, 0.0, 1.0);
        size_t worst;
        for (int solver = 0; solver < TEST_CPU_SOLVER_COUNT; solver++) {
            if (solver == DDOF_SOLVER_REFERENCE_F64)
                continue; /* whole lines in double, no blocks */
            ddof_params p = params_for((ddof_solver)solver, 2);
            worst = rows_differing_when_moved(ctx, &p, 0, color, coc, w, h, ch);
            CHECK_MSG(worst == 0, "%s, %u channels: %zu rows differ with the output moved",
                      ddof_solver_name((ddof_solver)solver), ch, worst);
        }
        /* The disc kernel's driver too (its blocks lie in its own complex image). */
        ddof_params p = params_for(DDOF_SOLVER_THOMAS, 1);
        p.kernel = DDOF_KERNEL_DISC_2X2;
        worst = rows_differing_when_moved(ctx, &p, 0, color, coc, w, h, ch);
        CHECK_MSG(worst == 0, "disc-2x2, %u channels: %zu rows differ with the output moved", ch,
                  worst);
        /* A layered frame with the background layer on: its CoC fill and colour diffusions
         * carry heat capacities (a matte), which Thomas's precision choice reads too. */
        ddof_params_init(&p);
        p.background = DDOF_LAYER_ON;
        p.kernel = ch % 2 ? DDOF_KERNEL_HEAT : p.kernel; /* the colour through Thomas too */
        worst = rows_differing_when_moved(ctx, &p, 1, color, wide_coc, w, h, ch);
        CHECK_MSG(worst == 0, "layered, %u channels: %zu rows differ with the output moved", ch,
                  worst);
        /* Thomas's precision on the column pass across the switch. Chosen per block, a line's
         * precision followed where the blocks fell (14 of 15 offsets differed); it is chosen
         * for the whole pass. Columns of 64 px, so that float and double differ. */
        p = params_for(DDOF_SOLVER_THOMAS, 1);
        worst = rows_differing_when_moved(ctx, &p, 0, color, ramp_coc, w, tall, ch);
        CHECK_MSG(worst == 0, "CoC to 4000 px, %u channels: %zu rows differ with the output moved",
                  ch, worst);
    }
    free(coc);
    free(wide_coc);
    free(ramp_coc);
    free(color);
}

typedef struct progress_log {
    int calls;
    float first, last;
    int decreasing, out_of_range, wrong_thread;
    int cancel_at; /* cancel on this call (1-based); 0 never */
    pthread_t caller;
} progress_log;

static int progress_cb(void *user, float fraction)
{
    progress_log *log = user;
    log->calls++;
    if (!pthread_equal(pthread_self(), log->caller))
        log->wrong_thread++;
    if (!(fraction >= 0.0f && fraction <= 1.0f))
        log->out_of_range++;
    if (log->calls == 1)
        log->first = fraction;
    else if (fraction < log->last)
        log->decreasing++;
    log->last = fraction;
    return log->cancel_at && log->calls >= log->cancel_at;
}

static void test_progress(void)
{
    test_rng rng = {8};
    test_image im = image_alloc(test_quick() ? 96 : 256, test_quick() ? 80 : 256, 4);
    fill_uniform(im.color, im.n, &rng, 0.0, 1.0);
    fill_coc(im.coc, im.px, &rng, 40.0, 0.1);
    ddof_context *ctx = make_context(2);
    for (int solver = 0; solver < TEST_CPU_SOLVER_COUNT; solver++) {
        progress_log log;
        memset(&log, 0, sizeof log);
        log.caller = pthread_self();
        ddof_params p = params_for((ddof_solver)solver, 3);
        p.progress = progress_cb;
        p.progress_user = &log;
        CHECK_EQ_INT(image_diffuse(ctx, &p, &im, NULL), DDOF_OK);
        CHECK_MSG(log.calls >= 2, "solver %s: progress called %d times",
                  ddof_solver_name((ddof_solver)solver), log.calls);
        CHECK_EQ_INT(log.decreasing, 0);
        CHECK_EQ_INT(log.out_of_range, 0);
        CHECK_EQ_INT(log.wrong_thread, 0);
        CHECK_MSG(log.last >= 0.99f, "solver %s: last progress %g",
                  ddof_solver_name((ddof_solver)solver), (double)log.last);

        /* Cancel at the first and at the second report. */
        for (int at = 1; at <= 2; at++) {
            memset(&log, 0, sizeof log);
            log.caller = pthread_self();
            log.cancel_at = at;
            fill_const(im.out, im.n, NAN); /* e.g. uninitialised memory: must not survive */
            ddof_status s = image_diffuse(ctx, &p, &im, NULL);
            CHECK_MSG(s == DDOF_ERROR_CANCELLED, "solver %s, cancel at call %d: status %d",
                      ddof_solver_name((ddof_solver)solver), at, (int)s);
            CHECK_MSG(all_finite(im.out, im.n), "solver %s, cancel at call %d: output not finite",
                      ddof_solver_name((ddof_solver)solver), at);
            CHECK(ddof_context_last_error(ctx)[0] != '\0');
        }
        /* The context still works after a cancel. */
        p.progress = NULL;
        CHECK_EQ_INT(image_diffuse(ctx, &p, &im, NULL), DDOF_OK);
        CHECK(ddof_context_last_error(ctx)[0] == '\0');
    }
    ddof_context_free(ctx);
    image_free(&im);
}

int main(void)
{
    ddof_context *ctx = make_context(2);
    test_in_place(ctx);
    test_thread_counts();
    test_stats(ctx);
    test_strides_and_channels(ctx);
    test_output_alignment(ctx);
    test_progress();
    ddof_context_free(ctx);
    return test_report("test_invariants_calls");
}
