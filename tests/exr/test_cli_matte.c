/* SPDX-License-Identifier: MIT */
/* test_cli_matte.c - the `ddof` command and a render's object matte (Cryptomatte channels):
 * found beside the colour and handed to the library (the result is the library's
 * ddof_render_frame_with_matte on the same data, bit for bit, and not the colours' split),
 * named in --list and --stats, turned off, and the files it cannot use refused with a reason.
 *
 * CASE: matte */
#include "cli_test.h"

#include "exrio.h"

#include <stdlib.h>
#include <string.h>

/* Two objects by depth: the near one (z < 4 m) and the rest; rank 0 is the pixel's object
 * with all of it, rank 1 the other with nothing. */
static void make_matte(const scene *s, float planes[4][N])
{
    const uint32_t near_id = 0x3f000001u, rest_id = 0x3f000002u;
    for (size_t i = 0; i < N; i++) {
        const int near = s->z[i] < 4.0f;
        const uint32_t first = near ? near_id : rest_id, second = near ? rest_id : near_id;
        memcpy(&planes[0][i], &first, sizeof first); /* r: rank 0's id  */
        planes[1][i] = 1.0f;                        /* g: its coverage */
        memcpy(&planes[2][i], &second, sizeof second); /* b: rank 1's id */
        planes[3][i] = 0.0f;                          /* a: its coverage */
    }
}

/* The scene with the matte under `layer` (its r, g, b, a: ids stored as `id_type`; `with_a`
 * 0 leaves the last channel out), and under `second` (NULL: none) a matte of other ids. */
static void write_with_matte(const char *path, const scene *s, float matte[4][N],
                             const char *layer, exrio_pixel_type id_type, int with_a,
                             const char *second)
{
    static char names[8][64];
    static float other[4][N];
    const char *all_names[13];
    exrio_pixel_type types[13];
    const void *planes[13];
    int count = 0;
    const char *base[5] = {"A", "B", "G", "R", "Z"};
    const float *base_planes[5] = {s->rgba[3], s->rgba[2], s->rgba[1], s->rgba[0], s->z};
    for (int c = 0; c < 5; c++) {
        all_names[count] = base[c];
        types[count] = EXRIO_FLOAT;
        planes[count++] = base_planes[c];
    }
    for (int c = 0; c < 4; c++) {
        if (c == 3 && !with_a)
            continue;
        snprintf(names[c], sizeof names[c], "%s00.%c", layer, "rgba"[c]);
        all_names[count] = names[c];
        types[count] = c % 2 == 0 ? id_type : EXRIO_FLOAT;
        planes[count++] = matte[c];
    }
    for (int c = 0; second && c < 4; c++) {
        for (size_t i = 0; i < N; i++) {
            const uint32_t id = 0x3e000000u + (uint32_t)(i % 7);
            if (c % 2 == 0)
                memcpy(&other[c][i], &id, sizeof id);
            else
                other[c][i] = 0.5f;
        }
        snprintf(names[4 + c], sizeof names[4 + c], "%s00.%c", second, "rgba"[c]);
        all_names[count] = names[4 + c];
        types[count] = EXRIO_FLOAT;
        planes[count++] = other[c];
    }
    const exrio_box box = test_box(0, 0, W, H);
    CHECK(test_write_exr(path, &box, NULL, count, all_names, types, planes,
                         EXRIO_COMPRESSION_NONE) == 0);
}

/* The library's result with the matte, as the command calls it. */
static void library_with_matte(const scene *s, float matte[4][N], float *out, ddof_stats *stats)
{
    static float color[N * 4], pairs[N * 4];
    for (size_t i = 0; i < N; i++)
        for (int c = 0; c < 4; c++) {
            color[i * 4 + (size_t)c] = s->rgba[c][i];
            pairs[i * 4 + (size_t)c] = matte[c][i];
        }
    ddof_camera camera;
    camera_50mm(&camera, 1.4, 3.0);
    camera.focal_length_mm = 200.0; /* the far wall's CoC about 10 px at this size */
    ddof_params params;
    ddof_params_init(&params);
    ddof_frame frame;
    ddof_frame_init(&frame);
    frame.color = (ddof_image_in){color, W, H, 4, 0};
    frame.depth = (ddof_image_in){s->z, W, H, 1, 0};
    frame.camera = &camera;
    ddof_context_options options;
    ddof_context_options_init(&options);
    options.thread_count = 1;
    ddof_context *ctx = NULL;
    CHECK(ddof_context_create(&options, &ctx) == DDOF_OK);
    CHECK(ddof_render_frame_with_matte(ctx, &params, &frame,
                                       &(ddof_image_in){pairs, W, H, 4, 0},
                                       &(ddof_image){out, W, H, 4, 0}, stats) == DDOF_OK);
    ddof_context_free(ctx);
}

static int case_matte(void)
{
    static scene s;
    static float matte[4][N], want[N * 4];
    const char *in = test_path(dir, "in.exr"), *json = test_path(dir, "camera.json");
    const char *camera =
        "{\"focal_length_mm\": 200, \"sensor_width_mm\": 36, \"sensor_fit\": \"AUTO\","
        " \"fstop\": 1.4, \"focus_distance_m\": 3.0, \"resolution\": [48, 32],"
        " \"pixel_aspect\": 1.0, \"depth\": \"planar\", \"unit_scale_m\": 1.0}";
    make_scene(&s, 0);
    make_matte(&s, matte);
    test_write_file(json, camera, strlen(camera));
    ddof_stats stats = {.struct_size = sizeof stats};
    library_with_matte(&s, matte, want, &stats);
    CHECK_MSG(stats.effects & DDOF_EFFECT_SILHOUETTES, "the scene has no silhouette to split: "
              "the test shows nothing\n%s", stats.plan);

    /* Found beside the colour, handed to the library: its result, bit for bit. */
    write_with_matte(in, &s, matte, "CryptoObject", EXRIO_FLOAT, 1, NULL);
    CHECK(ddof(in, "-o", test_path(dir, "auto.exr"), "--camera", json, "--pixel-type", "float",
               "--threads", "1", "--stats", test_path(dir, "auto.json"), NULL) == 0);
    CHECK(compare_output(test_path(dir, "auto.exr"), want, 1, 0.0, 0) == 0);
    char *text = test_read_file(test_path(dir, "auto.json"), NULL);
    CHECK(text && strstr(text, "\"matte\":") && strstr(text, "\"CryptoObject\""));
    free(text);
    CHECK(ddof(in, "--list", NULL) == 0);
    CHECK(out_contains("; matte CryptoObject (2 ranks)"));

    /* Off: the colours' split, as without the channels; named: the same as auto. */
    CHECK(ddof(in, "-o", test_path(dir, "off.exr"), "--camera", json, "--pixel-type", "float",
               "--matte", "off", "--stats", test_path(dir, "off.json"), NULL) == 0);
    text = test_read_file(test_path(dir, "off.json"), NULL);
    CHECK(text && !strstr(text, "\"matte\":"));
    free(text);
    write_scene(test_path(dir, "plain.exr"), &s, 0);
    CHECK(ddof(test_path(dir, "plain.exr"), "-o", test_path(dir, "plain_out.exr"), "--camera",
               json, "--pixel-type", "float", NULL) == 0);
    uint32_t w, h;
    float *off = test_read_channel(test_path(dir, "off.exr"), "R", &w, &h);
    float *plain = test_read_channel(test_path(dir, "plain_out.exr"), "R", &w, &h);
    float *with = test_read_channel(test_path(dir, "auto.exr"), "R", &w, &h);
    CHECK(off && plain && memcmp(off, plain, N * sizeof(float)) == 0);
    /* The matte's shares are not the colours': the two results differ. */
    CHECK(off && with && memcmp(off, with, N * sizeof(float)) != 0);
    free(off);
    free(plain);
    free(with);
    write_with_matte(in, &s, matte, "crypto_object", EXRIO_FLOAT, 1, NULL);
    CHECK(ddof(in, "-o", test_path(dir, "named.exr"), "--camera", json, "--pixel-type", "float",
               "--threads", "1", "--matte", "crypto_object", NULL) == 0);
    CHECK(compare_output(test_path(dir, "named.exr"), want, 1, 0.0, 0) == 0);
    /* Both spellings in one file: auto takes one layer whole, never channels of both. */
    write_with_matte(in, &s, matte, "CryptoObject", EXRIO_FLOAT, 1, "crypto_object");
    CHECK(ddof(in, "-o", test_path(dir, "both.exr"), "--camera", json, "--pixel-type", "float",
               "--threads", "1", NULL) == 0);
    CHECK(compare_output(test_path(dir, "both.exr"), want, 1, 0.0, 0) == 0);

    /* What it cannot use: a matte named but absent, ids in half floats, a channel missing. */
    CHECK(ddof(in, "-o", test_path(dir, "x.exr"), "--camera", json, "--matte", "CryptoAsset",
               NULL) != 0);
    CHECK(err_contains("no matte CryptoAsset"));
    write_with_matte(in, &s, matte, "CryptoObject", EXRIO_HALF, 1, NULL);
    CHECK(ddof(in, "-o", test_path(dir, "x.exr"), "--camera", json, NULL) != 0);
    CHECK(err_contains("only 32-bit float holds them"));
    write_with_matte(in, &s, matte, "CryptoObject", EXRIO_FLOAT, 0, NULL);
    CHECK(ddof(in, "-o", test_path(dir, "x.exr"), "--camera", json, NULL) != 0);
    CHECK(err_contains("sub-layer 00 without its a channel"));
    CHECK(!test_file_exists(test_path(dir, "x.exr")));
    return test_finish("test_cli matte");
}

/* The scene with CryptoObject sub-layers `subs` (e.g. {1}: 01 without 00) of the matte. */
static void write_subs(const char *path, const scene *s, float matte[4][N], const int *subs,
                       int count)
{
    static char names[8][64];
    const char *all_names[13] = {"A", "B", "G", "R", "Z"};
    exrio_pixel_type types[13];
    const void *planes[13] = {s->rgba[3], s->rgba[2], s->rgba[1], s->rgba[0], s->z};
    int n = 5;
    for (int c = 0; c < 13; c++)
        types[c] = EXRIO_FLOAT;
    for (int k = 0; k < count; k++)
        for (int c = 0; c < 4; c++) {
            snprintf(names[n - 5], sizeof names[0], "CryptoObject%02d.%c", subs[k], "rgba"[c]);
            all_names[n] = names[n - 5];
            planes[n++] = matte[c];
        }
    const exrio_box box = test_box(0, 0, W, H);
    CHECK(test_write_exr(path, &box, NULL, n, all_names, types, planes,
                         EXRIO_COMPRESSION_NONE) == 0);
}

/* A matte whose sub-layers do not run from 00 without a gap is refused, not ignored. */
static int case_matte_gap(void)
{
    static scene s;
    static float matte[4][N];
    const char *in = test_path(dir, "in.exr"), *json = test_path(dir, "camera.json");
    const char *camera =
        "{\"focal_length_mm\": 200, \"sensor_width_mm\": 36, \"sensor_fit\": \"AUTO\","
        " \"fstop\": 1.4, \"focus_distance_m\": 3.0, \"resolution\": [48, 32],"
        " \"pixel_aspect\": 1.0}";
    static const int only_01[1] = {1}, gap[2] = {0, 2}, whole[2] = {0, 1};
    make_scene(&s, 0);
    make_matte(&s, matte);
    test_write_file(json, camera, strlen(camera));
    write_subs(in, &s, matte, only_01, 1);
    CHECK(ddof(in, "-o", test_path(dir, "x.exr"), "--camera", json, NULL) != 0);
    CHECK(err_contains("has sub-layer 01 but not 00"));
    write_subs(in, &s, matte, gap, 2);
    CHECK(ddof(in, "-o", test_path(dir, "x.exr"), "--camera", json, NULL) != 0);
    CHECK(err_contains("has sub-layer 02 but not 01"));
    CHECK(!test_file_exists(test_path(dir, "x.exr")));
    write_subs(in, &s, matte, whole, 2);
    CHECK(ddof(in, "-o", test_path(dir, "x.exr"), "--camera", json, NULL) == 0);
    CHECK(ddof("--list", in, NULL) == 0);
    CHECK(out_contains("matte CryptoObject (4 ranks)"));
    return test_finish("test_cli matte_gap");
}

int main(int argc, char **argv)
{
    static const cli_case cases[] = {
        {"matte", case_matte},
        {"matte_gap", case_matte_gap},
    };
    return cli_test_main(argc, argv, "test_cli_matte", cases, sizeof cases / sizeof cases[0]);
}
