/* SPDX-License-Identifier: MIT */
/* exr_write.c - writing one scanline part through OpenEXR's C core onto an open descriptor. */
#include "exr_dwa.h"
#include "exr_internal.h"
#include "exr_zip.h"

#include <pthread.h>
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
    if (rv == EXR_ERR_SUCCESS && spec->zip_level > 0)
        rv = exr_set_zip_compression_level(ctxt, part, spec->zip_level);
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

/* What the workers of one write share. Each chunk is claimed by one worker, encoded there (the
 * costly part: compression), and written once every chunk before it is: the file is the same,
 * byte for byte, whatever the number of threads. */
typedef struct write_job {
    exr_context_t ctxt;
    const exrio_write_spec *spec;
    int32_t lines;              /* scanlines per chunk                                      */
    int32_t chunks;
    pthread_mutex_t lock;
    pthread_cond_t written;     /* next_write moved on, or a worker failed                  */
    int32_t next_claim;
    int32_t next_write;
    exr_result_t failed;        /* the first failure; EXR_ERR_SUCCESS while none            */
    exrio_stream failure;       /* its error record                                          */
} write_job;

/* A worker's pipeline user data. */
typedef struct encode_user {
    write_job *job;
    struct libdeflate_compressor *zip;  /* ZIP and ZIPS parts: this worker's compressor     */
    int32_t chunk;              /* the chunk being encoded                                  */
} encode_user;

static exr_result_t zip_compress(exr_encode_pipeline_t *encoder)
{
    const encode_user *user = encoder->encoding_user_data;
    return exrio_zip_compress(encoder, user->zip);
}

/* The encoder's buffers come from the C library's heap, through these (exrio_zip_compress
 * grows them as the core would). */
static void *buffer_alloc(exr_transcoding_pipeline_buffer_id_t id, size_t size)
{
    (void)id;
    return malloc(size);
}

static void buffer_free(exr_transcoding_pipeline_buffer_id_t id, void *buffer)
{
    (void)id;
    free(buffer);
}

/* The pipeline's last step: waits for the chunk's turn, writes it, and passes the turn on. The
 * core's own step would write at once and refuse a chunk out of order. */
static exr_result_t write_in_order(exr_encode_pipeline_t *encoder)
{
    const encode_user *user = encoder->encoding_user_data;
    write_job *job = user->job;
    exr_result_t rv;

    pthread_mutex_lock(&job->lock);
    while (job->next_write != user->chunk && job->failed == EXR_ERR_SUCCESS)
        pthread_cond_wait(&job->written, &job->lock);
    rv = job->failed;
    pthread_mutex_unlock(&job->lock);
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    /* Only this worker holds the turn: the write itself needs no lock of ours. */
    rv = exr_write_scanline_chunk(job->ctxt, 0, encoder->chunk.start_y, encoder->compressed_buffer,
                                  encoder->compressed_bytes);
    pthread_mutex_lock(&job->lock);
    if (rv == EXR_ERR_SUCCESS)
        job->next_write++;
    pthread_cond_broadcast(&job->written);
    pthread_mutex_unlock(&job->lock);
    return rv;
}

/* Points the encoder's channels at the caller's rows of the chunk starting at `row`. */
static exr_result_t bind_channels(exr_encode_pipeline_t *encoder, const exrio_write_spec *spec,
                                  size_t row)
{
    int c;
    for (c = 0; c < encoder->channel_count; c++) {
        exr_coding_channel_info_t *out = &encoder->channels[c];
        const exrio_write_channel *ch = spec_channel(spec, out->channel_name);
        if (!ch)
            return EXR_ERR_INVALID_ARGUMENT;
        out->encode_from_ptr = (const uint8_t *)ch->pixels + row * ch->line_stride;
        out->user_pixel_stride = (int32_t)ch->pixel_stride;
        out->user_line_stride = (int32_t)ch->line_stride;
        out->user_bytes_per_element = 4;
        out->user_data_type = ch->type == EXRIO_UINT ? EXR_PIXEL_UINT : EXR_PIXEL_FLOAT;
    }
    return EXR_ERR_SUCCESS;
}

static void write_worker(void *arg, unsigned index)
{
    write_job *job = arg;
    const exrio_write_spec *spec = job->spec;
    exr_encode_pipeline_t encoder = EXR_ENCODE_PIPELINE_INITIALIZER;
    encode_user user;
    exrio_stream record;
    exr_chunk_info_t cinfo;
    exr_result_t rv = EXR_ERR_SUCCESS;
    int initialized = 0;

    (void)index;
    memset(&record, 0, sizeof record);
    record.fd = -1;
    record.size = -1;
    user.job = job;
    user.zip = NULL;
    user.chunk = -1;
    exrio_set_error_sink(&record);
    for (;;) {
        int32_t k = -1, y;
        pthread_mutex_lock(&job->lock);
        if (job->failed == EXR_ERR_SUCCESS && job->next_claim < job->chunks)
            k = job->next_claim++;
        pthread_mutex_unlock(&job->lock);
        if (k < 0)
            break;
        y = spec->data_window.min_y + k * job->lines;
        rv = exr_write_scanline_chunk_info(job->ctxt, 0, y, &cinfo);
        if (rv == EXR_ERR_SUCCESS)
            rv = initialized ? exr_encoding_update(job->ctxt, 0, &cinfo, &encoder)
                             : exr_encoding_initialize(job->ctxt, 0, &cinfo, &encoder);
        if (rv == EXR_ERR_SUCCESS)
            rv = bind_channels(&encoder, spec, (size_t)(y - spec->data_window.min_y));
        if (rv == EXR_ERR_SUCCESS && !initialized) {
            rv = exr_encoding_choose_default_routines(job->ctxt, 0, &encoder);
            if (rv != EXR_ERR_SUCCESS)
                break;
            initialized = 1;
            encoder.encoding_user_data = &user;
            encoder.yield_until_ready_fn = NULL;
            encoder.write_fn = write_in_order;
            encoder.alloc_fn = buffer_alloc;
            encoder.free_fn = buffer_free;
            if (encoder.compress_fn && (spec->compression == EXRIO_COMPRESSION_ZIP ||
                                        spec->compression == EXRIO_COMPRESSION_ZIPS)) {
                user.zip = exrio_zip_compressor(spec->zip_level);
                if (!user.zip) {
                    rv = EXR_ERR_OUT_OF_MEMORY;
                    break;
                }
                encoder.compress_fn = zip_compress;
            }
        }
        if (rv != EXR_ERR_SUCCESS)
            break;
        user.chunk = k;
        rv = exr_encoding_run(job->ctxt, 0, &encoder);
        if (rv != EXR_ERR_SUCCESS)
            break;
    }
    if (initialized || encoder.channels)
        exr_encoding_destroy(job->ctxt, &encoder);
    if (user.zip)
        exrio_zip_compressor_free(user.zip);
    exrio_set_error_sink(NULL);
    pthread_mutex_lock(&job->lock);
    if (rv != EXR_ERR_SUCCESS && job->failed == EXR_ERR_SUCCESS) {
        job->failed = rv;
        job->failure = record;
    }
    pthread_cond_broadcast(&job->written);
    pthread_mutex_unlock(&job->lock);
}

static exr_result_t write_pixels(exr_context_t ctxt, const exrio_write_spec *spec,
                                 exrio_stream *stream)
{
    write_job job;
    exr_result_t rv;
    unsigned workers;

    memset(&job, 0, sizeof job);
    job.ctxt = ctxt;
    job.spec = spec;
    rv = exr_get_scanlines_per_chunk(ctxt, 0, &job.lines);
    if (rv == EXR_ERR_SUCCESS && job.lines <= 0)
        rv = EXR_ERR_INVALID_ATTR;
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    job.chunks = (int32_t)(((int64_t)spec->data_window.max_y - spec->data_window.min_y +
                            job.lines) / job.lines);
    /* Uncompressed chunks have nothing to share out: the core packs under its context's lock. */
    workers = spec->threads > 1 && spec->compression != EXRIO_COMPRESSION_NONE ? spec->threads : 1;
    if (workers > EXRIO_MAX_WORKERS)
        workers = EXRIO_MAX_WORKERS;
    if (workers > (unsigned)job.chunks)
        workers = (unsigned)job.chunks;
    if (pthread_mutex_init(&job.lock, NULL) != 0)
        return EXR_ERR_OUT_OF_MEMORY;
    if (pthread_cond_init(&job.written, NULL) != 0) {
        pthread_mutex_destroy(&job.lock);
        return EXR_ERR_OUT_OF_MEMORY;
    }
    exrio_run_workers(workers, write_worker, &job);
    pthread_cond_destroy(&job.written);
    pthread_mutex_destroy(&job.lock);
    exrio_set_error_sink(stream);
    if (job.failed != EXR_ERR_SUCCESS) {
        stream->last_code = job.failure.last_code;
        memcpy(stream->message, job.failure.message, sizeof stream->message);
        if (job.failure.saved_errno)
            stream->saved_errno = job.failure.saved_errno;
    }
    return job.failed;
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
        snprintf(error, error_size, "%s: unknown compression %d", name, (int)spec->compression);
        return -1;
    }
    if (spec->zip_level < 0 || spec->zip_level > 9) {
        snprintf(error, error_size, "%s: zip level %d is not 1 to 9", name, spec->zip_level);
        return -1;
    }
    if (exrio_compression_is_dwa(spec->compression) &&
        !(spec->dwa_level >= 0.0f && spec->dwa_level <= 1e6f)) {
        snprintf(error, error_size, "%s: DWA level %g is not a level", name,
                 (double)spec->dwa_level);
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
    if (exrio_compression_is_dwa(spec->compression))
        return exrio_dwa_write_fd(fd, name, spec, error, error_size);

    memset(&stream, 0, sizeof stream);
    stream.fd = fd;
    stream.size = -1;
    init = exrio_stream_initializer(&stream, 1);
    exrio_set_error_sink(&stream);
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
        rv = write_pixels(ctxt, spec, &stream);
    }
    if (ctxt) {
        /* exr_finish writes the chunk offset table: its failure is a failed write too. */
        exr_result_t finish = exr_finish(&ctxt);
        if (rv == EXR_ERR_SUCCESS && finish != EXR_ERR_SUCCESS) {
            stage = "cannot finish the file";
            rv = finish;
        }
    }
    exrio_set_error_sink(NULL);
    if (rv != EXR_ERR_SUCCESS)
        return exrio_fail(rv == EXR_ERR_OUT_OF_MEMORY ? EXRIO_ERROR_MEMORY : EXRIO_ERROR_WRITE,
                          &stream, error, error_size, name, stage, rv);
    return EXRIO_OK;
}
