/* SPDX-License-Identifier: MIT */
/* output.c - small helpers: .npy images for report.py, directories, clocks, medians. */
#include "study.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

double study_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

double study_median(double *values, size_t count)
{
    if (count == 0)
        return 0.0;
    qsort(values, count, sizeof *values, cmp_double);
    return count % 2 ? values[count / 2] : 0.5 * (values[count / 2 - 1] + values[count / 2]);
}

int study_mkdirs(const char *path)
{
    char buf[4096];
    if (strlen(path) >= sizeof buf)
        return -1;
    strcpy(buf, path);
    for (char *p = buf + 1; *p; p++) {
        if (*p != '/')
            continue;
        *p = '\0';
        if (mkdir(buf, 0777) != 0 && errno != EEXIST)
            return -1;
        *p = '/';
    }
    return mkdir(buf, 0777) == 0 || errno == EEXIST ? 0 : -1;
}

char *study_read_text(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    size_t cap = 4096, n = 0;
    char *text = malloc(cap + 1);
    while (text) {
        n += fread(text + n, 1, cap - n, f);
        if (n < cap || cap >= (64u << 20))
            break;
        cap *= 2;
        char *bigger = realloc(text, cap + 1);
        if (!bigger) {
            free(text);
            text = NULL;
        }
        text = bigger;
    }
    fclose(f);
    if (text)
        text[n] = '\0';
    return text;
}

/* NumPy's format 1.0: magic, version, a little-endian uint16 header length, a Python dict
 * literal padded with spaces to a multiple of 64 bytes (newline last), then the raw data. */
int study_write_npy(const char *path, const float *data, uint32_t width, uint32_t height,
                    uint32_t channels)
{
    char header[256];
    int len = channels > 1
                  ? snprintf(header, sizeof header,
                             "{'descr': '<f4', 'fortran_order': False, 'shape': (%u, %u, %u), }",
                             height, width, channels)
                  : snprintf(header, sizeof header,
                             "{'descr': '<f4', 'fortran_order': False, 'shape': (%u, %u), }",
                             height, width);
    size_t total = 10 + (size_t)len + 1;
    size_t padded = (total + 63) / 64 * 64;
    while ((size_t)len < padded - 10 - 1)
        header[len++] = ' ';
    header[len++] = '\n';
    char tmp[4200];
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    FILE *f = fopen(tmp, "wb");
    if (!f)
        return -1;
    const unsigned char magic[8] = {0x93, 'N', 'U', 'M', 'P', 'Y', 1, 0};
    const unsigned char hl[2] = {(unsigned char)(len & 0xff), (unsigned char)(len >> 8)};
    size_t count = (size_t)width * height * channels;
    int ok = fwrite(magic, 1, 8, f) == 8 && fwrite(hl, 1, 2, f) == 2 &&
             fwrite(header, 1, (size_t)len, f) == (size_t)len &&
             fwrite(data, sizeof *data, count, f) == count; /* x86-64/ARM: little-endian */
    ok = (fclose(f) == 0) && ok;
    if (!ok || rename(tmp, path) != 0) {
        remove(tmp);
        return -1;
    }
    return 0;
}
