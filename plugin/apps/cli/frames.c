/* SPDX-License-Identifier: MIT */
/* frames.c - frame lists and '#' path patterns. */
#include "frames.h"

#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* 0, -1 (not a number) or -2 (above FRAMES_LARGEST). */
static int read_number(const char **p, long *out)
{
    char *end;
    long v;
    if (!isdigit((unsigned char)**p))
        return -1;
    errno = 0;
    v = strtol(*p, &end, 10);
    if (errno != 0 || v > FRAMES_LARGEST)
        return -2;
    *out = v;
    *p = end;
    return 0;
}

static int compare_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

int frames_parse(const char *text, int **frames, char *error, size_t error_size)
{
    const char *p = text;
    int *list = NULL;
    size_t count = 0, capacity = 0, i, kept;
    int r = 0;

    *frames = NULL;
    for (;;) {
        long first, last, step = 1, f;
        if ((r = read_number(&p, &first)) != 0)
            goto bad_number;
        last = first;
        if (*p == '-') {
            p++;
            if ((r = read_number(&p, &last)) != 0)
                goto bad_number;
            if (last < first)
                goto bad;
            if (*p == 'x' || *p == ':') {
                p++;
                if ((r = read_number(&p, &step)) != 0)
                    goto bad_number;
                if (step < 1)
                    goto bad;
            }
        }
        for (f = first; f <= last; f += step) {
            if (count == FRAMES_MAX) {
                snprintf(error, error_size, "--frames %s: more than %d frames", text, FRAMES_MAX);
                free(list);
                return -1;
            }
            if (count == capacity) {
                size_t grow = capacity ? capacity * 2 : 64;
                int *bigger = realloc(list, grow * sizeof *list);
                if (!bigger) {
                    snprintf(error, error_size, "out of memory");
                    free(list);
                    return -1;
                }
                list = bigger;
                capacity = grow;
            }
            list[count++] = (int)f;
        }
        if (*p == '\0')
            break;
        if (*p != ',')
            goto bad;
        p++;
    }
    /* Sorted and unique: each output is written once, in order. */
    qsort(list, count, sizeof *list, compare_int);
    for (i = 1, kept = 1; i < count; i++)
        if (list[i] != list[kept - 1])
            list[kept++] = list[i];
    *frames = list;
    return (int)kept;
bad_number:
    if (r == -2) {
        snprintf(error, error_size, "--frames %s: frame numbers (and steps) are at most %d",
                 text, FRAMES_LARGEST);
        free(list);
        return -1;
    }
bad:
    snprintf(error, error_size, "--frames wants e.g. 1-240, 1-240x2 or 1,4,10-12 (frame numbers "
             ">= 0), not '%s'", text);
    free(list);
    return -1;
}

static const char *last_run(const char *pattern, size_t *length)
{
    const char *run = NULL;
    const char *p;
    *length = 0;
    for (p = pattern; *p; p++) {
        if (*p == '#' && (p == pattern || p[-1] != '#')) {
            size_t n = 0;
            while (p[n] == '#')
                n++;
            run = p;
            *length = n;
        }
    }
    return run;
}

int frames_has_pattern(const char *pattern)
{
    size_t n;
    return last_run(pattern, &n) != NULL;
}

int frames_expand(const char *pattern, int frame, char *out, size_t out_size)
{
    size_t n;
    const char *run = last_run(pattern, &n);
    int written;
    if (!run)
        written = snprintf(out, out_size, "%s", pattern);
    else
        written = snprintf(out, out_size, "%.*s%0*d%s", (int)(run - pattern), pattern, (int)n,
                           frame, run + n);
    return written < 0 || (size_t)written >= out_size ? -1 : 0;
}
