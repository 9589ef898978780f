/* SPDX-License-Identifier: MIT */
/* json_strict.c - JSON read by stricter rules than cJSON's (json_strict.h). */
#include "json_strict.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The byte after the string that starts (with its quote) at text[i]. */
static size_t skip_string(const char *text, size_t size, size_t i)
{
    for (i++; i < size && text[i] != '"'; i++)
        if (text[i] == '\\')
            i++;
    return i + 1;
}

/* Nesting deeper than JSON_STRICT_MAX_DEPTH: its byte offset, else -1. Strings are skipped, so a
 * bracket inside one does not count; anything else malformed is left to cJSON. */
static long too_deep(const char *text, size_t size)
{
    size_t i;
    int depth = 0;
    for (i = 0; i < size; i++) {
        if (text[i] == '"') {
            i = skip_string(text, size, i) - 1;
        } else if (text[i] == '{' || text[i] == '[') {
            if (++depth > JSON_STRICT_MAX_DEPTH)
                return (long)i;
        } else if (text[i] == '}' || text[i] == ']') {
            depth--;
        }
    }
    return -1;
}

typedef struct json_key {
    const char *at; /* the key's text between its quotes */
    size_t length;
} json_key;

static int compare_keys(const void *pa, const void *pb)
{
    const json_key *a = pa, *b = pb;
    const size_t n = a->length < b->length ? a->length : b->length;
    const int c = memcmp(a->at, b->at, n);
    if (c != 0)
        return c;
    if (a->length != b->length)
        return a->length < b->length ? -1 : 1;
    return a->at < b->at ? -1 : a->at > b->at; /* the first one written first */
}

static unsigned hex4(const char *at)
{
    unsigned v = 0;
    int k;
    for (k = 0; k < 4; k++) {
        const char c = at[k];
        v = v * 16 + (unsigned)(c <= '9' ? c - '0' : (c | 0x20) - 'a' + 10);
    }
    return v;
}

/* Decodes the escapes of a valid JSON string's contents [from, to) in place (UTF-8 is never
 * longer than its escape); returns the decoded length. "fs\u0074op" is "fstop". */
static size_t unescape_in_place(char *from, const char *to)
{
    char *w = from;
    const char *r = from;
    while (r < to) {
        unsigned cp;
        if (*r != '\\') {
            *w++ = *r++;
            continue;
        }
        r++;
        switch (*r) {
        case 'b': cp = '\b'; break;
        case 'f': cp = '\f'; break;
        case 'n': cp = '\n'; break;
        case 'r': cp = '\r'; break;
        case 't': cp = '\t'; break;
        case 'u':
            cp = hex4(r + 1);
            r += 4;
            if (cp >= 0xD800 && cp < 0xDC00 && to - r >= 7 && r[1] == '\\' && r[2] == 'u') {
                const unsigned low = hex4(r + 3);
                if (low >= 0xDC00 && low < 0xE000) {
                    cp = 0x10000 + ((cp - 0xD800) << 10) + (low - 0xDC00);
                    r += 6;
                }
            }
            break;
        default: cp = (unsigned char)*r; break; /* \" \\ \/ */
        }
        r++;
        if (cp < 0x80) {
            *w++ = (char)cp;
        } else if (cp < 0x800) {
            *w++ = (char)(0xC0 | cp >> 6);
            *w++ = (char)(0x80 | (cp & 0x3F));
        } else if (cp < 0x10000) {
            *w++ = (char)(0xE0 | cp >> 12);
            *w++ = (char)(0x80 | (cp >> 6 & 0x3F));
            *w++ = (char)(0x80 | (cp & 0x3F));
        } else {
            *w++ = (char)(0xF0 | cp >> 18);
            *w++ = (char)(0x80 | (cp >> 12 & 0x3F));
            *w++ = (char)(0x80 | (cp >> 6 & 0x3F));
            *w++ = (char)(0x80 | (cp & 0x3F));
        }
    }
    return (size_t)(w - from);
}

/* A key written twice in one object of valid JSON, compared after unescaping (as cJSON reads
 * it: "fs\u0074op" is "fstop"): 1 with the byte offsets of the second and the first and
 * *decoded (the caller frees) holding the keys decoded in place, else 0; -1 when out of
 * memory. */
static int duplicate_key(const char *text, size_t size, size_t *second, size_t *first,
                         size_t *length, char **decoded)
{
    char *dec = malloc(size + 1);
    json_key *keys = NULL;
    size_t count = 0, capacity = 0, i;
    size_t begin[JSON_STRICT_MAX_DEPTH + 1]; /* per open container: its first key, or SIZE_MAX */
    int depth = 0, expect_key = 0, found = 0;
    *decoded = NULL;
    if (!dec)
        return -1;
    memcpy(dec, text, size + 1);
    for (i = 0; i < size && !found; i++) {
        const char ch = text[i];
        if (ch == '"') {
            const size_t end = skip_string(text, size, i);
            if (expect_key) {
                if (count == capacity) {
                    size_t grow = capacity ? capacity * 2 : 32;
                    json_key *bigger = realloc(keys, grow * sizeof *keys);
                    if (!bigger) {
                        free(keys);
                        free(dec);
                        return -1;
                    }
                    keys = bigger;
                    capacity = grow;
                }
                keys[count].at = dec + i + 1;
                keys[count].length = unescape_in_place(dec + i + 1, dec + end - 1);
                count++;
                expect_key = 0;
            }
            i = end - 1;
        } else if (ch == '{' || ch == '[') {
            if (depth >= JSON_STRICT_MAX_DEPTH)
                break; /* too_deep said no first */
            begin[depth++] = ch == '{' ? count : (size_t)-1;
            expect_key = ch == '{';
        } else if (ch == ',') {
            expect_key = depth > 0 && begin[depth - 1] != (size_t)-1;
        } else if ((ch == '}' || ch == ']') && depth > 0) {
            const size_t from = begin[--depth];
            if (ch == '}' && from != (size_t)-1 && count - from > 1) {
                size_t k;
                qsort(keys + from, count - from, sizeof *keys, compare_keys);
                for (k = from + 1; k < count && !found; k++)
                    if (keys[k].length == keys[k - 1].length &&
                        memcmp(keys[k].at, keys[k - 1].at, keys[k].length) == 0) {
                        *first = (size_t)(keys[k - 1].at - dec) - 1;
                        *second = (size_t)(keys[k].at - dec) - 1;
                        *length = keys[k].length;
                        found = 1;
                    }
            }
            if (from != (size_t)-1)
                count = from; /* the closed object's keys are done with */
            expect_key = 0;
        }
    }
    free(keys);
    if (found)
        *decoded = dec;
    else
        free(dec);
    return found;
}

cJSON *json_strict_parse(const char *text, size_t size, const char *path, const char *shape,
                         char *error, size_t error_size)
{
    const char *end = NULL;
    cJSON *root;
    size_t second = 0, first = 0, length = 0;
    char *decoded = NULL;
    long deep;
    int duplicate;
    if (strlen(text) != size) {
        snprintf(error, error_size, "%s: not valid JSON (a NUL byte at byte %lu)", path,
                 (unsigned long)strlen(text));
        return NULL;
    }
    deep = too_deep(text, size);
    if (deep >= 0) {
        snprintf(error, error_size, "%s: nested deeper than %d levels at byte %ld; %s", path,
                 JSON_STRICT_MAX_DEPTH, deep, shape);
        return NULL;
    }
    root = cJSON_ParseWithOpts(text, &end, 0);
    if (!root) {
        const char *at = cJSON_GetErrorPtr();
        long offset = at && at >= text ? (long)(at - text) : -1;
        snprintf(error, error_size, "%s: not valid JSON (near byte %ld)", path, offset);
        return NULL;
    }
    while (end && (*end == ' ' || *end == '\t' || *end == '\n' || *end == '\r'))
        end++;
    if (end && *end) {
        snprintf(error, error_size, "%s: not valid JSON: data after the end of the JSON value "
                 "at byte %ld", path, (long)(end - text));
        cJSON_Delete(root);
        return NULL;
    }
    duplicate = duplicate_key(text, size, &second, &first, &length, &decoded);
    if (duplicate != 0) {
        if (duplicate < 0)
            snprintf(error, error_size, "%s: out of memory", path);
        else
            snprintf(error, error_size, "%s: duplicate key \"%.*s\" at byte %lu (first at "
                     "byte %lu): which one is meant is unclear",
                     path, length > 64 ? 64 : (int)length, decoded + first + 1,
                     (unsigned long)second, (unsigned long)first);
        free(decoded);
        cJSON_Delete(root);
        return NULL;
    }
    return root;
}
