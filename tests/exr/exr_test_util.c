/* SPDX-License-Identifier: MIT */
/* exr_test_util.c - helpers of the EXR and CLI tests. */
#include "exr_test_util.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

int test_failures;

int test_finish(const char *name)
{
    if (test_failures == 0)
        printf("%s: all checks passed\n", name);
    else
        printf("%s: %d check%s failed\n", name, test_failures, test_failures == 1 ? "" : "s");
    return test_failures == 0 ? 0 : 1;
}

static void make_dirs(const char *dir)
{
    char copy[4096];
    char *p;
    snprintf(copy, sizeof copy, "%s", dir);
    for (p = copy + 1; *p; p++) {
        if (*p == '/') {
            *p = '\0';
            mkdir(copy, 0777);
            *p = '/';
        }
    }
    if (mkdir(copy, 0777) != 0 && errno != EEXIST) {
        fprintf(stderr, "cannot create %s: %s\n", dir, strerror(errno));
        exit(2);
    }
}

void test_fresh_dir(const char *dir)
{
    DIR *d;
    struct dirent *e;
    make_dirs(dir);
    d = opendir(dir);
    if (!d) {
        fprintf(stderr, "cannot open %s\n", dir);
        exit(2);
    }
    while ((e = readdir(d)) != NULL) {
        char path[4096];
        struct stat st;
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
            continue;
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        if (lstat(path, &st) == 0 && S_ISDIR(st.st_mode)) {
            chmod(path, 0777);
            test_fresh_dir(path);
            rmdir(path);
        } else {
            unlink(path);
        }
    }
    closedir(d);
}

/* Every path lives until exit: callers keep them across many calls. */
static char **paths;
static size_t path_count;

static void free_paths(void)
{
    size_t i;
    for (i = 0; i < path_count; i++)
        free(paths[i]);
    free(paths);
}

const char *test_path(const char *dir, const char *name)
{
    size_t size = strlen(dir) + strlen(name) + 2;
    char *p = malloc(size);
    char **bigger = realloc(paths, (path_count + 1) * sizeof *paths);
    if (!p || !bigger) {
        fprintf(stderr, "out of memory\n");
        exit(2);
    }
    if (!paths)
        atexit(free_paths);
    paths = bigger;
    snprintf(p, size, "%s/%s", dir, name);
    paths[path_count++] = p;
    return p;
}

exrio_box test_box(int32_t x0, int32_t y0, uint32_t w, uint32_t h)
{
    exrio_box b;
    b.min_x = x0;
    b.min_y = y0;
    b.max_x = x0 + (int32_t)w - 1;
    b.max_y = y0 + (int32_t)h - 1;
    return b;
}

int test_write_exr(const char *path, const exrio_box *data, const exrio_box *display,
                   int count, const char *const *names, const exrio_pixel_type *types,
                   const void *const *planes, exrio_compression compression)
{
    exrio_write_channel channels[16];
    exrio_write_spec spec;
    char error[1024];
    const size_t width = (size_t)(data->max_x - data->min_x + 1);
    int fd, c;
    exrio_status status;

    if (count > 16)
        return -1;
    for (c = 0; c < count; c++) {
        channels[c].name = names[c];
        channels[c].type = types[c];
        channels[c].pixels = planes[c];
        channels[c].pixel_stride = 4;
        channels[c].line_stride = width * 4;
    }
    memset(&spec, 0, sizeof spec);
    spec.data_window = *data;
    spec.display_window = display ? *display : *data;
    spec.pixel_aspect = 1.0f;
    spec.compression = compression;
    spec.channel_count = count;
    spec.channels = channels;
    fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0666);
    if (fd < 0) {
        fprintf(stderr, "cannot create %s: %s\n", path, strerror(errno));
        return -1;
    }
    status = exrio_write_fd(fd, path, &spec, error, sizeof error);
    close(fd);
    if (status != EXRIO_OK) {
        fprintf(stderr, "writing %s: %s\n", path, error);
        return -1;
    }
    return 0;
}

char *test_read_file(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    char *data;
    long n;
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    n = ftell(f);
    fseek(f, 0, SEEK_SET);
    data = malloc((size_t)n + 1);
    if (data && fread(data, 1, (size_t)n, f) != (size_t)n) {
        free(data);
        data = NULL;
    }
    fclose(f);
    if (data) {
        data[n] = '\0';
        if (size)
            *size = (size_t)n;
    }
    return data;
}

int test_write_file(const char *path, const void *data, size_t size)
{
    FILE *f = fopen(path, "wb");
    int ok;
    if (!f)
        return -1;
    ok = fwrite(data, 1, size, f) == size;
    return fclose(f) == 0 && ok ? 0 : -1;
}

int test_file_exists(const char *path)
{
    struct stat st;
    return lstat(path, &st) == 0;
}

int test_count_suffix(const char *dir, const char *suffix)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    size_t sl = strlen(suffix);
    int n = 0;
    if (!d)
        return 0;
    while ((e = readdir(d)) != NULL) {
        size_t l = strlen(e->d_name);
        if (l >= sl && strcmp(e->d_name + l - sl, suffix) == 0)
            n++;
    }
    closedir(d);
    return n;
}

int test_run(const char *dir, char *const *argv)
{
    pid_t pid;
    int status = 0;
    fflush(stdout);
    fflush(stderr);
    pid = fork();
    if (pid < 0)
        return -1;
    if (pid == 0) {
        int out = open(test_path(dir, "run.out"), O_WRONLY | O_CREAT | O_TRUNC, 0666);
        int err = open(test_path(dir, "run.err"), O_WRONLY | O_CREAT | O_TRUNC, 0666);
        if (out < 0 || err < 0)
            _exit(126);
        dup2(out, STDOUT_FILENO);
        dup2(err, STDERR_FILENO);
        execv(argv[0], argv);
        _exit(127);
    }
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR)
            return -1;
    if (WIFSIGNALED(status))
        return 128 + WTERMSIG(status);
    return WEXITSTATUS(status);
}

float *test_read_channel(const char *path, const char *name, uint32_t *width, uint32_t *height)
{
    exrio_image image;
    char error[1024];
    unsigned char *wanted;
    float *copy = NULL;
    int idx;
    if (exrio_open(path, &image, error, sizeof error) != EXRIO_OK) {
        fprintf(stderr, "%s\n", error);
        return NULL;
    }
    idx = exrio_find_channel(&image, name, -1);
    if (idx < 0) {
        fprintf(stderr, "%s: no channel %s\n", path, name);
        exrio_close(&image);
        return NULL;
    }
    wanted = calloc((size_t)image.channel_count, 1);
    wanted[idx] = 1;
    if (exrio_load(&image, wanted, error, sizeof error) == EXRIO_OK) {
        const exrio_part *part = &image.parts[image.channels[idx].part];
        size_t n = (size_t)part->width * part->height;
        copy = malloc(n * sizeof *copy);
        memcpy(copy, image.channels[idx].pixels, n * sizeof *copy);
        *width = part->width;
        *height = part->height;
    } else {
        fprintf(stderr, "%s\n", error);
    }
    free(wanted);
    exrio_close(&image);
    return copy;
}

float test_round_half(float v)
{
    /* Half has 11 significant bits: round the float's mantissa to 10 stored bits, ties to
     * even (normal range only; the tests stay inside it). */
    int e;
    double m;
    if (v == 0.0f || !isfinite(v))
        return v;
    m = frexp((double)v, &e); /* v = m * 2^e, 0.5 <= |m| < 1 */
    m = nearbyint(m * 2048.0) / 2048.0;
    return (float)ldexp(m, e);
}
