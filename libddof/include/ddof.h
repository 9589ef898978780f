/* SPDX-License-Identifier: MIT */
/*
 * ddof.h - diffusion depth of field (Kass, Lefohn, Owens 2006) as a C library.
 *
 * The one header a user includes. It turns a pinhole render (linear colour + depth) into a
 * depth-of-field image by simulating heat diffusion: the circle of confusion (CoC) becomes heat
 * conductivity, and an alternating-direction implicit step solves one tridiagonal system per row
 * and per column, so blur of any size costs the same per pixel and stops at in-focus edges.
 *
 * Conventions
 *  - Every function returns a ddof_status; ddof_status_string() explains a code, and
 *    ddof_context_last_error() says what exactly was wrong in the last failed call.
 *  - The library never prints, exits or aborts. Bad input is reported with a status and leaves
 *    the output untouched (every check runs before the first output pixel is written).
 *  - Images are owned by the caller and described by ddof_image; no pointer is kept past a call.
 *  - Parameter structs carry their size in `struct_size`; fill them with their *_init function
 *    first, then change what you need. Fields are only ever appended.
 *  - The struct rules (the ABI): each *_init(p) is a macro for *_init_sized(p, sizeof *p),
 *    which writes only the caller's size (never more than the library's own struct) and sets
 *    struct_size to what it wrote, so a caller built with an older, smaller struct is never
 *    overrun by a newer library. The functions of the plain names are for binaries built
 *    against 0.5, which called them directly: they write the 0.5 layout (DDOF_<STRUCT>_SIZE_0_5).
 *    (A literal NULL now needs a cast.) Each input struct is accepted from its named first size
 *    (the fields it lacks take their defaults), and beyond the library's own size only when
 *    the bytes it does not know are zero (a newer caller that left new fields at their
 *    defaults). Each output struct (ddof_stats, ddof_backend_info, ddof_kernel_info) is
 *    written up to the smaller of its struct_size and the library's own size, and struct_size
 *    then says how many bytes were written (a newer caller sees which fields an older library
 *    filled); one smaller than its first layout is DDOF_ERROR_BAD_PARAMETER, before anything
 *    runs.
 *  - Every enum is 32 bits wide (its *_FORCE_32BIT_ value keeps it so under -fshort-enums; the
 *    header's static assertions stop a compiler where it is not). The *_COUNT_ values are not
 *    values: they grow when one is added, so never store one or size a table that outlives a
 *    build by it. ddof_param_bounds() gives the range of each numeric parameter.
 *  - Versions: a binary built against 0.5 or later runs on any later 0.x library; the soname
 *    (libddof.so.0.5) names that ABI's first release and changes only when such a binary
 *    could not run any more. The CMake package accepts a newer minor (SameMajorVersion).
 *  - One context per thread. The library has no global mutable state. A call on a context
 *    that another call is using (another thread, or the progress callback calling back in)
 *    returns DDOF_ERROR_CONTEXT_BUSY at once and touches nothing: the context is then not
 *    shared safely, and the caller's design should change, but it gets a status, not a crash
 *    or wrong pixels. ddof_context_free while a call runs stays undefined.
 *
 * Usage: one frame from a renderer's colour and depth passes
 *
 *     ddof_context *ctx;
 *     if (ddof_context_create(NULL, &ctx) != DDOF_OK) return -1;   // keep it for many frames
 *     ddof_camera cam;  ddof_camera_init(&cam);
 *     cam.focal_length_mm = 85; cam.fstop = 1.4; cam.focus_distance_m = 3;
 *     ddof_params params;  ddof_params_init(&params);             // the default preset
 *     ddof_frame frame;  ddof_frame_init(&frame);
 *     frame.color = (ddof_image_in){rgba, width, height, 4, 0};
 *     frame.depth = (ddof_image_in){z, width, height, 1, 0};
 *     frame.camera = &cam;
 *     ddof_image out = {result, width, height, 4, 0};
 *     if (ddof_render_frame(ctx, &params, &frame, &out, NULL) != DDOF_OK)
 *         fprintf(stderr, "ddof: %s\n", ddof_context_last_error(ctx));
 *     ddof_context_free(ctx);
 *
 * A foreground element (its RGBA and depth in frame.foreground_color / _depth), a CoC of the
 * caller's own (frame.coc) and the CoC back (frame.coc_out) go through the same call; the
 * lower-level calls (ddof_coc_from_camera, ddof_diffuse, ddof_diffuse_layers) are the parts it
 * is made of.
 *
 * Stable API: everything in this header outside the DDOF_EXPERIMENTAL section at its end
 * (the backend selection, the disc kernels' tables), which a program sees only with
 * `#define DDOF_EXPERIMENTAL` before the #include, and which may change between minor versions.
 */
#ifndef DDOF_H
#define DDOF_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(_WIN32) && defined(DDOF_SHARED_BUILD)
#  define DDOF_API __declspec(dllexport)
#elif defined(__GNUC__) && __GNUC__ >= 4
#  define DDOF_API __attribute__((visibility("default")))
#else
#  define DDOF_API
#endif

/* ------------------------------------------------------------------------------------------ */
/* Version                                                                                      */

#define DDOF_VERSION_MAJOR 0
#define DDOF_VERSION_MINOR 9
#define DDOF_VERSION_PATCH 0
#define DDOF_VERSION_NUMBER (DDOF_VERSION_MAJOR * 10000 + DDOF_VERSION_MINOR * 100 + DDOF_VERSION_PATCH)

/* The version of the library actually loaded; compare with DDOF_VERSION_NUMBER. */
DDOF_API unsigned ddof_version_number(void);
/* "MAJOR.MINOR.PATCH" */
DDOF_API const char *ddof_version_string(void);

/* ------------------------------------------------------------------------------------------ */
/* Status codes                                                                                 */

typedef enum ddof_status {
    DDOF_OK = 0,
    DDOF_ERROR_NULL_POINTER,  /* a required pointer argument is NULL                          */
    DDOF_ERROR_BAD_PARAMETER, /* a parameter struct is malformed or a value is out of range   */
    DDOF_ERROR_BAD_SIZE,      /* width/height zero, above DDOF_MAX_DIMENSION or DDOF_MAX_PIXELS */
    DDOF_ERROR_BAD_STRIDE,    /* row stride smaller than a row, not a multiple of 4, overflows */
    DDOF_ERROR_BAD_CHANNELS,  /* channel count outside 1..4, or not what the call needs        */
    DDOF_ERROR_SIZE_MISMATCH, /* images of one call differ in size or channel count            */
    DDOF_ERROR_BAD_COLOR,     /* NaN, infinity or |value| > DDOF_MAX_COLOR in the colour image */
    DDOF_ERROR_BAD_DEPTH,     /* NaN, -inf, negative or zero depth (+inf is valid: the sky)    */
    DDOF_ERROR_BAD_COC,       /* NaN, infinite, negative CoC, or above DDOF_MAX_COC_PX         */
    DDOF_ERROR_BAD_CAMERA,    /* f-number <= 0, focus not beyond the focal length, pixel      */
                              /* aspect outside 0.01..100, ...                                 */
    DDOF_ERROR_OUT_OF_MEMORY, /* an allocation failed; nothing was written                     */
    DDOF_ERROR_THREADS,       /* a worker thread could not be started                          */
    DDOF_ERROR_CANCELLED,     /* the progress callback asked to stop                           */
    DDOF_ERROR_BACKEND_UNAVAILABLE, /* the GL plugin, its GL library or a GL 4.5 context could */
                              /* not be had (ddof_context_last_error says which); the context */
                              /* keeps the backend it had                                      */
    DDOF_ERROR_UNSUPPORTED,   /* the context's backend cannot run this solver or precision     */
    DDOF_ERROR_BACKEND_FAILED,/* the GL backend failed mid-call (shader, out of GPU memory);   */
                              /* out is untouched                                             */
    DDOF_ERROR_CONTEXT_BUSY,  /* another call is running on this context (another thread, or */
                              /* the progress callback calling back in); nothing was done and */
                              /* the last error is left to the running call                    */
    DDOF_STATUS_COUNT_,       /* not a status: the number of codes                             */
    DDOF_STATUS_FORCE_32BIT_ = 0x7fffffff /* not a value: keeps the enum 32 bits wide */
} ddof_status;

/* A short English sentence for any code (also for unknown values); never NULL. */
DDOF_API const char *ddof_status_string(ddof_status status);

/* ------------------------------------------------------------------------------------------ */
/* Limits                                                                                       */

#define DDOF_MAX_DIMENSION 65536u          /* width and height, each                        */
#define DDOF_MAX_PIXELS (1u << 28)         /* width * height (268 megapixels)               */
#define DDOF_MAX_COC_PX 100000.0f          /* a CoC diameter larger than this is an error;   */
                                           /* CoC computed from a camera is clamped to it    */
#define DDOF_MAX_COLOR 1e20f               /* |colour value| beyond this is an error: with   */
                                           /* links up to 1e14 (DDOF_MAX_COC_PX^2 times the  */
                                           /* pixel aspect^2), larger values overflow float */
                                           /* inside the solvers                            */
#define DDOF_MAX_APERTURE_BLADES 16u       /* ddof_camera.aperture_blades                   */
#define DDOF_MIN_APERTURE_RATIO 0.01       /* ddof_camera.aperture_ratio, and its product   */
#define DDOF_MAX_APERTURE_RATIO 100.0      /* with pixel_aspect                             */
#define DDOF_MAX_APERTURE_IMAGE 256u       /* ddof_camera.aperture_image's sides            */

/* ------------------------------------------------------------------------------------------ */
/* Images: caller-owned, 32-bit float, interleaved channels, rows `row_stride` bytes apart.      */

typedef struct ddof_image {
    float *pixels;        /* first channel of the top-left pixel                               */
    uint32_t width;       /* pixels per row, 1..DDOF_MAX_DIMENSION                             */
    uint32_t height;      /* rows, 1..DDOF_MAX_DIMENSION                                       */
    uint32_t channels;    /* 1..4 interleaved floats per pixel (RGBA is 4)                     */
    size_t row_stride;    /* bytes from one row to the next; 0 means tightly packed            */
} ddof_image;

/* An input image: the same, read only. */
typedef struct ddof_image_in {
    const float *pixels;
    uint32_t width;
    uint32_t height;
    uint32_t channels;
    size_t row_stride;
} ddof_image_in;

/* ------------------------------------------------------------------------------------------ */
/* Memory and progress hooks                                                                    */

/* Optional allocator. alloc returns NULL on failure; free accepts NULL. The library asks for
 * sizes up to about 3x the colour image and aligns what it gets itself. */
typedef struct ddof_allocator {
    void *(*alloc)(void *user, size_t size);
    void (*free)(void *user, void *ptr);
    void *user;
} ddof_allocator;

/* Called from the thread that made the call, with progress in [0, 1] growing monotonically.
 * Return non-zero to cancel: the call then returns DDOF_ERROR_CANCELLED soon after, and the
 * output holds finite values (the input, or a partly diffused image), never garbage. The last
 * report, 1.0, comes when the work is done; returning non-zero then changes nothing. */
typedef int (*ddof_progress_fn)(void *user, float fraction);

/* ------------------------------------------------------------------------------------------ */
/* Context                                                                                      */

typedef struct ddof_context ddof_context;

typedef struct ddof_context_options {
    uint32_t struct_size;            /* sizeof(ddof_context_options)                        */
    uint32_t thread_count;           /* 0 = number of online cores; 1 = no worker threads;   */
                                     /* at most 1024 (more is DDOF_ERROR_BAD_PARAMETER)      */
    const ddof_allocator *allocator; /* NULL = malloc/free; copied, need not outlive call    */
} ddof_context_options;

DDOF_API void (ddof_context_options_init)(ddof_context_options *options);
DDOF_API void ddof_context_options_init_sized(ddof_context_options *options, size_t size);
#define ddof_context_options_init(options) ddof_context_options_init_sized((options), sizeof *(options))

/* options may be NULL for the defaults. On success *out_context is a new context. */
DDOF_API ddof_status ddof_context_create(const ddof_context_options *options,
                                         ddof_context **out_context);
/* Accepts NULL. */
DDOF_API void ddof_context_free(ddof_context *context);
/* The number of threads the context works with (the caller's thread included). */
DDOF_API uint32_t ddof_context_thread_count(const ddof_context *context);
/* A sentence about the last error in this context ("" after a success); never NULL. */
DDOF_API const char *ddof_context_last_error(const ddof_context *context);

/* ------------------------------------------------------------------------------------------ */
/* Circle of confusion                                                                          */

typedef enum ddof_lens_model {
    /* Blender/Cycles: fixed pinhole projection and a planar focus plane,
     * c = f^2 / (N * S1) * |Z - S1| / Z. Matches Cycles renders; the default. */
    DDOF_LENS_CYCLES = 0,
    /* Textbook thin lens: c = (f / N) * |S2 - S1| / S2 * f / (S1 - f).
     * Larger than the Cycles model by S1 / (S1 - f). */
    DDOF_LENS_THIN_LENS = 1,
    DDOF_LENS_FORCE_32BIT_ = 0x7fffffff /* not a value: keeps the enum 32 bits wide */
} ddof_lens_model;

typedef enum ddof_depth_kind {
    DDOF_DEPTH_PLANAR = 0, /* camera-space Z along the optical axis (Blender's Depth pass)  */
    DDOF_DEPTH_RADIAL = 1, /* distance from the centre of projection; converted to planar   */
    DDOF_DEPTH_FORCE_32BIT_ = 0x7fffffff /* not a value: keeps the enum 32 bits wide */
} ddof_depth_kind;

typedef enum ddof_sensor_fit {
    DDOF_SENSOR_FIT_AUTO = 0,       /* sensor width spans the larger image dimension         */
    DDOF_SENSOR_FIT_HORIZONTAL = 1, /* sensor width spans the image width                    */
    DDOF_SENSOR_FIT_VERTICAL = 2,   /* sensor width spans the image height                   */
    DDOF_SENSOR_FIT_FORCE_32BIT_ = 0x7fffffff /* not a value: keeps the enum 32 bits wide */
} ddof_sensor_fit;

/* The camera sidecar of docs/design.md in C. Lengths: focal length and sensor in millimetres, focus
 * distance in metres, depth values in scene units of `depth_unit_m` metres each. */
typedef struct ddof_camera {
    uint32_t struct_size;         /* sizeof(ddof_camera)                                     */
    ddof_lens_model lens_model;   /* default DDOF_LENS_CYCLES                                */
    ddof_depth_kind depth_kind;   /* default DDOF_DEPTH_PLANAR                               */
    ddof_sensor_fit sensor_fit;   /* default DDOF_SENSOR_FIT_AUTO                            */
    double focal_length_mm;       /* default 50; > 0                                         */
    double sensor_width_mm;       /* default 36; > 0                                         */
    double fstop;                 /* default 2.8; > 0 (N)                                     */
    double focus_distance_m;      /* default 10; must exceed the focal length                */
    double pixel_aspect;          /* pixel width / pixel height, default 1; > 0 (0.01..100   */
                                  /* for ddof_depth_of_field, as params.pixel_aspect)       */
    double depth_unit_m;          /* metres per depth unit, default 1; > 0                   */
    uint32_t signed_coc;          /* 1: write the CoC of points nearer than the focus plane  */
                                  /* negative (see ddof_params.coc_signed). Default 0.       */
    /* version 0.5 of this struct: a crop (a render border, an EXR data window). The sensor fit */
    /* and the image centre are the full frame's, and radial depth is converted about the full */
    /* frame's centre, so the CoC of a crop is the same region of the full frame's CoC. The     */
    /* window may reach outside the frame (overscan). A caller with an older struct_size gets   */
    /* the defaults: all 0, the image is the full frame.                                        */
    uint32_t frame_width, frame_height; /* the full frame's size in pixels; 0 = the image's own */
    int32_t window_x, window_y; /* the image's top-left pixel within the full frame */
    /* version 0.7 of this struct: the aperture's shape, Blender's camera Blades, Rotation and */
    /* Ratio as Cycles renders them. ddof_depth_of_field and ddof_render_frame draw highlights */
    /* (the highlight pass) in its shape; the diffusion follows the ratio (an ellipse) and      */
    /* stays round for blades. A caller with an older struct_size gets a round aperture.        */
    uint32_t aperture_blades;     /* 0: round (1 and 2 too, as Cycles); 3..16: a regular      */
                                  /* polygon inscribed in the round aperture. Default 0.       */
    double aperture_rotation_deg; /* the polygon's rotation, counter-clockwise: at 0 an edge's */
                                  /* middle points along +x. Default 0; finite, +-360.        */
    double aperture_ratio;        /* anamorphic ratio: the blur of a point is CoC / ratio     */
                                  /* wide and CoC tall (ratio 2: tall ovals). The CoC this     */
                                  /* camera gives (ddof_coc_from_camera, coc_out) is the       */
                                  /* blur's width in pixels; a caller diffusing it itself sets */
                                  /* params.pixel_aspect = pixel_aspect * aperture_ratio.      */
                                  /* Default 1; 0.01..100, and so its product with             */
                                  /* pixel_aspect.                                             */
    double aperture_catseye;      /* optical vignetting ("cat's eye" bokeh), for highlights:   */
                                  /* a highlight's aperture is clipped by a second circle of    */
                                  /* its size whose centre lies toward the full frame's centre  */
                                  /* by catseye x its radius x its distance from that centre    */
                                  /* (1 at the frame's corners), so discs turn into lens shapes */
                                  /* drawn out along the frame's circles. Cycles has no such    */
                                  /* effect. Default 0 (off); 0..1.                             */
    /* A custom aperture for highlights (as Nuke ZDefocus' filter image): one channel, row 0 at */
    /* the top, width x height floats packed, finite and >= 0, not all 0; 1..                   */
    /* DDOF_MAX_APERTURE_IMAGE per side. Stretched over the square of a highlight's CoC (the    */
    /* CoC wide, and as tall times the ratio), turned by 180 degrees for a near highlight,      */
    /* each pixel weighted by the image's average over its footprint; it replaces the blades.   */
    /* Its light is kept; its cost is its area, not its rows (the pass's budget counts it so).  */
    /* NULL (default): the blades' shape. The diffusion stays round.                            */
    const float *aperture_image;
    uint32_t aperture_image_width, aperture_image_height;
} ddof_camera;

DDOF_API void (ddof_camera_init)(ddof_camera *camera);
DDOF_API void ddof_camera_init_sized(ddof_camera *camera, size_t size);
#define ddof_camera_init(camera) ddof_camera_init_sized((camera), sizeof *(camera))
/* The 0.5 layout: what (ddof_camera_init) writes (see Conventions). */
#define DDOF_CAMERA_SIZE_0_5 (offsetof(ddof_camera, window_y) + sizeof(int32_t))

/* Fills `coc` (1 channel, same size as depth) with CoC diameters in horizontal pixels.
 * depth: its first channel is read. +inf depth (sky) is valid and gets the far-limit CoC.
 * NaN, -inf, zero or negative depth: DDOF_ERROR_BAD_DEPTH, coc untouched. CoC values above
 * DDOF_MAX_COC_PX (depth very close to the lens) are clamped to it. */
DDOF_API ddof_status ddof_coc_from_camera(ddof_context *context, const ddof_camera *camera,
                                          const ddof_image_in *depth, const ddof_image *coc);

/* The artist curve (GPU Gems 3 ch. 28): piecewise linear in depth. Blur is near_blur_px up to
 * near_start, falls linearly to 0 at near_end, stays 0 up to far_start, rises linearly to
 * far_blur_px at far_end and stays there. Distances in depth units, non-decreasing in that
 * order; blur sizes in pixels, 0..DDOF_MAX_COC_PX. */
typedef struct ddof_curve {
    uint32_t struct_size; /* sizeof(ddof_curve)                                               */
    double near_blur_px;  /* default 0                                                        */
    double near_start;    /* default 0                                                        */
    double near_end;      /* default 0                                                        */
    double far_start;     /* default 10                                                       */
    double far_end;       /* default 100                                                      */
    double far_blur_px;   /* default 16                                                       */
    uint32_t signed_coc;  /* 1: the near part of the curve is written negative. Default 0.    */
} ddof_curve;

DDOF_API void (ddof_curve_init)(ddof_curve *curve);
DDOF_API void ddof_curve_init_sized(ddof_curve *curve, size_t size);
#define ddof_curve_init(curve) ddof_curve_init_sized((curve), sizeof *(curve))
/* The 0.5 layout: what (ddof_curve_init) writes (see Conventions). */
#define DDOF_CURVE_SIZE_0_5 (offsetof(ddof_curve, signed_coc) + sizeof(uint32_t))

/* As ddof_coc_from_camera, with the curve. Depth must not be NaN or negative (+inf is far). */
DDOF_API ddof_status ddof_coc_from_curve(ddof_context *context, const ddof_curve *curve,
                                         const ddof_image_in *depth, const ddof_image *coc);

/* ------------------------------------------------------------------------------------------ */
/* Diffusion                                                                                    */

typedef enum ddof_solver {
    DDOF_SOLVER_THOMAS = 0,          /* LU forward/back substitution; default on the CPU      */
    DDOF_SOLVER_CYCLIC_REDUCTION = 1,/* Kass et al. fig. 5: odd/even reduction, back-subst.   */
    DDOF_SOLVER_PCR = 2,             /* parallel cyclic reduction (Zhang, Cohen, Owens 2010)  */
    DDOF_SOLVER_JACOBI = 3,          /* approximate: `jacobi_iterations` sweeps from the input */
    DDOF_SOLVER_REFERENCE_F64 = 4,   /* double precision throughout, one thread; for tests    */
    DDOF_SOLVER_GRUEN = 5,           /* GL backends only: Gruen's fast DDOF solver (Game Engine */
                                     /* Gems 2 ch. 8): four-to-one reduction, Cramer at 2 or 3 */
    DDOF_SOLVER_COUNT_,              /* not a solver                                          */
    DDOF_SOLVER_FORCE_32BIT_ = 0x7fffffff /* not a value: keeps the enum 32 bits wide */
} ddof_solver;

/* The name of a solver ("thomas", "cr", "pcr", "jacobi", "reference", "gruen"); NULL if
 * unknown. */
DDOF_API const char *ddof_solver_name(ddof_solver solver);

/* k that matches second moments: an implicit step's variance 2 beta equals a uniform disk's
 * d^2 / 16. It is *not* ddof_params_init's k: that is the default preset's, which the accuracy
 * study (docs/accuracy.md) measures against lens renders and chooses together with the
 * sub-steps (fewer steps want a larger k). */
#define DDOF_MOMENT_BETA_SCALE (1.0f / 32.0f)
#define DDOF_DEFAULT_BETA_SCALE DDOF_MOMENT_BETA_SCALE /* the moment-matched k, by its other name */

/* ddof_params_init's in_focus_threshold_px (a CoC diameter in pixels). */
#define DDOF_DEFAULT_IN_FOCUS_THRESHOLD_PX 0.5f

/* How a call computes the blur. */
typedef enum ddof_method {
    DDOF_METHOD_DIFFUSION = 0,    /* the heat-diffusion solve (with layers as planned)         */
    DDOF_METHOD_COD4_PREVIEW = 1, /* the practical post-process DOF of Call of Duty 4 (GPU    */
                                  /* Gems 3 ch. 28): quarter-resolution near CoC, blurred and */
                                  /* dilated, three blur levels interpolated. Fast, approximate;*/
                                  /* CPU only; ignores solver, substeps and layer fields. The */
                                  /* near spread needs signed CoC; blur beyond a quarter of   */
                                  /* the image's larger side saturates at that size.          */
    DDOF_METHOD_FORCE_32BIT_ = 0x7fffffff /* not a value: keeps the enum 32 bits wide */
} ddof_method;

/* The shape of the blur a diffusion draws around a point (its point spread).
 * HEAT is the paper's real diffusion: `substeps` implicit steps of k d^2 per axis, a soft blob
 * with long tails (a diamond at one step, a Gaussian at many); cheap, the reference.
 * The DISC kernels draw the disc a real lens (and Cycles) draws: chains of complex implicit
 * steps whose real parts sum to an approximately uniform disc of diameter |CoC|
 * (docs/disc-kernel.md; the tables are fitted by study/lens/fit_disc_kernel.py). Still one
 * tridiagonal solve per line and step, so the cost per pixel does not depend on the CoC,
 * in-focus pixels stay bit for bit, nothing crosses them, flat regions stay flat and the
 * energy is kept. The output is not a convex combination any more: the disc's rim rings
 * (about -7% of its height for disc-2x2, measured in tests/test_disc_kernel.c), so the result
 * is clamped to the input's range per channel (no negative light next to a highlight; that
 * clamp adds up to ~6% to an isolated highlight's energy on black). C x M in the name:
 * components x chained steps per axis; a disc costs 2 C M complex line solves per pixel.
 * They ignore substeps and beta_scale (the disc's diameter is |CoC|). They run with
 * DDOF_SOLVER_THOMAS on the CPU and on the GL backends (docs/gl-backend.md), and with
 * DDOF_SOLVER_REFERENCE_F64 (on the CPU, whatever the backend); with any other solver a call
 * runs the heat kernel instead, and ddof_stats.kernel reports the kernel that ran. */
typedef enum ddof_kernel {
    DDOF_KERNEL_HEAT = 0,     /* real diffusion                                               */
    DDOF_KERNEL_DISC_2X2 = 1, /* 2 components x 2 steps: 8 complex solves per pixel           */
    DDOF_KERNEL_DISC_2X3 = 2, /* 2 x 3: 12                                                   */
    DDOF_KERNEL_DISC_3X3 = 3, /* 3 x 3: 18; the closest disc                                 */
    DDOF_KERNEL_COUNT_,       /* not a kernel                                                 */
    DDOF_KERNEL_FORCE_32BIT_ = 0x7fffffff /* not a value: keeps the enum 32 bits wide */
} ddof_kernel;

/* "heat", "disc-2x2", "disc-2x3", "disc-3x3"; NULL if unknown. */
DDOF_API const char *ddof_kernel_name(ddof_kernel kernel);

/* Arithmetic of the GL solvers. The CPU solvers compute in float (Thomas carries its running
 * value in double on lines whose beta exceeds 65,536 times gamma); DDOF_SOLVER_REFERENCE_F64
 * is double throughout. */
typedef enum ddof_precision {
    DDOF_PRECISION_FLOAT = 0,      /* 32-bit float everywhere                                   */
    DDOF_PRECISION_PACKED_HALF = 1, /* GL Gruen solver only: a, b, c and x packed into one      */
                                   /* RGBA32UI texel per pixel and channel group (half floats) */
    DDOF_PRECISION_FORCE_32BIT_ = 0x7fffffff /* not a value: keeps the enum 32 bits wide */
} ddof_precision;

/* Named settings measured in docs/accuracy.md: the fastest point of the accuracy-vs-time front
 * for each purpose. ddof_params_init gives DDOF_PRESET_DEFAULT. */
typedef enum ddof_preset {
    DDOF_PRESET_PREVIEW = 0,
    DDOF_PRESET_DEFAULT = 1,
    DDOF_PRESET_FINAL = 2,
    DDOF_PRESET_COUNT_,
    DDOF_PRESET_FORCE_32BIT_ = 0x7fffffff /* not a value: keeps the enum 32 bits wide */
} ddof_preset;

/* Whether an optional effect runs: AUTO lets the planner decide from the CoC field (and says
 * why in ddof_stats.plan); ON and OFF force it. */
typedef enum ddof_layer_mode {
    DDOF_LAYER_AUTO = 0,
    DDOF_LAYER_OFF = 1,
    DDOF_LAYER_ON = 2,
    DDOF_LAYER_FORCE_32BIT_ = 0x7fffffff /* not a value: keeps the enum 32 bits wide */
} ddof_layer_mode;

/* Bits of ddof_stats.effects: what a call simulated. */
#define DDOF_EFFECT_MIDGROUND 1u   /* the single-layer diffusion                               */
#define DDOF_EFFECT_BACKGROUND 2u  /* blurring underneath (Kass et al. 3.1)                    */
#define DDOF_EFFECT_FOREGROUND 4u  /* a separate foreground element blurred on top (3.2)       */
#define DDOF_EFFECT_NEAR_SPREAD 8u /* one image: near-CoC dilation (GPU Gems 3 ch. 28)         */
#define DDOF_EFFECT_HIGHLIGHTS 16u /* the highlight pass: the brightest pixels drawn as discs   */
#define DDOF_EFFECT_NEAR_LAYER 32u /* one image: the near field split off as an element          */
#define DDOF_EFFECT_FAR_FIELD 64u  /* the smooth blur gathered in the aperture's exact shape    */
#define DDOF_EFFECT_SILHOUETTES 128u /* mixed pixels of in-focus silhouettes split            */

typedef struct ddof_params {
    uint32_t struct_size;      /* sizeof(ddof_params)                                         */
    ddof_solver solver;        /* default: the default preset's (DDOF_SOLVER_THOMAS)          */
    uint32_t substeps;         /* n >= 1 ADI steps of beta/n each; more approaches a Gaussian  */
                               /* kernel at linear cost. Default: the default preset's.       */
    float beta_scale;          /* k in beta = k * d^2 (d: CoC diameter in pixels). 1/32 makes  */
                               /* the kernel's per-axis variance (2 beta) equal a uniform     */
                               /* disk's (d^2 / 16). Default: the default preset's; > 0 and   */
                               /* at most 1 (where every solver stays finite at the largest  */
                               /* CoC, DDOF_MAX_COC_PX, and the largest pixel_aspect).        */
    float pixel_aspect;        /* pixel width / height: column links use d * pixel_aspect.    */
                               /* Default 1; 0.01..100 (anamorphic pixels are 0.5..2).        */
    uint32_t jacobi_iterations;/* sweeps for DDOF_SOLVER_JACOBI, >= 1; default 50             */
    ddof_progress_fn progress; /* optional; NULL for none                                     */
    void *progress_user;       /* passed to progress                                          */

    /* --- layers (version 0.2 of this struct; older callers get the defaults) --------------- */
    uint32_t coc_signed;       /* 1: negative CoC marks the near field (in front of the focus */
                               /* plane), diameter |CoC|. 0: negative CoC is an error.         */
                               /* Default 0; ddof_depth_of_field always uses signed CoC.       */
    ddof_layer_mode background;     /* blurring underneath: in-focus midground pixels become   */
                                    /* holes the background is diffused across. Default AUTO: */
                                    /* on when a CoC >= threshold borders an in-focus pixel.   */
    float background_threshold_px;  /* CoC at which a pixel is wholly background (matte 1).    */
                                    /* Default 8; > background_ramp_start_px, at most         */
                                    /* DDOF_MAX_COC_PX.                                        */
    float background_ramp_start_px; /* CoC below which a pixel is wholly midground (matte 0);  */
                                    /* the matte is linear in between. Default 2; >= 0.        */
    uint32_t background_levels;     /* background layers at thresholds t, 2t, 4t, ... (a log  */
                                    /* scale; the paper's highest quality). Default 1, 1..8.   */
    ddof_layer_mode near_spread;    /* one image only: spread near-field CoC over what lies    */
                                    /* behind it, D(p) = max over near q of |CoC(q)| - 4|p-q| */
                                    /* (falls to 0 a quarter of the CoC away; GPU Gems 3 ch.  */
                                    /* 28's dilation, made to hold for small objects too), so */
                                    /* blurred near objects get soft silhouettes. Needs signed */
                                    /* CoC, and no foreground element (forced ON with one is  */
                                    /* DDOF_ERROR_BAD_PARAMETER: the element is the near       */
                                    /* field).                                                 */
                                    /* Default AUTO: on when a near CoC >= the threshold       */
                                    /* borders a pixel with less than half its CoC.            */
    float near_spread_threshold_px; /* default 4; > 0, at most DDOF_MAX_COC_PX                 */

    /* --- version 0.3 of this struct ------------------------------------------------------- */
    ddof_method method;        /* default DDOF_METHOD_DIFFUSION                               */
    ddof_precision precision;  /* default DDOF_PRECISION_FLOAT                                */

    /* --- version 0.4 of this struct ------------------------------------------------------- */
    ddof_kernel kernel;        /* the point spread of every colour diffusion (the layers'     */
                               /* CoC fills stay heat). Default: the default preset's.        */

    /* --- version 0.5 of this struct ------------------------------------------------------- */
    float in_focus_threshold_px; /* a |CoC| below this counts as in focus: such a pixel      */
                               /* conducts as CoC 0 (no link to or from it blurs; it keeps   */
                               /* its value), and a frame whose largest |CoC| is below it is */
                               /* a copy (0 lines solved, copied_only 1). Default 0.5         */
                               /* (diameter); >= 0, at most DDOF_MAX_COC_PX; 0 lets every    */
                               /* CoC above 0 conduct (in focus means CoC exactly 0). The     */
                               /* layers' own CoC fills are not cut; the CoD4 preview ignores */
                               /* it (docs/design.md, the planner).                           */
    ddof_layer_mode highlights;  /* the highlight pass: the part of a pixel brighter than      */
                               /* highlight_threshold (its largest colour channel) with |CoC|  */
                               /* >= 4 px is taken out before the diffusion and drawn as a    */
                               /* uniform disc afterwards (of the CoC of the brightest pixel */
                               /* of its 3x3: a light's anti-aliased rim goes with the light; */
                               /* on the pixels at or behind its depth), so HDR highlights    */
                               /* come out as the crisp discs a lens draws, without a disc    */
                               /* kernel's dark rim; with a camera, in its aperture's shape  */
                               /* (ddof_camera.aperture_blades, _ratio). A                    */
                               /* disc costs its rows and rim, not its area, and the pass at  */
                               /* most 8 operations per frame pixel: the brightest first (the */
                               /* threshold rises in quarter octaves until they fit).        */
                               /* Colour with 3 or 4 channels only. Default AUTO: on when     */
                               /* such a pixel exists; ON is AUTO's rule too.                */
    float highlight_threshold; /* default 0.25 (scene-linear); > 0, finite                    */

    /* --- version 0.6 of this struct ------------------------------------------------------- */
    ddof_layer_mode near_layer; /* one image: near pixels blurred more than the threshold are  */
                               /* split off into a foreground element (premultiplied by a     */
                               /* soft matte from their CoC), what they hid is filled in from */
                               /* the rest of the frame (the far side preferred), and the     */
                               /* element is blurred over the filled rest as a separately     */
                               /* rendered one would be: a very blurred near object turns     */
                               /* see-through. Needs signed CoC, colour with 3 or 4 channels  */
                               /* and no foreground element; replaces the near spread where   */
                               /* it runs. Default AUTO: on when a near CoC >= the threshold  */
                               /* borders a pixel with less than half its CoC.                */
    float near_layer_threshold_px; /* |CoC| at which a near pixel is wholly in the element   */
                               /* (matte 1; linear from half of it). Default 8; > 0, at most  */
                               /* DDOF_MAX_COC_PX.                                            */

    /* --- version 0.8 of this struct ------------------------------------------------------- */
    ddof_layer_mode far_field; /* the smooth blur drawn with the aperture's exact shape: where */
                               /* no depth edge lies within a pixel's reach, its output is     */
                               /* the mean of the colour over the pixels whose disc covers it */
                               /* (the CoC taken as locally linear; the frame continued by    */
                               /* its edge pixels), blended with the layers' result toward    */
                               /* the edges, where the diffusion stays the method. Round      */
                               /* (with the pixel aspect) whatever the blades. O(1) rows per   */
                               /* pixel at any CoC (reduced images for large ones). Default:  */
                               /* the preset's; AUTO and ON: on when the largest CoC is 1 px  */
                               /* or more (docs/design.md, "The far field").                  */
    ddof_layer_mode silhouettes; /* mixed pixels where an in-focus object meets a blurred      */
                               /* background behind it (a CoC of 4 px or more): each split by */
                               /* the colours on both sides, the object's share kept sharp,  */
                               /* the background's blurred (docs/design.md, "Mixed pixels").  */
                               /* Needs signed CoC and colour with 3 or 4 channels. Default:  */
                               /* the preset's; AUTO and ON: on when such a pair exists.      */

    /* --- version 0.9 of this struct ------------------------------------------------------- */
    ddof_layer_mode blurred_edges; /* where two blurred surfaces meet (both |CoC| >= 2 px and */
                               /* 2 px apart: a tree's crown before the sky) with no in-focus */
                               /* pixel in reach, the far field's gather in depth slices      */
                               /* instead of the diffusion: the frame cut into up to 4 slices */
                               /* at such edges, each surface gathered with the lens's shape  */
                               /* (as the far field), the nearer covering the farther by its  */
                               /* coverage, the farthest continued under the nearer ones.     */
                               /* Needs the far field and signed CoC. Default: the preset's;  */
                               /* AUTO and ON: on when such an edge exists (docs/design.md,   */
                               /* "The far field").                                           */
} ddof_params;

/* The default preset (see ddof_params_init_preset). */
DDOF_API void (ddof_params_init)(ddof_params *params);
DDOF_API void ddof_params_init_sized(ddof_params *params, size_t size);
#define ddof_params_init(params) ddof_params_init_sized((params), sizeof *(params))
/* The 0.5 layout: what (ddof_params_init) writes (see Conventions). */
#define DDOF_PARAMS_SIZE_0_5 (offsetof(ddof_params, highlight_threshold) + sizeof(float))

/* The range ddof_params_check accepts for a numeric field of ddof_params, by the field's name
 * ("substeps", "beta_scale", "near_layer_threshold_px", ...): *lowest and *highest are the
 * smallest and largest values accepted (inclusive; for a field that must be > 0, the smallest
 * float above 0). DDOF_ERROR_BAD_PARAMETER for a name that is not a numeric field, with the
 * outputs untouched. What ties two fields (background_threshold_px above
 * background_ramp_start_px; jacobi_iterations read only by the Jacobi solver) is not a range:
 * ddof_params_check judges it. Hosts read their sliders' limits here. */
DDOF_API ddof_status ddof_param_bounds(const char *field, double *lowest, double *highest);

/* Fills params with a preset's settings; an unknown preset gives DDOF_ERROR_BAD_PARAMETER and
 * the default preset. "preview", "default", "final" by name; NULL if unknown. */
DDOF_API ddof_status (ddof_params_init_preset)(ddof_params *params, ddof_preset preset);
/* ddof_params_init_preset writing only `size` bytes (ddof_params_init_sized's rule). */
DDOF_API ddof_status ddof_params_init_preset_sized(ddof_params *params, size_t size,
                                                   ddof_preset preset);
#define ddof_params_init_preset(params, preset)                                                 \
    ddof_params_init_preset_sized((params), sizeof *(params), (preset))
DDOF_API const char *ddof_preset_name(ddof_preset preset);

/* What a call simulated, skipped, and how long each stage took. An output struct (see
 * Conventions): written up to the caller's struct_size, at least DDOF_STATS_SIZE_0_1. */
typedef struct ddof_stats {
    uint32_t struct_size;      /* set by the caller to sizeof(ddof_stats) before the call     */
    uint32_t solver;           /* the ddof_solver that ran                                    */
    uint32_t threads;          /* threads that worked on the call                             */
    uint32_t substeps;         /* ADI steps run (0 when nothing was out of focus)             */
    uint64_t lines_solved;     /* tridiagonal systems solved, rows and columns, all substeps  */
    uint64_t lines_skipped;    /* lines with no conductive link: copied, not solved           */
    float max_coc_px;          /* largest CoC in the input                                    */
    uint32_t copied_only;      /* 1 when nothing was out of focus (every |CoC| below          */
                               /* params.in_focus_threshold_px): output = input, 0 solves     */
    double seconds_total;      /* wall time of the call                                       */
    double seconds_coc;        /* computing or validating the CoC                             */
    double seconds_rows;       /* the row passes (every layer)                                */
    double seconds_columns;    /* the column passes (every layer)                             */

    /* --- layers (version 0.2 of this struct) ---------------------------------------------- */
    uint32_t effects;          /* DDOF_EFFECT_* bits of what was simulated                    */
    double seconds_plan;       /* analysing the CoC field                                     */
    double seconds_background; /* the background layer(s): matte, CoC fill, colour, blend     */
    double seconds_foreground; /* the foreground element or the near-field spread             */
    char plan[512];            /* one line per decision, '\n'-separated: "<effect>: on: why", */
                               /* "<effect>: off: why", "<effect>: forced on|off"; effects   */
                               /* are midground, background, near layer, near spread,        */
                               /* foreground, highlights, far field, silhouettes (the last   */
                               /* three once their pass has looked at the frame). The CoD4   */
                               /* preview's plan is its one line "preview: ...", without a   */
                               /* '\n'. A plan longer than this is cut after a whole line,   */
                               /* and its last line is then "(the plan goes on)".            */

    /* --- version 0.3 of this struct ------------------------------------------------------- */
    uint32_t backend;          /* the ddof_backend_kind that ran the call                     */
    uint32_t method;           /* the ddof_method that ran                                    */
    uint64_t device_bytes;     /* GL backends: peak GPU memory the call's buffers and         */
                               /* textures took (0 on the CPU)                                */
    uint64_t host_bytes;       /* working memory the context holds after the call (grown to   */
                               /* the largest call, reused by later ones), besides the images */

    /* --- version 0.4 of this struct ------------------------------------------------------- */
    uint32_t kernel;           /* the ddof_kernel that ran: the heat kernel where the         */
                               /* solver has no disc form (ddof_kernel); lines_solved         */
                               /* counts each of a disc's complex solves, on any backend      */

    /* --- version 0.5 of this struct ------------------------------------------------------- */
    uint32_t device_uploads;   /* GL backends: host-to-device transfers of image data the     */
    uint32_t device_readbacks; /* call made, and device-to-host ones (0 on the CPU)           */
    double seconds_highlights; /* the highlight pass: finding, taking out, drawing the discs */

    /* --- version 0.6 of this struct ------------------------------------------------------- */
    double seconds_near_layer; /* splitting the near layer off and filling what it hid (its  */
                               /* blur and composite count as seconds_foreground)            */

    /* --- version 0.8 of this struct ------------------------------------------------------- */
    double seconds_far_field;  /* the far field's gather and blend (params.far_field)        */
    double seconds_silhouettes;/* splitting the mixed pixels of silhouettes                   */
} ddof_stats;

/* The first layout (0.1): the smallest struct_size a call takes (smaller is
 * DDOF_ERROR_BAD_PARAMETER before anything runs). */
#define DDOF_STATS_SIZE_0_1 offsetof(ddof_stats, effects)

/* The single-layer diffusion: diffuses `color` (1..4 channels) with the CoC diameters in pixels
 * in the first channel of `coc` (same size) into `out` (same size and channels as color). The
 * layer fields of params are ignored except coc_signed (with it, |CoC| conducts); for the
 * background layer, near spread and foreground element use ddof_diffuse_layers.
 * out may be the very same buffer as color (in place); any other overlap is undefined.
 * stats may be NULL; if given, set its struct_size first (an older, smaller stats struct gets
 * the fields it has room for).
 *  - NULL context/params/images: DDOF_ERROR_NULL_POINTER. params NULL is *not* allowed: call
 *    ddof_params_init so that the defaults are explicit.
 *  - NaN/inf or |value| > DDOF_MAX_COLOR in colour: DDOF_ERROR_BAD_COLOR. NaN/inf CoC, |CoC| > DDOF_MAX_COC_PX, or a
 *    negative CoC without coc_signed: DDOF_ERROR_BAD_COC. Sizes, strides, channels: as their status codes say.
 *    In each case out is untouched and ddof_context_last_error() names the first bad pixel.
 *  - A pixel with CoC 0 (or |CoC| below params.in_focus_threshold_px) is left exactly
 *    unchanged and nothing diffuses across it.
 *  - With the heat kernel the output is a convex combination of the input along each row then
 *    each column: it never leaves the input's range, and each row sum is conserved by the row
 *    pass (and each column sum by the column pass). A disc kernel keeps the sums and is clamped
 *    to the input's range (see ddof_kernel). */
DDOF_API ddof_status ddof_diffuse(ddof_context *context, const ddof_params *params,
                                  const ddof_image_in *color, const ddof_image_in *coc,
                                  const ddof_image *out, ddof_stats *stats);

/* A separately rendered foreground element (Kass et al. 3.2): near objects with their own alpha,
 * blurred on top of the main image so that a very blurred one turns partly transparent. */
typedef struct ddof_foreground {
    uint32_t struct_size;  /* sizeof(ddof_foreground)                                         */
    ddof_image_in color;   /* 4 channels, RGB and alpha (channel 3); same size. Alpha outside */
                           /* [0, 1] is clamped to it; NaN/inf alpha is DDOF_ERROR_BAD_COLOR  */
    ddof_image_in coc;     /* its CoC diameters in pixels (first channel; the sign is ignored)*/
    uint32_t premultiplied;/* 1: RGB is already multiplied by alpha. Default 1.               */
} ddof_foreground;

DDOF_API void (ddof_foreground_init)(ddof_foreground *foreground);
DDOF_API void ddof_foreground_init_sized(ddof_foreground *foreground, size_t size);
#define ddof_foreground_init(foreground) ddof_foreground_init_sized((foreground), sizeof *(foreground))

/* ddof_diffuse with the layers: the planner analyses the CoC field and runs the midground
 * diffusion, the background layer(s), the near layer or the near-field spread and the
 * foreground element as params and the scene call for (ddof_stats.effects and .plan say what
 * ran and why).
 *  - Background: matte a = 0 below background_ramp_start_px, 1 at the threshold; the CoC is
 *    filled into the holes (where a = 0: diffused with gamma = 0 there and 1 elsewhere,
 *    constant beta of the threshold), then the colour is diffused with the same gamma and the
 *    filled CoC; out = (1 - a w) mid + a w background, where w = 1 within |CoC| / 2 of an
 *    in-focus pixel (|CoC| < background_ramp_start_px), falling linearly to 0 at |CoC| away:
 *    farther out the midground met no insulator, and it keeps the halos of near objects.
 *    Pixels that no background pixel can reach (a run of a = 0 closed by insulators in both
 *    passes) have no background: their background value is 0 and their matte 0, so they keep
 *    the midground; never NaN, never a division by a tiny number.
 *  - Foreground (when `foreground` is not NULL): its CoC is filled outwards (gamma = its alpha,
 *    constant beta of its largest CoC), then its premultiplied colour and alpha are diffused
 *    (gamma = 1, beta from the filled CoC) and composited over: out = F + (1 - F.a) out. Its
 *    colour is only read where alpha > 0, so NaN there is harmless. Requires colour with 3 or
 *    4 channels and an element with 4 (else DDOF_ERROR_BAD_CHANNELS); with 4 the output alpha
 *    is composited too. Its CoC is filled in two ADI steps: the first reaches the pixels that
 *    share a row or column with the element, the second all the others, so its halo is round.
 *  - Near layer (one image, coc_signed = 1, colour with 3 or 4 channels, no element): the
 *    near matte m = 0 down to |CoC| = near_layer_threshold_px / 2, 1 from the threshold,
 *    linear between; the element is m times the colour (premultiplied, alpha m), the rest is
 *    the colour with every pixel of m = 1 replaced by a fill of its surroundings' colour and
 *    CoC (pixels of m = 0, near ones counting less), and the foreground path above runs with
 *    them: out = F + (1 - F.a) (the layers of the rest). Where nothing blurs this gives the
 *    input back. With 4 channels and an alpha other than 1 under the near field, the element
 *    carries m times that alpha into the output's alpha channel, so the alpha is kept. A frame
 *    with no pixel outside the element has nothing to fill from: the rest keeps the input.
 *  - Near spread needs coc_signed = 1 and no foreground element; it does not run where the
 *    near layer does.
 * Every failure leaves out untouched, as for ddof_diffuse. */
DDOF_API ddof_status ddof_diffuse_layers(ddof_context *context, const ddof_params *params,
                                         const ddof_image_in *color, const ddof_image_in *coc,
                                         const ddof_foreground *foreground,
                                         const ddof_image *out, ddof_stats *stats);

/* ------------------------------------------------------------------------------------------ */
/* The one call a host needs                                                                    */

/* A frame as a renderer hands it over. The CoC comes from exactly one source:
 *  - depth + camera: the lens model (ddof_coc_from_camera), signed; params.pixel_aspect is
 *    taken from camera->pixel_aspect;
 *  - depth + curve: the artist curve (ddof_coc_from_curve), signed;
 *  - coc: CoC diameters in pixels that the caller computed (signed if params.coc_signed);
 *    with a camera (and no depth) too, the camera gives the aperture only (its blades,
 *    rotation, ratio, cat's eye or image, as from depth; params.pixel_aspect is then
 *    camera->pixel_aspect times the ratio), never the CoC (version 0.9).
 * Images left with pixels NULL (ddof_frame_init's state) are absent. */
typedef struct ddof_frame {
    uint32_t struct_size;           /* sizeof(ddof_frame)                                    */
    ddof_image_in color;            /* 1..4 channels; required                               */
    ddof_image_in depth;            /* first channel read; with camera or curve              */
    const ddof_camera *camera;      /* NULL, or the camera the CoC (or the aperture) comes from */
    const ddof_curve *curve;        /* NULL, or the curve the CoC comes from                 */
    ddof_image_in coc;              /* the caller's CoC (first channel); instead of depth    */
    /* An optional, separately rendered foreground element (ddof_diffuse_layers): RGBA of the */
    /* colour's size, with its own depth (camera or curve) or its own CoC (a given coc).     */
    /* With depth, a partly covered pixel of the element (0 < alpha < 0.999) whose depth lies */
    /* behind the nearest fully covered pixel within 2 px (a first sample that missed: "no    */
    /* surface", 1e10 in Blender, or +inf) takes that pixel's CoC: the element's part of the  */
    /* pixel is that surface, not the far field (element_edges.h).                           */
    ddof_image_in foreground_color;
    ddof_image_in foreground_depth;
    ddof_image_in foreground_coc;
    uint32_t foreground_premultiplied; /* 1: its RGB is multiplied by alpha. Default 1.      */
    /* Optional: receives the CoC the call used (1 channel, the colour's size, signed as the  */
    /* call used it). Written once every input is valid, before the diffusion runs (so also  */
    /* when that then fails for memory, the backend or a cancel). Must share no byte with an */
    /* input (the matte included) or the output: DDOF_ERROR_BAD_PARAMETER.                    */
    ddof_image coc_out;
} ddof_frame;

/* The smallest struct_size accepted for the structs that had no older layout: their 0.5
 * layouts (fields appended later are optional). */
#define DDOF_CONTEXT_OPTIONS_SIZE_0_5 (offsetof(ddof_context_options, allocator) + sizeof(void *))
#define DDOF_FOREGROUND_SIZE_0_5 (offsetof(ddof_foreground, premultiplied) + sizeof(uint32_t))
#define DDOF_FRAME_SIZE_0_5 (offsetof(ddof_frame, coc_out) + sizeof(ddof_image))

DDOF_API void (ddof_frame_init)(ddof_frame *frame);
DDOF_API void ddof_frame_init_sized(ddof_frame *frame, size_t size);
#define ddof_frame_init(frame) ddof_frame_init_sized((frame), sizeof *(frame))

/* Depth of field of one frame: the CoC from the frame's source, then the layers as the planner
 * and params decide (ddof_diffuse_layers), with the foreground element when there is one.
 * The rules for every combination live here:
 *  - exactly one CoC source (else DDOF_ERROR_BAD_PARAMETER, naming what was given);
 *  - the foreground element needs its depth with a camera or curve, its CoC with a given CoC;
 *  - params.method DDOF_METHOD_COD4_PREVIEW blurs one image: with a foreground element it is
 *    DDOF_ERROR_UNSUPPORTED (ddof_params_check cannot know the frame; check it there);
 *  - params.near_spread forced ON with an element is DDOF_ERROR_BAD_PARAMETER.
 * Every failure before the diffusion leaves out (and coc_out) untouched.
 * stats->seconds_coc includes computing both CoCs. */
DDOF_API ddof_status ddof_render_frame(ddof_context *context, const ddof_params *params,
                                       const ddof_frame *frame, const ddof_image *out,
                                       ddof_stats *stats);

/* Validates params (and on this context's backend: the solver and precision it can run)
 * without running anything; DDOF_OK or the status and last error a call would give. What
 * depends on the frame is judged by the call: a forced near spread needs signed CoC (always so
 * with a camera or curve), and the CoD4 preview takes no foreground element. */
DDOF_API ddof_status ddof_params_check(ddof_context *context, const ddof_params *params);

/* Validates a camera as ddof_render_frame would (focus beyond the focal length, f-number > 0,
 * pixel aspect within 0.01..100, ...), without images. */
DDOF_API ddof_status ddof_camera_check(ddof_context *context, const ddof_camera *camera);

/* Validates a curve as ddof_coc_from_curve would, without images. */
DDOF_API ddof_status ddof_curve_check(ddof_context *context, const ddof_curve *curve);

/* ddof_render_frame with depth + camera and nothing else; kept for 0.2-0.4 callers. */
DDOF_API ddof_status ddof_depth_of_field(ddof_context *context, const ddof_params *params,
                                         const ddof_camera *camera, const ddof_image_in *color,
                                         const ddof_image_in *depth, const ddof_image *out,
                                         ddof_stats *stats);

/* Every enum 32 bits wide, as the library was built (see Conventions). */
#if defined(__cplusplus) && __cplusplus >= 201103L
#define DDOF_ASSERT_32_BITS(type) static_assert(sizeof(type) == 4, #type " must be 32 bits wide")
#elif defined(__STDC_VERSION__) && __STDC_VERSION__ >= 201112L
#define DDOF_ASSERT_32_BITS(type) _Static_assert(sizeof(type) == 4, #type " must be 32 bits wide")
#else
#define DDOF_ASSERT_32_BITS(type) typedef char ddof_assert_##type[sizeof(type) == 4 ? 1 : -1]
#endif
DDOF_ASSERT_32_BITS(ddof_status);
DDOF_ASSERT_32_BITS(ddof_lens_model);
DDOF_ASSERT_32_BITS(ddof_depth_kind);
DDOF_ASSERT_32_BITS(ddof_sensor_fit);
DDOF_ASSERT_32_BITS(ddof_solver);
DDOF_ASSERT_32_BITS(ddof_method);
DDOF_ASSERT_32_BITS(ddof_kernel);
DDOF_ASSERT_32_BITS(ddof_precision);
DDOF_ASSERT_32_BITS(ddof_preset);
DDOF_ASSERT_32_BITS(ddof_layer_mode);

#ifdef __cplusplus
}
#endif

#endif /* DDOF_H */

/* ========================================================================================== */
/* DDOF_EXPERIMENTAL: what is not promised yet. Define DDOF_EXPERIMENTAL before including     */
/* this header to see it. These declarations may change or go in any minor version; a       */
/* program that uses them should check ddof_version_number() at run time equals the version */
/* it was built against. Outside the include guard, so that a second inclusion with the     */
/* macro defined adds this part.                                                             */
/* ========================================================================================== */
#if defined(DDOF_EXPERIMENTAL) && !defined(DDOF_H_EXPERIMENTAL)
#define DDOF_H_EXPERIMENTAL

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------------------------------ */
/* Backends: where the diffusion runs                                                           */

/* The CPU path is in libddof itself. The GL backends live in the plugin library libddof_gl
 * (built when GL support is on), which the context loads at run time with dlopen(RTLD_LOCAL):
 * from `plugin_path`, else from the file the DDOF_GL_PLUGIN environment variable names (either
 * one named is the only file tried), else next to libddof, else from the loader's search path.
 * GL itself is loaded the same way (libEGL / libOSMesa), so linking other GL libraries into the
 * process does not interfere. Missing GL is a status, never a crash; the context then keeps
 * running on the CPU. */
typedef enum ddof_backend_kind {
    DDOF_BACKEND_CPU = 0,     /* the default: libddof's threads                                 */
    DDOF_BACKEND_AUTO = 1,    /* a hardware GPU through EGL when one is found, else the CPU     */
    DDOF_BACKEND_EGL = 2,     /* EGL without a display: a GPU device when there is one, else    */
                              /* Mesa's surfaceless platform (software, llvmpipe)               */
    DDOF_BACKEND_OSMESA = 3,  /* Mesa's off-screen software renderer                           */
    DDOF_BACKEND_HOST_GL = 4, /* the GL 4.5 context current on the calling thread (a host     */
                              /* application's); it must stay current during every call       */
    DDOF_BACKEND_COUNT_,      /* not a backend                                                  */
    DDOF_BACKEND_FORCE_32BIT_ = 0x7fffffff /* not a value: keeps the enum 32 bits wide */
} ddof_backend_kind;

/* "cpu", "auto", "egl", "osmesa", "host"; NULL if unknown. */
DDOF_API const char *ddof_backend_name(ddof_backend_kind kind);

/* Switches the context to a backend. On failure the context keeps its backend, the status is
 * DDOF_ERROR_BACKEND_UNAVAILABLE and ddof_context_last_error() says what was missing. AUTO
 * never fails for want of a GPU: it falls back to the CPU and says why in the backend info.
 * plugin_path: the libddof_gl file to load, or NULL for the search described above. */
DDOF_API ddof_status ddof_context_set_backend(ddof_context *context, ddof_backend_kind kind,
                                              const char *plugin_path);

typedef struct ddof_backend_info {
    uint32_t struct_size;   /* sizeof(ddof_backend_info), set by the caller                     */
    uint32_t kind;          /* the ddof_backend_kind that runs (AUTO resolves to EGL or CPU)    */
    uint32_t hardware;      /* 1 when the GL renderer is a GPU, 0 for software or the CPU       */
    char renderer[128];     /* GL_RENDERER and GL_VERSION, or "CPU, N threads"                 */
    char note[256];         /* why AUTO chose what it chose; "" otherwise                       */
} ddof_backend_info;
#define DDOF_BACKEND_INFO_SIZE_0_3 (offsetof(ddof_backend_info, note) + 256u) /* first layout */

DDOF_API ddof_status ddof_context_backend_info(const ddof_context *context,
                                               ddof_backend_info *info);

/* ------------------------------------------------------------------------------------------ */
/* The disc kernels' fitted tables (docs/disc-kernel.md)                                      */

/* The shape of a disc kernel: per component c and axis, a chain of `steps` implicit steps of
 * complex conductance kappa_cm * d^2 (d: the link's CoC diameter), output x + Re sum_c
 * mix_c (Z_c - x). */
typedef struct ddof_kernel_info {
    uint32_t struct_size;  /* sizeof(ddof_kernel_info), set by the caller                       */
    uint32_t components;   /* C (0 for DDOF_KERNEL_HEAT)                                        */
    uint32_t steps;        /* M per axis                                                        */
    float reach_coc;       /* how far it carries anything, in CoC diameters                     */
    float fit_snr_db;      /* the fit's kernel SNR against a uniform disc of diameter 32 px    */
} ddof_kernel_info;
#define DDOF_KERNEL_INFO_SIZE_0_4 (offsetof(ddof_kernel_info, fit_snr_db) + sizeof(float))

DDOF_API ddof_status ddof_kernel_get_info(ddof_kernel kernel, ddof_kernel_info *info);

/* kappa (re, im) of step `step` of component `component`, and that component's mix (re, im).
 * DDOF_ERROR_BAD_PARAMETER for the heat kernel or an index out of range. */
DDOF_API ddof_status ddof_kernel_get_step(ddof_kernel kernel, uint32_t component, uint32_t step,
                                          float kappa[2], float mix[2]);

/* ------------------------------------------------------------------------------------------ */
/* Cards: depth of field per textured polygon (docs/cards.md)                                 */

/* The per-polygon method of US 8,035,641: each card (a convex textured polygon in camera space)
 * gets a CoC per vertex from the camera, is expanded by those radii on screen, and every pixel
 * of the expanded polygon averages the card's texture over the disc of its own, perspective-
 * correct radius; the cards are composited far to near. A blurred near card thus shows exactly
 * what lies behind it. Texture averages come from a summed-area table (double precision): the
 * disc, mapped into texels by the card's local projection, as `strips` rectangles of exact
 * slice area, so a pixel costs the same whatever its radius. */

#define DDOF_CARD_MAX_VERTICES 8u
/* How near a card's vertex may be: 1 micrometre in front of the camera (Blender's smallest clip
 * start). Nearer (z = -1e-10), a texel covers so many pixels that the disc's area in texels
 * falls below what the average resolves, and the card would draw nothing. */
#define DDOF_CARD_MIN_DEPTH_M 1e-6

typedef struct ddof_card {
    uint32_t vertex_count; /* 3..DDOF_CARD_MAX_VERTICES; planar, convex, either winding          */
    /* camera space in metres: x right, y up, the camera at the origin looking down -z (Blender, */
    /* OpenGL). Every vertex must have z <= -DDOF_CARD_MIN_DEPTH_M: a card behind, crossing or */
    /* nearer than that to the camera's plane is DDOF_ERROR_BAD_PARAMETER (split it first).      */
    float position[DDOF_CARD_MAX_VERTICES][3];
    /* texture coordinates, affine over the card: (0, 0) the texture's bottom-left corner,      */
    /* (1, 1) its top-right. Texels outside the uv polygon are transparent.                     */
    float uv[DDOF_CARD_MAX_VERTICES][2];
    ddof_image_in texture; /* 4 channels, premultiplied RGBA, row 0 at the top (as EXR)          */
} ddof_card;

typedef enum ddof_cards_expansion {
    DDOF_CARDS_EXPAND_OFFSET = 0,   /* default: each edge moved out by its larger vertex radius  */
    DDOF_CARDS_EXPAND_CENTROID = 1, /* the patent's: each vertex pushed from the centroid by its */
                                    /* radius (clips the blur at corners: docs/cards.md)         */
    DDOF_CARDS_EXPAND_FORCE_32BIT_ = 0x7fffffff /* not a value: keeps the enum 32 bits wide */
} ddof_cards_expansion;

typedef struct ddof_cards_params {
    uint32_t struct_size;           /* sizeof(ddof_cards_params)                                */
    ddof_cards_expansion expansion; /* default DDOF_CARDS_EXPAND_OFFSET                         */
    uint32_t strips;                /* rectangles per disc, 1..64, default 8                    */
} ddof_cards_params;

DDOF_API void (ddof_cards_params_init)(ddof_cards_params *params);
DDOF_API void ddof_cards_params_init_sized(ddof_cards_params *params, size_t size);
#define ddof_cards_params_init(params) ddof_cards_params_init_sized((params), sizeof *(params))
/* The 0.5 layout: what (ddof_cards_params_init) writes and the smallest ddof_render_cards
 * accepts (see Conventions). */
#define DDOF_CARDS_PARAMS_SIZE_0_5 (offsetof(ddof_cards_params, strips) + sizeof(uint32_t))

/* Renders `cards` seen through `camera` into `out` (4 channels, premultiplied RGBA; alpha 0
 * where no card lands; every pixel written). The camera's lens model, focus, f-number, sensor
 * fit, pixel aspect and crop window apply; its depth_kind, depth_unit_m and signed_coc do not
 * (geometry is in metres). Projection and pixel centres as Blender's camera. params NULL: the
 * defaults. Order: a card drawn before another that is wholly behind its plane; cards that
 * intersect, or overlap on screen in no consistent order, are DDOF_ERROR_BAD_PARAMETER naming
 * them (split them). Card errors (DDOF_ERROR_BAD_PARAMETER: vertex count, NaN/inf position or
 * uv, z > -DDOF_CARD_MIN_DEPTH_M, a degenerate, non-planar or concave polygon, uv not affine,
 * a texture sharing bytes with out; DDOF_ERROR_BAD_COLOR: NaN/inf texel; the texture's size
 * and channel codes) name the card; nothing is written. A card seen exactly edge-on draws
 * nothing. On a context whose backend is GL (EGL, OSMesa) the
 * device draws the cards (vertex and fragment shaders, blending), within float rounding of the
 * CPU; a texture more than GL_MAX_TEXTURE_SIZE - 1 texels a side (its summed-area table is
 * one larger; 16,383 on llvmpipe), or a frame larger than GL_MAX_TEXTURE_SIZE, is
 * DDOF_ERROR_UNSUPPORTED naming the limit (nothing written: use the CPU backend); a device
 * failure is DDOF_ERROR_BACKEND_FAILED with its reason. */
DDOF_API ddof_status ddof_render_cards(ddof_context *context, const ddof_cards_params *params,
                                       const ddof_camera *camera, const ddof_card *cards,
                                       uint32_t card_count, const ddof_image *out);

/* ------------------------------------------------------------------------------------------ */
/* Object mattes for the silhouettes' split (Cryptomatte)                                       */

/* The most (id, coverage) ranks a matte may hold per pixel (Blender writes 6 by default). */
#define DDOF_MATTE_MAX_RANKS 16

/* ddof_render_frame with an object matte: per pixel, `matte->channels / 2` ranks of (id,
 * coverage), interleaved: id as Cryptomatte stores it (a float whose bits name the object,
 * compared bit for bit), coverage 0..1 (the share of the pixel the object covers). The same
 * width and height as frame->color (DDOF_ERROR_SIZE_MISMATCH otherwise), channels even and
 * 2..2 * DDOF_MATTE_MAX_RANKS (DDOF_ERROR_BAD_CHANNELS otherwise), row_stride as for images.
 * Where the silhouettes' split runs (params.silhouettes), a mixed pixel's object share is what
 * the background leaves of it (the object of rank 0 of the blurred pixel beside it, or the
 * world, what no object covers and Cryptomatte leaves without an id, where that covers more of
 * the blurred pixel), instead of the guess from the colours on both sides; with it the object's
 * colour is solved on the sharp side too (a 1-2 px strand, which has no fully covered pixel to
 * show it), and the split comes after the highlights' discs: a mixed pixel's uncovered share
 * shows the disc of a far light behind it, its covered share hides it (a strand across a
 * light). A NaN or infinite coverage is DDOF_ERROR_BAD_PARAMETER naming the pixel, as is a
 * matte that shares bytes with out or frame->coc_out; matte NULL is ddof_render_frame. The CLI
 * (--matte) and the Blender add-on (Object Matte) read a render's CryptoObject channels into
 * this. */
DDOF_API ddof_status ddof_render_frame_with_matte(ddof_context *context,
                                                  const ddof_params *params,
                                                  const ddof_frame *frame,
                                                  const ddof_image_in *matte,
                                                  const ddof_image *out, ddof_stats *stats);

/* ------------------------------------------------------------------------------------------ */
/* The focal-plane view: a frame in false colour by its CoC, to check the focus before a render */

/* 8-bit RGB of the frame (rgb: width x height x 3 bytes, rows top first, rgb_size at least
 * that), by its signed CoC (coc: one channel, as ddof_coc_from_camera writes it with
 * signed_coc set; unsigned shows all blur as far):
 *   in focus  (|CoC| < 1 px):               green
 *   near blur (CoC < 0, before the focus):  orange, brighter with more blur
 *   far blur  (CoC > 0 or NaN, behind it):  blue, brighter with more blur
 * Blur strength t = (|CoC| - 1) / (the frame's largest finite |CoC| - 1), clamped to 0..1, is
 * the hue's brightness 0.35 + 0.65 t; every colour is shaded by the colour's luminance (0.35 +
 * 0.65 sqrt(Y), Y of linear Rec. 709 clamped to 0..1), so the frame stays recognisable. A
 * camera (NULL: none) whose aperture is not round (blades, a ratio, an image) is drawn as the
 * legend of ddof_focus_map_legend. counts (NULL: not wanted) gets the pixels in focus, near
 * and far. The `ddof` command's --focus-map and the Blender add-on's view are this call. */
DDOF_API ddof_status ddof_focus_map(ddof_context *context, const ddof_image_in *color,
                                    const ddof_image_in *coc, const ddof_camera *camera,
                                    uint8_t *rgb, size_t rgb_size, uint64_t counts[3]);

/* Draws the camera's aperture into a width x height RGB map as its legend, as a light behind
 * the focus draws it: a square of min(64, the smaller side / 4) pixels, 2 from the top and
 * right edges, white inside the shape and black around it (an aperture image: its texels at
 * least half its brightest). Nothing for a round aperture or a map under 48 pixels a side. For
 * a host that maps part of a frame (a render border) and shows it in the whole. */
DDOF_API ddof_status ddof_focus_map_legend(ddof_context *context, const ddof_camera *camera,
                                           uint32_t width, uint32_t height, uint8_t *rgb,
                                           size_t rgb_size);

/* ------------------------------------------------------------------------------------------ */
/* The whole plan                                                                               */

/* The room a whole plan can take, its terminating 0 included. */
#define DDOF_PLAN_MAX_BYTES 2048u

/* The plan of the context's last call, whole: ddof_stats.plan's lines, none cut (a frame with
 * every pass on and its device's line outgrows that field's 512 bytes, which then ends with
 * "(the plan goes on)"). "" when the last call made no plan (it failed before planning, or
 * plans nothing: ddof_diffuse, the cards); never NULL. Valid until the next call on the
 * context. The `ddof` command's plan lines and the Blender add-on's report are this text. */
DDOF_API const char *ddof_context_last_plan(const ddof_context *context);

DDOF_ASSERT_32_BITS(ddof_backend_kind);
DDOF_ASSERT_32_BITS(ddof_cards_expansion);

#ifdef __cplusplus
}
#endif

#endif /* DDOF_EXPERIMENTAL */
