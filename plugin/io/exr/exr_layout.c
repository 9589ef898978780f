/* SPDX-License-Identifier: MIT */
/* exr_layout.c - which channels are colour, depth and CoC: Blender's multilayer names, plain
 * single-layer names, or names given explicitly (see exrio_layout.h). */
#include "exrio_layout.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_CANDIDATES 16

void exrio_list_channels(const exrio_image *image, int max_names, char *out, size_t out_size)
{
    size_t used = 0;
    int i;
    if (out_size == 0)
        return;
    out[0] = '\0';
    for (i = 0; i < image->channel_count; i++) {
        int n;
        if (i == max_names) {
            snprintf(out + used, out_size - used, " and %d more", image->channel_count - i);
            return;
        }
        if (image->part_count > 1 && image->parts[image->channels[i].part].name)
            n = snprintf(out + used, out_size - used, "%s%s/%s", i ? ", " : "",
                         image->parts[image->channels[i].part].name, image->channels[i].name);
        else
            n = snprintf(out + used, out_size - used, "%s%s", i ? ", " : "",
                         image->channels[i].name);
        if (n < 0 || (size_t)n >= out_size - used)
            return;
        used += (size_t)n;
    }
    if (image->channel_count == 0)
        snprintf(out, out_size, "(none)");
}

static void missing(const exrio_image *image, char *error, size_t error_size, const char *what,
                    const char *hint)
{
    char list[1024];
    exrio_list_channels(image, 40, list, sizeof list);
    snprintf(error, error_size, "%s: %s; channels in the file: %s%s%s", image->path, what, list,
             hint ? "; " : "", hint ? hint : "");
}

/* Channel `prefix` + "." + `component` (or just `component` for an empty prefix). */
static int find_component(const exrio_image *image, const char *prefix, const char *component,
                          int part)
{
    char name[512];
    if (prefix[0])
        snprintf(name, sizeof name, "%s.%s", prefix, component);
    else
        snprintf(name, sizeof name, "%s", component);
    return exrio_find_channel(image, name, part);
}

/* Fills layout->color from prefix P: P.R, P.G, P.B and, if present, P.A, in one part. */
static int color_from_prefix(const exrio_image *image, const char *prefix, int part,
                             exrio_layout *layout)
{
    static const char *const rgba[4] = {"R", "G", "B", "A"};
    int c, p;
    for (p = part < 0 ? 0 : part; p < (part < 0 ? image->part_count : part + 1); p++) {
        int idx[4];
        for (c = 0; c < 4; c++)
            idx[c] = find_component(image, prefix, rgba[c], p);
        if (idx[0] < 0 || idx[1] < 0 || idx[2] < 0)
            continue;
        memcpy(layout->color, idx, sizeof idx);
        layout->color_count = idx[3] >= 0 ? 4 : 3;
        layout->part = p;
        snprintf(layout->color_prefix, sizeof layout->color_prefix, "%s", prefix);
        return 0;
    }
    return -1;
}

/* "R,G,B[,A]": explicit names. */
static exrio_layout_status color_from_list(const exrio_image *image, const char *list,
                                           exrio_layout *layout, char *error, size_t error_size)
{
    char copy[1024];
    char *save = NULL, *token;
    int n = 0;
    snprintf(copy, sizeof copy, "%s", list);
    for (token = strtok_r(copy, ",", &save); token; token = strtok_r(NULL, ",", &save)) {
        int idx;
        if (n == 4) {
            snprintf(error, error_size, "--color: at most 4 channels (R,G,B,A), not '%s'", list);
            return EXRIO_LAYOUT_MISSING;
        }
        idx = exrio_find_channel(image, token, -1);
        if (idx < 0) {
            char what[600];
            snprintf(what, sizeof what, "no channel '%s' (from --color %s)", token, list);
            missing(image, error, error_size, what, NULL);
            return EXRIO_LAYOUT_MISSING;
        }
        layout->color[n++] = idx;
    }
    if (n < 3) {
        snprintf(error, error_size, "--color wants 3 or 4 channel names (R,G,B[,A]), not '%s'",
                 list);
        return EXRIO_LAYOUT_MISSING;
    }
    layout->color_count = n;
    layout->part = image->channels[layout->color[0]].part;
    layout->color_prefix[0] = '\0';
    return EXRIO_LAYOUT_OK;
}

/* The layer part of a colour prefix: "ViewLayer" for "ViewLayer.Combined", "" for "Combined"
 * or "". */
static void layer_of(const char *prefix, char *layer, size_t size)
{
    const char *dot = strrchr(prefix, '.');
    size_t n = dot ? (size_t)(dot - prefix) : 0;
    if (n >= size)
        n = size - 1;
    memcpy(layer, prefix, n);
    layer[n] = '\0';
}

/* Depth for a colour prefix: "<layer>.Depth.Z" first (Blender), then the single-layer names. */
static int find_depth(const exrio_image *image, const char *prefix, int part)
{
    static const char *const plain[] = {"Z", "Depth.Z", "depth.Z", "depth", "Depth", "Z.Z",
                                        "zdepth", "ZDepth"};
    char layer[256];
    size_t i;
    int idx, pass;
    layer_of(prefix, layer, sizeof layer);
    /* First in the colour's part, then anywhere (multi-part files may split them). */
    for (pass = 0; pass < 2; pass++) {
        int p = pass == 0 ? part : -1;
        if (layer[0]) {
            if ((idx = find_component(image, layer, "Depth.Z", p)) >= 0 ||
                (idx = find_component(image, layer, "Z", p)) >= 0)
                return idx;
        }
        for (i = 0; i < sizeof plain / sizeof plain[0]; i++)
            if ((idx = exrio_find_channel(image, plain[i], p)) >= 0)
                return idx;
    }
    return -1;
}

/* The one channel named "<layer>.Depth.Z" in the file, or -1 (none, or several layers). */
static int only_layer_depth(const exrio_image *image)
{
    static const char suffix[] = ".Depth.Z";
    const size_t s = sizeof suffix - 1;
    int found = -1;
    for (int i = 0; i < image->channel_count; i++) {
        const char *name = image->channels[i].name;
        const size_t n = strlen(name);
        if (n > s && !strcmp(name + n - s, suffix)) {
            if (found >= 0)
                return -1;
            found = i;
        }
    }
    return found;
}

int exrio_find_depth(const exrio_image *image, const char *color_prefix, const char *name)
{
    if (name)
        return exrio_find_channel(image, name, -1);
    const int idx = find_depth(image, color_prefix ? color_prefix : "", -1);
    /* A separate depth file need not share the colour's layer names: a Blender multilayer
     * file beside a plain RGB image (a composite, a lens truth) holds its depth as
     * "<layer>.Depth.Z"; with one such layer there is no doubt which it is. */
    return idx >= 0 ? idx : only_layer_depth(image);
}

/* Collects the automatic colour candidates: "" (plain R, G, B) and every "*.Combined" or
 * "Combined" prefix with R, G and B; with a layer, only those of that layer or part. */
static int collect_candidates(const exrio_image *image, const char *layer, const char *exclude,
                              char candidates[MAX_CANDIDATES][256])
{
    int count = 0, i, j;
    for (i = 0; i < image->channel_count; i++) {
        const exrio_channel *ch = &image->channels[i];
        const exrio_part *part = &image->parts[ch->part];
        size_t len = strlen(ch->name);
        char prefix[256];
        exrio_layout probe;
        if (len < 1 || ch->name[len - 1] != 'R' || (len > 1 && ch->name[len - 2] != '.'))
            continue;
        if (len - 1 >= sizeof prefix)
            continue;
        memcpy(prefix, ch->name, len > 1 ? len - 2 : 0);
        prefix[len > 1 ? len - 2 : 0] = '\0';
        if (prefix[0] && strcmp(prefix, "Combined") != 0) {
            size_t pl = strlen(prefix);
            if (pl < 9 || strcmp(prefix + pl - 9, ".Combined") != 0)
                continue;
        }
        if (layer) {
            char own[256];
            int by_part = part->name && strcmp(part->name, layer) == 0;
            layer_of(prefix, own, sizeof own);
            if (!by_part && strcmp(own, layer) != 0 && strcmp(prefix, layer) != 0)
                continue;
        }
        if (exclude) {
            char own[256];
            layer_of(prefix, own, sizeof own);
            if ((part->name && strcmp(part->name, exclude) == 0) || strcmp(own, exclude) == 0 ||
                strcmp(prefix, exclude) == 0)
                continue;
        }
        if (color_from_prefix(image, prefix, ch->part, &probe) != 0)
            continue;
        for (j = 0; j < count; j++)
            if (strcmp(candidates[j], prefix) == 0)
                break;
        if (j == count && count < MAX_CANDIDATES)
            snprintf(candidates[count++], 256, "%s", prefix);
    }
    return count;
}

static exrio_layout_status auto_color(const exrio_image *image, const exrio_layout_request *req,
                                      exrio_layout *layout, char *error, size_t error_size)
{
    char candidates[MAX_CANDIDATES][256];
    int count = collect_candidates(image, req->layer, req->exclude_layer, candidates);
    int with_depth[MAX_CANDIDATES];
    int i, best = -1, ties = 0;

    if (count == 0) {
        char what[400];
        if (req->layer)
            snprintf(what, sizeof what, "no colour channels (R, G, B) in layer '%s'", req->layer);
        else
            snprintf(what, sizeof what, "no colour channels found (looked for R, G, B and "
                     "<layer>.Combined.R/G/B)");
        missing(image, error, error_size, what, "name them with --color or --layer");
        return EXRIO_LAYOUT_MISSING;
    }
    /* A candidate whose layer also has depth wins (Blender adds a "Composite" layer with no
     * depth when compositing is on); among equals the choice must be the user's. */
    for (i = 0; i < count; i++) {
        exrio_layout probe;
        color_from_prefix(image, candidates[i], -1, &probe);
        with_depth[i] = find_depth(image, candidates[i], probe.part) >= 0;
    }
    for (i = 0; i < count; i++) {
        if (best < 0 || with_depth[i] > with_depth[best]) {
            best = i;
            ties = 0;
        } else if (with_depth[i] == with_depth[best]) {
            ties++;
        }
    }
    if (ties > 0 && !(req->layer && count == 1)) {
        char names[1024];
        size_t used = 0;
        for (i = 0; i < count && used < sizeof names; i++) {
            int n;
            if (with_depth[i] != with_depth[best])
                continue;
            n = snprintf(names + used, sizeof names - used, "%s'%s'", used ? ", " : "",
                         candidates[i][0] ? candidates[i] : "R,G,B");
            if (n < 0)
                break;
            used += (size_t)n;
        }
        snprintf(error, error_size, "%s: several colour layers: %s; choose one with --layer or "
                 "--color", image->path, names);
        return EXRIO_LAYOUT_AMBIGUOUS;
    }
    color_from_prefix(image, candidates[best], -1, layout);
    return EXRIO_LAYOUT_OK;
}

static int same_window(const exrio_part *a, const exrio_part *b)
{
    return a->data_window.min_x == b->data_window.min_x &&
           a->data_window.min_y == b->data_window.min_y &&
           a->data_window.max_x == b->data_window.max_x &&
           a->data_window.max_y == b->data_window.max_y;
}

static exrio_layout_status check_sizes(const exrio_image *image, const exrio_layout *layout,
                                       char *error, size_t error_size)
{
    const exrio_part *color = &image->parts[layout->part];
    int others[6], n = 0, i;
    for (i = 0; i < layout->color_count; i++)
        others[n++] = layout->color[i];
    if (layout->depth >= 0)
        others[n++] = layout->depth;
    if (layout->coc >= 0)
        others[n++] = layout->coc;
    for (i = 0; i < n; i++) {
        const exrio_channel *ch = &image->channels[others[i]];
        const exrio_part *part = &image->parts[ch->part];
        if (!same_window(color, part)) {
            snprintf(error, error_size,
                     "%s: mismatched layer sizes: %s is %ux%u at (%d,%d) but colour (%s) is "
                     "%ux%u at (%d,%d)", image->path, ch->name, part->width, part->height,
                     (int)part->data_window.min_x, (int)part->data_window.min_y,
                     image->channels[layout->color[0]].name, color->width, color->height,
                     (int)color->data_window.min_x, (int)color->data_window.min_y);
            return EXRIO_LAYOUT_MISMATCH;
        }
    }
    return EXRIO_LAYOUT_OK;
}

exrio_layout_status exrio_find_layout(const exrio_image *image,
                                      const exrio_layout_request *req, exrio_layout *layout,
                                      char *error, size_t error_size)
{
    exrio_layout_status status;
    memset(layout, 0, sizeof *layout);
    layout->color[3] = -1;
    layout->depth = -1;
    layout->coc = -1;

    if (req->color && strchr(req->color, ',')) {
        status = color_from_list(image, req->color, layout, error, error_size);
    } else if (req->color) {
        status = EXRIO_LAYOUT_OK;
        if (color_from_prefix(image, req->color, -1, layout) != 0) {
            char what[600];
            snprintf(what, sizeof what, "no channels %s.R, %s.G, %s.B (from --color)",
                     req->color, req->color, req->color);
            missing(image, error, error_size, what, NULL);
            status = EXRIO_LAYOUT_MISSING;
        }
    } else {
        status = auto_color(image, req, layout, error, error_size);
    }
    if (status != EXRIO_LAYOUT_OK)
        return status;

    if (req->coc) {
        layout->coc = exrio_find_channel(image, req->coc, layout->part);
        if (layout->coc < 0)
            layout->coc = exrio_find_channel(image, req->coc, -1);
        if (layout->coc < 0) {
            char what[600];
            snprintf(what, sizeof what, "no CoC channel '%s'", req->coc);
            missing(image, error, error_size, what, NULL);
            return EXRIO_LAYOUT_MISSING;
        }
    }
    if (req->depth) {
        layout->depth = exrio_find_channel(image, req->depth, layout->part);
        if (layout->depth < 0)
            layout->depth = exrio_find_channel(image, req->depth, -1);
        if (layout->depth < 0 && req->need_depth) {
            char what[600];
            snprintf(what, sizeof what, "no depth channel '%s'", req->depth);
            missing(image, error, error_size, what, NULL);
            return EXRIO_LAYOUT_MISSING;
        }
    } else if (req->need_depth) {
        layout->depth = find_depth(image, layout->color_prefix, layout->part);
        if (layout->depth < 0) {
            char what[600];
            char layer[256];
            layer_of(layout->color_prefix, layer, sizeof layer);
            snprintf(what, sizeof what, "no depth channel found (looked for %s%sZ, depth, "
                     "Depth.Z)", layer[0] ? layer : "", layer[0] ? ".Depth.Z, " : "");
            missing(image, error, error_size, what,
                    "name it with --depth, or give CoC in a channel with --coc-channel");
            return EXRIO_LAYOUT_MISSING;
        }
    }
    return check_sizes(image, layout, error, error_size);
}
