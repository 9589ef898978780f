/* SPDX-License-Identifier: MIT */
/* study.h - the accuracy-vs-cost study (issue 7, docs/accuracy.md): shared types.
 *
 * ddof-study loads a scene folder (pinhole.exr, truth.exr, camera.json, and when present fg.exr,
 * pinhole_1080.exr, defocus.exr/.json), runs a list of configurations on it and writes one JSON
 * object per (scene, configuration) to a results file. study/report.py turns the results into
 * docs/accuracy.md, its plots and libddof/src/api/presets_measured.inc. */
#ifndef DDOF_STUDY_H
#define DDOF_STUDY_H

#include <ddof.h>

#include <stddef.h>
#include <stdint.h>

/* ---- configurations (configs.c) ----------------------------------------------------------- */

typedef enum study_kind {
    STUDY_DIFFUSION = 0, /* ddof_diffuse_layers with the method DIFFUSION                       */
    STUDY_COD4,          /* the library's CoD4 preview (DDOF_METHOD_COD4_PREVIEW)               */
    STUDY_GATHER,        /* study/baselines/gather_blur.c: a naive per-pixel gather by CoC     */
    STUDY_PINHOLE,       /* the input itself (identity)                                         */
    STUDY_DEFOCUS        /* Blender's compositor Defocus node (defocus*.exr/.json of the scene) */
} study_kind;

/* The Defocus nodes the study compares, one per Blender: the ids of their baselines and the
 * names of their files in a scene folder (<name>.exr, <name>.json, <name>_1080.json), as
 * study/scenes/defocus_node.py names them: Debian's Blender 3.4, then 4.2 LTS and 5.3 (PyPI's
 * bpy). */
enum { STUDY_NODE_COUNT = 3 };
extern const char *const study_node_names[STUDY_NODE_COUNT];

/* What the layer knob sets. */
typedef enum study_layers {
    LAYERS_SINGLE = 0, /* background OFF, near spread OFF                                      */
    LAYERS_BG,         /* background ON, 1 level, near spread OFF                               */
    LAYERS_BG2,        /* background ON, 2 levels, near spread OFF                              */
    LAYERS_BGNEAR,     /* background ON, 1 level, near spread ON                                */
    LAYERS_AUTO,       /* background AUTO, 1 level, near layer AUTO, near spread AUTO (the      */
                       /* planner decides; the near layer takes the near field where it runs)  */
    LAYERS_AUTO2,      /* background AUTO, 2 levels, near layer and near spread AUTO            */
    LAYERS_FG,         /* background ON, 1 level, and the scene's fg.exr as a foreground       */
                       /* element over rest.exr (everything but the near objects: the paper's  */
                       /* separately rendered layers); scenes without one: near spread ON       */
    LAYERS_FGPIN,      /* the same element over pinhole.exr (`ddof pinhole.exr --foreground`):  */
                       /* the near objects are then in the main image too                       */
    LAYERS_AUTOSPREAD, /* background AUTO, 1 level, near layer OFF, near spread AUTO (a blurred */
                       /* near object stays opaque, its silhouette spread)                      */
    LAYERS_COUNT_
} study_layers;

typedef struct study_config {
    char id[96];              /* unique, parseable: "cpu/thomas/f32/n4/k0.03125/auto", "cod4"  */
    char sweeps[96];          /* the sweeps it belongs to, comma-separated: "base,solver,..."   */
    study_kind kind;
    ddof_backend_kind backend;
    ddof_solver solver;
    uint32_t jacobi_iterations;
    ddof_precision precision;
    uint32_t substeps;
    float beta_scale;
    study_layers layers;
    ddof_kernel kernel;       /* heat (the ids above) or a disc: "cpu/thomas/f32/disc-2x2/auto" */
    int node;                 /* STUDY_DEFOCUS: which Blender's node (study_node_names)        */
    int far_field;            /* the far field's gather (AUTO): "+ff" after the layers' name   */
    int blurred_edges;        /* with it, its depth slices (AUTO): "+be" after "+ff"          */
    int silhouettes;          /* the mixed pixels' split (AUTO): "+sil" after that            */
    int matte;                /* with silhouettes: the scene's object matte (matte.exr) for    */
                              /* the split, "+matte" after "+sil"; an input, not a setting     */
} study_config;

typedef struct study_config_list {
    study_config *items;
    size_t count, capacity;
} study_config_list;

const char *study_layers_name(study_layers layers);
/* Parses an id (as study_config_id writes them) into *out; 0 or -1. */
int study_config_parse(const char *id, study_config *out);
/* Writes cfg->id from its fields. */
void study_config_make_id(study_config *cfg);
/* "cpu thomas n=4 k=1/32 auto": for progress lines. */
void study_config_label(const study_config *cfg, char *out, size_t size);
/* Whether cfg runs with the scene's foreground element (fg_element: the scene has one). */
int study_config_uses_fg(const study_config *cfg, int fg_element);
/* Appends cfg (merging its sweep tag when the same id is already listed); 0 or -1. */
int study_config_add(study_config_list *list, const study_config *cfg, const char *sweep);
/* The named list: "full" (the study), "smoke" (two configurations), "baselines". 0 or -1. */
int study_config_named(study_config_list *list, const char *name);
/* A comma-separated list of ids and names; 0 or -1 with a message. */
int study_config_from_spec(study_config_list *list, const char *spec, char *error, size_t size);
void study_config_list_free(study_config_list *list);
/* ddof_params for a diffusion or CoD4 configuration, every preset field set explicitly (so the
 * study does not depend on the presets it chooses); fg_element: whether the scene gives one. */
void study_config_params(const study_config *cfg, int fg_element, ddof_params *params);

/* ---- scenes (scene.c) --------------------------------------------------------------------- */

/* One frame size of a scene. */
typedef struct study_frame {
    uint32_t width, height;
    float *rgba;          /* premultiplied linear RGBA                                          */
    float *depth;         /* planar Z                                                            */
    float *coc;           /* signed CoC in pixels (negative in front of the focus plane)        */
    float *fg_rgba;       /* the foreground element (NULL when the scene has none)              */
    float *fg_coc;        /* its CoC                                                             */
    float *rest_rgba;     /* rest.exr: the scene without the near objects (NULL when absent)    */
    float *rest_coc;      /* its CoC                                                             */
    int fg_resampled;     /* 1: fg and rest upscaled (nearest) from the small frame (no 1080p   */
                          /* renders of them): for timing only                                  */
    float *matte;         /* matte.exr's Cryptomatte: matte_ranks interleaved (id, coverage)    */
    uint32_t matte_ranks; /* pairs a pixel (0: no matte); at 1080p upscaled (nearest), timing   */
} study_frame;

/* One Blender's Defocus node on a scene. */
typedef struct study_node {
    float *image;         /* its image (NULL when the scene folder has none)                    */
    double seconds, seconds_large; /* median composite times; < 0 when absent                 */
    char blender[64];     /* the version that ran it (its JSON's "blender"), "" if unknown      */
} study_node;

typedef struct study_scene {
    char name[128];
    char dir[4096];
    ddof_camera camera;
    study_frame small;    /* the scene's own size (480x270): errors and small timings           */
    study_frame large;    /* pinhole_1080.exr (width 0 when absent): timings only               */
    float *truth;         /* RGBA of the Cycles lens-DOF render, small size                     */
    unsigned char *band;  /* 1 where a pixel lies in the band around depth edges                */
    size_t band_pixels;
    unsigned char *smooth; /* 1 where a pixel lies in the smooth far field (study_smooth)       */
    size_t smooth_pixels;
    unsigned char *silhouette; /* 1 in the silhouette band (study_silhouettes)               */
    size_t silhouette_pixels;
    unsigned char *blurred_edges; /* 1 where two blurred surfaces meet (study_blurred_edges)  */
    size_t blurred_edge_pixels;
    float max_abs_coc;
    double seconds_coc_small, seconds_coc_large; /* ddof_coc_from_camera, median             */
    study_node nodes[STUDY_NODE_COUNT]; /* the Defocus nodes' results (study_node_names)      */
    char blender[64];     /* Blender version from render.json / defocus.json, "" if unknown     */
} study_scene;

/* Loads the scene folder; on failure returns -1 with a message. ctx computes the CoC. */
/* The object matte of matte.exr (width x height, as `ddof --matte auto` finds it): *ranks
 * pairs of (id, coverage) a pixel into *pairs (malloc'd); 0, or -1 with error. */
int study_read_matte(const char *path, uint32_t width, uint32_t height, float **pairs,
                     uint32_t *ranks, char *error, size_t size);

int study_scene_load(ddof_context *ctx, const char *dir, int want_large, study_scene *scene,
                     char *error, size_t size);
void study_scene_free(study_scene *scene);

/* ---- metrics (metrics.c) ------------------------------------------------------------------ */

/* The band around depth edges: a depth edge is a pair of 4-neighbours whose signed CoC differs
 * by at least STUDY_EDGE_COC_PX; every pixel within max(STUDY_BAND_MIN_PX, max |CoC| of the
 * pair / 2) pixels (Euclidean) of either pixel of the pair belongs to the band. */
#define STUDY_EDGE_COC_PX 2.0f
#define STUDY_BAND_MIN_PX 4.0f
size_t study_band(const float *coc, uint32_t width, uint32_t height, unsigned char *band);

/* The smooth far field: pixels with |CoC| > STUDY_SMOOTH_MIN_COC_PX, no pixel of a depth edge
 * (as the band defines it) within max(STUDY_SMOOTH_EDGE_PX, half the pair's larger |CoC|)
 * (Euclidean: 12 px, or the reach of a near object's blur), and no highlight reaching
 * them: a pixel of the input or of the truth whose largest colour channel exceeds
 * STUDY_SMOOTH_HIGHLIGHT excludes every pixel within its own |CoC| / 2 +
 * STUDY_SMOOTH_HIGHLIGHT_MARGIN_PX (where its disc lands). The threshold is 1 (the metric's
 * white), not the library's highlight_threshold 0.25: in a daylight frame the sky and sunlit
 * grass exceed 0.25 (the library raises its threshold on such frames), and 0.25 would leave
 * 8 % of the daylight scene's smooth pixels; 1 takes the sun glints and lights. The blurred
 * plain texture where the diffusion's kernel shape alone makes the error. The CoC is at the
 * scene's size; rgba and truth are RGBA. Returns the count. */
#define STUDY_SMOOTH_EDGE_PX 12.0f
#define STUDY_SMOOTH_MIN_COC_PX 8.0f
#define STUDY_SMOOTH_HIGHLIGHT 1.0f
#define STUDY_SMOOTH_HIGHLIGHT_MARGIN_PX 2.0f
size_t study_smooth(const float *coc, const float *rgba, const float *truth, uint32_t width,
                    uint32_t height, unsigned char *smooth);

/* The silhouette band: in-focus silhouettes are 4-neighbour pairs of an in-focus pixel (|CoC|
 * below STUDY_IN_FOCUS_PX, the library's default threshold) and a blurred one (|CoC| of
 * STUDY_EDGE_COC_PX or more); every pixel within STUDY_SILHOUETTE_PX (Euclidean) of either
 * belongs to the band: where the mixed pixels of thin in-focus structure are. The count. */
#define STUDY_IN_FOCUS_PX 0.5f
#define STUDY_SILHOUETTE_PX 2.0f
size_t study_silhouettes(const float *coc, uint32_t width, uint32_t height,
                         unsigned char *silhouette);

/* The blurred-edge band: where two blurred surfaces meet (a tree's crown before the sky). A
 * depth edge (STUDY_EDGE_COC_PX) whose two sides both have |CoC| of STUDY_EDGE_COC_PX or more
 * marks every pixel within STUDY_SMOOTH_EDGE_PX of it, less those within that distance of an
 * edge touching a sharper pixel (the silhouettes' side). The count. */
size_t study_blurred_edges(const float *coc, uint32_t width, uint32_t height,
                           unsigned char *band);

/* PSNR over RGB of sRGB-encoded values clamped to [0, 1], peak 1: plugin/apps/cli/compare.c's
 * definition (`ddof --compare`). mask NULL: every pixel. +inf when identical; NAN when the mask
 * is empty. Both images RGBA. */
double study_psnr(const float *a, const float *b, size_t pixels, const unsigned char *mask);
/* The mean brightness of `a` over the truth's `b` (linear RGB, every pixel equal), inside the
 * frame (pixels STUDY_BORDER_PX or more from every side) and in the border band within
 * STUDY_BORDER_PX of a side: light whose disc reaches past the frame's edge leaves the frame,
 * so a border folded back reads too bright there. NAN where a region is empty or black. */
#define STUDY_BORDER_PX 14u
void study_brightness(const float *a, const float *b, uint32_t width, uint32_t height,
                      double *inside, double *border);
/* Linear differences over RGBA: the largest absolute and the root mean square. */
void study_linear_diff(const float *a, const float *b, size_t pixels, double *max_abs,
                       double *rms);

/* ---- output (output.c) -------------------------------------------------------------------- */

/* Writes a float32 .npy file of shape (height, width, channels) (channels 1: (height, width)). */
int study_write_npy(const char *path, const float *data, uint32_t width, uint32_t height,
                    uint32_t channels);
/* mkdir -p; 0 or -1. */
int study_mkdirs(const char *path);
/* Reads a small text file into a malloc'ed, NUL-terminated string (NULL on failure). */
char *study_read_text(const char *path);

double study_now(void);
double study_median(double *values, size_t count);

/* ---- the command (main.c, cmd_run.c, cmd_images.c) ----------------------------------------- */

/* What the command line sets (main.c's usage says what each does). */
typedef struct study_options {
    const char *out;
    const char *configs;
    const char *gl_plugin;
    int reps_small, reps_large;
    double budget_small, budget_large; /* seconds of timed calls per configuration and size */
    int large;                         /* time at 1920x1080 when the scene has it           */
    double large_limit;                /* skip a 1080p timing predicted to take longer (s)  */
    int egl_software;                  /* measure EGL on a software renderer too            */
    int no_gl;                         /* never load the GL plugin                          */
    uint32_t threads;
    int append;
    int quiet;
    const char **scenes;
    int scene_count;
} study_options;

/* `ddof-study run`: every configuration on every scene into OUT/results.jsonl (cmd_run.c). */
int study_cmd_run(const study_options *o, const study_config_list *list);
/* `ddof-study images`: the inputs and the configurations' outputs as OUT/<scene>/<id>.npy
 * (cmd_images.c). */
int study_cmd_images(const study_options *o, const study_config_list *list);

/* ---- contexts (contexts.c) ------------------------------------------------------------------ */

/* A GL backend of the plugin: probed once, its context kept for every configuration on it. */
typedef struct study_gl_backend {
    ddof_backend_kind kind;
    ddof_context *ctx;   /* NULL when unavailable */
    char renderer[160];
    int hardware;
    char why[512];       /* why unavailable */
    int probed;
} study_gl_backend;

/* A CPU context with --threads' thread count. */
ddof_status study_cpu_context(const study_options *o, ddof_context **ctx);

enum { STUDY_GL_BACKEND_COUNT = 2 };
extern const ddof_backend_kind study_gl_backend_kinds[STUDY_GL_BACKEND_COUNT];
/* The GL backend of that kind, probed on the first call (NULL for a kind that is not GL). */
study_gl_backend *study_gl_get(const study_options *o, ddof_backend_kind kind);
/* Frees the GL backends' contexts. */
void study_gl_free(void);
/* A context for one configuration: a fresh CPU context (so host_bytes is this configuration's
 * own; *owned = 1, the caller frees it), or the GL backend's. NULL with *why when the backend
 * is unavailable. */
ddof_context *study_context_for(const study_options *o, const study_config *cfg, int *owned,
                                const char **why, const char **renderer);

/* ---- one call (call.c) ---------------------------------------------------------------------- */

/* One configuration on one frame into out. */
typedef struct study_call {
    const study_config *cfg;
    const study_scene *scene;
    const study_frame *frame;
    ddof_context *ctx;
    const float *abs_coc; /* |CoC|, for the gather baseline */
    float *out;
    ddof_stats stats;
    char error[1024];
} study_call;

ddof_status study_run_call(study_call *c);
/* A warm-up call, then up to `reps` timed calls while the budget lasts (at least one); runs
 * gets the seconds of each. */
ddof_status study_time_calls(study_call *c, int reps, double budget, double *runs, int *count);
/* |coc| of n values, malloc'ed (NULL when out of memory): the gather baseline's input. */
float *study_abs_of(const float *coc, size_t n);

/* ---- references (references.c) -------------------------------------------------------------- */

/* The double-precision solve of cfg's settings on the scene's own size (cached; the cache is
 * per scene: study_references_clear after each). NULL with a message on failure. */
const float *study_reference_image(ddof_context *ctx, const study_scene *scene,
                                   const study_config *cfg, char *error, size_t size);
void study_references_clear(void);
/* The seconds spent computing references (the sweep's overhead). */
double study_references_seconds(void);

/* ---- measuring (measure.c, machine.c) ------------------------------------------------------- */

struct cJSON;
/* Measures one configuration on one scene: its JSON record; summary gets a progress line.
 * shared computes the references; out_* and abs_* are the scene's sizes' scratch images. */
struct cJSON *study_measure(const study_options *o, ddof_context *shared,
                            const study_scene *scene, const study_config *cfg, float *out_small,
                            float *out_large, const float *abs_small, const float *abs_large,
                            char *summary, size_t summary_size);
/* The machine line of results.jsonl (probes the GL backends). */
struct cJSON *study_machine_json(const study_options *o);

#endif
