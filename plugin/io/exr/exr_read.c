/* SPDX-License-Identifier: MIT */
/* exr_read.c - reading OpenEXR files through the C core: the header (exrio_open) and then the
 * pixels of the channels asked for (exrio_load), scanline or tiled, into float/uint32 planes. */
#include "exr_dwa.h"
#include "exr_internal.h"

#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* The same bound as libddof's DDOF_MAX_PIXELS: a header asking for more is not a render ddof
 * could process, and refusing it here keeps a damaged header from causing a huge allocation. */
#define EXRIO_MAX_PIXELS (1u << 28)

static char *copy_string(const char *s, size_t length)
{
    char *copy = malloc(length + 1);
    if (copy) {
        memcpy(copy, s, length);
        copy[length] = '\0';
    }
    return copy;
}

/* Names what a file that is not an EXR looks like, so that "not an OpenEXR file" comes with a
 * hint when someone passes the PNG preview or a JPEG by mistake. Only magic numbers. */
static const char *sniff_kind(const unsigned char *head, size_t n)
{
    if (n == 0)
        return "it is empty";
    if (n >= 8 && memcmp(head, "\x89PNG\r\n\x1a\n", 8) == 0)
        return "it is a PNG image";
    if (n >= 3 && head[0] == 0xff && head[1] == 0xd8 && head[2] == 0xff)
        return "it is a JPEG image";
    if (n >= 4 && (memcmp(head, "II*\0", 4) == 0 || memcmp(head, "MM\0*", 4) == 0))
        return "it is a TIFF image";
    if (n >= 2 && head[0] == '{')
        return "it looks like JSON text";
    return "it does not start with the OpenEXR magic number 76 2f 31 01";
}

static exrio_status open_file(const char *path, int *out_fd, int64_t *out_size, char *error,
                              size_t error_size)
{
    struct stat st;
    unsigned char head[8];
    ssize_t n;
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        int e = errno;
        snprintf(error, error_size, "%s: cannot open: %s", path, strerror(e));
        return e == ENOENT || e == ENOTDIR ? EXRIO_ERROR_MISSING : EXRIO_ERROR_ACCESS;
    }
    if (fstat(fd, &st) != 0) { /* st is undefined then: report errno, read nothing from st */
        snprintf(error, error_size, "%s: %s", path, strerror(errno));
        close(fd);
        return EXRIO_ERROR_ACCESS;
    }
    if (S_ISDIR(st.st_mode)) {
        snprintf(error, error_size, "%s: is a directory, not an EXR file", path);
        close(fd);
        return EXRIO_ERROR_ACCESS;
    }
    do {
        n = pread(fd, head, sizeof head, 0);
    } while (n < 0 && errno == EINTR);
    if (n < 0) {
        snprintf(error, error_size, "%s: cannot read: %s", path, strerror(errno));
        close(fd);
        return EXRIO_ERROR_ACCESS;
    }
    if (n < 4 || memcmp(head, "\x76\x2f\x31\x01", 4) != 0) {
        snprintf(error, error_size, "%s: not an OpenEXR file (%s)", path,
                 sniff_kind(head, (size_t)n));
        close(fd);
        return EXRIO_ERROR_NOT_EXR;
    }
    *out_fd = fd;
    *out_size = (int64_t)st.st_size;
    return EXRIO_OK;
}

static exrio_box box_from(const exr_attr_box2i_t *b)
{
    exrio_box box;
    box.min_x = b->min.x;
    box.min_y = b->min.y;
    box.max_x = b->max.x;
    box.max_y = b->max.y;
    return box;
}

/* Fills image->parts and image->channels from the parsed header. */
static exrio_status describe_parts(exrio_image *image, exr_context_t ctxt,
                                   const exrio_stream *stream, char *error, size_t error_size)
{
    const char *path = image->path;
    exr_result_t rv;
    int count = 0, p, total = 0;

    rv = exr_get_count(ctxt, &count);
    if (rv != EXR_ERR_SUCCESS || count < 1)
        return exrio_fail(EXRIO_ERROR_CORRUPT, stream, error, error_size, path,
                          "no image part in the header", rv);
    image->parts = calloc((size_t)count, sizeof *image->parts);
    if (!image->parts)
        return EXRIO_ERROR_MEMORY;
    image->part_count = count;

    for (p = 0; p < count; p++) {
        exrio_part *part = &image->parts[p];
        const exr_attr_chlist_t *chlist = NULL;
        exr_attr_box2i_t dw, disp;
        exr_storage_t storage;
        exr_compression_t compression;
        const char *name = NULL;
        float aspect = 1.0f;
        uint64_t w, h;

        if ((rv = exr_get_storage(ctxt, p, &storage)) != EXR_ERR_SUCCESS ||
            (rv = exr_get_data_window(ctxt, p, &dw)) != EXR_ERR_SUCCESS ||
            (rv = exr_get_display_window(ctxt, p, &disp)) != EXR_ERR_SUCCESS ||
            (rv = exr_get_compression(ctxt, p, &compression)) != EXR_ERR_SUCCESS ||
            (rv = exr_get_channels(ctxt, p, &chlist)) != EXR_ERR_SUCCESS || !chlist)
            return exrio_fail(EXRIO_ERROR_CORRUPT, stream, error, error_size, path,
                              "incomplete header", rv);
        if (exr_get_name(ctxt, p, &name) == EXR_ERR_SUCCESS && name) {
            part->name = copy_string(name, strlen(name));
            if (!part->name)
                return EXRIO_ERROR_MEMORY;
        }
        if (exr_get_pixel_aspect_ratio(ctxt, p, &aspect) != EXR_ERR_SUCCESS || !(aspect > 0.0f))
            aspect = 1.0f;
        part->data_window = box_from(&dw);
        part->display_window = box_from(&disp);
        part->compression = (exrio_compression)compression;
        part->tiled = storage == EXR_STORAGE_TILED || storage == EXR_STORAGE_DEEP_TILED;
        part->deep = storage == EXR_STORAGE_DEEP_SCANLINE || storage == EXR_STORAGE_DEEP_TILED;
        part->pixel_aspect = aspect;
        if (dw.max.x < dw.min.x || dw.max.y < dw.min.y) {
            snprintf(error, error_size, "%s: empty data window (%d,%d)-(%d,%d)", path, dw.min.x,
                     dw.min.y, dw.max.x, dw.max.y);
            return EXRIO_ERROR_CORRUPT;
        }
        w = (uint64_t)((int64_t)dw.max.x - dw.min.x + 1);
        h = (uint64_t)((int64_t)dw.max.y - dw.min.y + 1);
        if (w * h > EXRIO_MAX_PIXELS) {
            snprintf(error, error_size, "%s: data window %llux%llu is larger than %u pixels", path,
                     (unsigned long long)w, (unsigned long long)h, EXRIO_MAX_PIXELS);
            return EXRIO_ERROR_UNSUPPORTED;
        }
        part->width = (uint32_t)w;
        part->height = (uint32_t)h;
        total += chlist->num_channels;
    }

    image->channels = calloc(total > 0 ? (size_t)total : 1, sizeof *image->channels);
    if (!image->channels)
        return EXRIO_ERROR_MEMORY;
    for (p = 0; p < count; p++) {
        const exr_attr_chlist_t *chlist = NULL;
        int c;
        exr_get_channels(ctxt, p, &chlist);
        for (c = 0; c < chlist->num_channels; c++) {
            const exr_attr_chlist_entry_t *e = &chlist->entries[c];
            exrio_channel *ch = &image->channels[image->channel_count];
            ch->name = copy_string(e->name.str, (size_t)e->name.length);
            if (!ch->name)
                return EXRIO_ERROR_MEMORY;
            ch->part = p;
            ch->type = (exrio_pixel_type)e->pixel_type;
            ch->x_sampling = e->x_sampling;
            ch->y_sampling = e->y_sampling;
            image->channel_count++;
        }
    }
    return EXRIO_OK;
}

exrio_status exrio_open(const char *path, exrio_image *image, char *error, size_t error_size)
{
    exr_context_initializer_t init;
    exr_context_t ctxt = NULL;
    exrio_stream *stream;
    exrio_status status;
    exr_result_t rv;
    int64_t size = 0;
    int fd = -1;

    memset(image, 0, sizeof *image);
    status = open_file(path, &fd, &size, error, error_size);
    if (status != EXRIO_OK)
        return status;

    stream = calloc(1, sizeof *stream);
    image->path = copy_string(path, strlen(path));
    if (!stream || !image->path) {
        free(stream);
        close(fd);
        exrio_close(image);
        snprintf(error, error_size, "%s: out of memory", path);
        return EXRIO_ERROR_MEMORY;
    }
    stream->fd = fd;
    stream->size = size;
    init = exrio_stream_initializer(stream, 0);
    rv = exr_start_read(&ctxt, path, &init);
    if (rv != EXR_ERR_SUCCESS) {
        status = rv == EXR_ERR_OUT_OF_MEMORY ? EXRIO_ERROR_MEMORY
                 : rv == EXR_ERR_READ_IO && stream->saved_errno ? EXRIO_ERROR_ACCESS
                                                                : EXRIO_ERROR_CORRUPT;
        exrio_fail(status, stream, error, error_size, path,
                   status == EXRIO_ERROR_CORRUPT ? "damaged or truncated header" : "cannot read",
                   rv);
        if (ctxt)
            exr_finish(&ctxt);
        close(fd);
        free(stream);
        exrio_close(image);
        return status;
    }
    image->source_ = ctxt;
    status = describe_parts(image, ctxt, stream, error, error_size);
    if (status != EXRIO_OK) {
        if (status == EXRIO_ERROR_MEMORY)
            snprintf(error, error_size, "%s: out of memory", path);
        exrio_close(image);
    }
    return status;
}

/* ---- pixels ----------------------------------------------------------------------------- */

typedef exr_result_t (*decompress_fn_t)(exr_decode_pipeline_t *);

/* A B44 chunk of exactly the raw size is raw: OpenEXR's C++ writer stores a chunk raw when B44
 * does not make it smaller (always so for float-only parts), but OpenEXR 3.1's C core decodes
 * it as B44, which shuffles the channels. The unpacked buffer is the pipeline's, from the
 * context's allocator: exrio's contexts keep the default, malloc and free. */
static exr_result_t b44_or_raw(exr_decode_pipeline_t *decoder)
{
    const decompress_fn_t b44 = *(const decompress_fn_t *)decoder->decoding_user_data;
    const uint64_t size = decoder->chunk.unpacked_size;
    if (decoder->chunk.packed_size != size || size == 0 || size > SIZE_MAX)
        return b44(decoder);
    if (decoder->unpacked_buffer == decoder->packed_buffer) {
        decoder->unpacked_buffer = NULL;
        decoder->unpacked_alloc_size = 0;
    }
    if (decoder->unpacked_alloc_size < size) {
        free(decoder->unpacked_buffer);
        decoder->unpacked_alloc_size = 0;
        decoder->unpacked_buffer = malloc((size_t)size);
        if (!decoder->unpacked_buffer)
            return EXR_ERR_OUT_OF_MEMORY;
        decoder->unpacked_alloc_size = (size_t)size;
    }
    memcpy(decoder->unpacked_buffer, decoder->packed_buffer, (size_t)size);
    return EXR_ERR_SUCCESS;
}

/* What the workers decoding one part share. Chunks are numbered in file order (scanline
 * blocks top first, or tiles row by row) and claimed one at a time; each lands in its own rows
 * or tile of the planes, so the workers never write the same bytes. */
typedef struct read_job {
    exrio_image *image;
    int p, first_channel;
    int32_t chunk_lines;        /* scanlines per chunk, or the tile height                  */
    int32_t tile_width;         /* tiled parts: the tile size and tiles per row             */
    int32_t tiles_x;
    int32_t chunks;
    pthread_mutex_t lock;
    int32_t next_claim;
    int32_t failed_chunk;       /* the lowest chunk that failed; `chunks` while none         */
    exr_result_t failed;
    exrio_stream failure;       /* its error record                                          */
} read_job;

/* Decodes chunk `k` into the planes of the wanted channels of the part. A decoder is set up by
 * its first chunk (*initialized) and reused for the next ones. */
static exr_result_t decode_chunk(read_job *job, int32_t k, uint8_t *scratch,
                                 exr_decode_pipeline_t *decoder, decompress_fn_t *b44,
                                 int *initialized, exrio_stream *record)
{
    exr_context_t ctxt = job->image->source_;
    const exrio_part *part = &job->image->parts[job->p];
    const size_t line = (size_t)part->width * 4;
    exr_chunk_info_t cinfo;
    int32_t x0 = 0, y0 = 0;
    exr_result_t rv;
    int c;

    if (!part->tiled) {
        rv = exr_read_scanline_chunk_info(ctxt, job->p,
                                          part->data_window.min_y + k * job->chunk_lines, &cinfo);
        if (rv == EXR_ERR_SUCCESS)
            y0 = cinfo.start_y - part->data_window.min_y;
    } else {
        const int32_t tx = k % job->tiles_x, ty = k / job->tiles_x;
        rv = exr_read_tile_chunk_info(ctxt, job->p, tx, ty, 0, 0, &cinfo);
        x0 = tx * job->tile_width;
        y0 = ty * job->chunk_lines;
    }
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    /* An uncompressed chunk holds exactly its pixels. OpenEXR 3.1's C core decodes a shorter one
     * without a word, leaving its rows as they were (black). */
    if (part->compression == EXRIO_COMPRESSION_NONE && cinfo.packed_size != cinfo.unpacked_size) {
        snprintf(record->message, sizeof record->message,
                 "the uncompressed chunk holds %llu bytes where its pixels take %llu",
                 (unsigned long long)cinfo.packed_size, (unsigned long long)cinfo.unpacked_size);
        return EXR_ERR_CORRUPT_CHUNK;
    }
    rv = *initialized ? exr_decoding_update(ctxt, job->p, &cinfo, decoder)
                      : exr_decoding_initialize(ctxt, job->p, &cinfo, decoder);
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    /* The pipeline lists the part's channels in header order, which is our order too. */
    for (c = 0; c < decoder->channel_count; c++) {
        exr_coding_channel_info_t *out = &decoder->channels[c];
        const exrio_channel *ch = &job->image->channels[job->first_channel + c];
        /* Channels not asked for go to a chunk-sized scratch buffer with the same strides.
         * The header says a NULL pointer skips a channel, but OpenEXRCore 3.1.5's specialised
         * unpackers (e.g. four half channels to float) write through it regardless. */
        out->decode_to_ptr = ch->pixels
                                 ? (uint8_t *)ch->pixels + (size_t)y0 * line + (size_t)x0 * 4
                                 : scratch + (size_t)x0 * 4;
        out->user_pixel_stride = 4;
        out->user_line_stride = (int32_t)line;
        out->user_bytes_per_element = 4;
        out->user_data_type = ch->type == EXRIO_UINT ? EXR_PIXEL_UINT : EXR_PIXEL_FLOAT;
    }
    if (!*initialized) {
        /* Chosen once: the routine depends on the layout (strides, types), not the pointers. */
        rv = exr_decoding_choose_default_routines(ctxt, job->p, decoder);
        if (rv != EXR_ERR_SUCCESS)
            return rv;
        *initialized = 1;
        if (decoder->decompress_fn && (part->compression == EXRIO_COMPRESSION_B44 ||
                                       part->compression == EXRIO_COMPRESSION_B44A)) {
            *b44 = decoder->decompress_fn;
            decoder->decoding_user_data = b44;
            decoder->decompress_fn = b44_or_raw;
        }
    }
    return exr_decoding_run(ctxt, job->p, decoder);
}

static void read_worker(void *arg, unsigned index)
{
    read_job *job = arg;
    const exrio_part *part = &job->image->parts[job->p];
    exr_decode_pipeline_t decoder = EXR_DECODE_PIPELINE_INITIALIZER;
    decompress_fn_t b44 = NULL;
    exrio_stream record;
    exr_result_t rv = EXR_ERR_SUCCESS;
    int initialized = 0;
    int32_t k = -1;
    uint8_t *scratch = malloc((size_t)part->width * 4 * (size_t)job->chunk_lines);

    (void)index;
    memset(&record, 0, sizeof record);
    record.fd = -1;
    exrio_set_error_sink(&record);
    if (!scratch)
        rv = EXR_ERR_OUT_OF_MEMORY;
    while (rv == EXR_ERR_SUCCESS) {
        pthread_mutex_lock(&job->lock);
        k = job->failed == EXR_ERR_SUCCESS && job->next_claim < job->chunks ? job->next_claim++
                                                                           : -1;
        pthread_mutex_unlock(&job->lock);
        if (k < 0)
            break;
        rv = decode_chunk(job, k, scratch, &decoder, &b44, &initialized, &record);
    }
    if (initialized || decoder.channels)
        exr_decoding_destroy(job->image->source_, &decoder);
    free(scratch);
    exrio_set_error_sink(NULL);
    if (rv != EXR_ERR_SUCCESS) {
        /* Every chunk below a claimed one was claimed before it and is decoded before its
         * worker looks again: the lowest failure, the one reported, is the same every run. */
        if (k < 0)
            k = 0;
        pthread_mutex_lock(&job->lock);
        if (k < job->failed_chunk) {
            job->failed_chunk = k;
            job->failed = rv;
            job->failure = record;
        }
        pthread_mutex_unlock(&job->lock);
    }
}

static exrio_status load_part(exrio_image *image, int p, int first_channel, unsigned threads,
                              exrio_stream *stream, char *error, size_t error_size)
{
    exr_context_t ctxt = image->source_;
    const exrio_part *part = &image->parts[p];
    read_job job;
    exr_result_t rv = EXR_ERR_SUCCESS;
    char where[96];

    memset(&job, 0, sizeof job);
    job.image = image;
    job.p = p;
    job.first_channel = first_channel;
    where[0] = '\0';
    if (!part->tiled)
        rv = exr_get_scanlines_per_chunk(ctxt, p, &job.chunk_lines);
    else
        rv = exr_get_tile_sizes(ctxt, p, 0, 0, &job.tile_width, &job.chunk_lines);
    if (rv == EXR_ERR_SUCCESS && (job.chunk_lines <= 0 || (part->tiled && job.tile_width <= 0)))
        rv = EXR_ERR_INVALID_ATTR;
    if (rv == EXR_ERR_SUCCESS) {
        const int64_t rows = ((int64_t)part->height + job.chunk_lines - 1) / job.chunk_lines;
        job.tiles_x = part->tiled ? (int32_t)(((int64_t)part->width + job.tile_width - 1) /
                                              job.tile_width)
                                  : 1;
        job.chunks = (int32_t)(rows * job.tiles_x);
        job.failed_chunk = job.chunks;
        if (pthread_mutex_init(&job.lock, NULL) != 0)
            rv = EXR_ERR_OUT_OF_MEMORY;
    }
    if (rv == EXR_ERR_SUCCESS) {
        unsigned workers = threads > 1 ? threads : 1;
        if (workers > EXRIO_MAX_WORKERS)
            workers = EXRIO_MAX_WORKERS;
        if (workers > (unsigned)job.chunks)
            workers = (unsigned)job.chunks;
        exrio_run_workers(workers, read_worker, &job);
        pthread_mutex_destroy(&job.lock);
        rv = job.failed;
        if (rv != EXR_ERR_SUCCESS) {
            const int32_t k = job.failed_chunk;
            if (!part->tiled)
                snprintf(where, sizeof where, "pixel data of scanline %d",
                         (int)(part->data_window.min_y + k * job.chunk_lines));
            else
                snprintf(where, sizeof where, "pixel data of tile (%d, %d)",
                         (int)(k % job.tiles_x), (int)(k / job.tiles_x));
            if (stream) {
                stream->last_code = job.failure.last_code;
                memcpy(stream->message, job.failure.message, sizeof stream->message);
                stream->saved_errno = job.failure.saved_errno;
            }
        }
    }
    if (rv != EXR_ERR_SUCCESS) {
        exrio_status status = rv == EXR_ERR_OUT_OF_MEMORY               ? EXRIO_ERROR_MEMORY
                              : rv == EXR_ERR_FEATURE_NOT_IMPLEMENTED ? EXRIO_ERROR_UNSUPPORTED
                                                                      : EXRIO_ERROR_CORRUPT;
        char what[160];
        snprintf(what, sizeof what, "%s%s", status == EXRIO_ERROR_CORRUPT ? "damaged or truncated " : "",
                 where[0] ? where : "pixel data");
        return exrio_fail(status, stream, error, error_size, image->path, what, rv);
    }
    return EXRIO_OK;
}

static const char *part_label(const exrio_image *image, int p, char *buf, size_t size)
{
    if (image->part_count == 1)
        snprintf(buf, size, "the image");
    else
        snprintf(buf, size, "part %d%s%s%s", p, image->parts[p].name ? " '" : "",
                 image->parts[p].name ? image->parts[p].name : "", image->parts[p].name ? "'" : "");
    return buf;
}

exrio_status exrio_load(exrio_image *image, const unsigned char *wanted, char *error,
                        size_t error_size)
{
    return exrio_load_threads(image, wanted, 1, error, error_size);
}

exrio_status exrio_load_threads(exrio_image *image, const unsigned char *wanted, unsigned threads,
                                char *error, size_t error_size)
{
    exrio_stream *stream = NULL;
    void *user = NULL;
    int p, c, first = 0;
    char label[300];

    if (!image || !image->source_) {
        snprintf(error, error_size, "exrio_load: no open image");
        return EXRIO_ERROR_ARGUMENT;
    }
    if (exr_get_user_data(image->source_, &user) == EXR_ERR_SUCCESS)
        stream = user;

    for (p = 0; p < image->part_count; p++) {
        const exrio_part *part = &image->parts[p];
        const size_t plane = (size_t)part->width * part->height * 4;
        int end = first, any = 0;
        exrio_status status;

        while (end < image->channel_count && image->channels[end].part == p)
            end++;
        for (c = first; c < end; c++) {
            if ((wanted && !wanted[c]) || image->channels[c].pixels)
                continue;
            if (part->deep) {
                snprintf(error, error_size, "%s: channel %s is in %s, which holds deep data: "
                         "deep images are not supported", image->path, image->channels[c].name,
                         part_label(image, p, label, sizeof label));
                return EXRIO_ERROR_UNSUPPORTED;
            }
            if (image->channels[c].x_sampling != 1 || image->channels[c].y_sampling != 1) {
                snprintf(error, error_size, "%s: channel %s is subsampled (%dx%d): subsampled "
                         "channels are not supported", image->path, image->channels[c].name,
                         (int)image->channels[c].x_sampling, (int)image->channels[c].y_sampling);
                return EXRIO_ERROR_UNSUPPORTED;
            }
            any = 1;
        }
        if (any) {
            unsigned char *fresh = calloc((size_t)(end - first), 1);
            if (!fresh) {
                snprintf(error, error_size, "%s: out of memory", image->path);
                return EXRIO_ERROR_MEMORY;
            }
            for (c = first; c < end; c++) {
                if ((wanted && !wanted[c]) || image->channels[c].pixels)
                    continue;
                /* calloc: a chunk the core skips for any reason reads as 0, never garbage. */
                image->channels[c].pixels = calloc(plane, 1);
                fresh[c - first] = 1;
                if (!image->channels[c].pixels) {
                    status = EXRIO_ERROR_MEMORY;
                    snprintf(error, error_size, "%s: out of memory for %ux%u pixels",
                             image->path, part->width, part->height);
                    goto undo;
                }
            }
            if (stream) {
                stream->saved_errno = 0;
                stream->message[0] = '\0';
            }
            if (exrio_compression_is_dwa(part->compression)) {
                /* fresh is indexed from `first`: the C++ path takes one over all channels. */
                unsigned char *fill = calloc((size_t)image->channel_count, 1);
                if (fill) {
                    memcpy(fill + first, fresh, (size_t)(end - first));
                    status = exrio_dwa_load_part(image, p, fill, threads, error, error_size);
                    free(fill);
                } else {
                    status = EXRIO_ERROR_MEMORY;
                    snprintf(error, error_size, "%s: out of memory", image->path);
                }
            } else {
                status = load_part(image, p, first, threads, stream, error, error_size);
            }
        undo:
            if (status != EXRIO_OK) {
                /* Take back what this call allocated: a failed load leaves no half-read plane
                 * that could pass for data. */
                for (c = first; c < end; c++) {
                    if (fresh[c - first]) {
                        free(image->channels[c].pixels);
                        image->channels[c].pixels = NULL;
                    }
                }
                free(fresh);
                return status;
            }
            free(fresh);
        }
        first = end;
    }
    return EXRIO_OK;
}
