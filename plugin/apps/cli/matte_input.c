/* SPDX-License-Identifier: MIT */
/* matte_input.c - the object matte among the input's channels (matte_input.h). Cryptomatte
 * writes a layer's ranks two to a sub-layer: <layer>00.r/.g the first (id, coverage), .b/.a
 * the second, <layer>01 the next two; Blender prefixes them with the view layer
 * ("ViewLayer.CryptoObject00.r"), other renderers write them bare ("crypto_object00.R"). */
#include "matte_input.h"

#include <ctype.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

/* The view layer's prefix of the colour's channels: "ViewLayer." of "ViewLayer.Combined". */
static size_t view_prefix_length(const char *color_prefix)
{
    const char *dot = strrchr(color_prefix, '.');
    return dot ? (size_t)(dot - color_prefix) + 1 : 0;
}

/* Whether `layer` names the matte wanted: `name`, or for auto either spelling of the objects'. */
static int is_wanted(const char *layer, size_t length, const char *name)
{
    if (name)
        return strlen(name) == length && strncasecmp(layer, name, length) == 0;
    return (length == 12 && strncasecmp(layer, "CryptoObject", 12) == 0) ||
           (length == 13 && strncasecmp(layer, "crypto_object", 13) == 0);
}

/* Splits "<layer>NN.c" into the layer's length, NN and c's slot (r 0, g 1, b 2, a 3); 0 when
 * the channel is not of that shape. */
static int parse_channel(const char *rest, size_t *layer_length, int *sub, int *slot)
{
    const char *dot = strrchr(rest, '.');
    if (!dot || dot - rest < 3 || strlen(dot) != 2)
        return 0;
    const char *digits = dot - 2;
    if (!isdigit((unsigned char)digits[0]) || !isdigit((unsigned char)digits[1]))
        return 0;
    const char *slots = "rgba", *found = strchr(slots, tolower((unsigned char)dot[1]));
    if (!found || !dot[1])
        return 0;
    *layer_length = (size_t)(digits - rest);
    *sub = (digits[0] - '0') * 10 + (digits[1] - '0');
    *slot = (int)(found - slots);
    return 1;
}

int matte_find(const exrio_image *image, const exrio_layout *layout, const char *name,
               int *index, char *found, size_t found_size, char *error, size_t error_size)
{
    found[0] = '\0';
    if (name && strcmp(name, "off") == 0)
        return 0;
    const int automatic = !name || strcmp(name, "auto") == 0;
    const size_t prefix = view_prefix_length(layout->color_prefix);
    enum { SUBS = DDOF_MATTE_MAX_RANKS / 2 };
    int channel[SUBS][4];
    memset(channel, -1, sizeof channel);
    for (int c = 0; c < image->channel_count; c++) {
        const char *full = image->channels[c].name;
        size_t length;
        int sub, slot;
        if (image->channels[c].part != layout->part ||
            strncmp(full, layout->color_prefix, prefix) != 0 ||
            !parse_channel(full + prefix, &length, &sub, &slot) ||
            !is_wanted(full + prefix, length, automatic ? NULL : name) || sub >= SUBS)
            continue;
        /* One layer whole: a file with both spellings gives the first it holds, never a mix. */
        if (!found[0])
            snprintf(found, found_size, "%.*s", (int)(prefix + length), full);
        else if (strlen(found) != prefix + length || strncmp(full, found, prefix + length) != 0)
            continue;
        channel[sub][slot] = c;
    }
    /* The sub-layers run from 00 without a gap: a missing 00 (01 present) or 01 (02 present)
     * is a damaged or mis-named matte, not a file without one. */
    int last = -1;
    for (int sub = 0; sub < SUBS; sub++)
        for (int slot = 0; slot < 4; slot++)
            if (channel[sub][slot] >= 0)
                last = sub;
    int ranks = 0;
    for (int sub = 0; sub <= last; sub++) {
        if (channel[sub][0] < 0 && channel[sub][1] < 0 && channel[sub][2] < 0 &&
            channel[sub][3] < 0) {
            snprintf(error, error_size, "the matte %s has sub-layer %02d but not %02d: its "
                     "sub-layers run from 00 without a gap", found, last, sub);
            return -1;
        }
        for (int slot = 0; slot < 4; slot++) {
            const int c = channel[sub][slot];
            if (c < 0) {
                snprintf(error, error_size, "the matte %s has sub-layer %02d without its %c "
                         "channel", found, sub, "rgba"[slot]);
                return -1;
            }
            if (slot % 2 == 0 && image->channels[c].type != EXRIO_FLOAT) {
                snprintf(error, error_size, "the matte's ids (%s) are stored as %s: only 32-bit "
                         "float holds them", image->channels[c].name,
                         exrio_pixel_type_name(image->channels[c].type));
                return -1;
            }
            index[2 * ranks + slot] = c;
        }
        ranks += 2;
    }
    if (!ranks && !automatic) {
        snprintf(error, error_size, "no matte %s (channels %.*s%s00.r, .g, .b, .a) beside the "
                 "colour %s", name, (int)prefix, layout->color_prefix, name,
                 layout->color_prefix[0] ? layout->color_prefix : "R,G,B");
        return -1;
    }
    if (!ranks)
        found[0] = '\0';
    return ranks;
}
