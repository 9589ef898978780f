/* SPDX-License-Identifier: MIT */
/* input_file.c - inputs are regular files (input_file.h). */
#include "input_file.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static const char *file_kind(mode_t mode)
{
    if (S_ISDIR(mode))
        return "a directory";
    if (S_ISFIFO(mode))
        return "a FIFO";
    if (S_ISSOCK(mode))
        return "a socket";
    if (S_ISCHR(mode) || S_ISBLK(mode))
        return "a device";
    return "something else";
}

/* A descriptor of the regular file at path (blocking reads restored), or -1 with error. */
static int open_regular(const char *path, const char *what, char *error, size_t error_size)
{
    struct stat st;
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    int flags;
    if (fd < 0) {
        snprintf(error, error_size, "%s: cannot open %s: %s", path, what, strerror(errno));
        return -1;
    }
    if (fstat(fd, &st) != 0) {
        snprintf(error, error_size, "%s: cannot read %s's status: %s", path, what,
                 strerror(errno));
        close(fd);
        return -1;
    }
    if (!S_ISREG(st.st_mode)) {
        snprintf(error, error_size, "%s: the %s is %s, not a regular file", path, what,
                 file_kind(st.st_mode));
        close(fd);
        errno = EINVAL; /* not "missing" */
        return -1;
    }
    flags = fcntl(fd, F_GETFL);
    if (flags >= 0)
        (void)fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
    return fd;
}

FILE *input_file_open(const char *path, const char *what, char *error, size_t error_size)
{
    const int fd = open_regular(path, what, error, error_size);
    FILE *f = fd >= 0 ? fdopen(fd, "rb") : NULL;
    if (fd >= 0 && !f) {
        snprintf(error, error_size, "%s: cannot open %s: %s", path, what, strerror(errno));
        close(fd);
    }
    return f;
}

char *input_file_read_text(const char *path, const char *what, size_t max_bytes, size_t *size,
                           char *error, size_t error_size)
{
    FILE *f = input_file_open(path, what, error, error_size);
    if (!f)
        return NULL;
    /* Grown as it fills, so a small file costs little of the bound; one byte past the bound
     * tells a file that is too large. */
    size_t capacity = 0, n = 0;
    char *text = NULL;
    while (!ferror(f) && !feof(f) && n <= max_bytes) {
        if (n == capacity) {
            const size_t grown = capacity ? capacity * 2 : 4096;
            char *more = realloc(text, (grown < max_bytes + 1 ? grown : max_bytes + 1) + 1);
            if (!more) {
                fclose(f);
                free(text);
                snprintf(error, error_size, "%s: out of memory", path);
                return NULL;
            }
            text = more;
            capacity = grown < max_bytes + 1 ? grown : max_bytes + 1;
        }
        n += fread(text + n, 1, capacity - n, f);
    }
    if (ferror(f) || n > max_bytes) {
        if (ferror(f))
            snprintf(error, error_size, "%s: cannot read %s", path, what);
        else
            snprintf(error, error_size, "%s: too large for a %s (over %zu bytes)", path, what,
                     max_bytes);
        fclose(f);
        free(text);
        return NULL;
    }
    fclose(f);
    text[n] = '\0';
    *size = n;
    return text;
}

int input_file_check(const char *path, const char *what, char *error, size_t error_size)
{
    const int fd = open_regular(path, what, error, error_size);
    if (fd < 0)
        return -1;
    close(fd);
    return 0;
}

exrio_status input_file_open_exr(const char *path, const char *what, exrio_image *image,
                                 char *error, size_t error_size)
{
    if (input_file_check(path, what, error, error_size) != 0) {
        const int missing = errno == ENOENT || errno == ENOTDIR;
        memset(image, 0, sizeof *image);
        return missing ? EXRIO_ERROR_MISSING : EXRIO_ERROR_ACCESS;
    }
    return exrio_open(path, image, error, error_size);
}
