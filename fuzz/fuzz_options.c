/* SPDX-License-Identifier: MIT */
/* fuzz_options.c - the command line (options.c) and the frame lists and '#' patterns it
 * feeds (frames.c) on fuzzed argument vectors: the input split at NUL bytes is argv[1..].
 * Run with -close_fd_mask=3: the parser's messages go to stdout and stderr. */
#include "frames.h"
#include "options.h"

#include <limits.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef PATH_MAX
#define PATH_MAX 4096
#endif

#define MAX_ARGS 48

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = malloc(size + 1);
    char *argv[MAX_ARGS + 2];
    cli_options options;
    int argc = 1, rc;
    size_t i, start = 0;
    if (!text)
        return 0;
    memcpy(text, data, size);
    text[size] = '\0';
    argv[0] = "ddof";
    for (i = 0; i <= size && argc <= MAX_ARGS; i++)
        if (text[i] == '\0') {
            argv[argc++] = text + start;
            start = i + 1;
        }
    argv[argc] = NULL;
    rc = cli_parse_options(argc, argv, &options);
    if (rc == 0 && options.frames) {
        int *frames = NULL;
        char error[256], path[PATH_MAX];
        const int n = frames_parse(options.frames, &frames, error, sizeof error);
        if (n > 0) {
            int k;
            for (k = 1; k < n; k++)
                if (frames[k] <= frames[k - 1] || frames[k] > FRAMES_LARGEST) {
                    fprintf(stderr, "fuzz_options: frame list not ascending and unique\n");
                    abort();
                }
            (void)frames_expand(options.input, frames[0], path, sizeof path);
            if (options.output)
                (void)frames_expand(options.output, frames[n - 1], path, sizeof path);
        } else if (!error[0]) {
            abort();
        }
        free(frames);
    }
    fflush(stdout);
    free(text);
    return 0;
}
