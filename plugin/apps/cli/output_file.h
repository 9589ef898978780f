/* SPDX-License-Identifier: MIT */
/* output_file.h - outputs that are never half-written and removed on Ctrl-C (which paths may
 * be written at all: path_safety.h).
 *
 * Every output (EXR, PNG preview, stats JSON) is written to a hidden temporary file in the
 * directory of its final path (".NAME.ddof-PID-N.tmp": same file system, so the final rename is
 * atomic) and renamed over the final path only once complete and flushed. A failure removes
 * the temporary file and leaves any previous output as it was.
 *
 * SIGINT, SIGTERM, SIGHUP and SIGPIPE are handled by a dedicated thread (sigwait) rather than
 * an asynchronous handler: it takes the registry lock, removes every registered temporary file
 * and exits with 128 + signal. A write to a closed standard output (EPIPE) ends the run the
 * same way (output_broken_pipe). Creating a temporary file and renaming it happen under the same
 * lock, so no temporary file can appear after the clean-up or survive it. A temporary file
 * that does survive (SIGKILL, a power cut) is removed by the next run that writes into its
 * directory, once the process that made it is gone (output_remove_stale_temps).
 *
 * Outputs are regular files only: an existing device, FIFO, socket, directory or symbolic
 * link at an output path is refused (output_check_target), never replaced. Symbolic links are
 * refused rather than followed so that a rename never lands somewhere the path does not say. */
#ifndef DDOF_CLI_OUTPUT_FILE_H
#define DDOF_CLI_OUTPUT_FILE_H

#include <stddef.h>
#include <stdio.h>

typedef struct output_file {
    char *final_path;
    char *temp_path;
    int fd;
    FILE *stream; /* optional: set by output_file_stream() */
} output_file;

/* Blocks the four signals in the calling thread (threads created later inherit this) and
 * starts the clean-up thread. Call at the start of main, before any other thread exists.
 * Returns 0 or -1. */
int output_signals_install(void);
/* Stops the clean-up thread (at normal exit). */
void output_signals_shutdown(void);
/* `stream` ("standard output") is a closed pipe: removes every temporary file, says so on
 * stderr and exits with 128 + SIGPIPE. The caller must not be inside output_file_begin or
 * _commit. */
void output_broken_pipe(const char *stream);

/* 0 when `path` is absent or a regular file; -1 with a message when it is a device, FIFO,
 * socket, directory or symbolic link (output_file_begin checks it too). */
int output_check_target(const char *path, char *error, size_t error_size);

/* Removes the temporary files (".NAME.ddof-PID-N.tmp") of processes that no longer exist from
 * the directory of `path`. Returns how many; note gets the first one's path. */
int output_remove_stale_temps(const char *path, char *note, size_t note_size);

/* Creates the registered temporary file for `path` (creating missing directories). Returns 0,
 * or -1 with a message that names the directory when it is not writable. */
int output_file_begin(output_file *file, const char *path, char *error, size_t error_size);
/* A stdio stream on the temporary file (for libpng); owned by `file`. NULL on failure. */
FILE *output_file_stream(output_file *file);
/* Flushes, syncs and renames the temporary file over the final path. On failure the temporary
 * file is removed. Returns 0 or -1 (error). `file` is finished either way. */
int output_file_commit(output_file *file, char *error, size_t error_size);
/* Removes the temporary file. Accepts a file that was never begun or already finished. */
void output_file_abort(output_file *file);

/* Checks, by creating and removing a temporary file, that outputs can be written to the
 * directory of `path` (access() says yes to root even on a read-only directory entry of some
 * file systems; only trying tells). Returns 0 or -1 (error). */
int output_check_directory(const char *path, char *error, size_t error_size);

#endif
