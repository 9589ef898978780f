/* SPDX-License-Identifier: MIT */
/* test_enum_width.c - ddof.h's enums stay 32 bits wide when a caller's compiler packs enums
 * (this file is built with -fshort-enums where the compiler has it: tests/CMakeLists.txt), so
 * the structs such a caller fills have the library's layout: the defaults it gets pass the
 * library's checks and a frame renders. */
#include "test_util.h"

#include <ddof.h>

int main(void)
{
    CHECK_EQ_INT(sizeof(ddof_status), 4);
    CHECK_EQ_INT(sizeof(ddof_solver), 4);
    CHECK_EQ_INT(sizeof(ddof_layer_mode), 4);
    CHECK_EQ_INT(sizeof(ddof_lens_model), 4);
    CHECK_EQ_INT(sizeof(ddof_backend_kind), 4);
    CHECK_EQ_INT(sizeof(ddof_cards_expansion), 4);
    ddof_context *ctx = NULL;
    CHECK(ddof_context_create(NULL, &ctx) == DDOF_OK);
    ddof_params p;
    ddof_params_init(&p);
    CHECK_EQ_INT(p.struct_size, sizeof p);
    p.near_layer = DDOF_LAYER_OFF;
    CHECK_EQ_INT(ddof_params_check(ctx, &p), DDOF_OK);
    ddof_camera cam;
    ddof_camera_init(&cam);
    cam.focus_distance_m = 2.0;
    cam.sensor_fit = DDOF_SENSOR_FIT_HORIZONTAL;
    CHECK_EQ_INT(ddof_camera_check(ctx, &cam), DDOF_OK);
    enum { W = 16, H = 8 };
    static float color[W * H * 4], depth[W * H], out[W * H * 4];
    for (int i = 0; i < W * H; i++) {
        depth[i] = 1.0f + (float)(i % W);
        for (int c = 0; c < 4; c++)
            color[i * 4 + c] = c == 3 ? 1.0f : (float)((i + c) % 5) / 5.0f;
    }
    ddof_stats st = {.struct_size = sizeof st};
    CHECK_EQ_INT(ddof_depth_of_field(ctx, &p, &cam, &(ddof_image_in){color, W, H, 4, 0},
                                     &(ddof_image_in){depth, W, H, 1, 0},
                                     &(ddof_image){out, W, H, 4, 0}, &st),
                 DDOF_OK);
    CHECK(st.max_coc_px > 0.0f);
    ddof_context_free(ctx);
    return test_report("test_enum_width");
}
