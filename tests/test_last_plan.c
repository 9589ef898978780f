/* SPDX-License-Identifier: MIT */
/* test_last_plan.c - ddof_context_last_plan: the whole plan of the context's last call, where
 * ddof_stats.plan (512 bytes) is cut. A frame with every pass on says more than 512 bytes; the
 * stats keep its first whole lines and the mark, the context all of them (the passes' own
 * lines, said last, included). A call that plans nothing, or fails before its plan, leaves "". */
#include "test_util.h"

#include <ddof.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { W = 64, H = 48, N = W * H, CH = 3 };

static const char cut_mark[] = "(the plan goes on)\n";

/* Two blurred backgrounds meeting (CoC 9 and 20 px) with bright points in them, an in-focus
 * bar before them and a near disc (CoC -20 px) over the bar's end: every pass has work. */
static void make_scene(float *color, float *coc)
{
    test_rng rng = {777u};
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const int i = y * W + x;
            for (int c = 0; c < CH; c++)
                color[i * CH + c] = 0.2f + 0.3f * (float)test_uniform(&rng);
            coc[i] = y < H / 2 ? 20.0f : 9.0f;
            if ((x * 7 + y * 3) % 23 == 0)
                color[i * CH] = 30.0f;
            if (x >= 20 && x < 28 && y >= 6 && y < 42)
                coc[i] = 0.0f;
            const float dx = (float)x - 26.0f, dy = (float)y - 36.0f;
            if (dx * dx + dy * dy < 64.0f)
                coc[i] = -20.0f;
        }
}

static ddof_status render(ddof_context *ctx, const ddof_params *p, const float *color,
                          const float *coc, float *out, ddof_stats *st)
{
    ddof_camera camera;
    ddof_camera_init(&camera);
    camera.aperture_blades = 5; /* the highlights' line names the polygon */
    ddof_frame f;
    ddof_frame_init(&f);
    f.color = (ddof_image_in){color, W, H, CH, 0};
    f.coc = (ddof_image_in){coc, W, H, 1, 0};
    f.camera = &camera;
    return ddof_render_frame(ctx, p, &f, &(ddof_image){out, W, H, CH, 0}, st);
}

static ddof_params every_pass(void)
{
    ddof_params p;
    ddof_params_init(&p);
    p.coc_signed = 1;
    p.highlights = DDOF_LAYER_ON;
    p.far_field = DDOF_LAYER_ON;
    p.blurred_edges = DDOF_LAYER_ON;
    p.silhouettes = DDOF_LAYER_ON;
    return p;
}

static int has_line(const char *plan, const char *start)
{
    for (const char *line = plan; *line;) {
        if (strncmp(line, start, strlen(start)) == 0)
            return 1;
        const char *end = strchr(line, '\n');
        if (!end)
            break;
        line = end + 1;
    }
    return 0;
}

static void long_plan_kept_whole(ddof_context *ctx, const float *color, const float *coc,
                                 float *out)
{
    ddof_params p = every_pass();
    ddof_stats st = {.struct_size = sizeof st};
    CHECK_EQ_INT(render(ctx, &p, color, coc, out, &st), DDOF_OK);
    const char *whole = ddof_context_last_plan(ctx);
    const size_t length = strlen(whole), kept = strlen(st.plan);
    const char *verbose = getenv("DDOF_TEST_VERBOSE");
    if (verbose && verbose[0] && verbose[0] != '0')
        printf("whole plan, %zu bytes:\n%s", length, whole);
    CHECK_MSG(length >= sizeof st.plan, "the plan (%zu bytes) fits the stats: no test", length);
    static const char *const lines[] = {"midground:", "background:", "near layer:",
                                        "foreground:", "highlights:", "far field:",
                                        "silhouettes:"};
    for (size_t i = 0; i < sizeof lines / sizeof *lines; i++)
        CHECK_MSG(has_line(whole, lines[i]), "no \"%s\" in the whole plan:\n%s", lines[i], whole);
    CHECK_MSG(strstr(whole, "(the plan goes on)") == NULL, "the whole plan is cut:\n%s", whole);
    /* The stats: its first whole lines, then the mark, within 512 bytes. */
    CHECK_MSG(kept < sizeof st.plan && kept > sizeof cut_mark &&
                  strcmp(st.plan + kept - strlen(cut_mark), cut_mark) == 0,
              "the stats' plan is not marked as cut:\n%s", st.plan);
    const size_t lines_kept = kept - strlen(cut_mark);
    CHECK_MSG(strncmp(st.plan, whole, lines_kept) == 0 && whole[lines_kept - 1] == '\n',
              "the stats' plan is not the whole plan's first lines:\n%s", st.plan);
    CHECK_MSG(!has_line(st.plan, "silhouettes:"), "the stats' plan held every line: no test");

    /* Without stats the context keeps it too; the next call on the context replaces it. */
    char first[DDOF_PLAN_MAX_BYTES];
    snprintf(first, sizeof first, "%s", whole);
    CHECK_EQ_INT(render(ctx, &p, color, coc, out, NULL), DDOF_OK);
    CHECK_MSG(strcmp(ddof_context_last_plan(ctx), first) == 0, "without stats: \"%s\"",
              ddof_context_last_plan(ctx));
    p.silhouettes = DDOF_LAYER_OFF;
    CHECK_EQ_INT(render(ctx, &p, color, coc, out, NULL), DDOF_OK);
    CHECK_MSG(strstr(ddof_context_last_plan(ctx), "silhouettes: forced off") != NULL,
              "the next call's plan: \"%s\"", ddof_context_last_plan(ctx));
}

/* A failed call, and calls that plan nothing, leave no plan behind them. */
static void no_plan_left(ddof_context *ctx, const float *color, const float *coc, float *out)
{
    ddof_params p = every_pass();
    CHECK_EQ_INT(render(ctx, &p, color, coc, out, NULL), DDOF_OK);
    CHECK(ddof_context_last_plan(ctx)[0] != '\0');
    p.beta_scale = -1.0f;
    CHECK_EQ_INT(render(ctx, &p, color, coc, out, NULL), DDOF_ERROR_BAD_PARAMETER);
    CHECK_MSG(ddof_context_last_plan(ctx)[0] == '\0', "after a failed call: \"%s\"",
              ddof_context_last_plan(ctx));

    p = every_pass();
    CHECK_EQ_INT(render(ctx, &p, color, coc, out, NULL), DDOF_OK);
    float *mag = malloc(sizeof(float) * N);
    for (int i = 0; i < N; i++)
        mag[i] = coc[i] < 0.0f ? -coc[i] : coc[i];
    ddof_params plain;
    ddof_params_init(&plain);
    CHECK_EQ_INT(ddof_diffuse(ctx, &plain, &(ddof_image_in){color, W, H, CH, 0},
                              &(ddof_image_in){mag, W, H, 1, 0}, &(ddof_image){out, W, H, CH, 0},
                              NULL),
                 DDOF_OK);
    CHECK_MSG(ddof_context_last_plan(ctx)[0] == '\0', "after ddof_diffuse: \"%s\"",
              ddof_context_last_plan(ctx));
    free(mag);

    /* The preview's plan is its one line, unterminated, as in the stats. */
    p.method = DDOF_METHOD_COD4_PREVIEW;
    ddof_stats st = {.struct_size = sizeof st};
    CHECK_EQ_INT(render(ctx, &p, color, coc, out, &st), DDOF_OK);
    CHECK_MSG(strcmp(ddof_context_last_plan(ctx), st.plan) == 0 &&
                  strncmp(st.plan, "preview:", 8) == 0 && !strchr(st.plan, '\n'),
              "the preview's plan \"%s\", the stats' \"%s\"", ddof_context_last_plan(ctx),
              st.plan);
    CHECK_MSG(strcmp(ddof_context_last_plan(NULL), "") == 0, "a NULL context's plan");
}

int main(void)
{
    float *color = malloc(sizeof(float) * N * CH), *coc = malloc(sizeof(float) * N);
    float *out = malloc(sizeof(float) * N * CH);
    make_scene(color, coc);
    ddof_context *ctx = NULL;
    ddof_context_options options;
    ddof_context_options_init(&options);
    options.thread_count = 2;
    CHECK_EQ_INT(ddof_context_create(&options, &ctx), DDOF_OK);
    CHECK_MSG(strcmp(ddof_context_last_plan(ctx), "") == 0, "a new context's plan");
    long_plan_kept_whole(ctx, color, coc, out);
    no_plan_left(ctx, color, coc, out);
    ddof_context_free(ctx);
    free(color);
    free(coc);
    free(out);
    return test_report("last_plan");
}
