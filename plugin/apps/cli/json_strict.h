/* SPDX-License-Identifier: MIT */
/* json_strict.h - the command's JSON files (the camera sidecar, the cards scene) read by rules
 * stricter than cJSON's, each broken rule said with its byte offset: no NUL byte, nesting at
 * most JSON_STRICT_MAX_DEPTH levels (cJSON's own limit, 1000, would report a deep file as
 * invalid JSON at byte 1000, not as what it is), nothing but white space after the value, and
 * no key written twice in one object (compared after unescaping, as cJSON reads keys:
 * "fs\u0074op" is "fstop"), since which of the two is meant is unclear. */
#ifndef DDOF_CLI_JSON_STRICT_H
#define DDOF_CLI_JSON_STRICT_H

#include <cJSON.h>

#include <stddef.h>

/* The files are a few levels deep. */
#define JSON_STRICT_MAX_DEPTH 32

/* Parses text[0..size) (NUL-terminated at text[size]); `path` names it in messages and
 * `shape` says what the file should be after a depth error. Returns the tree (cJSON_Delete
 * it), or NULL with the reason in error. */
cJSON *json_strict_parse(const char *text, size_t size, const char *path, const char *shape,
                         char *error, size_t error_size);

#endif
