/* SPDX-License-Identifier: MIT */
/* test_gl_backends.c - the backends side by side in one process: OSMesa then EGL then OSMesa
 * again (each call releases its context, so the next backend can make its own current), GL
 * missing (a clear DDOF_ERROR_BACKEND_UNAVAILABLE, and the context keeps working on the CPU),
 * AUTO without a GPU (the CPU, with a note), cancellation, and a host application's context:
 * an OSMesa context this test creates and makes current itself, used through
 * DDOF_BACKEND_HOST_GL and through ddof_gl_host_diffuse on textures. */
#define _GNU_SOURCE /* setenv, unsetenv */
#include "gl_test.h"
#include "ddof_gl.h"

#include <GL/osmesa.h>
#include <dlfcn.h>

enum { W = 53, H = 37, CH = 4 };

static float color[W * H * CH], coc[W * H], ref[W * H * CH];
/* The same without the in-focus threshold (in_focus_threshold_px 0), which the host-texture
 * entry point (ddof_gl_host_diffuse) must follow too. */
static float ref_no_threshold[W * H * CH];

static void make_images(void)
{
    test_rng rng = {5};
    fill_uniform(color, W * H * CH, &rng, 0.0, 1.0);
    fill_coc(coc, W * H, &rng, 25.0, 0.2);
    ddof_context *cpu = make_context(1);
    ddof_params p = params_for(DDOF_SOLVER_REFERENCE_F64, 1);
    CHECK(diffuse(cpu, &p, color, coc, ref, W, H, CH, NULL) == DDOF_OK);
    p.in_focus_threshold_px = 0.0f;
    CHECK(diffuse(cpu, &p, color, coc, ref_no_threshold, W, H, CH, NULL) == DDOF_OK);
    /* The random CoC has values below the threshold, so the two must differ. */
    CHECK(max_diff(ref, ref_no_threshold, W * H * CH) > 1e-4);
    ddof_context_free(cpu);
}

/* ddof_diffuse with `solver` on ctx into out; its status. */
static ddof_status run(ddof_context *ctx, ddof_solver solver, float *out)
{
    ddof_params p = params_for(solver, 1);
    return diffuse(ctx, &p, color, coc, out, W, H, CH, NULL);
}

static void test_one_after_the_other(void)
{
    ddof_context *osmesa = gl_context_for(DDOF_BACKEND_OSMESA);
    ddof_context *egl = gl_context_for(DDOF_BACKEND_EGL);
    CHECK(osmesa != NULL);
    if (!osmesa)
        return;
    static float a[W * H * CH], b[W * H * CH], c[W * H * CH];
    const ddof_solver solvers[] = {DDOF_SOLVER_THOMAS, DDOF_SOLVER_PCR, DDOF_SOLVER_GRUEN};
    for (size_t k = 0; k < 3; k++) {
        CHECK(run(osmesa, solvers[k], a) == DDOF_OK);
        CHECK(max_diff(a, ref, W * H * CH) <= 1e-5);
        if (!egl) {
            printf("EGL unavailable: only OSMesa checked\n");
            continue;
        }
        CHECK(run(egl, solvers[k], b) == DDOF_OK);
        CHECK(run(osmesa, solvers[k], c) == DDOF_OK);
        /* The same llvmpipe behind both: the same code on the same data, bit for bit. */
        CHECK_MSG(memcmp(a, b, sizeof a) == 0, "%s: OSMesa and EGL differ by %.3g",
                  ddof_solver_name(solvers[k]), max_diff(a, b, W * H * CH));
        CHECK_MSG(memcmp(a, c, sizeof a) == 0, "%s: OSMesa after EGL differs by %.3g",
                  ddof_solver_name(solvers[k]), max_diff(a, c, W * H * CH));
    }
    ddof_context_free(egl);
    ddof_context_free(osmesa);
}

static void test_gl_missing(void)
{
    static float out[W * H * CH];
    const struct {
        const char *env;
        ddof_backend_kind kind;
    } cases[] = {{"DDOF_GL_OSMESA_LIBRARY", DDOF_BACKEND_OSMESA},
                 {"DDOF_GL_EGL_LIBRARY", DDOF_BACKEND_EGL}};
    for (size_t k = 0; k < 2; k++) {
        setenv(cases[k].env, "/nonexistent/libGL-is-missing.so", 1);
        ddof_context *ctx = make_context(1);
        ddof_status s = ddof_context_set_backend(ctx, cases[k].kind, DDOF_TEST_GL_PLUGIN);
        CHECK_EQ_INT(s, DDOF_ERROR_BACKEND_UNAVAILABLE);
        CHECK_MSG(strstr(ddof_context_last_error(ctx), "libGL-is-missing") != NULL,
                  "message does not name the library: %s", ddof_context_last_error(ctx));
        ddof_backend_info info = {.struct_size = sizeof info};
        CHECK(ddof_context_backend_info(ctx, &info) == DDOF_OK);
        CHECK_EQ_INT(info.kind, DDOF_BACKEND_CPU);
        CHECK(run(ctx, DDOF_SOLVER_THOMAS, out) == DDOF_OK); /* still works, on the CPU */
        CHECK(max_diff(out, ref, W * H * CH) <= 1e-5);
        if (cases[k].kind == DDOF_BACKEND_EGL) { /* AUTO falls back to the CPU, with a note */
            CHECK(ddof_context_set_backend(ctx, DDOF_BACKEND_AUTO, DDOF_TEST_GL_PLUGIN) ==
                  DDOF_OK);
            CHECK(ddof_context_backend_info(ctx, &info) == DDOF_OK);
            CHECK_EQ_INT(info.kind, DDOF_BACKEND_CPU);
            CHECK(info.note[0] != '\0');
        }
        ddof_context_free(ctx);
        unsetenv(cases[k].env);
    }
    /* A plugin that is not there at all. */
    ddof_context *ctx = make_context(1);
    CHECK_EQ_INT(ddof_context_set_backend(ctx, DDOF_BACKEND_OSMESA, "/nonexistent/libddof_gl.so"),
                 DDOF_ERROR_BACKEND_UNAVAILABLE);
    ddof_context_free(ctx);
}

static void test_auto(void)
{
    ddof_context *ctx = make_context(1);
    CHECK(ddof_context_set_backend(ctx, DDOF_BACKEND_AUTO, DDOF_TEST_GL_PLUGIN) == DDOF_OK);
    ddof_backend_info info = {.struct_size = sizeof info};
    CHECK(ddof_context_backend_info(ctx, &info) == DDOF_OK);
    printf("auto: %s (%s)\n", ddof_backend_name(info.kind), info.note);
    /* AUTO never picks software GL: a GPU through EGL, or the CPU. */
    CHECK(info.kind == DDOF_BACKEND_CPU || (info.kind == DDOF_BACKEND_EGL && info.hardware));
    ddof_context_free(ctx);
}

static int cancel_at_half(void *user, float fraction)
{
    (void)user;
    return fraction >= 0.5f;
}

static void test_cancel(void)
{
    ddof_context *ctx = gl_context_for(DDOF_BACKEND_OSMESA);
    if (!ctx)
        return;
    static float out[W * H * CH];
    ddof_params p = params_for(DDOF_SOLVER_CYCLIC_REDUCTION, 2);
    p.progress = cancel_at_half;
    CHECK_EQ_INT(diffuse(ctx, &p, color, coc, out, W, H, CH, NULL), DDOF_ERROR_CANCELLED);
    int finite = 1;
    for (size_t i = 0; i < W * H * CH; i++)
        finite &= isfinite(out[i]) != 0;
    CHECK(finite);
    ddof_context_free(ctx);
}

/* ---- a host application's context ----------------------------------------------------- */

typedef OSMesaContext (*create_fn)(const int *, OSMesaContext);
typedef GLboolean (*make_current_fn)(OSMesaContext, void *, GLenum, GLsizei, GLsizei);
typedef void (*destroy_fn)(OSMesaContext);
typedef void (*(*get_proc_fn)(const char *))(void);
typedef void (*gen_textures_fn)(GLsizei, GLuint *);
typedef void (*bind_texture_fn)(GLenum, GLuint);
typedef void (*tex_storage_fn)(GLenum, GLsizei, GLenum, GLsizei, GLsizei);
typedef void (*tex_sub_image_fn)(GLenum, GLint, GLint, GLint, GLsizei, GLsizei, GLenum, GLenum,
                                 const void *);
typedef void (*get_tex_image_fn)(GLenum, GLint, GLenum, GLenum, void *);
typedef void (*delete_textures_fn)(GLsizei, const GLuint *);
typedef ddof_status (*host_create_fn)(ddof_gl_host **);
typedef const char *(*host_last_error_fn)(const ddof_gl_host *);
typedef ddof_status (*host_diffuse_fn)(ddof_gl_host *, const ddof_params *, unsigned, unsigned,
                                       unsigned, uint32_t, uint32_t, ddof_stats *);
typedef void (*host_free_fn)(ddof_gl_host *);
typedef ddof_status (*host_diffuse_depth_fn)(ddof_gl_host *, const ddof_params *,
                                             const ddof_camera *, unsigned, unsigned, unsigned,
                                             uint32_t, uint32_t, ddof_stats *);

/* The host context's texture calls the tests use. */
typedef struct texture_calls {
    gen_textures_fn gen;
    bind_texture_fn bind;
    tex_storage_fn storage;
    tex_sub_image_fn sub_image;
    get_tex_image_fn get_image;
    delete_textures_fn del;
} texture_calls;

static void *symbol(void *lib, const char *name)
{
    return dlsym(lib, name);
}

#define LOOKUP(type, var, lib, name)                                                       \
    type var;                                                                              \
    do {                                                                                   \
        void *s_ = symbol(lib, name);                                                      \
        memcpy(&var, &s_, sizeof var);                                                     \
    } while (0)

/* The CoC computed on the device from a depth texture (ddof_gl_host_diffuse_depth) against the
 * CPU's: ddof_coc_from_camera on the same depth, then the double-precision reference. Depths
 * from a set whose CoC lies far from the in-focus threshold (the device computes in float, the
 * CPU in double), for planar depth with the Cycles model and radial depth with the thin lens
 * in a crop of a larger frame; then a NaN depth and a bad camera, each a status with the
 * output texture untouched. */
static void test_host_depth(void *plugin, ddof_gl_host *gl_host, const texture_calls *t)
{
    LOOKUP(host_diffuse_depth_fn, host_depth, plugin, "ddof_gl_host_diffuse_depth");
    LOOKUP(host_last_error_fn, host_last_error, plugin, "ddof_gl_host_last_error");
    CHECK(host_depth && host_last_error);
    if (!host_depth || !host_last_error)
        return;
    static float depth[W * H], cpu_coc[W * H], expect[W * H * CH], out[W * H * CH];
    static float sentinel[W * H * CH];
    const float planar_set[] = {0.5f, 1.0f, 1.5f, 2.0f, 4.0f, 8.0f, INFINITY};
    const float radial_set[] = {0.5f, 1.0f, 4.0f, 8.0f, INFINITY}; /* none near the focus */
    test_rng rng = {23};
    GLuint tex[3];
    t->gen(3, tex);
    const GLenum formats[3] = {GL_RGBA32F, GL_R32F, GL_RGBA32F};
    for (int i = 0; i < 3; i++) {
        t->bind(GL_TEXTURE_2D, tex[i]);
        t->storage(GL_TEXTURE_2D, 1, formats[i], W, H);
    }
    t->bind(GL_TEXTURE_2D, tex[0]);
    t->sub_image(GL_TEXTURE_2D, 0, 0, 0, W, H, GL_RGBA, GL_FLOAT, color);
    ddof_context *cpu = make_context(1);
    for (int radial = 0; radial < 2; radial++) {
        ddof_camera camera;
        ddof_camera_init(&camera);
        camera.focal_length_mm = 100.0; /* a 5.3 px CoC at infinity on a 53-px frame */
        camera.fstop = 1.4;
        camera.focus_distance_m = 2.0;
        if (radial) {
            camera.lens_model = DDOF_LENS_THIN_LENS;
            camera.depth_kind = DDOF_DEPTH_RADIAL;
            camera.frame_width = 200;
            camera.frame_height = 100;
            camera.window_x = 20;
            camera.window_y = 10;
        }
        for (int i = 0; i < W * H; i++)
            depth[i] = radial ? radial_set[(int)(test_uniform(&rng) * 5) % 5]
                              : planar_set[(int)(test_uniform(&rng) * 7) % 7];
        ddof_image_in depth_in = {depth, W, H, 1, 0};
        ddof_image coc_image = {cpu_coc, W, H, 1, 0};
        CHECK_EQ_INT(ddof_coc_from_camera(cpu, &camera, &depth_in, &coc_image), DDOF_OK);
        ddof_params p = params_for(DDOF_SOLVER_REFERENCE_F64, 1);
        CHECK_EQ_INT(diffuse(cpu, &p, color, cpu_coc, expect, W, H, CH, NULL), DDOF_OK);
        t->bind(GL_TEXTURE_2D, tex[1]);
        t->sub_image(GL_TEXTURE_2D, 0, 0, 0, W, H, GL_RED, GL_FLOAT, depth);
        p = params_for(DDOF_SOLVER_THOMAS, 1);
        ddof_stats st = stats_init();
        ddof_status s = host_depth(gl_host, &p, &camera, tex[0], tex[1], tex[2], W, H, &st);
        CHECK_MSG(s == DDOF_OK, "host depth (radial %d): %d %s", radial, (int)s,
                  host_last_error(gl_host));
        t->bind(GL_TEXTURE_2D, tex[2]);
        t->get_image(GL_TEXTURE_2D, 0, GL_RGBA, GL_FLOAT, out);
        const double e = max_diff(out, expect, W * H * CH);
        CHECK_MSG(e <= 1e-5, "host depth (radial %d) vs the CPU: %.3g", radial, e);
        printf("host texture, CoC from %s depth on the device vs the CPU: %.3g\n",
               radial ? "radial" : "planar", e);
        CHECK(st.max_coc_px > 5.0f); /* the CoC did reach the solver */
    }
    /* An anamorphic aperture: the CoC is the blur's width (half for ratio 2) and the blur twice
     * as tall, as the CPU's ddof_coc_from_camera with pixel_aspect * ratio; and a 0.5 caller's
     * camera, which has no ratio field, is round (its struct once read as ratio 0: refused). */
    for (int old = 0; old < 2; old++) {
        ddof_camera camera;
        ddof_camera_init(&camera);
        camera.focal_length_mm = 100.0;
        camera.fstop = 1.4;
        camera.focus_distance_m = 2.0;
        camera.aperture_ratio = 2.0;
        if (old)
            camera.struct_size = (uint32_t)DDOF_CAMERA_SIZE_0_5;
        ddof_camera as_read = camera;
        as_read.aperture_ratio = old ? 1.0 : 2.0;
        as_read.struct_size = sizeof as_read;
        ddof_image_in depth_in = {depth, W, H, 1, 0};
        ddof_image coc_image = {cpu_coc, W, H, 1, 0};
        CHECK_EQ_INT(ddof_coc_from_camera(cpu, &as_read, &depth_in, &coc_image), DDOF_OK);
        ddof_params p = params_for(DDOF_SOLVER_REFERENCE_F64, 1);
        p.pixel_aspect = (float)as_read.aperture_ratio;
        CHECK_EQ_INT(diffuse(cpu, &p, color, cpu_coc, expect, W, H, CH, NULL), DDOF_OK);
        t->bind(GL_TEXTURE_2D, tex[1]);
        t->sub_image(GL_TEXTURE_2D, 0, 0, 0, W, H, GL_RED, GL_FLOAT, depth);
        p = params_for(DDOF_SOLVER_THOMAS, 1);
        ddof_status s = host_depth(gl_host, &p, &camera, tex[0], tex[1], tex[2], W, H, NULL);
        CHECK_MSG(s == DDOF_OK, "host depth (ratio 2, %s camera): %d %s", old ? "0.5" : "0.7",
                  (int)s, host_last_error(gl_host));
        t->bind(GL_TEXTURE_2D, tex[2]);
        t->get_image(GL_TEXTURE_2D, 0, GL_RGBA, GL_FLOAT, out);
        const double e = max_diff(out, expect, W * H * CH);
        CHECK_MSG(e <= 1e-5, "host depth (ratio 2, %s camera) vs the CPU: %.3g",
                  old ? "0.5" : "0.7", e);
    }
    /* A NaN depth: a status naming the pixel, and the output texture as it was. */
    fill_const(sentinel, W * H * CH, 0.25f);
    t->bind(GL_TEXTURE_2D, tex[2]);
    t->sub_image(GL_TEXTURE_2D, 0, 0, 0, W, H, GL_RGBA, GL_FLOAT, sentinel);
    depth[3 * W + 7] = NAN;
    depth[9 * W + 2] = -1.0f;
    t->bind(GL_TEXTURE_2D, tex[1]);
    t->sub_image(GL_TEXTURE_2D, 0, 0, 0, W, H, GL_RED, GL_FLOAT, depth);
    ddof_camera camera;
    ddof_camera_init(&camera);
    ddof_params p = params_for(DDOF_SOLVER_THOMAS, 1);
    CHECK_EQ_INT(host_depth(gl_host, &p, &camera, tex[0], tex[1], tex[2], W, H, NULL),
                 DDOF_ERROR_BAD_DEPTH);
    CHECK_MSG(strstr(host_last_error(gl_host), "(7, 3)") != NULL, "%s",
              host_last_error(gl_host));
    t->bind(GL_TEXTURE_2D, tex[2]);
    t->get_image(GL_TEXTURE_2D, 0, GL_RGBA, GL_FLOAT, out);
    CHECK(max_diff(out, sentinel, W * H * CH) == 0.0);
    /* A bad camera and none: statuses, as ddof_camera_check and a NULL argument give. */
    camera.fstop = 0.0;
    CHECK_EQ_INT(host_depth(gl_host, &p, &camera, tex[0], tex[1], tex[2], W, H, NULL),
                 DDOF_ERROR_BAD_CAMERA);
    CHECK(strstr(host_last_error(gl_host), "f-number") != NULL);
    CHECK_EQ_INT(host_depth(gl_host, &p, NULL, tex[0], tex[1], tex[2], W, H, NULL),
                 DDOF_ERROR_NULL_POINTER);
    t->get_image(GL_TEXTURE_2D, 0, GL_RGBA, GL_FLOAT, out);
    CHECK(max_diff(out, sentinel, W * H * CH) == 0.0);
    ddof_context_free(cpu);
    t->del(3, tex);
}

static void test_host_context(void)
{
    void *osmesa = dlopen("libOSMesa.so.8", RTLD_NOW | RTLD_LOCAL);
    void *plugin = dlopen(DDOF_TEST_GL_PLUGIN, RTLD_NOW | RTLD_LOCAL);
    CHECK(osmesa && plugin);
    if (!osmesa || !plugin)
        return;
    LOOKUP(create_fn, create, osmesa, "OSMesaCreateContextAttribs");
    LOOKUP(make_current_fn, make_current, osmesa, "OSMesaMakeCurrent");
    LOOKUP(destroy_fn, destroy, osmesa, "OSMesaDestroyContext");
    LOOKUP(get_proc_fn, get_proc, osmesa, "OSMesaGetProcAddress");
    const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION, 4, OSMESA_CONTEXT_MINOR_VERSION, 5, 0};
    OSMesaContext host = create(attribs, NULL);
    static unsigned char framebuffer[4 * 4 * 4];
    CHECK(host && make_current(host, framebuffer, GL_UNSIGNED_BYTE, 4, 4));

    /* 1: the library's calls on the current context (ddof_diffuse reads host memory). */
    static float out[W * H * CH];
    ddof_context *ctx = make_context(1);
    CHECK(ddof_context_set_backend(ctx, DDOF_BACKEND_HOST_GL, DDOF_TEST_GL_PLUGIN) == DDOF_OK);
    ddof_params p = params_for(DDOF_SOLVER_PCR, 1);
    ddof_stats st = stats_init();
    CHECK(diffuse(ctx, &p, color, coc, out, W, H, CH, &st) == DDOF_OK);
    CHECK_EQ_INT(st.backend, DDOF_BACKEND_HOST_GL);
    CHECK(max_diff(out, ref, W * H * CH) <= 1e-5);

    /* 2: the host's own textures, no read-back by ddof. */
    gen_textures_fn gen_textures = (gen_textures_fn)get_proc("glGenTextures");
    bind_texture_fn bind_texture = (bind_texture_fn)get_proc("glBindTexture");
    tex_storage_fn tex_storage = (tex_storage_fn)get_proc("glTexStorage2D");
    tex_sub_image_fn tex_sub_image = (tex_sub_image_fn)get_proc("glTexSubImage2D");
    get_tex_image_fn get_tex_image = (get_tex_image_fn)get_proc("glGetTexImage");
    delete_textures_fn delete_textures = (delete_textures_fn)get_proc("glDeleteTextures");
    GLuint tex[3];
    gen_textures(3, tex);
    const GLenum formats[3] = {GL_RGBA32F, GL_R32F, GL_RGBA32F};
    for (int i = 0; i < 3; i++) {
        bind_texture(GL_TEXTURE_2D, tex[i]);
        tex_storage(GL_TEXTURE_2D, 1, formats[i], W, H);
    }
    bind_texture(GL_TEXTURE_2D, tex[0]);
    tex_sub_image(GL_TEXTURE_2D, 0, 0, 0, W, H, GL_RGBA, GL_FLOAT, color);
    bind_texture(GL_TEXTURE_2D, tex[1]);
    tex_sub_image(GL_TEXTURE_2D, 0, 0, 0, W, H, GL_RED, GL_FLOAT, coc);

    LOOKUP(host_create_fn, host_create, plugin, "ddof_gl_host_create");
    LOOKUP(host_diffuse_fn, host_diffuse, plugin, "ddof_gl_host_diffuse");
    LOOKUP(host_free_fn, host_free, plugin, "ddof_gl_host_free");
    LOOKUP(host_last_error_fn, host_last_error, plugin, "ddof_gl_host_last_error");
    CHECK(host_create && host_diffuse && host_free && host_last_error);
    ddof_gl_host *gl_host = NULL;
    CHECK_MSG(host_create(&gl_host) == DDOF_OK, "%s", host_last_error(gl_host));
    static const ddof_solver solvers[] = {DDOF_SOLVER_THOMAS, DDOF_SOLVER_CYCLIC_REDUCTION,
                                          DDOF_SOLVER_PCR, DDOF_SOLVER_GRUEN};
    for (size_t k = 0; gl_host && k < 4; k++) {
        p = params_for(solvers[k], 1);
        st = stats_init();
        ddof_status s = host_diffuse(gl_host, &p, tex[0], tex[1], tex[2], W, H, &st);
        CHECK_MSG(s == DDOF_OK, "host %s: %d %s", ddof_solver_name(solvers[k]), (int)s,
                  host_last_error(gl_host));
        CHECK_EQ_INT(host_last_error(gl_host)[0], 0);
        memset(out, 0, sizeof out);
        bind_texture(GL_TEXTURE_2D, tex[2]);
        get_tex_image(GL_TEXTURE_2D, 0, GL_RGBA, GL_FLOAT, out);
        const double e = max_diff(out, ref, W * H * CH);
        CHECK_MSG(e <= 1e-5, "host %s: max error %.3g", ddof_solver_name(solvers[k]), e);
        CHECK(st.device_bytes > 0);
        /* Threshold 0: every CoC above 0 conducts, as ddof_diffuse does then. */
        p.in_focus_threshold_px = 0.0f;
        CHECK_EQ_INT(host_diffuse(gl_host, &p, tex[0], tex[1], tex[2], W, H, NULL), DDOF_OK);
        memset(out, 0, sizeof out);
        get_tex_image(GL_TEXTURE_2D, 0, GL_RGBA, GL_FLOAT, out);
        const double e0 = max_diff(out, ref_no_threshold, W * H * CH);
        CHECK_MSG(e0 <= 1e-5, "host %s, threshold 0: max error %.3g",
                  ddof_solver_name(solvers[k]), e0);
    }
    /* Every CoC below the in-focus threshold: nothing conducts, and the largest CoC reported is
     * the one before the cut, as ddof_diffuse reports it (the host's path said 0 before). */
    if (gl_host) {
        float *below = malloc((size_t)W * H * sizeof *below);
        for (size_t i = 0; i < (size_t)W * H; i++)
            below[i] = 0.01f * coc[i]; /* |CoC| <= 0.25 px, the threshold 0.5 */
        float largest = 0.0f;
        for (size_t i = 0; i < (size_t)W * H; i++)
            largest = fabsf(below[i]) > largest ? fabsf(below[i]) : largest;
        bind_texture(GL_TEXTURE_2D, tex[1]);
        tex_sub_image(GL_TEXTURE_2D, 0, 0, 0, W, H, GL_RED, GL_FLOAT, below);
        p = params_for(DDOF_SOLVER_THOMAS, 1);
        st = stats_init();
        CHECK_EQ_INT(host_diffuse(gl_host, &p, tex[0], tex[1], tex[2], W, H, &st), DDOF_OK);
        CHECK_MSG(st.max_coc_px == largest && largest > 0.0f,
                  "host, CoC below the threshold: max_coc_px %.9g, wanted %.9g",
                  (double)st.max_coc_px, (double)largest);
        /* ddof_diffuse on the host's context: the device reports it, as the CPU does. */
        st = stats_init();
        CHECK_EQ_INT(diffuse(ctx, &p, color, below, out, W, H, CH, &st), DDOF_OK);
        CHECK_MSG(st.max_coc_px == largest, "ddof_diffuse, CoC below the threshold: %.9g",
                  (double)st.max_coc_px);
        tex_sub_image(GL_TEXTURE_2D, 0, 0, 0, W, H, GL_RED, GL_FLOAT, coc);
        free(below);
    }
    /* A threshold outside 0..DDOF_MAX_COC_PX is refused, as by ddof_diffuse. */
    p.in_focus_threshold_px = -1.0f;
    CHECK_EQ_INT(host_diffuse(gl_host, &p, tex[0], tex[1], tex[2], W, H, NULL),
                 DDOF_ERROR_BAD_PARAMETER);
    p.in_focus_threshold_px = NAN;
    CHECK_EQ_INT(host_diffuse(gl_host, &p, tex[0], tex[1], tex[2], W, H, NULL),
                 DDOF_ERROR_BAD_PARAMETER);
    p.in_focus_threshold_px = DDOF_DEFAULT_IN_FOCUS_THRESHOLD_PX;
    /* The ranges ddof_diffuse judges by (ddof_param_bounds): each value just past its end is
     * refused with the field named and nothing written; the end itself runs. */
    static const struct {
        const char *field;
        int above; /* 1: past the highest value, 0: below the lowest */
    } bounds[] = {{"substeps", 1}, {"beta_scale", 1}, {"pixel_aspect", 1}, {"pixel_aspect", 0}};
    for (size_t i = 0; i < sizeof bounds / sizeof bounds[0]; i++) {
        double lowest, highest;
        CHECK_EQ_INT(ddof_param_bounds(bounds[i].field, &lowest, &highest), DDOF_OK);
        ddof_params q = p;
        const double end = bounds[i].above ? highest : lowest;
        const double past = bounds[i].above ? (strcmp(bounds[i].field, "substeps") == 0
                                                   ? end + 1.0
                                                   : (double)nextafterf((float)end, INFINITY))
                                            : (double)nextafterf((float)end, 0.0f);
        float *field = strcmp(bounds[i].field, "beta_scale") == 0 ? &q.beta_scale
                                                                   : &q.pixel_aspect;
        if (strcmp(bounds[i].field, "substeps") == 0)
            q.substeps = (uint32_t)past;
        else
            *field = (float)past;
        CHECK_EQ_INT(host_diffuse(gl_host, &q, tex[0], tex[1], tex[2], W, H, NULL),
                     DDOF_ERROR_BAD_PARAMETER);
        CHECK_MSG(strstr(host_last_error(gl_host), bounds[i].field) != NULL,
                  "host refuses %s %.9g with '%s'", bounds[i].field, past,
                  host_last_error(gl_host));
        if (strcmp(bounds[i].field, "substeps") != 0) {
            *field = (float)end;
            CHECK_EQ_INT(host_diffuse(gl_host, &q, tex[0], tex[1], tex[2], W, H, NULL), DDOF_OK);
        }
    }
    /* A wrong texture is a status, not a crash. */
    CHECK_EQ_INT(host_diffuse(gl_host, &p, tex[0], tex[1], 987654u, W, H, NULL),
                 DDOF_ERROR_BAD_PARAMETER);
    CHECK(strstr(host_last_error(gl_host), "987654") != NULL);
    const texture_calls calls = {gen_textures, bind_texture,  tex_storage,
                                 tex_sub_image, get_tex_image, delete_textures};
    if (gl_host)
        test_host_depth(plugin, gl_host, &calls);
    host_free(gl_host);
    delete_textures(3, tex);
    ddof_context_free(ctx);
    make_current(NULL, NULL, 0, 0, 0);
    destroy(host);
    /* With nothing current, the host backend is unavailable. */
    ctx = make_context(1);
    CHECK_EQ_INT(ddof_context_set_backend(ctx, DDOF_BACKEND_HOST_GL, DDOF_TEST_GL_PLUGIN),
                 DDOF_ERROR_BACKEND_UNAVAILABLE);
    ddof_context_free(ctx);
    /* And the host API says so through the host it still hands back. */
    gl_host = NULL;
    CHECK_EQ_INT(host_create(&gl_host), DDOF_ERROR_BACKEND_UNAVAILABLE);
    CHECK(gl_host != NULL && strlen(host_last_error(gl_host)) > 10);
    p = params_for(DDOF_SOLVER_THOMAS, 1);
    CHECK_EQ_INT(host_diffuse(gl_host, &p, 1, 2, 3, W, H, NULL), DDOF_ERROR_BACKEND_UNAVAILABLE);
    host_free(gl_host);
    CHECK(strlen(host_last_error(NULL)) > 0);
    dlclose(plugin);
}

int main(void)
{
    make_images();
    test_one_after_the_other();
    test_gl_missing();
    test_auto();
    test_cancel();
    test_host_context();
    return test_report("test_gl_backends");
}
