/* SPDX-License-Identifier: MIT */
/* main.c - a tiny outside program that uses the installed ddof library.
 *
 * It includes only <ddof.h>, checks that the header and the loaded library agree on the
 * version, computes CoC from a camera, runs depth of field on a small RGBA image (left half in
 * focus, right half far behind it with fine stripes) and checks the result. Standard C only, no
 * libm, so that `pkg-config --libs ddof` is all it needs. Returns non-zero on any failure. */
#include <ddof.h>

#include <stdio.h>
#include <string.h>

enum { W = 64, H = 32, C = 4 };

static int failures;

#define EXPECT(cond)                                                                        \
    do {                                                                                    \
        if (!(cond)) {                                                                      \
            fprintf(stderr, "consumer: %s:%d: failed: %s\n", __FILE__, __LINE__, #cond);    \
            failures++;                                                                     \
        }                                                                                   \
    } while (0)

static int is_finite(float v) { return v == v && v - v == 0.0f; }

static float absf(float v) { return v < 0.0f ? -v : v; }

int main(void)
{
    static float color[W * H * C], depth[W * H], coc[W * H], out[W * H * C], untouched[W * H * C];
    char expected_version[32];
    ddof_context_options options;
    ddof_context *context = NULL;
    ddof_camera camera;
    ddof_params params;
    ddof_stats stats;
    ddof_status status;
    float max_step = 0.0f;
    int x, y, c;

    /* The header this was compiled with and the library it loaded must be the same version. */
    EXPECT(ddof_version_number() == DDOF_VERSION_NUMBER);
    snprintf(expected_version, sizeof expected_version, "%d.%d.%d", DDOF_VERSION_MAJOR,
             DDOF_VERSION_MINOR, DDOF_VERSION_PATCH);
    EXPECT(strcmp(ddof_version_string(), expected_version) == 0);
    EXPECT(ddof_solver_name(DDOF_SOLVER_THOMAS) != NULL);

    ddof_context_options_init(&options);
    options.thread_count = 2;
    status = ddof_context_create(&options, &context);
    if (status != DDOF_OK || context == NULL) {
        fprintf(stderr, "consumer: ddof_context_create: %s\n", ddof_status_string(status));
        return 1;
    }

    /* Left half: flat colour at the focus distance. Right half: 1-pixel stripes at 30 m. */
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            float *p = &color[(y * W + x) * C];
            if (x < W / 2) {
                p[0] = 0.25f, p[1] = 0.5f, p[2] = 0.75f;
                depth[y * W + x] = 4.0f;
            } else {
                p[0] = p[1] = p[2] = (float)(x % 2);
                depth[y * W + x] = 30.0f;
            }
            p[3] = 1.0f;
        }
    }
    ddof_image_in color_in = {color, W, H, C, 0};
    ddof_image_in depth_in = {depth, W, H, 1, 0};
    ddof_image coc_img = {coc, W, H, 1, 0};
    ddof_image_in coc_in = {coc, W, H, 1, 0};
    ddof_image out_img = {out, W, H, C, 0};

    ddof_camera_init(&camera);
    camera.focal_length_mm = 200.0;
    camera.fstop = 2.0;
    camera.focus_distance_m = 4.0;

    status = ddof_coc_from_camera(context, &camera, &depth_in, &coc_img);
    EXPECT(status == DDOF_OK);
    EXPECT(coc[0] >= 0.0f && coc[0] < 1e-6f);     /* in focus */
    EXPECT(coc[W - 1] > 2.0f && is_finite(coc[W - 1])); /* far: several pixels */

    ddof_params_init(&params);
    memset(&stats, 0, sizeof stats);
    stats.struct_size = sizeof stats;
    status = ddof_depth_of_field(context, &params, &camera, &color_in, &depth_in, &out_img, &stats);
    if (status != DDOF_OK) {
        fprintf(stderr, "consumer: ddof_depth_of_field: %s (%s)\n", ddof_status_string(status),
                ddof_context_last_error(context));
        failures++;
    } else {
        EXPECT(stats.lines_solved > 0);
        EXPECT(stats.max_coc_px > 2.0f);
        for (y = 0; y < H; y++) {
            for (x = 0; x < W; x++) {
                const float *p = &out[(y * W + x) * C];
                for (c = 0; c < C; c++)
                    EXPECT(is_finite(p[c]) && p[c] >= -1e-6f && p[c] <= 1.0f + 1e-6f);
                EXPECT(absf(p[3] - 1.0f) < 1e-5f);
                if (x < W / 2 - 4) /* in focus, away from the edge: unchanged */
                    EXPECT(absf(p[0] - 0.25f) < 1e-6f && absf(p[2] - 0.75f) < 1e-6f);
                if (x > W / 2 + 4 && x < W - 1) { /* blurred: stripe contrast mostly gone */
                    float step = absf(p[0] - p[C]);
                    if (step > max_step)
                        max_step = step;
                }
            }
        }
        EXPECT(max_step < 0.5f);
    }

    /* A bad call reports an error and leaves the output alone. */
    memcpy(untouched, out, sizeof out);
    status = ddof_diffuse(context, NULL, &color_in, &coc_in, &out_img, NULL);
    EXPECT(status == DDOF_ERROR_NULL_POINTER);
    EXPECT(ddof_status_string(status) != NULL && ddof_status_string(status)[0] != '\0');
    EXPECT(ddof_context_last_error(context) != NULL);
    EXPECT(memcmp(untouched, out, sizeof out) == 0);

    ddof_context_free(context);

    if (failures) {
        fprintf(stderr, "consumer: %d check(s) failed\n", failures);
        return 1;
    }
    printf("consumer: ddof %s: %llu lines solved, max CoC %.2f px, stripe step %.3f: ok\n",
           ddof_version_string(), (unsigned long long)stats.lines_solved, (double)stats.max_coc_px,
           (double)max_step);
    return 0;
}
