/* SPDX-License-Identifier: MIT */
/* camera_json.c - reading the camera sidecar JSON with cJSON. */
#include "camera_json.h"

#include <cJSON.h>

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* A sidecar is a few hundred bytes; anything past this is not one. */
#define MAX_SIDECAR_BYTES (1u << 20)

/* A sidecar is two levels deep; cJSON's own limit (1000) would report a deep file as invalid
 * JSON at byte 1000, not as what it is. */
#define MAX_SIDECAR_DEPTH 32

static char *read_text(const char *path, size_t *size, char *error, size_t error_size)
{
    FILE *f = fopen(path, "rb");
    char *text;
    size_t n;
    if (!f) {
        snprintf(error, error_size, "%s: cannot open camera file: %s", path, strerror(errno));
        return NULL;
    }
    text = malloc(MAX_SIDECAR_BYTES + 1);
    if (!text) {
        fclose(f);
        snprintf(error, error_size, "%s: out of memory", path);
        return NULL;
    }
    n = fread(text, 1, MAX_SIDECAR_BYTES + 1, f);
    if (ferror(f) || n > MAX_SIDECAR_BYTES) {
        snprintf(error, error_size, "%s: %s", path,
                 ferror(f) ? "cannot read camera file" : "too large for a camera sidecar");
        fclose(f);
        free(text);
        return NULL;
    }
    fclose(f);
    text[n] = '\0';
    *size = n;
    return text;
}

/* The byte after the string that starts (with its quote) at text[i]. */
static size_t skip_string(const char *text, size_t size, size_t i)
{
    for (i++; i < size && text[i] != '"'; i++)
        if (text[i] == '\\')
            i++;
    return i + 1;
}

/* Nesting deeper than MAX_SIDECAR_DEPTH: its byte offset, else -1. Strings are skipped, so a
 * bracket inside one does not count; anything else malformed is left to cJSON. */
static long too_deep(const char *text, size_t size)
{
    size_t i;
    int depth = 0;
    for (i = 0; i < size; i++) {
        if (text[i] == '"') {
            i = skip_string(text, size, i) - 1;
        } else if (text[i] == '{' || text[i] == '[') {
            if (++depth > MAX_SIDECAR_DEPTH)
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
    size_t begin[MAX_SIDECAR_DEPTH + 1]; /* per open container: its first key, or SIZE_MAX */
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
            if (depth >= MAX_SIDECAR_DEPTH)
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

/* An optional finite number of any sign (the aperture's blades, rotation and cat's eye: the
 * library judges their ranges). */
static int finite_number(const cJSON *root, const char *key, double *out, const char *path,
                         char *error, size_t error_size)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(root, key);
    if (!item)
        return 0;
    if (!cJSON_IsNumber(item) || !isfinite(item->valuedouble)) {
        snprintf(error, error_size, "%s: \"%s\" must be a finite number", path, key);
        return -1;
    }
    *out = item->valuedouble;
    return 0;
}

static int number(const cJSON *root, const char *key, int required, double *out,
                  const char *path, char *error, size_t error_size)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(root, key);
    if (!item) {
        if (!required)
            return 0;
        snprintf(error, error_size, "%s: missing \"%s\"", path, key);
        return -1;
    }
    if (!cJSON_IsNumber(item)) {
        snprintf(error, error_size, "%s: \"%s\" must be a number > 0", path, key);
        return -1;
    }
    if (!isfinite(item->valuedouble)) { /* cJSON reads 1e999 as infinity */
        snprintf(error, error_size, "%s: \"%s\" is larger than a double can hold; it must be "
                 "a finite number > 0", path, key);
        return -1;
    }
    if (!(item->valuedouble > 0.0)) {
        snprintf(error, error_size, "%s: \"%s\" is %.9g%s; it must be a number > 0", path,
                 key, item->valuedouble,
                 item->valuedouble == 0.0 ? " (or closer to 0 than a double can hold)" : "");
        return -1;
    }
    *out = item->valuedouble;
    return 0;
}

static int choice(const cJSON *root, const char *key, int required, const char *const *names,
                  int count, int *out, const char *path, char *error, size_t error_size)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(root, key);
    int i;
    if (!item) {
        if (!required)
            return 0;
        snprintf(error, error_size, "%s: missing \"%s\"", path, key);
        return -1;
    }
    if (cJSON_IsString(item)) {
        for (i = 0; i < count; i++) {
            if (strcasecmp(item->valuestring, names[i]) == 0) {
                *out = i;
                return 0;
            }
        }
    }
    snprintf(error, error_size, "%s: \"%s\" must be one of \"%s\", \"%s\"%s%s%s", path, key,
             names[0], names[1], count > 2 ? ", \"" : "", count > 2 ? names[2] : "",
             count > 2 ? "\"" : "");
    return -1;
}

static int resolution(const cJSON *root, uint32_t out[2], const char *path, char *error,
                      size_t error_size)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(root, "resolution");
    int i;
    if (!item) {
        snprintf(error, error_size, "%s: missing \"resolution\"", path);
        return -1;
    }
    if (!cJSON_IsArray(item) || cJSON_GetArraySize(item) != 2)
        goto bad;
    for (i = 0; i < 2; i++) {
        const cJSON *v = cJSON_GetArrayItem(item, i);
        if (!cJSON_IsNumber(v) || !(v->valuedouble >= 1.0) || v->valuedouble > 1e6 ||
            v->valuedouble != floor(v->valuedouble))
            goto bad;
        out[i] = (uint32_t)v->valuedouble;
    }
    return 0;
bad:
    snprintf(error, error_size, "%s: \"resolution\" must be [width, height] in whole pixels",
             path);
    return -1;
}

/* The sidecar's spellings, in the order of ddof_sensor_fit and ddof_depth_kind. */
static const char *const fits[] = {"AUTO", "HORIZONTAL", "VERTICAL"};
static const char *const depths[] = {"planar", "radial"};

const char *camera_sidecar_fit_name(ddof_sensor_fit fit)
{
    return (unsigned)fit < 3u ? fits[fit] : "?";
}

const char *camera_sidecar_depth_name(ddof_depth_kind kind)
{
    return (unsigned)kind < 2u ? depths[kind] : "?";
}

int camera_sidecar_parse(const char *text, size_t size, const char *path, camera_sidecar *out,
                         char *error, size_t error_size)
{
    const char *end = NULL;
    cJSON *root;
    size_t second = 0, first = 0, length = 0;
    char *decoded = NULL;
    long deep;
    int fit = 0, depth = 0, rc = -1, duplicate;
    double blades = 0.0;

    memset(out, 0, sizeof *out);
    ddof_camera_init(&out->camera);
    if (strlen(text) != size) {
        snprintf(error, error_size, "%s: not valid JSON (a NUL byte at byte %lu)", path,
                 (unsigned long)strlen(text));
        return -1;
    }
    deep = too_deep(text, size);
    if (deep >= 0) {
        snprintf(error, error_size, "%s: nested deeper than %d levels at byte %ld; a camera "
                 "sidecar is one object of numbers, strings and [width, height]", path,
                 MAX_SIDECAR_DEPTH, deep);
        return -1;
    }
    root = cJSON_ParseWithOpts(text, &end, 0);
    if (!root) {
        const char *at = cJSON_GetErrorPtr();
        long offset = at && at >= text ? (long)(at - text) : -1;
        snprintf(error, error_size, "%s: not valid JSON (near byte %ld)", path, offset);
        return -1;
    }
    while (end && (*end == ' ' || *end == '\t' || *end == '\n' || *end == '\r'))
        end++;
    if (end && *end) {
        snprintf(error, error_size, "%s: not valid JSON: data after the end of the JSON value "
                 "at byte %ld", path, (long)(end - text));
        goto done;
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
        goto done;
    }
    if (!cJSON_IsObject(root)) {
        snprintf(error, error_size, "%s: the camera sidecar must be a JSON object", path);
        goto done;
    }
    if (number(root, "focal_length_mm", 1, &out->camera.focal_length_mm, path, error,
               error_size) ||
        number(root, "sensor_width_mm", 1, &out->camera.sensor_width_mm, path, error,
               error_size) ||
        choice(root, "sensor_fit", 1, fits, 3, &fit, path, error, error_size) ||
        number(root, "fstop", 1, &out->camera.fstop, path, error, error_size) ||
        number(root, "focus_distance_m", 1, &out->camera.focus_distance_m, path, error,
               error_size) ||
        resolution(root, out->resolution, path, error, error_size) ||
        number(root, "pixel_aspect", 1, &out->camera.pixel_aspect, path, error, error_size) ||
        choice(root, "depth", 0, depths, 2, &depth, path, error, error_size) ||
        number(root, "unit_scale_m", 0, &out->camera.depth_unit_m, path, error, error_size) ||
        finite_number(root, "aperture_blades", &blades, path, error, error_size) ||
        finite_number(root, "aperture_rotation_deg", &out->camera.aperture_rotation_deg, path,
                      error, error_size) ||
        number(root, "aperture_ratio", 0, &out->camera.aperture_ratio, path, error,
               error_size) ||
        finite_number(root, "aperture_catseye", &out->camera.aperture_catseye, path, error,
                      error_size))
        goto done;
    if (!(blades >= 0.0 && blades <= DDOF_MAX_APERTURE_BLADES && blades == floor(blades))) {
        snprintf(error, error_size, "%s: \"aperture_blades\" must be a whole number within "
                 "0..%u (0: round)", path, DDOF_MAX_APERTURE_BLADES);
        goto done;
    }
    out->camera.aperture_blades = (uint32_t)blades;
    out->camera.sensor_fit = (ddof_sensor_fit)fit;
    out->camera.depth_kind = depth ? DDOF_DEPTH_RADIAL : DDOF_DEPTH_PLANAR;
    rc = 0;
done:
    cJSON_Delete(root);
    return rc;
}

int camera_sidecar_read(const char *path, camera_sidecar *out, char *error, size_t error_size)
{
    size_t size = 0;
    char *text = read_text(path, &size, error, error_size);
    int rc;
    memset(out, 0, sizeof *out);
    ddof_camera_init(&out->camera);
    if (!text)
        return -1;
    rc = camera_sidecar_parse(text, size, path, out, error, error_size);
    free(text);
    return rc;
}
