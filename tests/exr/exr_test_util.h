/* SPDX-License-Identifier: MIT */
/* exr_test_util.h - what the EXR and CLI tests share: checks that count failures, a scratch
 * directory in the build tree, writing EXR files from planes, running the `ddof` binary. */
#ifndef DDOF_EXR_TEST_UTIL_H
#define DDOF_EXR_TEST_UTIL_H

#include "exrio.h"

#include <stddef.h>
#include <stdint.h>

extern int test_failures;

#define CHECK(cond)                                                                        \
    do {                                                                                   \
        if (!(cond)) {                                                                     \
            test_failures++;                                                               \
            fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond);       \
        }                                                                                  \
    } while (0)

#define CHECK_MSG(cond, ...)                                                               \
    do {                                                                                   \
        if (!(cond)) {                                                                     \
            test_failures++;                                                               \
            fprintf(stderr, "%s:%d: CHECK failed: %s: ", __FILE__, __LINE__, #cond);       \
            fprintf(stderr, __VA_ARGS__);                                                  \
            fprintf(stderr, "\n");                                                         \
        }                                                                                  \
    } while (0)

/* Prints "name: N passed, M failed"-style closing line and returns the exit status. */
int test_finish(const char *name);

/* Creates `dir` (and parents) and removes the files directly inside it. Aborts on failure. */
void test_fresh_dir(const char *dir);
/* dir + "/" + name, valid until the program exits. */
const char *test_path(const char *dir, const char *name);

/* Writes a single-part scanline EXR with `count` channels, each a plane of width*height
 * 32-bit values (float for HALF/FLOAT, uint32 for UINT) over data window `data` inside
 * display window `display` (NULL: the same as data). Returns 0 or -1 (message printed). */
int test_write_exr(const char *path, const exrio_box *data, const exrio_box *display,
                   int count, const char *const *names, const exrio_pixel_type *types,
                   const void *const *planes, exrio_compression compression);

/* A box from (x0, y0) of w x h pixels. */
exrio_box test_box(int32_t x0, int32_t y0, uint32_t w, uint32_t h);

/* Reads a whole file into a new NUL-terminated buffer (NULL if missing); *size gets the size. */
char *test_read_file(const char *path, size_t *size);
int test_write_file(const char *path, const void *data, size_t size);
int test_file_exists(const char *path);
/* Number of entries in `dir` whose name ends in `suffix` (".tmp" to look for leftovers). */
int test_count_suffix(const char *dir, const char *suffix);

/* Runs argv (argv[0] is the program path) with stdout and stderr sent to files in `dir`
 * (run.out, run.err) and returns the exit status (128 + signal when killed). The outputs are
 * readable with test_read_file afterwards. */
int test_run(const char *dir, char *const *argv);

/* Reads channel `name` of an EXR written by the tool as floats (new buffer), with size. */
float *test_read_channel(const char *path, const char *name, uint32_t *width, uint32_t *height);

/* Rounds a float to the nearest half-precision value (ties to even), as a float. */
float test_round_half(float v);

#endif
