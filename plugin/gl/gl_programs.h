/* SPDX-License-Identifier: MIT */
/* gl_programs.h - the compute programs, built from the embedded GLSL sources (this folder's
 * and the parts' gl/) on first use
 * (compiling all of them up front would cost a second on llvmpipe for solvers never run). */
#ifndef DDOF_GL_PROGRAMS_H
#define DDOF_GL_PROGRAMS_H

#include "gl_functions.h"

typedef enum gl_program_id {
    GL_PROG_PACK,
    GL_PROG_UNPACK,
    GL_PROG_ANALYSE,
    GL_PROG_COPY,
    GL_PROG_THOMAS,
    GL_PROG_CR_REDUCE,
    GL_PROG_CR_BACK,
    GL_PROG_PCR_SHARED,
    GL_PROG_GRUEN_REDUCE4,
    GL_PROG_GRUEN_CRAMER,
    GL_PROG_GRUEN_BACK4,
    GL_PROG_CR_REDUCE_PACKED,   /* the same kernels on RGBA32UI-packed rows */
    GL_PROG_CR_BACK_PACKED,
    GL_PROG_GRUEN_REDUCE4_PACKED,
    GL_PROG_GRUEN_CRAMER_PACKED,
    GL_PROG_GRUEN_BACK4_PACKED,
    GL_PROG_JACOBI_INIT,
    GL_PROG_JACOBI_SWEEP,
    GL_PROG_HOST_PACK,
    GL_PROG_HOST_PACK_DEPTH,
    GL_PROG_HOST_UNPACK_RGBA32F,
    GL_PROG_HOST_UNPACK_RGBA16F,
    GL_PROG_LENS_ANALYSE,       /* analyse.comp with the disc kernel's links */
    GL_PROG_LENS_THOMAS,
    GL_PROG_RANGE,              /* the disc's clamp range of a device-resident input */
    GL_PROG_CONE_DILATE,        /* the layers (gl_layers.c, layers.comp)             */
    GL_PROG_LAYER_NEAR_MAP,
    GL_PROG_LAYER_SPREAD,
    GL_PROG_LAYER_MATTE,
    GL_PROG_LAYER_INSULATOR,
    GL_PROG_LAYER_BLEND,
    GL_PROG_LAYER_FG_PREPARE,
    GL_PROG_LAYER_HOLDS_VALUE,
    GL_PROG_LAYER_COMPOSITE,
    GL_PROG_FAR_SEED,          /* the far field (gl_far_field.c, far_field.comp) */
    GL_PROG_FAR_WEIGHT,
    GL_PROG_FAR_PAIRS_RANGE,
    GL_PROG_FAR_PAIRS_RUNS,
    GL_PROG_FAR_SLICE_INDEX,
    GL_PROG_FAR_SLICE_MEAN,
    GL_PROG_FAR_SLICE_IMAGE,
    GL_PROG_FAR_SLICE_BOX,
    GL_PROG_FAR_SLICE_RADII,
    GL_PROG_FAR_SLICES_BLEND,
    GL_PROG_FAR_DOWNSAMPLE,
    GL_PROG_FAR_PREFIX,
    GL_PROG_FAR_EDGE_ROWS,
    GL_PROG_FAR_EDGE_SIDES,
    GL_PROG_FAR_MARK,
    GL_PROG_FAR_SAMPLES,
    GL_PROG_FAR_GATHER,
    GL_PROG_SIL_CLEAN,          /* the silhouettes (gl_silhouettes.c, silhouettes.comp) */
    GL_PROG_SIL_DELTA,
    GL_PROG_SIL_APPLY,
    GL_PROG_HL_COPY,            /* the highlights (gl_highlights.c, highlights.comp) */
    GL_PROG_HL_TAKE_OUT,
    GL_PROG_HL_LANDING,
    GL_PROG_HL_WEIGH,
    GL_PROG_HL_SCATTER,
    GL_PROG_HL_SUM,
    GL_PROG_HLF_COUNT,          /* finding them (gl_highlights_find.c, highlights_find.comp) */
    GL_PROG_HLF_TOTALS,
    GL_PROG_HLF_OFFSETS,
    GL_PROG_HLF_FILL,
    GL_PROG_HLF_CLEAR,
    GL_PROG_HLF_MARK,
    GL_PROG_HLF_SCAN_BLOCKS,
    GL_PROG_HLF_SCAN_TOP,
    GL_PROG_HLF_SCAN_NUMBER,
    GL_PROG_HLF_GATHER,
    GL_PROG_HLF_SPEND,
    GL_PROG_HLF_MERGE,
    GL_PROG_HLF_SORT_COUNT,
    GL_PROG_HLF_SORT_TOP,
    GL_PROG_HLF_SORT_FIRST,
    GL_PROG_HLF_SORT_PLACE,
    GL_PROG_HLF_SORT_BOXES,
    GL_PROG_NEAR_MATTE,         /* the near layer (gl_near_layer.c, near_layer.comp) */
    GL_PROG_NEAR_PULL,
    GL_PROG_NEAR_PUSH,
    GL_PROG_NEAR_LINES,
    GL_PROG_NEAR_SETTLE,
    GL_PROG_NEAR_FINISH,
    GL_PROG_NEAR_ANALYSE,
    GL_PROG_NOFF_REDUCE,        /* its offset fill (near_offsets.comp) */
    GL_PROG_NOFF_BOX_ROWS,
    GL_PROG_NOFF_BOX_COLUMNS,
    GL_PROG_NOFF_BAND,
    GL_PROG_NOFF_PHASES,
    GL_PROG_NOFF_GRID,
    GL_PROG_NOFF_BAND_ROWS,
    GL_PROG_NOFF_BAND_TOTAL,
    GL_PROG_NOFF_BAND_SAMPLES,
    GL_PROG_NOFF_SEARCH,
    GL_PROG_NOFF_REFINE,
    GL_PROG_NOFF_VARIANCE_MAPS,
    GL_PROG_NOFF_VARIANCE,
    GL_PROG_NOFF_CANDIDATE,
    GL_PROG_NOFF_KEEP,
    GL_PROG_NOFF_COPY,
    GL_PROG_COUNT
} gl_program_id;

typedef struct gl_programs {
    GLuint name[GL_PROG_COUNT];
} gl_programs;

/* The program, compiled and linked on first use; 0 with the compiler's log in message. */
GLuint gl_programs_get(const gl_functions *gl, gl_programs *programs, gl_program_id id,
                       char *message, size_t message_size);
void gl_programs_free(const gl_functions *gl, gl_programs *programs);

/* The text of an embedded GLSL file, or NULL when there is none of that name. */
const char *gl_shader_text(const char *name);

/* A shader of `kind` from `count` parts of source, or 0 with a sentence in message: a part is
 * missing (NULL) or the compiler's log. `name` names the shader in the message. */
GLuint gl_compile_shader(const gl_functions *gl, GLenum kind, const char *name, int count,
                         const char *const *parts, char *message, size_t size);

/* A program linked from the shaders, which it takes over (deleted, they live on while
 * attached), or 0 with the linker's log in message, `name` naming the program. */
GLuint gl_link_program(const gl_functions *gl, const GLuint *shaders, int count,
                       const char *name, char *message, size_t size);

/* Sets a uniform of a program by name (ignored when the program does not use it). */
void gl_uniform_u(const gl_functions *gl, GLuint program, const char *name, GLuint value);
void gl_uniform_f(const gl_functions *gl, GLuint program, const char *name, GLfloat value);

#endif
