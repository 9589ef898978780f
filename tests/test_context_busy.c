/* SPDX-License-Identifier: MIT */
/* test_context_busy.c - one context used by two calls at once (issue 22): the second call,
 * from another thread or from the progress callback, gets DDOF_ERROR_CONTEXT_BUSY and
 * touches nothing; the running call finishes with the right pixels, and the context is free
 * again afterwards. The second thread's call is made while the first is held inside its
 * progress callback, so the overlap is certain, not a matter of timing. ddof_render_cards
 * too (issue 40: it once ran unguarded, deadlocking from the callback and drawing wrong pixels
 * beside another thread's call). */
#ifndef DDOF_EXPERIMENTAL
#define DDOF_EXPERIMENTAL
#endif
#include "test_util.h"

#include <ddof.h>

#include <pthread.h>
#include <string.h>

enum { W = 64, H = 48, N = W * H };

static float color[N * 4], coc[N], out[N * 4], want[N * 4], other_out[N * 4];
static float texture[16 * 16 * 4], cards_out[N * 4];
static ddof_context *ctx;

typedef struct race {
    pthread_mutex_t lock;
    pthread_cond_t changed;
    int asked, answered, done;
    ddof_status second[5];  /* the other thread's calls while the first one ran */
    ddof_status reentrant;  /* a call from inside the progress callback */
    ddof_status reentrant_cards;
} race;

/* One card over the frame, into cards_out. */
static ddof_status render_card(void)
{
    ddof_camera cam;
    ddof_camera_init(&cam);
    const ddof_card card = {.vertex_count = 4,
                            .position = {{-1, -1, -2}, {1, -1, -2}, {1, 1, -2.5f}, {-1, 1, -2.5f}},
                            .uv = {{0, 0}, {1, 0}, {1, 1}, {0, 1}},
                            .texture = {texture, 16, 16, 4, 0}};
    return ddof_render_cards(ctx, NULL, &cam, &card, 1, &(ddof_image){cards_out, W, H, 4, 0});
}

static void *other_thread(void *user)
{
    race *r = user;
    pthread_mutex_lock(&r->lock);
    while (!r->asked)
        pthread_cond_wait(&r->changed, &r->lock);
    pthread_mutex_unlock(&r->lock);
    /* The first call is inside its progress callback now. */
    ddof_params p;
    ddof_params_init(&p);
    ddof_camera cam;
    ddof_camera_init(&cam);
    cam.focal_length_mm = 50;
    cam.fstop = 2;
    cam.focus_distance_m = 3;
    for (int i = 0; i < N * 4; i++)
        other_out[i] = -5.0f;
    r->second[0] = ddof_diffuse(ctx, &p, &(ddof_image_in){color, W, H, 4, 0},
                                &(ddof_image_in){coc, W, H, 1, 0},
                                &(ddof_image){other_out, W, H, 4, 0}, NULL);
    r->second[1] = ddof_params_check(ctx, &p);
    r->second[2] = ddof_camera_check(ctx, &cam);
    r->second[3] = ddof_context_set_backend(ctx, DDOF_BACKEND_CPU, NULL);
    r->second[4] = render_card();
    pthread_mutex_lock(&r->lock);
    r->answered = 1;
    pthread_cond_broadcast(&r->changed);
    pthread_mutex_unlock(&r->lock);
    return NULL;
}

static int progress(void *user, float fraction)
{
    race *r = user;
    (void)fraction;
    if (r->done)
        return 0;
    r->done = 1;
    ddof_params p;
    ddof_params_init(&p);
    r->reentrant = ddof_params_check(ctx, &p);
    r->reentrant_cards = render_card();
    pthread_mutex_lock(&r->lock);
    r->asked = 1;
    pthread_cond_broadcast(&r->changed);
    while (!r->answered)
        pthread_cond_wait(&r->changed, &r->lock);
    pthread_mutex_unlock(&r->lock);
    return 0;
}

int main(void)
{
    for (int i = 0; i < N; i++) {
        const int x = i % W, y = i / W;
        for (int c = 0; c < 3; c++)
            color[i * 4 + c] = (float)((x * 7 + y * 3 + c * 11) % 17) / 17.0f;
        color[i * 4 + 3] = 1.0f;
        coc[i] = 2.0f + (float)(x % 9);
        cards_out[i * 4] = cards_out[i * 4 + 1] = cards_out[i * 4 + 2] = -5.0f;
        cards_out[i * 4 + 3] = -5.0f;
    }
    for (int i = 0; i < 16 * 16 * 4; i++)
        texture[i] = (i % 4 == 3) ? 1.0f : (float)(i % 9) / 8.0f;
    ddof_context_options co;
    ddof_context_options_init(&co);
    co.thread_count = 2;
    CHECK(ddof_context_create(&co, &ctx) == DDOF_OK);
    ddof_params p;
    ddof_params_init(&p);
    CHECK(ddof_diffuse(ctx, &p, &(ddof_image_in){color, W, H, 4, 0},
                       &(ddof_image_in){coc, W, H, 1, 0}, &(ddof_image){want, W, H, 4, 0},
                       NULL) == DDOF_OK);

    race r = {.lock = PTHREAD_MUTEX_INITIALIZER, .changed = PTHREAD_COND_INITIALIZER};
    pthread_t thread;
    CHECK(pthread_create(&thread, NULL, other_thread, &r) == 0);
    ddof_params q = p;
    q.progress = progress;
    q.progress_user = &r;
    const ddof_status first = ddof_diffuse(ctx, &q, &(ddof_image_in){color, W, H, 4, 0},
                                           &(ddof_image_in){coc, W, H, 1, 0},
                                           &(ddof_image){out, W, H, 4, 0}, NULL);
    pthread_join(thread, NULL);
    CHECK_MSG(first == DDOF_OK, "the first call: %d (%s)", (int)first,
              ddof_context_last_error(ctx));
    CHECK(r.done);
    CHECK_MSG(memcmp(out, want, sizeof out) == 0, "the first call's pixels changed");
    for (int k = 0; k < 5; k++)
        CHECK_MSG(r.second[k] == DDOF_ERROR_CONTEXT_BUSY, "the other thread's call %d: %d", k,
                  (int)r.second[k]);
    CHECK_MSG(r.reentrant == DDOF_ERROR_CONTEXT_BUSY, "a call from the callback: %d",
              (int)r.reentrant);
    CHECK_MSG(r.reentrant_cards == DDOF_ERROR_CONTEXT_BUSY, "cards from the callback: %d",
              (int)r.reentrant_cards);
    int touched = 0;
    for (int i = 0; i < N * 4; i++)
        touched += (other_out[i] != -5.0f) + (cards_out[i] != -5.0f);
    CHECK_MSG(touched == 0, "the refused call wrote %d values", touched);
    CHECK(strstr(ddof_status_string(DDOF_ERROR_CONTEXT_BUSY), "one context per thread"));

    /* Free again: every kind of call works, and a failure still says why. */
    CHECK(ddof_params_check(ctx, &p) == DDOF_OK);
    CHECK(ddof_diffuse(ctx, &p, &(ddof_image_in){color, W, H, 4, 0},
                       &(ddof_image_in){coc, W, H, 1, 0}, &(ddof_image){other_out, W, H, 4, 0},
                       NULL) == DDOF_OK);
    CHECK(memcmp(other_out, want, sizeof want) == 0);
    CHECK(render_card() == DDOF_OK);
    CHECK(cards_out[(H / 2 * W + W / 2) * 4 + 3] > 0.5f);
    q = p;
    q.substeps = 0;
    CHECK(ddof_params_check(ctx, &q) == DDOF_ERROR_BAD_PARAMETER);
    CHECK(strlen(ddof_context_last_error(ctx)) > 10);
    CHECK(ddof_render_frame(NULL, &p, NULL, NULL, NULL) == DDOF_ERROR_NULL_POINTER);
    ddof_context_free(ctx);
    return test_report("test_context_busy");
}
