/* SPDX-License-Identifier: MIT */
/* test_cli_guards.c - what the command refuses or guards against, run as a user runs it: a
 * FIFO given as any input (refused, never a hang), values beyond half's range (float where
 * half is the command's choice, refused where the user asked for half), outputs that would
 * overwrite an input (--cards) or another frame's output, a truncated output under
 * --skip-existing, a cards scene of doubtful JSON or UINT textures, and one decode per
 * texture file shared by many cards. */
#include "cli_test.h"

#include <png.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

static const char *const camera_sidecar =
    "{\"focal_length_mm\": 50, \"sensor_width_mm\": 36, \"sensor_fit\": \"AUTO\", \"fstop\": 1.4,"
    " \"focus_distance_m\": 3, \"resolution\": [48, 32], \"pixel_aspect\": 1}";

/* A cards scene of one card showing `image` (relative to the scene) at 3 m, `resolution` the
 * camera's "[w, h]". */
static void write_cards_scene(const char *path, const char *image, const char *resolution)
{
    char text[1024];
    snprintf(text, sizeof text,
             "{\"camera\": {\"focal_length_mm\": 50, \"sensor_width_mm\": 36, \"sensor_fit\": "
             "\"AUTO\", \"fstop\": 1.4, \"focus_distance_m\": 3, \"resolution\": %s, "
             "\"pixel_aspect\": 1}, \"cards\": [{\"image\": \"%s\", \"corners\": [[-1, -1, -3], "
             "[1, -1, -3], [1, 1, -3], [-1, 1, -3]]}]}",
             resolution, image);
    test_write_file(path, text, strlen(text));
}

/* An 8x4 RGBA texture: R = r everywhere, G = B = 0.5, A = 1, R stored as r_type. */
static void write_texture(const char *path, float r, exrio_pixel_type r_type)
{
    static float planes[4][32];
    static const char *const names[4] = {"R", "G", "B", "A"};
    const exrio_pixel_type types[4] = {r_type, EXRIO_FLOAT, EXRIO_FLOAT, EXRIO_FLOAT};
    const void *cplanes[4] = {planes[0], planes[1], planes[2], planes[3]};
    const exrio_box box = test_box(0, 0, 8, 4);
    for (int i = 0; i < 32; i++) {
        if (r_type == EXRIO_UINT) {
            const uint32_t u = (uint32_t)r;
            memcpy(&planes[0][i], &u, sizeof u);
        } else {
            planes[0][i] = r;
        }
        planes[1][i] = planes[2][i] = 0.5f;
        planes[3][i] = 1.0f;
    }
    CHECK(test_write_exr(path, &box, NULL, 4, names, types, cplanes, EXRIO_COMPRESSION_NONE) ==
          0);
}

static char *file_bytes(const char *path, size_t *size)
{
    char *bytes = test_read_file(path, size);
    CHECK_MSG(bytes != NULL, "%s unreadable", path);
    return bytes;
}

static int same_bytes(const char *path, const char *bytes, size_t size)
{
    size_t now_size = 0;
    char *now = test_read_file(path, &now_size);
    const int same = now && now_size == size && memcmp(now, bytes, size) == 0;
    free(now);
    return same;
}

/* Every input given as a FIFO without a writer: a clear refusal, not a hang (ctest's timeout
 * would fail the case). */
static int case_fifo(void)
{
    static scene s;
    const char *in = test_path(dir, "in.exr"), *cam = test_path(dir, "camera.json");
    const char *fifo = test_path(dir, "fifo"), *out = test_path(dir, "out.exr");
    const char *cards = test_path(dir, "cards.json");
    make_scene(&s, 0);
    write_scene(in, &s, 0);
    test_write_file(cam, camera_sidecar, strlen(camera_sidecar));
    CHECK(mkfifo(fifo, 0600) == 0);
    write_cards_scene(cards, "fifo", "[48, 32]");
    const struct {
        const char *args[6];
        const char *says;
    } runs[] = {
        {{fifo, "-o", out, "--camera", cam, NULL}, "the input is a FIFO"},
        {{in, "-o", out, "--camera", fifo, NULL}, "the camera file is a FIFO"},
        {{in, "-o", out, "--camera", cam, "--aperture-image"}, "the aperture image is a FIFO"},
        {{in, "-o", out, "--camera", cam, "--depth-file"}, "the depth file is a FIFO"},
        {{in, "-o", out, "--camera", cam, "--foreground"}, "the foreground element is a FIFO"},
        {{in, "-o", out, "--camera", cam, "--compare"}, "the ground truth is a FIFO"},
        {{"--list", fifo, NULL}, "the file to list is a FIFO"},
        {{"--cards", fifo, "-o", out, NULL}, "the cards scene is a FIFO"},
        {{"--cards", cards, "-o", out, NULL}, "the card texture is a FIFO"},
    };
    for (size_t r = 0; r < sizeof runs / sizeof runs[0]; r++) {
        const char *const *a = runs[r].args;
        /* Runs whose sixth word is an option take the FIFO after it. */
        const int rc = a[5] ? ddof(a[0], a[1], a[2], a[3], a[4], a[5], fifo, NULL)
                            : ddof(a[0], a[1], a[2], a[3], a[4], NULL);
        CHECK_MSG(rc != 0 && err_contains(runs[r].says), "run %zu: exit %d", r, rc);
    }
    CHECK(!test_file_exists(out));
    return test_finish("test_cli fifo");
}

/* A float texture with R = 1e5 (an HDR light): half, the default, would store +inf. */
static int case_half_range(void)
{
    static scene s;
    const char *tex = test_path(dir, "bright.exr"), *cards = test_path(dir, "cards.json");
    const char *out = test_path(dir, "out.exr"), *in = test_path(dir, "in.exr");
    const char *cam = test_path(dir, "camera.json");
    write_texture(tex, 1e5f, EXRIO_FLOAT);
    write_cards_scene(cards, "bright.exr", "[48, 32]");
    CHECK(ddof("--cards", cards, "-o", out, "-q", NULL) == 0);
    uint32_t w = 0, h = 0;
    float *r = test_read_channel(out, "R", &w, &h);
    float *g = test_read_channel(out, "G", &w, &h);
    exrio_image image;
    char error[256];
    CHECK(exrio_open(out, &image, error, sizeof error) == EXRIO_OK);
    const int ri = exrio_find_channel(&image, "R", 0), gi = exrio_find_channel(&image, "G", 0);
    CHECK(ri >= 0 && image.channels[ri].type == EXRIO_FLOAT); /* the channel that overflows */
    CHECK(gi >= 0 && image.channels[gi].type == EXRIO_HALF);  /* the others stay half */
    exrio_close(&image);
    float most = 0.0f;
    int infinite = 0;
    for (size_t i = 0; r && i < (size_t)w * h; i++) {
        infinite += !isfinite(r[i]);
        most = r[i] > most ? r[i] : most;
    }
    CHECK_MSG(r && g && infinite == 0 && most > 9e4f && most <= 1e5f,
              "%d infinite, largest R %g", infinite, (double)most);
    free(r);
    free(g);

    /* Half asked for: refused, nothing written. */
    CHECK(ddof("--cards", cards, "-o", test_path(dir, "half.exr"), "--pixel-type", "half",
               NULL) != 0);
    CHECK(err_contains("beyond half's range"));
    CHECK(!test_file_exists(test_path(dir, "half.exr")));
    /* The frame path the same: a float input with a 1e5 highlight, --pixel-type half. */
    make_scene(&s, 0);
    for (size_t i = 0; i < N; i++)
        s.rgba[0][i] = i % W < 8 ? 1e5f : s.rgba[0][i];
    write_scene(in, &s, 0);
    test_write_file(cam, camera_sidecar, strlen(camera_sidecar));
    CHECK(ddof(in, "-o", test_path(dir, "frame.exr"), "--camera", cam, "--pixel-type", "half",
               NULL) != 0);
    CHECK(err_contains("channel R holds"));
    CHECK(!test_file_exists(test_path(dir, "frame.exr")));
    return test_finish("test_cli half_range");
}

/* --cards -o its own texture or scene, under other spellings and a hard link: refused, the
 * files untouched. */
static int case_cards_clobber(void)
{
    const char *tex = test_path(dir, "tex.exr"), *cards = test_path(dir, "scene.json");
    char dotted[PATH_MAX], linked[PATH_MAX];
    size_t tex_size = 0, scene_size = 0;
    write_texture(tex, 0.25f, EXRIO_FLOAT);
    write_cards_scene(cards, "tex.exr", "[48, 32]");
    snprintf(dotted, sizeof dotted, "%s/./scene.json", dir);
    snprintf(linked, sizeof linked, "%s/hard.exr", dir);
    CHECK(link(tex, linked) == 0);
    char *tex_bytes = file_bytes(tex, &tex_size), *scene_bytes = file_bytes(cards, &scene_size);
    const char *outputs[3] = {tex, dotted, linked};
    for (int k = 0; k < 3; k++) {
        CHECK(ddof("--cards", cards, "-o", outputs[k], "-q", NULL) != 0);
        CHECK(err_contains("it is an input"));
    }
    CHECK(same_bytes(tex, tex_bytes, tex_size));
    CHECK(same_bytes(cards, scene_bytes, scene_size));
    free(tex_bytes);
    free(scene_bytes);
    CHECK(ddof("--cards", cards, "-o", test_path(dir, "fine.exr"), "-q", NULL) == 0);
    return test_finish("test_cli cards_clobber");
}

/* A cards scene is read by the sidecar's rules: a key twice, data after the value; a
 * resolution over the limits says so; UINT colour refused. */
static int case_cards_scene(void)
{
    const char *cards = test_path(dir, "scene.json"), *out = test_path(dir, "out.exr");
    const char *card = "{\"image\": \"tex.exr\", \"corners\": [[-1, -1, -3], [1, -1, -3], "
                       "[1, 1, -3], [-1, 1, -3]]}";
    char text[2048];
    write_texture(test_path(dir, "tex.exr"), 0.25f, EXRIO_FLOAT);
    const struct {
        const char *format;
        const char *says;
    } bad[] = {
        {"{\"camera\": %s, \"cards\": [%s], \"cards\": []}", "duplicate key \"cards\""},
        {"{\"camera\": %s, \"camera\": {}, \"cards\": [%s]}", "duplicate key \"camera\""},
        {"{\"camera\": %s, \"cards\": [%s]} {}", "data after the end"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        snprintf(text, sizeof text, bad[k].format, camera_sidecar, card);
        test_write_file(cards, text, strlen(text));
        CHECK(ddof("--cards", cards, "-o", out, NULL) != 0);
        CHECK(err_contains(bad[k].says));
    }
    snprintf(text, sizeof text, "{\"camera\": %s, \"cards\": [{\"image\": \"tex.exr\", "
             "\"image\": \"other.exr\", \"corners\": [[-1, -1, -3], [1, -1, -3], [1, 1, -3], "
             "[-1, 1, -3]]}]}", camera_sidecar);
    test_write_file(cards, text, strlen(text));
    CHECK(ddof("--cards", cards, "-o", out, NULL) != 0);
    CHECK(err_contains("duplicate key \"image\""));
    write_cards_scene(cards, "tex.exr", "[65537, 4]");
    CHECK(ddof("--cards", cards, "-o", out, NULL) != 0);
    CHECK(err_contains("over the limits") && !err_contains("out of memory"));
    write_cards_scene(cards, "tex.exr", "[60000, 60000]");
    CHECK(ddof("--cards", cards, "-o", out, NULL) != 0);
    CHECK(err_contains("over the limits"));
    write_texture(test_path(dir, "ids.exr"), 7.0f, EXRIO_UINT);
    write_cards_scene(cards, "ids.exr", "[48, 32]");
    CHECK(ddof("--cards", cards, "-o", out, NULL) != 0);
    CHECK(err_contains("channel R is UINT"));
    CHECK(!test_file_exists(out));
    return test_finish("test_cli cards_scene");
}

/* 20 cards showing one 1920x1080 PNG (two spellings of its path): the file is decoded once.
 * Each decode holds 33 MB of float RGBA, so 20 copies would add about 630 MB to the run's
 * peak; measured against one card's run by the children's peak resident size. */
static int case_cards_shared_texture(void)
{
    enum { TW = 1920, TH = 1080, CARDS = 20 };
    const char *cards = test_path(dir, "scene.json"), *one = test_path(dir, "one.json");
    uint8_t *bytes = calloc((size_t)TW * TH * 4, 1);
    png_image png;
    struct rusage usage;
    char *text = malloc(CARDS * 160 + 512);
    size_t n;
    CHECK(bytes && text);
    if (!bytes || !text)
        return test_finish("test_cli cards_shared_texture");
    for (size_t i = 0; i < (size_t)TW * TH * 4; i++)
        bytes[i] = (uint8_t)(i % 4 == 3 ? 255 : (i * 7) % 251);
    memset(&png, 0, sizeof png);
    png.version = PNG_IMAGE_VERSION;
    png.width = TW;
    png.height = TH;
    png.format = PNG_FORMAT_RGBA;
    CHECK(png_image_write_to_file(&png, test_path(dir, "tex.png"), 0, bytes, 0, NULL) != 0);
    free(bytes);
    write_cards_scene(one, "tex.png", "[96, 54]");
    CHECK(ddof("--cards", one, "-o", test_path(dir, "one.exr"), "-q", NULL) == 0);
    CHECK(getrusage(RUSAGE_CHILDREN, &usage) == 0);
    const long one_kb = usage.ru_maxrss;
    n = (size_t)snprintf(text, 512, "{\"camera\": {\"focal_length_mm\": 50, \"sensor_width_mm\": "
                         "36, \"sensor_fit\": \"AUTO\", \"fstop\": 1.4, \"focus_distance_m\": 3, "
                         "\"resolution\": [96, 54], \"pixel_aspect\": 1}, \"cards\": [");
    for (int k = 0; k < CARDS; k++)
        n += (size_t)sprintf(text + n, "%s{\"image\": \"%s\", \"corners\": [[-1, -1, %g], [1, -1, "
                             "%g], [1, 1, %g], [-1, 1, %g]]}", k ? ", " : "",
                             k % 2 ? "tex.png" : "./tex.png", -3.0 - 0.1 * k, -3.0 - 0.1 * k,
                             -3.0 - 0.1 * k, -3.0 - 0.1 * k);
    strcpy(text + n, "]}");
    test_write_file(cards, text, strlen(text));
    free(text);
    CHECK(ddof("--cards", cards, "-o", test_path(dir, "many.exr"), "-q", NULL) == 0);
    CHECK(getrusage(RUSAGE_CHILDREN, &usage) == 0);
    CHECK_MSG(usage.ru_maxrss < one_kb + 150 * 1024,
              "one card's run peaked at %ld kB, 20 cards' at %ld kB", one_kb, usage.ru_maxrss);
    return test_finish("test_cli cards_shared_texture");
}

/* Across a sequence: frame 0's --preview q_1#.exr (q_10.exr) is frame 10's output, and the
 * same with --focus-map: refused before the first frame, nothing written. */
static int case_sequence_collision(void)
{
    static scene s;
    const char *cam = test_path(dir, "camera.json");
    char in[PATH_MAX], out[PATH_MAX], side[PATH_MAX];
    make_scene(&s, 0);
    write_scene(test_path(dir, "a_0.exr"), &s, 0);
    write_scene(test_path(dir, "a_10.exr"), &s, 0);
    test_write_file(cam, camera_sidecar, strlen(camera_sidecar));
    snprintf(in, sizeof in, "%s/a_#.exr", dir);
    snprintf(out, sizeof out, "%s/q_#.exr", dir);
    snprintf(side, sizeof side, "%s/q_1#.exr", dir);
    CHECK(ddof(in, "-o", out, "--preview", side, "--frames", "0,10", "--camera", cam, NULL) != 0);
    CHECK(err_contains("frame 0's preview") && err_contains("frame 10's output"));
    CHECK(ddof(in, "-o", out, "--focus-map", side, "--frames", "0,10", "--camera", cam, NULL) !=
          0);
    CHECK(err_contains("frame 0's focus map") && err_contains("frame 10's output"));
    CHECK(!test_file_exists(test_path(dir, "q_0.exr")) &&
          !test_file_exists(test_path(dir, "q_10.exr")));
    /* Distinct paths still run. */
    snprintf(side, sizeof side, "%s/p_#.png", dir);
    CHECK(ddof(in, "-o", out, "--preview", side, "--frames", "0,10", "--camera", cam, "-q",
               NULL) == 0);
    return test_finish("test_cli sequence_collision");
}

/* --skip-existing with an output cut to a third after its header: the frame is computed
 * again (and comes out as the first run's), not kept as complete. */
static int case_skip_truncated(void)
{
    static scene s;
    const char *cam = test_path(dir, "camera.json"), *out1 = test_path(dir, "o_1.exr");
    char in[PATH_MAX], out[PATH_MAX];
    size_t size = 0;
    make_scene(&s, 0);
    write_scene(test_path(dir, "i_1.exr"), &s, 0);
    test_write_file(cam, camera_sidecar, strlen(camera_sidecar));
    snprintf(in, sizeof in, "%s/i_#.exr", dir);
    snprintf(out, sizeof out, "%s/o_#.exr", dir);
    CHECK(ddof(in, "-o", out, "--frames", "1", "--camera", cam, "--compression", "none", "-q",
               NULL) == 0);
    char *whole = file_bytes(out1, &size);
    /* Complete: skipped. */
    CHECK(ddof(in, "-o", out, "--frames", "1", "--camera", cam, "--skip-existing", NULL) == 0);
    CHECK(out_contains("skipped: complete"));
    /* Cut: recomputed, whole again. */
    CHECK(whole && truncate(out1, (off_t)(size / 3)) == 0);
    CHECK(ddof(in, "-o", out, "--frames", "1", "--camera", cam, "--compression", "none",
               "--skip-existing", NULL) == 0);
    char *text = out_text();
    CHECK_MSG(!strstr(text, "skipped: complete"), "%s", text);
    free(text);
    CHECK(whole && same_bytes(out1, whole, size));
    free(whole);
    return test_finish("test_cli skip_truncated");
}

int main(int argc, char **argv)
{
    static const cli_case cases[] = {
        {"fifo", case_fifo},
        {"half_range", case_half_range},
        {"cards_clobber", case_cards_clobber},
        {"cards_scene", case_cards_scene},
        {"cards_shared_texture", case_cards_shared_texture},
        {"sequence_collision", case_sequence_collision},
        {"skip_truncated", case_skip_truncated},
    };
    return cli_test_main(argc, argv, "test_cli_guards", cases, sizeof cases / sizeof cases[0]);
}
