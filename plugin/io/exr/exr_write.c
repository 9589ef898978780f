/* SPDX-License-Identifier: MIT */
/* exr_write.c - writing one scanline part through OpenEXR's C core onto an open descriptor. */
#include "exr_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static exr_attr_box2i_t box_to(const exrio_box *b)
{
    exr_attr_box2i_t box;
    box.min.x = b->min_x;
    box.min.y = b->min_y;
    box.max.x = b->max_x;
    box.max.y = b->max_y;
    return box;
}

static int box_valid(const exrio_box *b)
{
    return b->max_x >= b->min_x && b->max_y >= b->min_y;
}

/* B44 compresses half channels only; a part without one gets a chunk layout of exactly the raw
 * size, which OpenEXR's C++ reader (Blender's, Nuke's) takes as uncompressed and reads with its
 * channels shuffled while the C core decodes it. Such a part is written uncompressed, which both
 * read alike. */
static exrio_compression stored_compression(const exrio_write_spec *spec)
{
    int c;
    if (spec->compression != EXRIO_COMPRESSION_B44 && spec->compression != EXRIO_COMPRESSION_B44A)
        return spec->compression;
    for (c = 0; c < spec->channel_count; c++)
        if (spec->channels[c].type == EXRIO_HALF)
            return spec->compression;
    return EXRIO_COMPRESSION_NONE;
}

/* Sets the part's attributes and channels. Channels are declared in the caller's order; the
 * core keeps its list sorted by name, as the file format requires. */
static exr_result_t define_part(exr_context_t ctxt, const exrio_write_spec *spec)
{
    exr_attr_box2i_t data = box_to(&spec->data_window);
    exr_attr_box2i_t display = box_to(&spec->display_window);
    exr_attr_v2f_t center;
    exr_result_t rv;
    int part = 0, c;

    center.x = 0.0f;
    center.y = 0.0f;
    rv = exr_add_part(ctxt, NULL, EXR_STORAGE_SCANLINE, &part);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_initialize_required_attr(ctxt, part, &display, &data,
                                          spec->pixel_aspect > 0.0f ? spec->pixel_aspect : 1.0f,
                                          &center, 1.0f, EXR_LINEORDER_INCREASING_Y,
                                          (exr_compression_t)stored_compression(spec));
    for (c = 0; rv == EXR_ERR_SUCCESS && c < spec->channel_count; c++) {
        const exrio_write_channel *ch = &spec->channels[c];
        rv = exr_add_channel(ctxt, part, ch->name, (exr_pixel_type_t)ch->type,
                             ch->type == EXRIO_UINT ? EXR_PERCEPTUALLY_LINEAR
                                                    : EXR_PERCEPTUALLY_LOGARITHMIC,
                             1, 1);
    }
    if (rv == EXR_ERR_SUCCESS && spec->metadata_from && spec->metadata_from->source_)
        rv = exrio_copy_metadata(ctxt, spec->metadata_from->source_, spec->metadata_part);
    return rv;
}

/* Finds the caller's channel for the encoder's channel `name` (the encoder lists them sorted). */
static const exrio_write_channel *spec_channel(const exrio_write_spec *spec, const char *name)
{
    int c;
    for (c = 0; c < spec->channel_count; c++)
        if (strcmp(spec->channels[c].name, name) == 0)
            return &spec->channels[c];
    return NULL;
}

typedef exr_result_t (*compress_fn_t)(exr_encode_pipeline_t *);

/* A zip chunk whose deflated size is not below its raw size must be stored raw: readers take a
 * zip chunk of exactly the raw size as uncompressed. OpenEXR 3.1's zip encoder stores raw only
 * when deflate makes the chunk larger, so a chunk that deflates to exactly its raw size read back
 * as the zlib stream. (Its other encoders already store raw, or, like B44, write a layout of the
 * raw size that its reader decodes.) */
static exr_result_t deflate_or_store(exr_encode_pipeline_t *encoder)
{
    const compress_fn_t deflate = *(const compress_fn_t *)encoder->encoding_user_data;
    exr_result_t rv = deflate(encoder);
    if (rv == EXR_ERR_SUCCESS && encoder->compressed_buffer != encoder->packed_buffer &&
        encoder->compressed_bytes >= encoder->packed_bytes) {
        memcpy(encoder->compressed_buffer, encoder->packed_buffer, encoder->packed_bytes);
        encoder->compressed_bytes = encoder->packed_bytes;
    }
    return rv;
}

static exr_result_t write_pixels(exr_context_t ctxt, const exrio_write_spec *spec)
{
    exr_encode_pipeline_t encoder = EXR_ENCODE_PIPELINE_INITIALIZER;
    compress_fn_t deflate = NULL;
    exr_chunk_info_t cinfo;
    exr_result_t rv;
    int32_t lines = 0, y;
    int initialized = 0, c;

    rv = exr_get_scanlines_per_chunk(ctxt, 0, &lines);
    if (rv == EXR_ERR_SUCCESS && lines <= 0)
        rv = EXR_ERR_INVALID_ATTR;
    for (y = spec->data_window.min_y; rv == EXR_ERR_SUCCESS && y <= spec->data_window.max_y;
         y += lines) {
        const size_t row = (size_t)(y - spec->data_window.min_y);
        rv = exr_write_scanline_chunk_info(ctxt, 0, y, &cinfo);
        if (rv != EXR_ERR_SUCCESS)
            break;
        rv = initialized ? exr_encoding_update(ctxt, 0, &cinfo, &encoder)
                         : exr_encoding_initialize(ctxt, 0, &cinfo, &encoder);
        if (rv != EXR_ERR_SUCCESS)
            break;
        for (c = 0; c < encoder.channel_count; c++) {
            exr_coding_channel_info_t *out = &encoder.channels[c];
            const exrio_write_channel *ch = spec_channel(spec, out->channel_name);
            if (!ch) {
                rv = EXR_ERR_INVALID_ARGUMENT;
                break;
            }
            out->encode_from_ptr = (const uint8_t *)ch->pixels + row * ch->line_stride;
            out->user_pixel_stride = (int32_t)ch->pixel_stride;
            out->user_line_stride = (int32_t)ch->line_stride;
            out->user_bytes_per_element = 4;
            out->user_data_type = ch->type == EXRIO_UINT ? EXR_PIXEL_UINT : EXR_PIXEL_FLOAT;
        }
        if (rv != EXR_ERR_SUCCESS)
            break;
        if (!initialized) {
            rv = exr_encoding_choose_default_routines(ctxt, 0, &encoder);
            if (rv != EXR_ERR_SUCCESS)
                break;
            initialized = 1;
            if (encoder.compress_fn && (spec->compression == EXRIO_COMPRESSION_ZIP ||
                                        spec->compression == EXRIO_COMPRESSION_ZIPS)) {
                deflate = encoder.compress_fn;
                encoder.encoding_user_data = &deflate;
                encoder.compress_fn = deflate_or_store;
            }
        }
        rv = exr_encoding_run(ctxt, 0, &encoder);
    }
    if (initialized || encoder.channels)
        exr_encoding_destroy(ctxt, &encoder);
    return rv;
}

static int check_spec(const exrio_write_spec *spec, char *error, size_t error_size,
                      const char *name)
{
    uint64_t w, h;
    int c, d;
    if (!box_valid(&spec->data_window) || !box_valid(&spec->display_window)) {
        snprintf(error, error_size, "%s: empty data or display window", name);
        return -1;
    }
    if (spec->channel_count < 1 || !spec->channels) {
        snprintf(error, error_size, "%s: no channels to write", name);
        return -1;
    }
    if (!exrio_compression_can_encode(spec->compression)) {
        snprintf(error, error_size, "%s: OpenEXR's C core (OpenEXRCore 3.1) cannot write %s "
                 "compression; use zip, piz, zips, rle, pxr24, b44, b44a or none",
                 name, exrio_compression_name(spec->compression));
        return -1;
    }
    w = (uint64_t)((int64_t)spec->data_window.max_x - spec->data_window.min_x + 1);
    h = (uint64_t)((int64_t)spec->data_window.max_y - spec->data_window.min_y + 1);
    for (c = 0; c < spec->channel_count; c++) {
        const exrio_write_channel *ch = &spec->channels[c];
        if (!ch->name || !ch->name[0] || !ch->pixels || ch->pixel_stride < 4 ||
            ch->pixel_stride > 0x7fffffff || ch->line_stride < ch->pixel_stride * w ||
            ch->line_stride > 0x7fffffff || (unsigned)ch->type > EXRIO_FLOAT || h == 0) {
            snprintf(error, error_size, "%s: channel %d (%s) is badly described", name, c,
                     ch->name ? ch->name : "no name");
            return -1;
        }
        for (d = 0; d < c; d++) {
            if (strcmp(spec->channels[d].name, ch->name) == 0) {
                snprintf(error, error_size, "%s: channel %s given twice", name, ch->name);
                return -1;
            }
        }
    }
    return 0;
}

exrio_status exrio_write_fd(int fd, const char *name, const exrio_write_spec *spec, char *error,
                            size_t error_size)
{
    exrio_stream stream;
    exr_context_initializer_t init;
    exr_context_t ctxt = NULL;
    exr_result_t rv;
    const char *stage = "cannot start writing";

    if (!spec || fd < 0) {
        snprintf(error, error_size, "%s: nothing to write", name);
        return EXRIO_ERROR_ARGUMENT;
    }
    if (check_spec(spec, error, error_size, name) != 0)
        return EXRIO_ERROR_ARGUMENT;

    memset(&stream, 0, sizeof stream);
    stream.fd = fd;
    stream.size = -1;
    init = exrio_stream_initializer(&stream, 1);
    exrio_begin_write(&stream);
    rv = exr_start_write(&ctxt, name, EXR_WRITE_FILE_DIRECTLY, &init);
    /* Blender's own attributes (cycles.ViewLayer.synchronization_time) and layered channel
     * names pass 31 characters: allow the long names of the format (EXR version flag 0x400). */
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_set_longname_support(ctxt, 1);
    if (rv == EXR_ERR_SUCCESS) {
        stage = "cannot define the header";
        rv = define_part(ctxt, spec);
    }
    if (rv == EXR_ERR_SUCCESS) {
        stage = "cannot write the header";
        rv = exr_write_header(ctxt);
    }
    if (rv == EXR_ERR_SUCCESS) {
        stage = "cannot write pixels";
        rv = write_pixels(ctxt, spec);
    }
    if (ctxt) {
        /* exr_finish writes the chunk offset table: its failure is a failed write too. */
        exr_result_t finish = exr_finish(&ctxt);
        if (rv == EXR_ERR_SUCCESS && finish != EXR_ERR_SUCCESS) {
            stage = "cannot finish the file";
            rv = finish;
        }
    }
    exrio_end_write();
    if (rv != EXR_ERR_SUCCESS)
        return exrio_fail(rv == EXR_ERR_OUT_OF_MEMORY ? EXRIO_ERROR_MEMORY : EXRIO_ERROR_WRITE,
                          &stream, error, error_size, name, stage, rv);
    return EXRIO_OK;
}
