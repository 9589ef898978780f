/* SPDX-License-Identifier: MIT */
/* ddof_backend_seam.h - what crosses the seam between libddof and a diffusion backend.
 *
 * The core (libddof/src) decides *what* to simulate: it validates the caller's images, plans
 * the frame, builds the layers and issues one diffusion request at a time. A backend decides
 * *how* to run one request; a backend with run_layers (ABI 3) takes the whole planned layered
 * frame instead and runs every layer's steps itself (the GL plugin: on the device, with one
 * upload and one read-back). The CPU is a whole table of the same shape inside the core
 * (libddof/src/cpu/backend_cpu.c: its run_layers is the core's layers.c, each diffusion
 * through the dispatch, its render_cards the core's cards_draw.c); the GL backends live in the plugin library libddof_gl (plugin/gl,
 * with each part's GL code from libddof/src/PART/gl), which the core loads with
 * dlopen(RTLD_LOCAL) and asks for one table through the symbol DDOF_BACKEND_ENTRY_SYMBOL. The two libraries can be
 * mixed up on disk, so the table carries an ABI number and its size, both checked before use.
 *
 * Everything a backend may rely on is in this header, ddof_layer_rules.h and ddof.h; a backend
 * includes nothing else of the core (plugin/gl builds with libddof/src off its include path).
 * Not installed: the seam is between two libraries built from one tree.
 */
#ifndef DDOF_BACKEND_SEAM_H
#define DDOF_BACKEND_SEAM_H

#ifndef DDOF_EXPERIMENTAL
#define DDOF_EXPERIMENTAL 1 /* the backend kinds */
#endif
#include "ddof.h"

#include <stddef.h>
#include <stdint.h>

/* ---- the disc kernel's table (fitted in the core, run by either side) --------------------- */

/* One disc kernel (docs/disc-kernel.md): per component c and axis, a chain of `steps` implicit
 * steps with complex conductances beta = kappa_cm * d^2; the output is
 * x + Re sum_c mix_c (Z_c - x). */
#define DDOF_DISC_MAX_COMPONENTS 3
#define DDOF_DISC_MAX_STEPS 3

typedef struct disc_kernel {
    ddof_kernel id;
    uint32_t components;                                   /* C                            */
    uint32_t steps;                                        /* M chained steps per axis     */
    float kappa[DDOF_DISC_MAX_COMPONENTS][DDOF_DISC_MAX_STEPS][2]; /* re, im; per d^2      */
    float mix[DDOF_DISC_MAX_COMPONENTS][2];                /* w_c, re, im                  */
    float reach;     /* 12 decay lengths of the slowest step (times its order), in CoC      */
    float snr_db;    /* the fit's kernel SNR against the disc at d = 32 (documentation)      */
} disc_kernel;

/* Links whose |beta| would fall below this are no links: keeps |beta|^2 and the eliminated
 * excesses far from float underflow (a CoC this small, ~0.001 px, blurs nothing visible). */
#define DDOF_LENS_MIN_LINK 1e-6f

/* ---- one diffusion request ---------------------------------------------------------------- */

/* A validated request: images are checked, strides are in floats. */
typedef struct adi_request {
    const float *color;
    size_t color_stride;
    const float *coc; /* diameters in pixels (sign ignored), first of coc_channels floats per */
    size_t coc_stride;/* pixel; NULL: every pixel has uniform_coc                          */
    uint32_t coc_channels;
    float uniform_coc;
    const float *gamma; /* heat capacity per pixel (first of gamma_channels floats), >= 0; */
    size_t gamma_stride;/* NULL: 1 everywhere. Where it is 0 the colour is not read (as 0) */
    uint32_t gamma_channels;
    float *out; /* may equal color (then out_stride == color_stride) */
    size_t out_stride;
    uint32_t width, height, channels;
    ddof_solver solver;
    ddof_precision precision; /* packed half: GL Gruen only */
    uint32_t substeps;
    uint32_t jacobi_iterations;
    float beta_scale;   /* k in beta = k d^2                          */
    float pixel_aspect; /* column links use (d * pixel_aspect)          */
    const struct disc_kernel *disc; /* NULL: the heat kernel; else the disc kernel's table */
    ddof_progress_fn progress;
    void *progress_user;
    /* |CoC| below this (read from `coc`; a uniform CoC is the layers' own fill and is never
     * cut) conducts as 0: the pixel is in focus (params.in_focus_threshold_px). A device
     * applies it as the CPU does (the GL plugin: pack.comp). */
    float in_focus_px;
    /* 1: the caller measured `coc` (its largest |CoC|: known_max_coc) and every pixel is in
     * focus, so the output is the input: the CPU copies it without a pass over the lines (a
     * device may run it as any frame). 0 (what a zeroed request holds): not known. */
    uint32_t all_in_focus;
    float known_max_coc;
} adi_request;

/* The signed CoC of pixel (x, y) of a request: the one rule for reading `coc` (its first
 * channel, its stride) and its uniform fill. */
static inline float adi_request_coc(const adi_request *r, size_t x, size_t y)
{
    return r->coc ? r->coc[y * r->coc_stride + x * r->coc_channels] : r->uniform_coc;
}

typedef struct adi_report {
    uint64_t lines_solved;
    uint64_t lines_skipped;
    uint32_t substeps_run; /* 0 when nothing conducted (output is a copy) */
    uint32_t threads;
    float max_coc; /* ABI 4: the largest |CoC| of the request before the in-focus cut */
    double seconds_rows;
    double seconds_columns;
    uint64_t device_bytes; /* GL: peak GPU memory of the call; 0 on the CPU */
    /* ABI 3. Host <-> device transfers of image data (colour, CoC, gamma, result; not the few
     * bytes of counters an analysis reads): uploads are writes into device buffers from host
     * memory, read-backs reads or maps of a device buffer into host memory. 0 on the CPU. */
    uint32_t uploads;
    uint32_t readbacks;
} adi_report;

/* ---- one layered frame (run_layers) ------------------------------------------------------ */

/* A rectangle of pixels [x0, x1) x [y0, y1); empty when x0 >= x1 or y0 >= y1. */
typedef struct adi_box {
    uint32_t x0, y0, x1, y1;
} adi_box;

/* A highlight the highlight pass found (libddof/src/passes/highlights.h): a pixel, the signed
 * CoC its light is drawn with, its colour above the threshold, and whether it is a part hidden
 * by a sharp occluder (filled in: not taken out of the colour, its disc not renormalised). */
typedef struct adi_highlight {
    uint32_t x, y;
    float coc;
    float excess[3];
    uint32_t hidden;
} adi_highlight;

/* A frame's highlights and the aperture they are drawn with (highlights.h's
 * highlight_aperture; the pixel aspect is base's). The run finds them itself, the first of
 * its stages (highlights_find.c's rules: a brightness over `threshold`, raised in quarter
 * octaves until their discs fit the budget): the frame's in its colour, with the parts sharp
 * occluders hide; the element's (fg_highlights) in its area, read as its steps premultiply
 * it. */
typedef struct adi_highlights {
    uint32_t find;              /* 1: the run finds and draws them; 0: no highlight pass      */
    float threshold;            /* ddof_params.highlight_threshold                            */
    const adi_highlight *items; /* what the CPU's steps found, sorted by row (a request: NULL) */
    uint32_t count;
    uint32_t coc_signed;
    uint32_t blades;            /* 0..2: a disc; else a polygon turned by rotation_rad          */
    double rotation_rad;
    double catseye, centre_x, centre_y, half_width, half_height;
    const double *image_sums;   /* an aperture image's summed-area table, (w + 1) x (h + 1),
                                 * scaled to a largest texel of 1; NULL: none                  */
    uint32_t image_width, image_height;
} adi_highlights;

/* A validated, planned layered frame (libddof/src/layers/layers.c's pipeline, docs/design.md
 * section 1): the midground diffusion of `base` (its CoC signed when params.coc_signed), then
 * what the plan switched on. The core has decided what runs and where the near spread and foreground
 * work; the background's area depends on the midground's largest CoC, so the backend grows
 * background_edges by the kernel's reach itself, by the rules layers.c uses
 * (ddof_layer_rules.h). */
typedef struct adi_layers_request {
    adi_request base;         /* colour, CoC, out, solver settings; progress for the frame  */
    uint32_t near_spread;     /* 1: dilate the near CoC and conduct the midground with it   */
    float near_slope;         /* px of CoC lost per px of distance                          */
    adi_box near_dilate;      /* where the dilation runs (empty: nowhere)                   */
    uint32_t background_levels; /* 0: no background layer                                   */
    float background_threshold_px;
    float background_ramp_start_px;
    adi_box background_edges; /* where far CoC meets in-focus pixels (whole frame if forced) */
    const float *fg_color;    /* NULL: no foreground element; else RGBA, alpha > 0 somewhere */
    size_t fg_color_stride;   /* floats                                                      */
    const float *fg_coc;
    size_t fg_coc_stride;
    uint32_t fg_coc_channels;
    uint32_t fg_premultiplied;
    float fg_max_coc;         /* largest |CoC| where alpha > 0                               */
    const float *fg_carried_alpha; /* with 4 channels: the element's part of the frame's alpha
                               * (a near layer's: its matte times the frame's alpha), blurred
                               * as its colour is and composited as the output's alpha; NULL:
                               * its coverage. ADI_ON_DEVICE with near_resident              */
    size_t fg_carried_stride; /* floats                                                      */
    adi_box fg_area;          /* where the element's blur can reach                          */
    uint32_t fg_gather;       /* 1: the far field gathers the element's blur with the lens's
                               * shape away from its own depth edges, before its composite    */
    adi_highlights fg_highlights; /* the element's own, in fg_area's coordinates: taken out
                               * of its premultiplied colour, drawn into its blur             */
    uint32_t far_field;       /* 1: the far field over the layers' result, before the element
                               * (libddof/src/passes/far_field.h), from base.color            */
    uint32_t far_slices;      /* 1: with its depth slices where blurred surfaces meet         */
    uint32_t silhouettes;     /* 1: the silhouettes' split (libddof/src/passes/silhouettes.h):
                               * the colour cleaned before the layers diffuse it, the split
                               * after the far field, before the element; 3 or 4 channels     */
    adi_highlights highlights; /* taken out of base.color before the layers (and before the
                               * silhouettes' clean), drawn into the result after the split
                               * (before it, through the split's scratch, with an object
                               * matte), before the element                                   */
    uint32_t near_resident;   /* 1: base's colour and CoC and the element's images are those a
                               * split_near left on the device (each ADI_ON_DEVICE)           */
    const float *matte;       /* the object matte's (id, coverage) pairs, matte_ranks a pixel,
                               * matte_stride floats a row; NULL: the shares from the colours  */
    size_t matte_stride;
    uint32_t matte_ranks;
} adi_layers_request;

/* ---- the near layer (libddof/src/passes/near_layer.h) ------------------------------------- */

/* An image that a backend's split_near left on its device, where the layers' run that follows
 * reads it: a mark in place of a host pointer, never to be read through (the address is none
 * the host maps). */
#define ADI_ON_DEVICE ((const float *)(uintptr_t)-64)

/* The near field of one frame split off as a foreground element, and what it hid filled in
 * (ddof_split_near's rules), with the analysis of the rest the layers need. */
typedef struct adi_near_request {
    adi_request base;          /* the frame: colour (3 or 4 channels), signed CoC; sizes     */
    float threshold;           /* |CoC| from which a near pixel is wholly in the element      */
    /* the rest's background edges: far CoC >= background_threshold_px beside a pixel of |CoC|
     * below background_ramp_start_px (the planner's rule) */
    float background_threshold_px, background_ramp_start_px;
} adi_near_request;

typedef struct adi_near_split {
    /* The split's images (near_layer.h's near_split), w x h tightly packed: the rest's colour
     * (the frame's channels), its signed CoC, the element's premultiplied RGBA and |CoC|, the
     * alpha it carries (4 channels; NULL where every element pixel's alpha is 1). In the
     * backend's host memory, or ADI_ON_DEVICE where the device keeps them for run_layers. */
    const float *rest, *rest_coc, *element, *element_coc, *carried_alpha;
    adi_box box;               /* where the element's alpha is above 0                         */
    float max_coc;             /* the element's largest |CoC|                                  */
    uint64_t element_pixels;   /* pixels with matte > 0                                        */
    uint64_t holes;            /* pixels with matte 1 (filled in the rest)                      */
    uint32_t filled;           /* 0: no pixel could serve as the fill's source                 */
    adi_box rest_background_box; /* where the rest's background edges are (empty: none)        */
    adi_box rest_near_box;     /* where the rest's CoC is negative                              */
} adi_near_split;

typedef struct adi_layers_report {
    adi_report adi;           /* summed over every diffusion (maxima for max_coc, bytes)     */
    double seconds_background;
    double seconds_foreground; /* the foreground element or the near spread                  */
    double seconds_far_field;
    uint64_t far_pixels;       /* the far field's far_field_report                           */
    uint64_t far_layered_pixels;
    uint32_t far_slices, far_levels;
    double seconds_silhouettes;
    double seconds_highlights;
    uint64_t silhouette_pixels; /* mixed pixels split                                        */
    uint32_t element_effects;   /* DDOF_EFFECT_FAR_FIELD, _HIGHLIGHTS: what the far field's
                                 * gather and the element's own highlights added to it        */
    /* The frame's highlights as the run found them (highlights.h's highlight_set): drawn (of
     * them, hidden parts), the threshold applied, their discs' cost, none for the budget. */
    uint32_t highlights_count, highlights_hidden, highlights_over_budget;
    float highlights_threshold;
    uint64_t highlights_cost;
} adi_layers_report;

/* ---- cards (ddof_render_cards, docs/cards.md) -------------------------------------------- */

/* One card as a backend draws it, prepared by the core: its expanded screen polygon (pixels,
 * x right, y down, counter-clockwise) and bounds, its plane and uv map, and its texture's
 * summed-area table in the form the backend asks for (adi_cards_request.card's `parts`):
 *  - ADI_CARD_TABLE: the sums in double, with the count of texels not wholly zero beside them
 *    (the CPU's form: a disc over empty texels is skipped from 4 reads of the counts);
 *  - ADI_CARD_SPLIT_TABLE: the sums in two float parts, `table_hi` each sum rounded to a
 *    multiple of a power of two chosen so that every value and every difference of four stays
 *    exact in float, `table_lo` the rest (small), so that a box's sum from the four corners is
 *    exact in float arithmetic (a GL device's form).
 * With no part asked for, the geometry alone (a backend that skips a card wholly hidden by
 * nearer ones does not pay for its table). */
enum { ADI_CARD_TABLE = 1u, ADI_CARD_SPLIT_TABLE = 2u };

typedef struct adi_card {
    uint32_t vertex_count;
    double expanded[DDOF_CARD_MAX_VERTICES][2];
    double box[4];                             /* the expanded polygon's x0, y0, x1, y1   */
    double normal[3], origin[3], e1[3], e2[3]; /* unit normal, centroid, the plane's axes */
    double uv_affine[2][3];                    /* u, v = a0 + a1 s + a2 q, s, q along e1, e2 */
    uint32_t tw, th;                           /* the texture's size, texels              */
    /* ADI_CARD_TABLE: (tw + 1) x (th + 1), row j: the texels of rows < j, columns < i */
    const double *table_sum;          /* RGBA                                              */
    const uint32_t *table_count;      /* of those, the texels not wholly zero              */
    const float *table_hi, *table_lo; /* ADI_CARD_SPLIT_TABLE: RGBA, as table_sum          */
} adi_card;

/* A frame of cards: drawn near to far, each under what is there (out += (1 - out.a) card). */
typedef struct adi_cards_request {
    uint32_t width, height;
    float *out;          /* premultiplied RGBA, row 0 at the top; the backend writes it whole */
    size_t out_stride;   /* floats */
    /* the view (libddof/src/cards/cards.h's cards_view) */
    double ray_a, ray_bx, ray_c, ray_by, k_px, focus_m, aspect;
    float max_radius_px, min_radius_px;
    uint32_t strips;
    double line[65], mid[64], slice[64]; /* strip edges, middles, unit-disc areas */
    uint32_t card_count;
    /* Fills card i (0: the nearest) with the parts asked for (ADI_CARD_*); what it points to
     * stays valid until the next call. */
    ddof_status (*card)(void *user, uint32_t i, uint32_t parts, adi_card *card);
    void *user;
} adi_cards_request;

/* ---- the backend's table ------------------------------------------------------------------ */

/* Bump when adi_request, adi_report or this table change layout or meaning. */
#define DDOF_BACKEND_ABI 9
#define DDOF_BACKEND_ENTRY_SYMBOL "ddof_gl_backend_table"

typedef struct ddof_device ddof_device; /* a backend's opened state, opaque to the core */

/* Where the device stands: what it is and what the last run took. */
typedef struct ddof_device_info {
    uint32_t hardware;      /* 1: a GPU; 0: a software renderer              */
    char renderer[128];     /* GL_RENDERER + GL_VERSION                      */
} ddof_device_info;

/* A backend: every backend fills every entry (the CPU's included, whose device is the context
 * and which opens none), so the core never asks which backend it runs on, only what the
 * context's device takes (supports, supports_disc, supports_cards); what it does not take the
 * CPU's table runs. A table with an entry missing is refused when the plugin is loaded. */
typedef struct ddof_backend_table {
    uint32_t abi;           /* DDOF_BACKEND_ABI                               */
    uint32_t table_size;    /* sizeof(ddof_backend_table)                     */

    /* Opens a device of `kind` (EGL, OSMESA or HOST_GL; never CPU or AUTO). `require_hardware`
     * (EGL only): fail unless a GPU is found, so AUTO does not pick software GL. On failure
     * returns NULL and writes a sentence into message. Must not leave any GL context current
     * (except HOST_GL, which never changes what is current). The CPU's: NULL and a sentence
     * (the core never asks it: its device is the context, held from the context's creation). */
    ddof_device *(*open)(ddof_backend_kind kind, int require_hardware, char *message,
                         size_t message_size);
    void (*close)(ddof_device *device);
    void (*describe)(const ddof_device *device, ddof_device_info *info);

    /* Whether run() supports this solver/precision pair (REFERENCE_F64 never: the core runs
     * it itself). */
    int (*supports)(const ddof_device *device, ddof_solver solver, ddof_precision precision);

    /* One diffusion with the same contract as ddof_adi_run (the request is validated; out may
     * equal color; progress may cancel). Makes its context current for the call and releases
     * it afterwards. On failure: a status (DDOF_ERROR_BACKEND_FAILED, _OUT_OF_MEMORY,
     * _CANCELLED), a sentence in message, and out untouched unless cancelled.
     * report->device_bytes: peak GPU memory of the call. */
    ddof_status (*run)(ddof_device *device, const adi_request *request, adi_report *report,
                       char *message, size_t message_size);

    /* Whether run() takes requests with `disc` set (DDOF_SOLVER_THOMAS, float). */
    int (*supports_disc)(const ddof_device *device);

    /* The whole layered frame (on a GL device: one upload of the images, none of those a
     * split_near left there, and one read-back of the result), with run()'s contract: the
     * same answer as the CPU table's (the core's layers.c) within float rounding, out
     * untouched on failure unless cancelled. */
    ddof_status (*run_layers)(ddof_device *device, const adi_layers_request *request,
                              adi_layers_report *report, char *message, size_t message_size);

    /* Whether render_cards() draws on this device (a device on the host's own context does
     * not: drawing sets a framebuffer, blending, the viewport and texture units that the
     * host's renderer owns); where it does not, the CPU's table draws. */
    int (*supports_cards)(const ddof_device *device);

    /* Cards (on a GL device the patent's path: a vertex shader places the expanded polygon,
     * the rasteriser covers its pixels, a fragment shader averages the texture over each
     * pixel's disc, blending composites; each card's table is uploaded once). The same image
     * as the CPU table's within float rounding; out untouched on failure. */
    ddof_status (*render_cards)(ddof_device *device, const adi_cards_request *request,
                                char *message, size_t message_size);

    /* The near layer's split of a frame whose layers this table runs next (run_layers, with
     * near_resident where the images stay on the device), with the CPU's answer within float
     * rounding: the same element pixels and holes, the same boxes. report: the call's device
     * memory and transfers. DDOF_ERROR_UNSUPPORTED (with a sentence) where the device does
     * not take the frame (a software renderer's loops too short for its lines): the core
     * then splits on the CPU. */
    ddof_status (*split_near)(ddof_device *device, const adi_near_request *request,
                              adi_near_split *split, adi_report *report, char *message,
                              size_t message_size);
} ddof_backend_table;

/* The plugin's one exported function. */
typedef const ddof_backend_table *(*ddof_backend_entry_fn)(void);

#endif
