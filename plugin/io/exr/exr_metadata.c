/* SPDX-License-Identifier: MIT */
/* exr_metadata.c - carrying an input's header attributes (camera matrices, render time, frame
 * rate, artist notes, ...) over to an output, attribute by attribute through the typed setters
 * of the C core, skipping those that describe a pixel layout the output does not have. */
#include "exr_dwa.h"
#include "exr_internal.h"

#include <stdlib.h>
#include <string.h>

/* Attributes the writer owns (they describe the new file's layout), and the embedded preview
 * image, which would show the input rather than the result. */
int exrio_is_layout_attribute(const char *name)
{
    static const char *const owned[] = {
        "channels",          "compression",        "dataWindow",  "displayWindow",
        "lineOrder",         "pixelAspectRatio",   "screenWindowCenter",
        "screenWindowWidth", "tiles",              "type",        "name",
        "chunkCount",        "version",            "maxSamplesPerPixel",
        "preview",           "dwaCompressionLevel"};
    size_t i;
    for (i = 0; i < sizeof owned / sizeof owned[0]; i++)
        if (strcmp(name, owned[i]) == 0)
            return 1;
    return 0;
}

static exr_result_t copy_string_vector(exr_context_t out, const exr_attribute_t *a)
{
    const exr_attr_string_vector_t *sv = a->stringvector;
    const char **strings;
    exr_result_t rv;
    int32_t i;
    if (sv->n_strings <= 0)
        return exr_attr_set_string_vector(out, 0, a->name, 0, NULL);
    strings = malloc((size_t)sv->n_strings * sizeof *strings);
    if (!strings)
        return EXR_ERR_OUT_OF_MEMORY;
    for (i = 0; i < sv->n_strings; i++)
        strings[i] = sv->strings[i].str ? sv->strings[i].str : "";
    rv = exr_attr_set_string_vector(out, 0, a->name, sv->n_strings, strings);
    free(strings);
    return rv;
}

static exr_result_t copy_string(exr_context_t out, const exr_attribute_t *a)
{
    /* Copied with its length: the stored string need not end in a NUL. */
    const exr_attr_string_t *s = a->string;
    exr_result_t rv;
    char *text = malloc((size_t)(s->length > 0 ? s->length : 0) + 1);
    if (!text)
        return EXR_ERR_OUT_OF_MEMORY;
    if (s->length > 0)
        memcpy(text, s->str, (size_t)s->length);
    text[s->length > 0 ? s->length : 0] = '\0';
    rv = exr_attr_set_string(out, 0, a->name, text);
    free(text);
    return rv;
}

static exr_result_t copy_attribute(exr_context_t out, const exr_attribute_t *a)
{
    switch (a->type) {
    case EXR_ATTR_BOX2I:
        return exr_attr_set_box2i(out, 0, a->name, a->box2i);
    case EXR_ATTR_BOX2F:
        return exr_attr_set_box2f(out, 0, a->name, a->box2f);
    case EXR_ATTR_CHROMATICITIES:
        return exr_attr_set_chromaticities(out, 0, a->name, a->chromaticities);
    case EXR_ATTR_COMPRESSION:
        return exr_attr_set_compression(out, 0, a->name, (exr_compression_t)a->uc);
    case EXR_ATTR_DOUBLE:
        return exr_attr_set_double(out, 0, a->name, a->d);
    case EXR_ATTR_ENVMAP:
        return exr_attr_set_envmap(out, 0, a->name, (exr_envmap_t)a->uc);
    case EXR_ATTR_FLOAT:
        return exr_attr_set_float(out, 0, a->name, a->f);
    case EXR_ATTR_FLOAT_VECTOR:
        return exr_attr_set_float_vector(out, 0, a->name, a->floatvector->length,
                                         a->floatvector->arr);
    case EXR_ATTR_INT:
        return exr_attr_set_int(out, 0, a->name, a->i);
    case EXR_ATTR_KEYCODE:
        return exr_attr_set_keycode(out, 0, a->name, a->keycode);
    case EXR_ATTR_LINEORDER:
        return exr_attr_set_lineorder(out, 0, a->name, (exr_lineorder_t)a->uc);
    case EXR_ATTR_M33F:
        return exr_attr_set_m33f(out, 0, a->name, a->m33f);
    case EXR_ATTR_M33D:
        return exr_attr_set_m33d(out, 0, a->name, a->m33d);
    case EXR_ATTR_M44F:
        return exr_attr_set_m44f(out, 0, a->name, a->m44f);
    case EXR_ATTR_M44D:
        return exr_attr_set_m44d(out, 0, a->name, a->m44d);
    case EXR_ATTR_RATIONAL:
        return exr_attr_set_rational(out, 0, a->name, a->rational);
    case EXR_ATTR_STRING:
        return copy_string(out, a);
    case EXR_ATTR_STRING_VECTOR:
        return copy_string_vector(out, a);
    case EXR_ATTR_TILEDESC:
        return exr_attr_set_tiledesc(out, 0, a->name, a->tiledesc);
    case EXR_ATTR_TIMECODE:
        return exr_attr_set_timecode(out, 0, a->name, a->timecode);
    case EXR_ATTR_V2I:
        return exr_attr_set_v2i(out, 0, a->name, a->v2i);
    case EXR_ATTR_V2F:
        return exr_attr_set_v2f(out, 0, a->name, a->v2f);
    case EXR_ATTR_V2D:
        return exr_attr_set_v2d(out, 0, a->name, a->v2d);
    case EXR_ATTR_V3I:
        return exr_attr_set_v3i(out, 0, a->name, a->v3i);
    case EXR_ATTR_V3F:
        return exr_attr_set_v3f(out, 0, a->name, a->v3f);
    case EXR_ATTR_V3D:
        return exr_attr_set_v3d(out, 0, a->name, a->v3d);
    case EXR_ATTR_OPAQUE:
        /* A type this core does not know: its bytes go across unchanged. */
        if (a->opaque && a->opaque->packed_data && a->opaque->size > 0)
            return exr_attr_set_user(out, 0, a->name, a->type_name, a->opaque->size,
                                     a->opaque->packed_data);
        return EXR_ERR_SUCCESS;
    default:
        /* chlist and preview are layout attributes, filtered above; anything else unknown is
         * left out rather than guessed at. */
        return EXR_ERR_SUCCESS;
    }
}

exr_result_t exrio_copy_metadata(exr_context_t out, exr_const_context_t source, int part)
{
    const exr_attribute_t *a = NULL;
    exr_result_t rv;
    int32_t count = 0, i;

    rv = exr_get_attribute_count(source, part, &count);
    for (i = 0; rv == EXR_ERR_SUCCESS && i < count; i++) {
        rv = exr_get_attribute_by_index(source, part, EXR_ATTR_LIST_FILE_ORDER, i, &a);
        if (rv == EXR_ERR_SUCCESS && a && !exrio_is_layout_attribute(a->name))
            rv = copy_attribute(out, a);
    }
    return rv;
}
