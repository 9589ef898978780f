/* SPDX-License-Identifier: MIT */
/* gl_programs.c - building the compute programs from the embedded shader sources.
 *
 * A program's source is "#version 450", its defines, prelude.glsl, then (solver
 * kernels) line.glsl and (reduction kernels) pyramid.glsl, then the kernel itself. */
#include "gl_programs.h"

#include "ddof_backend_seam.h"
#include "ddof_far_rules.h"
#include "ddof_highlight_rules.h"
#include "ddof_near_rules.h"
#include "ddof_silhouette_rules.h"

#include "gl_shader_sources.h"

#include <stdio.h>
#include <string.h>

enum { PART_LINE = 1, PART_PYRAMID = 2 };

/* The disc kernel's link floor, spelled as the CPU's (GLSL takes the f suffix). */
#define GL_STRING_(x) #x
#define GL_STRING(x) GL_STRING_(x)
#define LENS_DEFINES "#define LENS_MIN_LINK " GL_STRING(DDOF_LENS_MIN_LINK) "\n"
/* The far field's constants (ddof_far_rules.h) and the frame's size limit; the
 * silhouettes' (ddof_silhouette_rules.h). */
#define FAR_DEFINES                                                                          \
    "#define FAR_EDGE_STEP_PX " GL_STRING(FAR_EDGE_STEP_PX) "\n"                            \
    "#define FAR_BLURRED_PX " GL_STRING(FAR_BLURRED_PX) "\n"                                \
    "#define FAR_RAMP_PX " GL_STRING(FAR_RAMP_PX) "\n"                                      \
    "#define FAR_NO_EDGE " GL_STRING(FAR_NO_EDGE) "\n"                                      \
    "#define FAR_FIELD_MAX_CHANNELS " GL_STRING(FAR_FIELD_MAX_CHANNELS) "\n"                \
    "#define FAR_LEVEL_RADIUS " GL_STRING(FAR_LEVEL_RADIUS) "\n"                            \
    "#define DDOF_MAX_DIMENSION " GL_STRING(DDOF_MAX_DIMENSION) "\n"
#define SILHOUETTE_DEFINES                                                                   \
    "#define DDOF_SILHOUETTE_MIN_COC_PX " GL_STRING(DDOF_SILHOUETTE_MIN_COC_PX) "\n"        \
    "#define DDOF_MATTE_SOLVE_SHARE " GL_STRING(DDOF_MATTE_SOLVE_SHARE) "\n"                \
    "#define DDOF_THIN_OBJECT_SHARE " GL_STRING(DDOF_THIN_OBJECT_SHARE) "\n"                \
    "#define DDOF_THIN_NEIGHBOUR_SHARE " GL_STRING(DDOF_THIN_NEIGHBOUR_SHARE) "\n"

/* The highlights' find (ddof_highlight_rules.h). */
#define FIND_DEFINES                                                                         \
    "#define DDOF_HIGHLIGHT_CLASSES " GL_STRING(DDOF_HIGHLIGHT_CLASSES) "\n"                  \
    "#define DDOF_HIGHLIGHT_SIZE_CLASSES " GL_STRING(DDOF_HIGHLIGHT_SIZE_CLASSES) "\n"        \
    "#define DDOF_HIGHLIGHT_MIN_COC_PX " GL_STRING(DDOF_HIGHLIGHT_MIN_COC_PX) "\n"            \
    "#define DDOF_HIGHLIGHT_SHARP_PX " GL_STRING(DDOF_HIGHLIGHT_SHARP_PX) "\n"                \
    "#define DDOF_ROWS_PER_CHUNK " GL_STRING(DDOF_HIGHLIGHT_CHUNK_ROWS) "\n"                  \
    "#define DDOF_MAX_DIMENSION " GL_STRING(DDOF_MAX_DIMENSION) "\n"

/* The near layer's (ddof_near_rules.h); the two the CPU keeps in double, as doubles. */
#define NEAR_DEFINES                                                                         \
    "#define DDOF_NEAR_FRINGE_CONTRAST " GL_STRING(DDOF_NEAR_FRINGE_CONTRAST) "\n"            \
    "#define DDOF_NEAR_FRINGE_MAX_SHARE " GL_STRING(DDOF_NEAR_FRINGE_MAX_SHARE) "\n"          \
    "#define DDOF_NEAR_END_LEVEL " GL_STRING(DDOF_NEAR_END_LEVEL) "\n"                        \
    "#define DDOF_NEAR_MEAN_LIMIT " GL_STRING(DDOF_NEAR_MEAN_LIMIT) "lf\n"                    \
    "#define DDOF_NEAR_MIN_OVERLAP " GL_STRING(DDOF_NEAR_MIN_OVERLAP) "lf\n"                  \
    "#define DDOF_NEAR_KEPT " GL_STRING(DDOF_NEAR_KEPT) "\n"                                  \
    "#define DDOF_NEAR_CANDIDATES " GL_STRING(DDOF_NEAR_CANDIDATES) "\n"                      \
    "#define DDOF_NEAR_MIN_OFFSET " GL_STRING(DDOF_NEAR_MIN_OFFSET) "\n"                      \
    "#define DDOF_NEAR_OFFSET_STEP " GL_STRING(DDOF_NEAR_OFFSET_STEP) "\n"                    \
    "#define DDOF_NEAR_SAMPLE_STRIDE " GL_STRING(DDOF_NEAR_SAMPLE_STRIDE) "\n"                \
    "#define DDOF_NEAR_MAX_BOX_MAPS " GL_STRING(DDOF_NEAR_MAX_BOX_MAPS) "\n"                  \
    "#define DDOF_NEAR_REFINE_SAMPLES " GL_STRING(DDOF_NEAR_REFINE_SAMPLES) "\n"              \
    "#define DDOF_NEAR_SEARCH_LANES " GL_STRING(DDOF_NEAR_SEARCH_LANES) "\n"                  \
    "#define DDOF_NEAR_MIN_BAND_SAMPLES " GL_STRING(DDOF_NEAR_MIN_BAND_SAMPLES) "\n"          \
    "#define DDOF_NEAR_SOFTNESS " GL_STRING(DDOF_NEAR_SOFTNESS) "\n"                          \
    "#define DDOF_NEAR_SOFT_FLOOR " GL_STRING(DDOF_NEAR_SOFT_FLOOR) "\n"

typedef struct program_recipe {
    const char *kernel;
    unsigned parts;
    const char *defines;
} program_recipe;

/* The programs of a kernel whose steps share one source, each step its STEP_ define. */
#define STEP(id, kernel, defines, step) [id] = {kernel, 0, defines "#define STEP_" #step " 1\n"}
#define LAYER_STEP(s) STEP(GL_PROG_LAYER_##s, "layers.comp", "", s)
#define FAR_STEP(s) STEP(GL_PROG_FAR_##s, "far_field.comp", FAR_DEFINES, s)
#define SILHOUETTE_STEP(s) STEP(GL_PROG_SIL_##s, "silhouettes.comp", SILHOUETTE_DEFINES, s)
#define HIGHLIGHT_STEP(s) STEP(GL_PROG_HL_##s, "highlights.comp", "", s)
#define FIND_STEP(s) STEP(GL_PROG_HLF_##s, "highlights_find.comp", FIND_DEFINES, s)
#define NEAR_STEP(s) STEP(GL_PROG_NEAR_##s, "near_layer.comp", NEAR_DEFINES, s)
#define OFFSETS_STEP(s) STEP(GL_PROG_NOFF_##s, "near_offsets.comp", NEAR_DEFINES, s)

static const program_recipe recipes[GL_PROG_COUNT] = {
    [GL_PROG_PACK] = {"pack.comp", 0, ""},
    [GL_PROG_UNPACK] = {"unpack.comp", 0, ""},
    [GL_PROG_ANALYSE] = {"analyse.comp", PART_LINE, ""},
    [GL_PROG_COPY] = {"copy.comp", PART_LINE, ""},
    [GL_PROG_THOMAS] = {"thomas.comp", PART_LINE, ""},
    [GL_PROG_CR_REDUCE] = {"cr_reduce.comp", PART_LINE | PART_PYRAMID, ""},
    [GL_PROG_CR_BACK] = {"cr_back.comp", PART_LINE | PART_PYRAMID, ""},
    [GL_PROG_PCR_SHARED] = {"pcr_shared.comp", PART_LINE | PART_PYRAMID, ""},
    [GL_PROG_GRUEN_REDUCE4] = {"gruen_reduce4.comp", PART_LINE | PART_PYRAMID, ""},
    [GL_PROG_GRUEN_CRAMER] = {"gruen_cramer.comp", PART_LINE | PART_PYRAMID, ""},
    [GL_PROG_GRUEN_BACK4] = {"gruen_back4.comp", PART_LINE | PART_PYRAMID, ""},
    [GL_PROG_CR_REDUCE_PACKED] = {"cr_reduce.comp", PART_LINE | PART_PYRAMID,
                                  "#define PACKED 1\n"},
    [GL_PROG_CR_BACK_PACKED] = {"cr_back.comp", PART_LINE | PART_PYRAMID,
                                "#define PACKED 1\n"},
    [GL_PROG_GRUEN_REDUCE4_PACKED] = {"gruen_reduce4.comp", PART_LINE | PART_PYRAMID,
                                      "#define PACKED 1\n"},
    [GL_PROG_GRUEN_CRAMER_PACKED] = {"gruen_cramer.comp", PART_LINE | PART_PYRAMID,
                                     "#define PACKED 1\n"},
    [GL_PROG_GRUEN_BACK4_PACKED] = {"gruen_back4.comp", PART_LINE | PART_PYRAMID,
                                    "#define PACKED 1\n"},
    [GL_PROG_JACOBI_INIT] = {"jacobi_init.comp", PART_LINE, ""},
    [GL_PROG_JACOBI_SWEEP] = {"jacobi_sweep.comp", PART_LINE, ""},
    [GL_PROG_HOST_PACK] = {"host_pack.comp", 0, ""},
    [GL_PROG_HOST_PACK_DEPTH] = {"host_pack.comp", 0,
                                 "#define FROM_DEPTH 1\n"
                                 "#define MAX_COC " GL_STRING(DDOF_MAX_COC_PX) "\n"},
    [GL_PROG_HOST_UNPACK_RGBA32F] = {"host_unpack.comp", 0, "#define OUT_FORMAT rgba32f\n"},
    [GL_PROG_HOST_UNPACK_RGBA16F] = {"host_unpack.comp", 0, "#define OUT_FORMAT rgba16f\n"},
    [GL_PROG_LENS_ANALYSE] = {"analyse.comp", PART_LINE, LENS_DEFINES},
    [GL_PROG_LENS_THOMAS] = {"lens_thomas.comp", PART_LINE, LENS_DEFINES},
    [GL_PROG_RANGE] = {"range.comp", 0, ""},
    [GL_PROG_CONE_DILATE] = {"cone_dilate.comp", 0, ""},
    LAYER_STEP(NEAR_MAP), LAYER_STEP(SPREAD), LAYER_STEP(MATTE), LAYER_STEP(INSULATOR),
    LAYER_STEP(BLEND), LAYER_STEP(FG_PREPARE), LAYER_STEP(HOLDS_VALUE), LAYER_STEP(COMPOSITE),
    FAR_STEP(SEED), FAR_STEP(WEIGHT), FAR_STEP(PAIRS_RANGE), FAR_STEP(PAIRS_RUNS),
    FAR_STEP(SLICE_INDEX), FAR_STEP(SLICE_MEAN), FAR_STEP(SLICE_IMAGE), FAR_STEP(SLICE_BOX),
    FAR_STEP(SLICE_RADII), FAR_STEP(SLICES_BLEND), FAR_STEP(DOWNSAMPLE), FAR_STEP(PREFIX),
    FAR_STEP(EDGE_ROWS), FAR_STEP(EDGE_SIDES), FAR_STEP(MARK), FAR_STEP(SAMPLES),
    FAR_STEP(GATHER),
    SILHOUETTE_STEP(CLEAN), SILHOUETTE_STEP(DELTA), SILHOUETTE_STEP(APPLY),
    HIGHLIGHT_STEP(COPY), HIGHLIGHT_STEP(TAKE_OUT), HIGHLIGHT_STEP(LANDING),
    HIGHLIGHT_STEP(WEIGH), HIGHLIGHT_STEP(SCATTER), HIGHLIGHT_STEP(SUM),
    FIND_STEP(COUNT), FIND_STEP(TOTALS), FIND_STEP(OFFSETS), FIND_STEP(FILL), FIND_STEP(CLEAR),
    FIND_STEP(MARK), FIND_STEP(SCAN_BLOCKS), FIND_STEP(SCAN_TOP), FIND_STEP(SCAN_NUMBER),
    FIND_STEP(GATHER), FIND_STEP(SPEND), FIND_STEP(MERGE), FIND_STEP(SORT_COUNT),
    FIND_STEP(SORT_TOP), FIND_STEP(SORT_FIRST), FIND_STEP(SORT_PLACE), FIND_STEP(SORT_BOXES),
    NEAR_STEP(MATTE), NEAR_STEP(PULL), NEAR_STEP(PUSH), NEAR_STEP(LINES), NEAR_STEP(SETTLE),
    NEAR_STEP(FINISH), NEAR_STEP(ANALYSE),
    OFFSETS_STEP(REDUCE), OFFSETS_STEP(BOX_ROWS), OFFSETS_STEP(BOX_COLUMNS), OFFSETS_STEP(BAND),
    OFFSETS_STEP(PHASES), OFFSETS_STEP(GRID), OFFSETS_STEP(BAND_ROWS), OFFSETS_STEP(BAND_TOTAL),
    OFFSETS_STEP(BAND_SAMPLES), OFFSETS_STEP(SEARCH), OFFSETS_STEP(REFINE),
    OFFSETS_STEP(VARIANCE_MAPS), OFFSETS_STEP(VARIANCE), OFFSETS_STEP(CANDIDATE),
    OFFSETS_STEP(KEEP), OFFSETS_STEP(COPY),
};

const char *gl_shader_text(const char *name)
{
    for (size_t i = 0; i < sizeof gl_shader_sources / sizeof *gl_shader_sources; i++)
        if (strcmp(gl_shader_sources[i].name, name) == 0)
            return gl_shader_sources[i].text;
    return NULL;
}

/* How a compile or a link is judged: the shader's or the program's calls (the two sets share
 * their signatures), the status asked for, and the verb its message starts with. */
typedef struct build_step {
    PFNGLGETSHADERIVPROC get_status;
    PFNGLGETSHADERINFOLOGPROC get_log;
    PFNGLDELETESHADERPROC delete_object;
    GLenum status;
    const char *doing;
} build_step;

/* 1 when `object` passed the step; else 0 with "DOING NAME failed: LOG" in message, the object
 * deleted. */
static int step_passed(const build_step *step, GLuint object, const char *name, char *message,
                       size_t size)
{
    GLint ok = 0;
    step->get_status(object, step->status, &ok);
    if (ok)
        return 1;
    char log[400] = "";
    step->get_log(object, sizeof log, NULL, log);
    snprintf(message, size, "%s %s failed: %s", step->doing, name, log);
    step->delete_object(object);
    return 0;
}

GLuint gl_compile_shader(const gl_functions *gl, GLenum kind, const char *name, int count,
                         const char *const *parts, char *message, size_t size)
{
    for (int i = 0; i < count; i++)
        if (!parts[i]) {
            snprintf(message, size, "shader source missing for %s", name);
            return 0;
        }
    const build_step compiling = {gl->GetShaderiv, gl->GetShaderInfoLog, gl->DeleteShader,
                                  GL_COMPILE_STATUS, "compiling"};
    GLuint shader = gl->CreateShader(kind);
    gl->ShaderSource(shader, count, parts, NULL);
    gl->CompileShader(shader);
    return step_passed(&compiling, shader, name, message, size) ? shader : 0;
}

GLuint gl_link_program(const gl_functions *gl, const GLuint *shaders, int count,
                       const char *name, char *message, size_t size)
{
    const build_step linking = {gl->GetProgramiv, gl->GetProgramInfoLog, gl->DeleteProgram,
                                GL_LINK_STATUS, "linking"};
    GLuint program = gl->CreateProgram();
    for (int i = 0; i < count; i++)
        gl->AttachShader(program, shaders[i]);
    gl->LinkProgram(program);
    for (int i = 0; i < count; i++)
        gl->DeleteShader(shaders[i]); /* stays alive while attached */
    return step_passed(&linking, program, name, message, size) ? program : 0;
}

static GLuint build(const gl_functions *gl, const program_recipe *recipe, char *message,
                    size_t size)
{
    const char *parts[6];
    int count = 0;
    parts[count++] = "#version 450\n";
    parts[count++] = recipe->defines;
    parts[count++] = gl_shader_text("prelude.glsl");
    if (recipe->parts & PART_LINE)
        parts[count++] = gl_shader_text("line.glsl");
    if (recipe->parts & PART_PYRAMID)
        parts[count++] = gl_shader_text("pyramid.glsl");
    parts[count++] = gl_shader_text(recipe->kernel);
    GLuint shader =
        gl_compile_shader(gl, GL_COMPUTE_SHADER, recipe->kernel, count, parts, message, size);
    return shader ? gl_link_program(gl, &shader, 1, recipe->kernel, message, size) : 0;
}

GLuint gl_programs_get(const gl_functions *gl, gl_programs *programs, gl_program_id id,
                       char *message, size_t message_size)
{
    if (!programs->name[id])
        programs->name[id] = build(gl, &recipes[id], message, message_size);
    return programs->name[id];
}

void gl_programs_free(const gl_functions *gl, gl_programs *programs)
{
    for (int i = 0; i < GL_PROG_COUNT; i++)
        if (programs->name[i])
            gl->DeleteProgram(programs->name[i]);
    memset(programs, 0, sizeof *programs);
}

void gl_uniform_u(const gl_functions *gl, GLuint program, const char *name, GLuint value)
{
    gl->ProgramUniform1ui(program, gl->GetUniformLocation(program, name), value);
}

void gl_uniform_f(const gl_functions *gl, GLuint program, const char *name, GLfloat value)
{
    gl->ProgramUniform1f(program, gl->GetUniformLocation(program, name), value);
}
