/* SPDX-License-Identifier: MIT */
/* fuzz_cards_scene.c - `ddof --cards`'s scene parser (plugin/apps/cli/cards_scene.c) on fuzzed
 * JSON, and ddof_render_cards on every scene it accepts: the camera's keys, the cards' corners
 * and uv, and their images among four small files written at start-up into a scratch folder
 * (a premultiplied RGBA EXR, an RGB EXR, a grey PNG, and a text file that is no image).
 *
 * An input holding '/' or '\' is skipped, so that an image name (escapes included) can only
 * name a file of the scratch folder. A scene is rendered when its frame has at most
 * MAX_PIXELS pixels and it has at most MAX_CARDS cards (the parser itself sees every size).
 * Checked: a known status; on an error the output is untouched and there is a message; on
 * DDOF_OK every value is finite and within 0..1 and no colour exceeds its alpha: cards of
 * premultiplied texels in 0..1, averaged and composited with `over`, stay so (a texture whose
 * colour exceeds its alpha, which premultiplied RGBA allows for light, can rightly give more
 * than 1 where it lies under another card, so the RGBA texture here keeps colour <= alpha). */
#include "fuzz_reader.h"

#include "cards_scene.h"
#include "exrio.h"
#include "png_write.h"

#include <fcntl.h>
#include <unistd.h>

#define MAX_PIXELS (96u * 96u)
#define MAX_CARDS 32u

static char folder[64];
static char scene_path[96];

static void path_in_folder(char *out, size_t size, const char *name)
{
    snprintf(out, size, "%s/%s", folder, name);
}

static void write_exr(const char *name, uint32_t w, uint32_t h, int channels)
{
    static const char *const names[4] = {"R", "G", "B", "A"};
    float *pixels = malloc((size_t)w * h * 4 * sizeof *pixels);
    exrio_write_channel ch[4];
    exrio_write_spec spec;
    char path[160], error[256];
    if (!pixels)
        abort();
    for (size_t i = 0; i < (size_t)w * h * 4; i++)
        pixels[i] = (float)((i * 7u) % 11u) / 10.0f;
    if (channels == 4) /* premultiplied: colour = a straight colour in 0..1 times alpha */
        for (size_t i = 0; i < (size_t)w * h; i++)
            for (int c = 0; c < 3; c++)
                pixels[i * 4 + c] *= pixels[i * 4 + 3];
    for (int c = 0; c < channels; c++)
        ch[c] = (exrio_write_channel){names[c], EXRIO_HALF, pixels + c, 16, (size_t)w * 16};
    memset(&spec, 0, sizeof spec);
    spec.data_window = spec.display_window = (exrio_box){0, 0, (int32_t)w - 1, (int32_t)h - 1};
    spec.compression = EXRIO_COMPRESSION_NONE;
    spec.channel_count = channels;
    spec.channels = ch;
    path_in_folder(path, sizeof path, name);
    const int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0600);
    if (fd < 0 || exrio_write_fd(fd, path, &spec, error, sizeof error) != EXRIO_OK) {
        fprintf(stderr, "fuzz_cards_scene: cannot write %s: %s\n", path, error);
        abort();
    }
    close(fd);
    free(pixels);
}

static void remove_folder(void)
{
    static const char *const files[5] = {"a.exr", "c.exr", "g.png", "t.txt", "scene.json"};
    char path[160];
    for (int i = 0; i < 5; i++) {
        path_in_folder(path, sizeof path, files[i]);
        remove(path);
    }
    rmdir(folder);
}

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    const char *tmp = getenv("TMPDIR");
    snprintf(folder, sizeof folder, "%s/fuzz_cards.XXXXXX",
             tmp && tmp[0] && strlen(tmp) < 32 ? tmp : "/tmp");
    if (!mkdtemp(folder))
        abort();
    atexit(remove_folder);
    snprintf(scene_path, sizeof scene_path, "%s/scene.json", folder);
    write_exr("a.exr", 4, 3, 4);
    write_exr("c.exr", 2, 2, 3);
    static const uint8_t grey[6] = {0, 60, 120, 180, 240, 255};
    char path[160], error[256];
    path_in_folder(path, sizeof path, "g.png");
    if (png_write_file(path, grey, 3, 2, 1, error, sizeof error) != 0)
        abort();
    path_in_folder(path, sizeof path, "t.txt");
    FILE *f = fopen(path, "w");
    if (!f || fputs("not an image\n", f) < 0 || fclose(f) != 0)
        abort();
    return 0;
}

static void check_render(const cards_scene *scene)
{
    const size_t floats = (size_t)scene->width * scene->height * 4;
    float *out = malloc(floats * sizeof *out);
    ddof_context *ctx = NULL;
    if (!out || ddof_context_create(NULL, &ctx) != DDOF_OK)
        abort();
    for (size_t i = 0; i < floats; i++)
        out[i] = -7.0f;
    const ddof_image image = {out, scene->width, scene->height, 4, 0};
    const ddof_status s =
        ddof_render_cards(ctx, NULL, &scene->camera, scene->cards, scene->count, &image);
    if (!fuzz_known_status(s)) {
        fprintf(stderr, "fuzz_cards_scene: unknown status %d\n", (int)s);
        abort();
    }
    for (size_t i = 0; i < floats; i++) {
        const float v = out[i], alpha = out[i | 3];
        if (s != DDOF_OK ? v != -7.0f : !(v >= -0.01f && v <= 1.01f && v <= alpha + 1e-4f)) {
            fprintf(stderr, "fuzz_cards_scene: status %d (%s): value %zu is %g\n", (int)s,
                    ddof_context_last_error(ctx), i, (double)v);
            abort();
        }
    }
    if (s != DDOF_OK && !ddof_context_last_error(ctx)[0]) {
        fprintf(stderr, "fuzz_cards_scene: status %d without a message\n", (int)s);
        abort();
    }
    ddof_context_free(ctx);
    free(out);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (memchr(data, '/', size) || memchr(data, '\\', size))
        return 0;
    FILE *f = fopen(scene_path, "wb");
    if (!f || fwrite(data, 1, size, f) != size || fclose(f) != 0)
        abort();
    cards_scene scene;
    char error[1024] = "";
    if (cards_scene_read(scene_path, &scene, error, sizeof error) != 0) {
        if (!error[0]) {
            fprintf(stderr, "fuzz_cards_scene: a scene refused without a message\n");
            abort();
        }
        return 0;
    }
    if ((uint64_t)scene.width * scene.height <= MAX_PIXELS && scene.count <= MAX_CARDS)
        check_render(&scene);
    cards_scene_free(&scene);
    return 0;
}
