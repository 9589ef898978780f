/* SPDX-License-Identifier: MIT */
/* test_preview_cod4_calls.c - the CoD4 preview through the public entry points: what each call
 * takes and refuses (the foreground element among it), progress and cancellation, running out
 * of memory (the invariants and the blur's shape: test_preview_cod4.c). */
#include "preview_cod4_test.h"

#include <pthread.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------------------------------------- */
/* The public entry points                                                                    */

static void test_api(ddof_context *ctx)
{
    const uint32_t w = 64, h = 48, ch = 4;
    test_rng rng = {12};
    test_image im = image_alloc(w, h, ch);
    block_texture(im.color, w, h, ch, 5, 0.0, 1.0);
    fill_signed_coc(im.coc, im.px, &rng, 20.0, 0.3, 0.5);
    ddof_params p = preview_params(1);
    p.solver = DDOF_SOLVER_JACOBI; /* ignored */
    p.substeps = 7;
    ddof_stats st = stats_init();
    CHECK_EQ_INT(diffuse(ctx, &p, im.color, im.coc, im.out, w, h, ch, &st), DDOF_OK);
    CHECK_EQ_INT(st.method, DDOF_METHOD_COD4_PREVIEW);
    CHECK_EQ_INT(st.backend, DDOF_BACKEND_CPU);
    CHECK_EQ_INT(st.threads, ddof_context_thread_count(ctx));
    CHECK(st.seconds_rows > 0.0 && st.seconds_total >= st.seconds_rows);
    CHECK(st.host_bytes > 0);
    float *out2 = alloc_f(im.n);

    /* ddof_diffuse_layers: the same image */
    st = stats_init();
    CHECK_EQ_INT(diffuse_layers(ctx, &p, im.color, im.coc, NULL, out2, w, h, ch, &st), DDOF_OK);
    CHECK_EQ_INT(st.method, DDOF_METHOD_COD4_PREVIEW);
    CHECK(!memcmp(out2, im.out, im.n * sizeof(float)));

    /* a foreground element: unsupported, out untouched */
    float *fg_color = alloc_f(im.n), *fg_coc = alloc_f(im.px);
    fill_const(fg_color, im.n, 0.5f);
    fill_const(fg_coc, im.px, 3.0f);
    ddof_foreground fg;
    ddof_foreground_init(&fg);
    fg.color = (ddof_image_in){fg_color, w, h, 4, 0};
    fg.coc = (ddof_image_in){fg_coc, w, h, 1, 0};
    fill_const(out2, im.n, 42.0f);
    ddof_status s = diffuse_layers(ctx, &p, im.color, im.coc, &fg, out2, w, h, ch, NULL);
    CHECK_EQ_INT(s, DDOF_ERROR_UNSUPPORTED);
    CHECK(ddof_context_last_error(ctx)[0] != '\0');
    size_t touched = 0;
    for (size_t i = 0; i < im.n; i++)
        touched += out2[i] != 42.0f;
    CHECK_EQ_INT(touched, 0);

    /* bad input is still rejected before anything runs */
    im.coc[5] = NAN;
    CHECK_EQ_INT(diffuse(ctx, &p, im.color, im.coc, out2, w, h, ch, NULL), DDOF_ERROR_BAD_COC);
    im.coc[5] = -3.0f;
    p.coc_signed = 0;
    CHECK_EQ_INT(diffuse(ctx, &p, im.color, im.coc, out2, w, h, ch, NULL), DDOF_ERROR_BAD_COC);
    touched = 0;
    for (size_t i = 0; i < im.n; i++)
        touched += out2[i] != 42.0f;
    CHECK_EQ_INT(touched, 0);

    /* ddof_depth_of_field: signed CoC from the camera; a near disc over a far wall */
    float *depth = alloc_f(im.px);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            const double dx = x - 32.0, dy = y - 24.0;
            depth[(size_t)y * w + x] = dx * dx + dy * dy < 100.0 ? 0.5f : 10.0f;
        }
    ddof_camera cam;
    ddof_camera_init(&cam);
    cam.fstop = 1.4;
    ddof_params pd = preview_params(0); /* ddof_depth_of_field signs the CoC itself */
    ddof_image_in ci = {im.color, w, h, ch, 0}, di = {depth, w, h, 1, 0};
    ddof_image oi = {out2, w, h, ch, 0};
    st = stats_init();
    CHECK_EQ_INT(ddof_depth_of_field(ctx, &pd, &cam, &ci, &di, &oi, &st), DDOF_OK);
    CHECK_EQ_INT(st.method, DDOF_METHOD_COD4_PREVIEW);
    CHECK(st.max_coc_px > 1.0f);
    CHECK(outside_range(im.color, out2, im.px, ch) == 0);
    /* the same as the camera's signed CoC through ddof_diffuse */
    ddof_image co = {im.coc, w, h, 1, 0};
    cam.signed_coc = 1;
    CHECK_EQ_INT(ddof_coc_from_camera(ctx, &cam, &di, &co), DDOF_OK);
    CHECK_EQ_INT(preview(ctx, 1, im.color, im.coc, im.out, w, h, ch, NULL), DDOF_OK);
    CHECK_MSG(!memcmp(out2, im.out, im.n * sizeof(float)),
              "depth_of_field vs camera CoC + ddof_diffuse: %g", max_abs_diff_ff(out2, im.out, im.n));
    free(depth);
    free(fg_color);
    free(fg_coc);
    free(out2);
    image_free(&im);
}

/* ---------------------------------------------------------------------------------------- */
/* Progress, cancellation, memory                                                             */

typedef struct progress_log {
    int calls, decreasing, out_of_range, wrong_thread, cancel_at;
    float last;
    pthread_t caller;
} progress_log;

static int on_progress(void *user, float fraction)
{
    progress_log *log = user;
    log->calls++;
    if (!pthread_equal(pthread_self(), log->caller))
        log->wrong_thread++;
    if (!(fraction >= 0.0f && fraction <= 1.0f))
        log->out_of_range++;
    if (log->calls > 1 && fraction < log->last)
        log->decreasing++;
    log->last = fraction;
    return log->cancel_at && log->calls >= log->cancel_at;
}

static void test_progress_cancel(ddof_context *ctx)
{
    const uint32_t w = 90, h = 70, ch = 4;
    test_rng rng = {21};
    test_image im = image_alloc(w, h, ch);
    fill_uniform(im.color, im.n, &rng, 0.0, 1.0);
    fill_signed_coc(im.coc, im.px, &rng, 30.0, 0.2, 0.5);
    ddof_params p = preview_params(1);
    progress_log log;
    memset(&log, 0, sizeof log);
    log.caller = pthread_self();
    p.progress = on_progress;
    p.progress_user = &log;
    CHECK_EQ_INT(diffuse(ctx, &p, im.color, im.coc, im.out, w, h, ch, NULL), DDOF_OK);
    CHECK_MSG(log.calls >= 2, "progress called %d times", log.calls);
    CHECK_EQ_INT(log.decreasing, 0);
    CHECK_EQ_INT(log.out_of_range, 0);
    CHECK_EQ_INT(log.wrong_thread, 0);
    CHECK(log.last == 1.0f);
    const int calls = log.calls;
    float *ref = alloc_f(im.n), *work = alloc_f(im.n);
    memcpy(ref, im.out, im.n * sizeof(float));

    /* Cancel at every report but the last: CANCELLED, out finite (the input). */
    for (int at = 1; at < calls; at++)
        for (int in_place = 0; in_place < 2; in_place++) {
            memset(&log, 0, sizeof log);
            log.caller = pthread_self();
            log.cancel_at = at;
            float *dst = in_place ? work : im.out;
            if (in_place)
                memcpy(work, im.color, im.n * sizeof(float));
            else
                fill_const(im.out, im.n, NAN);
            ddof_status s = diffuse(ctx, &p, in_place ? work : im.color, im.coc, dst, w, h, ch,
                                    NULL);
            CHECK_MSG(s == DDOF_ERROR_CANCELLED, "cancel at report %d: status %d", at, (int)s);
            CHECK_MSG(all_finite(dst, im.n), "cancel at report %d: output not finite", at);
            CHECK(ddof_context_last_error(ctx)[0] != '\0');
        }
    /* Cancelling at the last report (1.0) changes nothing. */
    memset(&log, 0, sizeof log);
    log.caller = pthread_self();
    log.cancel_at = calls;
    CHECK_EQ_INT(diffuse(ctx, &p, im.color, im.coc, im.out, w, h, ch, NULL), DDOF_OK);
    CHECK(!memcmp(ref, im.out, im.n * sizeof(float)));
    /* The context still works. */
    p.progress = NULL;
    CHECK_EQ_INT(diffuse(ctx, &p, im.color, im.coc, im.out, w, h, ch, NULL), DDOF_OK);
    CHECK(ddof_context_last_error(ctx)[0] == '\0');
    CHECK(!memcmp(ref, im.out, im.n * sizeof(float)));
    free(ref);
    free(work);
    image_free(&im);
}

typedef struct budget {
    long left; /* allocations that may still succeed; < 0: unlimited */
    long live;
} budget;

static void *b_alloc(void *user, size_t size)
{
    budget *b = user;
    if (b->left == 0)
        return NULL;
    if (b->left > 0)
        b->left--;
    void *p = malloc(size);
    b->live += p != NULL;
    return p;
}

static void b_free(void *user, void *ptr)
{
    budget *b = user;
    if (ptr) {
        b->live--;
        free(ptr);
    }
}

/* Out of memory at each of the preview's allocations: DDOF_ERROR_OUT_OF_MEMORY, out untouched;
 * then it works, and nothing leaks. */
static void test_out_of_memory(void)
{
    const uint32_t w = 70, h = 130, ch = 3;
    test_rng rng = {8};
    test_image im = image_alloc(w, h, ch);
    fill_uniform(im.color, im.n, &rng, 0.0, 1.0);
    fill_signed_coc(im.coc, im.px, &rng, 30.0, 0.2, 0.5);
    budget b = {-1, 0};
    ddof_allocator a = {b_alloc, b_free, &b};
    for (int in_place = 0; in_place < 2; in_place++)
        for (long k = 0; k < 6; k++) {
            ddof_context_options o;
            ddof_context_options_init(&o);
            o.allocator = &a;
            o.thread_count = 2;
            ddof_context *c = NULL;
            b.left = -1;
            CHECK_EQ_INT(ddof_context_create(&o, &c), DDOF_OK);
            if (!c)
                break;
            b.left = k;
            float *dst = in_place ? alloc_f(im.n) : im.out;
            if (in_place)
                memcpy(dst, im.color, im.n * sizeof(float));
            else
                fill_const(dst, im.n, 42.0f);
            ddof_params p = preview_params(1);
            ddof_image_in ci = {in_place ? dst : im.color, w, h, ch, 0};
            ddof_image_in zi = {im.coc, w, h, 1, 0};
            ddof_image oi = {dst, w, h, ch, 0};
            ddof_status s = ddof_diffuse(c, &p, &ci, &zi, &oi, NULL);
            size_t touched = 0;
            for (size_t i = 0; i < im.n; i++)
                touched += in_place ? dst[i] != im.color[i] : dst[i] != 42.0f;
            if (s == DDOF_OK) {
                CHECK_MSG(k >= 4, "in place %d: the preview needs only %ld allocations?",
                          in_place, k);
            } else {
                CHECK_MSG(s == DDOF_ERROR_OUT_OF_MEMORY, "allocation %ld fails: status %d", k,
                          (int)s);
                CHECK_MSG(touched == 0, "allocation %ld fails: %zu output values written", k,
                          touched);
                CHECK(ddof_context_last_error(c)[0] != '\0');
            }
            b.left = -1;
            CHECK_EQ_INT(ddof_diffuse(c, &p, &ci, &zi, &oi, NULL), DDOF_OK);
            ddof_context_free(c);
            if (in_place)
                free(dst);
            CHECK_MSG(b.live == 0, "%ld blocks leaked", b.live);
        }
    image_free(&im);
}

int main(void)
{
    ddof_context *ctx = make_context(2);
    test_api(ctx);
    test_progress_cancel(ctx);
    test_out_of_memory();
    ddof_context_free(ctx);
    return test_report("test_preview_cod4_calls");
}
