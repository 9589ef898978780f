/* SPDX-License-Identifier: MIT */
/* host_api.c - ddof_gl.h: the single-layer diffusion on a host application's textures, through
 * the same ADI driver as every other call, with texture-reading and image-writing stages
 * (host_pack.comp, host_unpack.comp) in place of the host-memory upload and read-back. From a
 * depth texture the CoC is computed on the device too, from the camera's terms
 * (ddof_camera_terms.h, the formula the CPU uses). */
#include "ddof_gl.h"
#include "ddof_camera_terms.h"
#include "ddof_output_struct.h"
#include "ddof_param_rules.h"
#include "gl_adi.h"
#include "gl_solvers.h"

#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

struct ddof_gl_host {
    ddof_device *device; /* NULL when the current context could not be adopted */
    char last_error[256];
};

ddof_status ddof_gl_host_create(ddof_gl_host **out_host)
{
    if (!out_host)
        return DDOF_ERROR_NULL_POINTER;
    ddof_gl_host *host = calloc(1, sizeof *host);
    *out_host = host;
    if (!host)
        return DDOF_ERROR_OUT_OF_MEMORY;
    host->device = gl_device_open(DDOF_BACKEND_HOST_GL, 0, host->last_error,
                                  sizeof host->last_error);
    return host->device ? DDOF_OK : DDOF_ERROR_BACKEND_UNAVAILABLE;
}

const char *ddof_gl_host_last_error(const ddof_gl_host *host)
{
    return host ? host->last_error : "no host (ddof_gl_host_create ran out of memory)";
}

void ddof_gl_host_free(ddof_gl_host *host)
{
    if (!host)
        return;
    gl_device_close(host->device);
    free(host);
}

/* Size and internal format of a 2D texture's level 0; 0 when it is not a texture. */
static int texture_shape(const gl_functions *gl, GLuint texture, GLint *w, GLint *h,
                         GLint *format)
{
    if (!texture || !gl->IsTexture(texture))
        return 0;
    gl->BindTexture(GL_TEXTURE_2D, texture);
    gl->GetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, w);
    gl->GetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_HEIGHT, h);
    gl->GetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_INTERNAL_FORMAT, format);
    return 1;
}

typedef struct saved_state {
    GLint program, active, texture[2];
} saved_state;

static void save_state(const gl_functions *gl, saved_state *s)
{
    gl->GetIntegerv(GL_CURRENT_PROGRAM, &s->program);
    gl->GetIntegerv(GL_ACTIVE_TEXTURE, &s->active);
    for (int unit = 0; unit < 2; unit++) {
        gl->ActiveTexture(GL_TEXTURE0 + (GLenum)unit);
        gl->GetIntegerv(GL_TEXTURE_BINDING_2D, &s->texture[unit]);
    }
}

static void restore_state(const gl_functions *gl, const saved_state *s)
{
    for (int unit = 0; unit < 2; unit++) {
        gl->ActiveTexture(GL_TEXTURE0 + (GLenum)unit);
        gl->BindTexture(GL_TEXTURE_2D, (GLuint)s->texture[unit]);
    }
    gl->ActiveTexture((GLenum)s->active);
    gl->UseProgram((GLuint)s->program);
}

/* The in-focus threshold as ddof_diffuse applies it; a caller's struct from before the field
 * gets the default. */
static float in_focus_of(const ddof_params *p)
{
    return p->struct_size >= offsetof(ddof_params, in_focus_threshold_px) +
                                 sizeof p->in_focus_threshold_px
               ? p->in_focus_threshold_px
               : DDOF_DEFAULT_IN_FOCUS_THRESHOLD_PX;
}

/* One field against the core's range for it (ddof_param_rules.h). */
static int field_ok(param_id id, double value, char *message, size_t size)
{
    if (ddof_param_ok(id, value))
        return 1;
    const param_range *range = ddof_param_range(id);
    snprintf(message, size, "params.%s %.9g must be within %.9g..%.9g", range->field, value,
             range->lowest, range->highest);
    return 0;
}

/* The fields this path reads, judged by the ranges every other call is judged by. */
static ddof_status check_params(const ddof_params *p, char *message, size_t size)
{
    if (p->struct_size < offsetof(ddof_params, coc_signed)) {
        snprintf(message, size, "params.struct_size is %u: not initialised with "
                                "ddof_params_init", p->struct_size);
        return DDOF_ERROR_BAD_PARAMETER;
    }
    if ((unsigned)p->solver >= DDOF_SOLVER_COUNT_) {
        snprintf(message, size, "params.solver %u is not a solver", (unsigned)p->solver);
        return DDOF_ERROR_BAD_PARAMETER;
    }
    if (!field_ok(PARAM_SUBSTEPS, p->substeps, message, size) ||
        !field_ok(PARAM_BETA_SCALE, p->beta_scale, message, size) ||
        !field_ok(PARAM_PIXEL_ASPECT, p->pixel_aspect, message, size) ||
        (p->solver == DDOF_SOLVER_JACOBI &&
         !field_ok(PARAM_JACOBI_ITERATIONS, p->jacobi_iterations, message, size)) ||
        !field_ok(PARAM_IN_FOCUS_THRESHOLD, in_focus_of(p), message, size))
        return DDOF_ERROR_BAD_PARAMETER;
    const ddof_precision precision =
        p->struct_size >= offsetof(ddof_params, precision) + sizeof p->precision
            ? p->precision
            : DDOF_PRECISION_FLOAT;
    if (!gl_solver_supported(p->solver, precision)) {
        snprintf(message, size, "solver %d with precision %d does not run on the GPU",
                 (int)p->solver, (int)precision);
        return DDOF_ERROR_UNSUPPORTED;
    }
    return DDOF_OK;
}

/* The CoC from depth: the camera's terms as uniforms, and the first bad pixel's buffer reset. */
static int set_depth_terms(ddof_device *device, GLuint pack, const ddof_camera_terms *t,
                           char *message, size_t size)
{
    const gl_functions *gl = &device->gl;
    GLuint check = gl_need(device, GL_BUF_CHECK, sizeof(GLuint), message, size);
    if (!check)
        return 0;
    const GLuint none = 0xFFFFFFFFu;
    gl_bind(gl, 1, check);
    gl->BufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof none, &none);
    gl_uniform_f(gl, pack, "u_k_px", (GLfloat)t->k_px);
    gl_uniform_f(gl, pack, "u_focus", (GLfloat)t->focus_units);
    gl_uniform_u(gl, pack, "u_radial", (GLuint)t->radial);
    gl_uniform_f(gl, pack, "u_centre_x", (GLfloat)(0.5 * t->frame_width - t->window_x));
    gl_uniform_f(gl, pack, "u_centre_y", (GLfloat)(0.5 * t->frame_height - t->window_y));
    gl_uniform_f(gl, pack, "u_pixel_w_over_f", (GLfloat)t->pixel_w_over_f);
    gl_uniform_f(gl, pack, "u_pixel_h_over_f", (GLfloat)t->pixel_h_over_f);
    return 1;
}

/* After the depth pack: DDOF_ERROR_BAD_DEPTH naming the first bad pixel (row-major), before
 * anything is written to the host's output. One uint read back. */
static ddof_status check_depth(ddof_device *device, uint32_t width, char *message, size_t size)
{
    const gl_functions *gl = &device->gl;
    GLuint first_bad = 0xFFFFFFFFu;
    gl->MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    gl_bind(gl, 1, gl_need(device, GL_BUF_CHECK, sizeof(GLuint), message, size));
    gl->GetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof first_bad, &first_bad);
    if (first_bad == 0xFFFFFFFFu)
        return DDOF_OK;
    snprintf(message, size,
             "depth at pixel (%u, %u) is NaN, zero or negative; it must be > 0 (+inf for the sky)",
             first_bad % width, first_bad / width);
    return DDOF_ERROR_BAD_DEPTH;
}

static ddof_status host_stages(ddof_device *device, const gl_diffusion *d, float in_focus,
                               const ddof_camera_terms *depth_terms, GLuint color, GLuint coc,
                               GLuint out, GLint out_format, adi_report *report, char *message,
                               size_t size)
{
    const gl_functions *gl = &device->gl;
    const uint64_t pixels = (uint64_t)d->width * d->height;
    GLuint pack = gl_programs_get(gl, &device->programs,
                                  depth_terms ? GL_PROG_HOST_PACK_DEPTH : GL_PROG_HOST_PACK,
                                  message, size);
    GLuint unpack = gl_programs_get(gl, &device->programs,
                                    out_format == GL_RGBA32F ? GL_PROG_HOST_UNPACK_RGBA32F
                                                             : GL_PROG_HOST_UNPACK_RGBA16F,
                                    message, size);
    GLuint image = gl_need(device, GL_BUF_IMAGE_A, pixels * 16, message, size);
    GLuint coc_buffer = gl_need(device, GL_BUF_COC, pixels * 4, message, size);
    if (!pack || !unpack || !image || !coc_buffer)
        return DDOF_ERROR_BACKEND_FAILED;
    gl->ActiveTexture(GL_TEXTURE0);
    gl->BindTexture(GL_TEXTURE_2D, color);
    gl->ActiveTexture(GL_TEXTURE1);
    gl->BindTexture(GL_TEXTURE_2D, coc);
    gl_bind(gl, 0, coc_buffer);
    gl_bind(gl, 4, image);
    gl_uniform_u(gl, pack, "u_width", d->width);
    gl_uniform_u(gl, pack, "u_height", d->height);
    gl_uniform_f(gl, pack, "u_in_focus", in_focus);
    if (depth_terms && !set_depth_terms(device, pack, depth_terms, message, size))
        return DDOF_ERROR_BACKEND_FAILED;
    if (!gl_largest_reset(device, message, size))
        return DDOF_ERROR_BACKEND_FAILED;
    gl->UseProgram(pack);
    gl->DispatchCompute((d->width + 15) / 16, (d->height + 15) / 16, 1);
    gl->MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);

    ddof_status status = depth_terms ? check_depth(device, d->width, message, size) : DDOF_OK;
    if (status == DDOF_OK)
        status = gl_diffuse(device, d, report, message, size);
    if (status != DDOF_OK)
        return status;
    gl_bind(gl, 3, image);
    gl->BindImageTexture(0, out, 0, GL_FALSE, 0, GL_WRITE_ONLY, (GLenum)out_format);
    gl_uniform_u(gl, unpack, "u_width", d->width);
    gl_uniform_u(gl, unpack, "u_height", d->height);
    gl->UseProgram(unpack);
    gl->DispatchCompute((d->width + 15) / 16, (d->height + 15) / 16, 1);
    /* Whatever the host does next with the texture sees the writes. */
    gl->MemoryBarrier(GL_ALL_BARRIER_BITS);
    return DDOF_OK;
}

/* The caller's camera (not NULL) over the defaults (fields past an older struct are 0, as
 * ddof_camera_init sets them), then ddof_camera_check's rules. */
static ddof_status read_camera(const ddof_camera *caller, ddof_camera *camera, char *message,
                               size_t size)
{
    const size_t needed = offsetof(ddof_camera, signed_coc) + sizeof caller->signed_coc;
    if (caller->struct_size < needed) {
        snprintf(message, size, "camera.struct_size is %u, expected at least %zu (call "
                                "ddof_camera_init)", caller->struct_size, needed);
        return DDOF_ERROR_BAD_PARAMETER;
    }
    /* The defaults of the fields an older caller's struct lacks: 0, and a ratio of 1. */
    memset(camera, 0, sizeof *camera);
    camera->aperture_ratio = 1.0;
    memcpy(camera, caller, caller->struct_size < sizeof *camera ? caller->struct_size
                                                                : sizeof *camera);
    camera->struct_size = sizeof *camera;
    return ddof_camera_problem(camera, message, size) ? DDOF_ERROR_BAD_CAMERA : DDOF_OK;
}

/* Both entry points: the CoC from map_texture as it is (camera NULL) or from it as depth. */
static ddof_status host_run(ddof_gl_host *host, const ddof_params *params,
                            const ddof_camera *camera, unsigned color_texture,
                            unsigned coc_texture, unsigned out_texture, uint32_t width,
                            uint32_t height, ddof_stats *stats)
{
    if (!host)
        return DDOF_ERROR_NULL_POINTER;
    char *message = host->last_error;
    const size_t size = sizeof host->last_error;
    if (!host->device)
        return DDOF_ERROR_BACKEND_UNAVAILABLE; /* last_error still says why */
    message[0] = '\0';
    if (!params) {
        snprintf(message, size, "params is NULL");
        return DDOF_ERROR_NULL_POINTER;
    }
    ddof_status status = check_params(params, message, size);
    if (status == DDOF_OK && stats && stats->struct_size < DDOF_STATS_SIZE_0_1) {
        snprintf(message, size, "stats.struct_size is %u, expected at least %zu (set it to "
                                "sizeof(ddof_stats))", stats->struct_size, DDOF_STATS_SIZE_0_1);
        status = DDOF_ERROR_BAD_PARAMETER;
    }
    ddof_camera full_camera;
    if (status == DDOF_OK && camera)
        status = read_camera(camera, &full_camera, message, size);
    if (status != DDOF_OK)
        return status;
    if (width == 0 || height == 0 || width > DDOF_MAX_DIMENSION ||
        height > DDOF_MAX_DIMENSION || (uint64_t)width * height > DDOF_MAX_PIXELS) {
        snprintf(message, size, "size %ux%u out of range", width, height);
        return DDOF_ERROR_BAD_SIZE;
    }
    ddof_device *device = host->device;
    if (!gl_device_begin(device, message, size))
        return DDOF_ERROR_BACKEND_FAILED;
    const gl_functions *gl = &device->gl;
    struct timespec t0;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    saved_state saved;
    save_state(gl, &saved);
    while (gl->GetError() != GL_NO_ERROR) {
    }
    GLint w[3], h[3], format[3];
    const GLuint textures[3] = {color_texture, coc_texture, out_texture};
    for (int i = 0; i < 3 && status == DDOF_OK; i++)
        if (!texture_shape(gl, textures[i], &w[i], &h[i], &format[i]) ||
            (GLuint)w[i] != width || (GLuint)h[i] != height) {
            snprintf(message, size, "texture %u is not a %ux%u 2D texture", textures[i], width,
                     height);
            status = DDOF_ERROR_BAD_PARAMETER;
        }
    if (status == DDOF_OK && ((format[2] != GL_RGBA32F && format[2] != GL_RGBA16F) ||
                              out_texture == color_texture || out_texture == coc_texture)) {
        snprintf(message, size, "the output texture must be GL_RGBA32F or GL_RGBA16F and "
                                "differ from the inputs");
        status = DDOF_ERROR_BAD_PARAMETER;
    }
    adi_report report = {0};
    if (status == DDOF_OK) {
        gl_buffers_begin(&device->buffers);
        const ddof_precision precision =
            params->struct_size >= offsetof(ddof_params, precision) + sizeof params->precision
                ? params->precision
                : DDOF_PRECISION_FLOAT;
        /* With a camera the CoC is the blur's width, and its aperture ratio stretches the
         * blur's height as a pixel aspect does. */
        const float aspect =
            camera ? (float)(params->pixel_aspect * full_camera.aperture_ratio)
                   : params->pixel_aspect;
        const gl_diffusion d = {width, height, 4, params->solver, precision, params->substeps,
                                params->jacobi_iterations, params->beta_scale,
                                aspect, 0, params->progress,
                                params->progress_user, NULL /* the heat kernel */, {0}, {0}};
        const ddof_camera_terms terms =
            camera ? ddof_camera_terms_of(&full_camera, width, height) : (ddof_camera_terms){0};
        status = host_stages(device, &d, in_focus_of(params), camera ? &terms : NULL,
                             color_texture, coc_texture, out_texture,
                             format[2], &report, message, size);
        const GLenum error = gl->GetError();
        if (status == DDOF_OK && error != GL_NO_ERROR) {
            snprintf(message, size, "GL error 0x%x", (unsigned)error);
            status = DDOF_ERROR_BACKEND_FAILED;
        }
    }
    restore_state(gl, &saved);
    device->context->ops->release(device->context);
    if (stats) {
        struct timespec t1;
        clock_gettime(CLOCK_MONOTONIC, &t1);
        ddof_stats full = {
            .struct_size = sizeof full,
            .solver = (uint32_t)params->solver,
            .threads = 1,
            .substeps = report.substeps_run,
            .lines_solved = report.lines_solved,
            .lines_skipped = report.lines_skipped,
            .max_coc_px = report.max_coc,
            .seconds_total =
                (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec),
            .seconds_rows = report.seconds_rows,
            .seconds_columns = report.seconds_columns,
            .effects = report.substeps_run ? DDOF_EFFECT_MIDGROUND : 0,
            .backend = DDOF_BACKEND_HOST_GL,
            .device_bytes = gl_buffers_used(&device->buffers),
        };
        ddof_write_output_struct(stats, &full, sizeof full);
    }
    return status;
}

ddof_status ddof_gl_host_diffuse(ddof_gl_host *host, const ddof_params *params,
                                 unsigned color_texture, unsigned coc_texture,
                                 unsigned out_texture, uint32_t width, uint32_t height,
                                 ddof_stats *stats)
{
    return host_run(host, params, NULL, color_texture, coc_texture, out_texture, width, height,
                    stats);
}

ddof_status ddof_gl_host_diffuse_depth(ddof_gl_host *host, const ddof_params *params,
                                       const ddof_camera *camera, unsigned color_texture,
                                       unsigned depth_texture, unsigned out_texture,
                                       uint32_t width, uint32_t height, ddof_stats *stats)
{
    if (host && host->device && !camera) {
        snprintf(host->last_error, sizeof host->last_error, "camera is NULL");
        return DDOF_ERROR_NULL_POINTER;
    }
    return host_run(host, params, camera, color_texture, depth_texture, out_texture, width,
                    height, stats);
}
