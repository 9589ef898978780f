/* SPDX-License-Identifier: MIT */
/* test_backend_tables.c - every backend a whole table, and the core asking only what the
 * context's device takes: the CPU's table fills every entry; a plugin whose table lacks one is
 * refused when loaded; the cards go to the device that draws them and to the CPU's table
 * where the device says it does not (the same image, bit for bit, as a CPU context's). The
 * plugins are tests/backend/stub_backend.c, built whole and with render_cards missing. */
#include "backends/backend.h"
#include "cpu/backend_cpu.h"
#include "test_util.h"

#include <string.h>

#define W 40
#define H 24
#define TW 8
#define TH 8

static float texture[TW * TH * 4];

static ddof_card test_card(void)
{
    ddof_card card;
    memset(&card, 0, sizeof card);
    card.vertex_count = 4;
    const float corners[4][3] = {{-0.1f, -0.05f, -0.6f}, {0.1f, -0.05f, -0.6f},
                                 {0.1f, 0.05f, -0.4f}, {-0.1f, 0.05f, -0.4f}};
    const float uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    memcpy(card.position, corners, sizeof corners);
    memcpy(card.uv, uv, sizeof uv);
    card.texture = (ddof_image_in){texture, TW, TH, 4, 0};
    return card;
}

static ddof_status render(ddof_context *ctx, float *out)
{
    ddof_camera cam;
    ddof_camera_init(&cam);
    cam.fstop = 1.4;
    cam.focus_distance_m = 0.5;
    const ddof_card card = test_card();
    ddof_image img = {out, W, H, 4, 0};
    return ddof_render_cards(ctx, NULL, &cam, &card, 1, &img);
}

int main(void)
{
    test_rng rng = {7};
    for (int i = 0; i < TW * TH * 4; i++)
        texture[i] = (float)test_uniform(&rng);
    for (int i = 0; i < TW * TH; i++)
        for (int c = 0; c < 3; c++) /* premultiplied: colour no more than alpha */
            texture[i * 4 + c] *= texture[i * 4 + 3];

    /* The CPU's table is whole, of this ABI. */
    CHECK(ddof_backend_table_whole(&ddof_cpu_backend));
    CHECK_EQ_INT(ddof_cpu_backend.abi, DDOF_BACKEND_ABI);
    CHECK_EQ_INT(ddof_cpu_backend.table_size, sizeof(ddof_backend_table));
    /* It opens nothing: its device is the context. */
    char why[128] = "";
    CHECK(ddof_cpu_backend.open(DDOF_BACKEND_EGL, 0, why, sizeof why) == NULL && why[0]);

    ddof_context *cpu = NULL, *ctx = NULL;
    CHECK_EQ_INT(ddof_context_create(NULL, &cpu), DDOF_OK);
    CHECK_EQ_INT(ddof_context_create(NULL, &ctx), DDOF_OK);
    static float want[W * H * 4], got[W * H * 4];
    CHECK_EQ_INT(render(cpu, want), DDOF_OK);
    double drawn = 0.0;
    for (int i = 3; i < W * H * 4; i += 4)
        drawn += want[i];
    CHECK_MSG(drawn > 10.0, "the card covers %.3g pixels' alpha", drawn);

    /* A table with an entry missing is refused, and the context stays on the CPU. */
    CHECK_EQ_INT(ddof_context_set_backend(ctx, DDOF_BACKEND_EGL, STUB_PARTIAL_PLUGIN),
                 DDOF_ERROR_BACKEND_UNAVAILABLE);
    CHECK_MSG(strstr(ddof_context_last_error(ctx), "not built for this libddof") != NULL, "%s",
              ddof_context_last_error(ctx));
    ddof_backend_info info = {.struct_size = sizeof info};
    CHECK_EQ_INT(ddof_context_backend_info(ctx, &info), DDOF_OK);
    CHECK_EQ_INT(info.kind, DDOF_BACKEND_CPU);

    /* A device that draws cards draws them: the stub's mark everywhere. */
    CHECK_EQ_INT(ddof_context_set_backend(ctx, DDOF_BACKEND_EGL, STUB_WHOLE_PLUGIN), DDOF_OK);
    CHECK_EQ_INT(ddof_context_backend_info(ctx, &info), DDOF_OK);
    CHECK_MSG(strstr(info.renderer, "draws cards") != NULL, "%s", info.renderer);
    CHECK_EQ_INT(render(ctx, got), DDOF_OK);
    int marked = 1;
    for (int i = 0; i < W * H * 4; i++)
        marked &= got[i] == 0.25f;
    CHECK_MSG(marked, "the device that draws cards did not draw them");

    /* One that does not: the CPU's table draws, the same image as a CPU context's. */
    CHECK_EQ_INT(ddof_context_set_backend(ctx, DDOF_BACKEND_OSMESA, STUB_WHOLE_PLUGIN), DDOF_OK);
    memset(got, 0xff, sizeof got); /* NaN: every value must be written */
    CHECK_EQ_INT(render(ctx, got), DDOF_OK);
    CHECK_MSG(memcmp(got, want, sizeof got) == 0, "the CPU's table drew another image");

    /* The stub runs no diffusion: the call says so, with the backend's name. */
    const float coc[W * H] = {0};
    ddof_params p;
    ddof_params_init(&p);
    ddof_image_in color = {want, W, H, 4, 0}, cocs = {coc, W, H, 1, 0};
    ddof_image out = {got, W, H, 4, 0};
    CHECK_EQ_INT(ddof_diffuse(ctx, &p, &color, &cocs, &out, NULL), DDOF_ERROR_UNSUPPORTED);
    CHECK_MSG(strstr(ddof_context_last_error(ctx), "osmesa") != NULL, "%s",
              ddof_context_last_error(ctx));

    ddof_context_free(ctx);
    ddof_context_free(cpu);
    return test_report("test_backend_tables");
}
