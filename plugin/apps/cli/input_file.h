/* SPDX-License-Identifier: MIT */
/* input_file.h - the one rule for every file the command reads (the EXR, --camera,
 * --aperture-image, --depth-file, --foreground, --compare, --list, the cards scene and its
 * textures): it must be a regular file. It is opened with O_NONBLOCK, so that a FIFO with no
 * writer or a device cannot hang the open, then judged by fstat: a FIFO, device, socket or
 * directory is refused with a sentence instead of blocking a run (or a farm task) forever. */
#ifndef DDOF_CLI_INPUT_FILE_H
#define DDOF_CLI_INPUT_FILE_H

#include "exrio.h"

#include <stddef.h>
#include <stdio.h>

/* Opens `path` for reading ("rb"); NULL with "PATH: cannot open WHAT: ..." or "PATH: the WHAT
 * is a FIFO, not a regular file" in error. `what` names the input ("camera file"). */
FILE *input_file_open(const char *path, const char *what, char *error, size_t error_size);

/* The whole of a small text file (a JSON sidecar or scene), NUL-terminated, at most max_bytes
 * (*size: its length); NULL with "PATH: cannot read WHAT" or "PATH: too large for a WHAT
 * (over N bytes)" in error, or input_file_open's sentence. Read in one bounded piece, never
 * sized by seeking, so a pipe or a /proc file reads as what it holds. Free with free(). */
char *input_file_read_text(const char *path, const char *what, size_t max_bytes, size_t *size,
                           char *error, size_t error_size);

/* 0 when `path` is a regular file that can be opened for reading, else -1 with the sentence
 * input_file_open writes. For readers that open the path themselves (OpenEXR). */
int input_file_check(const char *path, const char *what, char *error, size_t error_size);

/* exrio_open after input_file_check: the command's way to open any EXR it reads. */
exrio_status input_file_open_exr(const char *path, const char *what, exrio_image *image,
                                 char *error, size_t error_size);

#endif
