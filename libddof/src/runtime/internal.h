/* SPDX-License-Identifier: MIT */
/* internal.h - what the library's source files share: the context, errors, memory, timing. */
#ifndef DDOF_INTERNAL_H
#define DDOF_INTERNAL_H

#include "ddof.h"
#include "ddof_layer_rules.h"
#include "float_ops.h"
#include "memory.h"
#include "thread_pool.h"

#include <stdarg.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>

#if defined(__GNUC__)
#  define DDOF_PRINTF(fmt, args) __attribute__((format(printf, fmt, args)))
#else
#  define DDOF_PRINTF(fmt, args)
#endif

/* Working memory kept by the context between calls: a batch of frames of one size allocates
 * (and page-faults) once instead of once per frame. Grows, never shrinks, freed with the
 * context. */
typedef struct ddof_scratch {
    void *memory;
    size_t size;
} ddof_scratch;

enum {
    DDOF_SCRATCH_SOLVER,
    DDOF_SCRATCH_COC,
    DDOF_SCRATCH_FOREGROUND_COC, /* the foreground element's CoC, computed by the frame call */
    DDOF_SCRATCH_HIGHLIGHT_COUNTS, /* highlights_find.c: per-chunk counts                    */
    DDOF_SCRATCH_HIGHLIGHTS,       /* highlights_find.c: the highlights found                 */
    DDOF_SCRATCH_ELEMENT_HIGHLIGHTS, /* highlights_find.c: those of a foreground element      */
    /* One image, three uses in frame_run.c's order: the colour with the highlights taken out
     * (read by the layers and the passes), then the scratch the frame's discs are drawn
     * through (the last reader of that colour; with an object matte the split reads it after
     * the discs, which then go through the split's own scratch), then the foreground
     * element's own pass (after the frame's draw): a second image would cost a frame's colour
     * for nothing. */
    DDOF_SCRATCH_HIGHLIGHT_BASE,
    DDOF_SCRATCH_NEAR_REST,        /* near_layer.c: the colour with the near field filled */
    DDOF_SCRATCH_NEAR_REST_COC,    /* near_layer.c: its CoC                              */
    DDOF_SCRATCH_NEAR_ELEMENT,     /* near_layer.c: the near field as premultiplied RGBA */
    DDOF_SCRATCH_NEAR_PYRAMID,     /* near_layer.c: the fill's pull-push levels          */
    DDOF_SCRATCH_NEAR_OFFSETS,     /* near_offsets_fill.c: the offset search and its scores   */
    DDOF_SCRATCH_APERTURE_SUMS,    /* highlights_find.c: the aperture image's summed areas    */
    DDOF_SCRATCH_HIGHLIGHT_HIDDEN, /* highlights_find.c: the parts hidden by sharp occluders  */
    DDOF_SCRATCH_FAR_FIELD_MAPS,   /* far_field.c: radius, weight and reach maps          */
    DDOF_SCRATCH_FAR_FIELD_LEVELS, /* far_field_gather.c: levels, prefix sums, samples   */
    DDOF_SCRATCH_FAR_LAYERS,       /* far_layers.c: the depth slices and their composite  */
    DDOF_SCRATCH_SILHOUETTES,      /* silhouettes.c: the mixed pixels' changes           */
    DDOF_SCRATCH_SILHOUETTE_COLOR, /* silhouettes.c: the colour with their objects out   */
    DDOF_SCRATCH_ELEMENT_EDGES,    /* element_edges.c: the CoC before the strands' fix    */
    DDOF_SCRATCH_LAYER_COLOR_COPY, /* layers.c: the input, when diffusing in place        */
    DDOF_SCRATCH_LAYER_COLOR,      /* layers.c: background B or foreground F              */
    DDOF_SCRATCH_ELEMENT_SHARP,    /* layers.c: the element before its blur, to gather    */
    DDOF_SCRATCH_LAYER_MATTE,      /* layers.c: the matte, or the element's carried alpha */
    DDOF_SCRATCH_LAYER_COC_ABS,    /* layers.c: |CoC| to fill, then the fill's sources     */
    DDOF_SCRATCH_LAYER_FILLED,     /* layers.c: the filled CoC, then the proximity map    */
    DDOF_SCRATCH_NEAR_SPREAD,      /* layers.c: the near-spread CoC                       */
    DDOF_SCRATCH_LAYER_CAPACITY,   /* layers.c: the background's heat capacity            */
    DDOF_SCRATCH_COD4_QUARTER,     /* preview_cod4.c: quarter-resolution colour images    */
    DDOF_SCRATCH_COD4_NEAR,        /* preview_cod4.c: quarter-resolution near CoC images  */
    DDOF_SCRATCH_COD4_STATS,       /* preview_cod4.c: per-chunk statistics of first pass  */
    DDOF_SCRATCH_COD4_BANDS,       /* preview_cod4.c: per-band rows of the last pass      */
    DDOF_SCRATCH_COD4_HALO,        /* preview_cod4.c: in place, rows saved before writing */
    DDOF_SCRATCH_COUNT
};

struct ddof_backend_table;
struct ddof_device;

/* Where the context's diffusions run (backend.c). */
typedef struct ddof_backend_state {
    ddof_backend_kind kind;                 /* CPU, EGL, OSMESA or HOST_GL (AUTO resolved) */
    void *plugin;                           /* dlopen handle of libddof_gl, NULL on the CPU */
    const struct ddof_backend_table *table;
    struct ddof_device *device;
    char note[256];                         /* why AUTO chose what it did                  */
} ddof_backend_state;

struct ddof_context {
    ddof_allocator allocator;
    ddof_backend_state backend;
    /* The CPU's table (cpu/backend_cpu.c), set when the context is created: what runs a
     * request the device does not take, and what a context without a device runs. The
     * dispatch (backends/) reaches it only through here: the CPU's layers are a part above. */
    const struct ddof_backend_table *cpu;
    thread_pool *pool;      /* NULL when the context works on the caller's thread only */
    uint32_t thread_count;  /* workers + the caller                                    */
    ddof_scratch scratch[DDOF_SCRATCH_COUNT];
    char last_error[256];
    char last_plan[DDOF_PLAN_MAX_BYTES]; /* ddof_context_last_plan                        */
    atomic_int in_use;      /* 1 while a call runs on the context (ddof_context_enter)     */
};

/* A context is one thread's: every call that works on one first marks it in use, so a second
 * call at the same time (another thread, or the progress callback) gets
 * DDOF_ERROR_CONTEXT_BUSY instead of a crash or wrong pixels. One atomic exchange per call. */
int ddof_context_enter(ddof_context *context); /* 1: entered; 0: busy (nothing touched)  */
void ddof_context_leave(ddof_context *context);

/* The body of a public call that takes a context, made exclusive: NULL is
 * DDOF_ERROR_NULL_POINTER, a context in use DDOF_ERROR_CONTEXT_BUSY (its last error left to
 * the call running on it). A call that enters starts with no last error and no plan, so that
 * the message and the plan a caller reads are always its own call's. */
#define DDOF_EXCLUSIVE_CALL(context, call)                                                      \
    do {                                                                                        \
        if (!(context))                                                                         \
            return DDOF_ERROR_NULL_POINTER;                                                     \
        if (!ddof_context_enter(context))                                                       \
            return DDOF_ERROR_CONTEXT_BUSY;                                                     \
        ddof_start_call(context);                                                               \
        const ddof_status exclusive_status_ = (call);                                           \
        ddof_context_leave(context);                                                            \
        return exclusive_status_;                                                               \
    } while (0)

/* At least `size` bytes of 64-byte aligned memory in the context's slot, or NULL. */
void *ddof_scratch_get(ddof_context *context, int slot, size_t size);


/* Records a message for ddof_context_last_error() and returns `status` (for `return fail(...)`). */
ddof_status ddof_fail(ddof_context *context, ddof_status status, const char *format, ...)
    DDOF_PRINTF(3, 4);
/* A call on the context begins: no last error, no plan (DDOF_EXCLUSIVE_CALL). */
void ddof_start_call(ddof_context *context);

/* 1 when the bytes of a caller's struct beyond the library's own size (`known`) up to its
 * struct_size are all zero (or there are none): a newer caller's fields at their defaults. */
int ddof_struct_tail_is_zero(const void *caller, size_t known);

/* Validates a struct that starts with `uint32_t struct_size`: non-NULL and at least as large
 * as the first version of the struct, `min_size`. */
ddof_status ddof_check_struct(ddof_context *context, const void *ptr, size_t min_size,
                              const char *what);

/* An optional ddof_stats (NULL is fine): at least its first layout, DDOF_STATS_SIZE_0_1. */
ddof_status ddof_check_stats(ddof_context *context, const ddof_stats *stats);

/* Reads a caller's versioned struct into `full` (already holding the defaults, full_size
 * bytes): as many bytes as the caller's struct_size says, so a caller built against an older
 * header gets the defaults for the fields it does not know. */
ddof_status ddof_read_struct(ddof_context *context, const void *caller, size_t min_size,
                             void *full, size_t full_size, const char *what);

/* Validates an image description; on success *stride_floats is its row stride in floats. */
ddof_status ddof_check_image(ddof_context *context, const char *what, const float *pixels,
                             uint32_t width, uint32_t height, uint32_t channels, size_t row_stride,
                             size_t *stride_floats);
/* The same for an image of up to most_channels channels (ddof_check_image: 4). */
ddof_status ddof_check_image_up_to(ddof_context *context, const char *what, const float *pixels,
                                   uint32_t width, uint32_t height, uint32_t channels,
                                   uint32_t most_channels, size_t row_stride,
                                   size_t *stride_floats);

/* A CoC image, read or written (an output through ddof_as_input): valid as ddof_check_image
 * says, and width x height with one channel. */
ddof_status ddof_check_coc_image(ddof_context *context, const char *what, ddof_image_in coc,
                                 uint32_t width, uint32_t height, size_t *stride_floats);

/* The bytes a validated image spans, [lo, hi): by byte range, not base pointer, so that the
 * colour's alpha (`color + 3` with its stride), an address inside an image or `out + 1` all
 * count as overlapping it. row_stride in bytes, 0 for packed rows (as ddof_image). */
typedef struct ddof_image_bytes {
    uintptr_t lo, hi;
} ddof_image_bytes;
ddof_image_bytes ddof_image_bytes_of(const float *pixels, uint32_t width, uint32_t height,
                                     uint32_t channels, size_t row_stride);

/* The one rule on images that share memory: an image a call writes (`what`) shares no byte
 * with another image of the call (`other`, an input or another output); otherwise
 * DDOF_ERROR_BAD_PARAMETER naming both. (Only ddof_diffuse's colour and out may be the very
 * same buffer, in place: its own check.) */
ddof_status ddof_check_apart(ddof_context *context, const char *what, ddof_image_bytes a,
                             const char *other, ddof_image_bytes b);

/* A rectangle of pixels [x0, x1) x [y0, y1); empty when x0 >= x1. The seam's box, so that the
 * layers' rules (ddof_layer_rules.h) serve the core and a device alike. */
typedef adi_box pixel_box;

static inline pixel_box box_empty(void)
{
    pixel_box b = {UINT32_MAX, UINT32_MAX, 0, 0};
    return b;
}

static inline int box_is_empty(pixel_box b)
{
    return ddof_box_is_empty(b);
}

static inline void box_add(pixel_box *b, uint32_t x, uint32_t y)
{
    b->x0 = x < b->x0 ? x : b->x0;
    b->y0 = y < b->y0 ? y : b->y0;
    b->x1 = x + 1 > b->x1 ? x + 1 : b->x1;
    b->y1 = y + 1 > b->y1 ? y + 1 : b->y1;
}

static inline pixel_box box_union(pixel_box a, pixel_box b)
{
    if (box_is_empty(a))
        return b;
    if (!box_is_empty(b)) {
        box_add(&a, b.x0, b.y0);
        box_add(&a, b.x1 - 1, b.y1 - 1);
    }
    return a;
}

/* b grown by margin pixels on every side, within a width x height image. */
static inline pixel_box box_grow(pixel_box b, uint32_t margin, uint32_t width, uint32_t height)
{
    return ddof_box_grow(b, margin, width, height);
}

/* ddof_image and ddof_image_in share their layout; this is the read-only view of an output. */
static inline ddof_image_in ddof_as_input(const ddof_image *image)
{
    ddof_image_in in = {image->pixels, image->width, image->height, image->channels,
                        image->row_stride};
    return in;
}

#endif
