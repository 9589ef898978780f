/* SPDX-License-Identifier: MIT */
/*
 * ddof_gl.h - diffusion depth of field on a host application's own GL textures.
 *
 * For a host that already has an OpenGL 4.5 context (a DCC viewport): it hands in texture
 * names and gets the single-layer diffusion (ddof_diffuse's semantics) written into its output
 * texture, with no read-back to host memory. Exported by libddof_gl.so (link it, or dlopen it
 * and look the functions up); the rest of ddof stays in libddof.
 *
 * The host's context must be current on the calling thread for every call, including
 * ddof_gl_host_free (which deletes ddof's buffers and programs in it). ddof never makes a
 * context current or releases one. It uses shader-storage binding points 0-7, image unit 0
 * and texture units 0-1 during a call and restores the current program, the active texture
 * unit and the 2D textures bound on units 0 and 1; other indexed bindings are left changed.
 */
#ifndef DDOF_GL_H
#define DDOF_GL_H

#include "ddof.h"

#ifdef __cplusplus
extern "C" {
#endif

#if defined(__GNUC__) && __GNUC__ >= 4
#  define DDOF_GL_API __attribute__((visibility("default")))
#else
#  define DDOF_GL_API
#endif

typedef struct ddof_gl_host ddof_gl_host;

/* Adopts the context current on this thread. On failure (no current context, below GL 4.5)
 * returns DDOF_ERROR_BACKEND_UNAVAILABLE and, as sqlite3_open does, still hands back a host
 * whose ddof_gl_host_last_error says why (free it as any other); *out_host is NULL only when
 * even that could not be allocated (DDOF_ERROR_OUT_OF_MEMORY). */
DDOF_GL_API ddof_status ddof_gl_host_create(ddof_gl_host **out_host);

/* A sentence about the host's last failure ("" after a success), as ddof_context_last_error;
 * never NULL, also for a NULL host. */
DDOF_GL_API const char *ddof_gl_host_last_error(const ddof_gl_host *host);

/* Diffuses color_texture (GL_TEXTURE_2D, level 0, RGBA read as floats) with the CoC diameters
 * in pixels in the first channel of coc_texture (same size; the sign is ignored) into
 * out_texture (GL_TEXTURE_2D of the same size, GL_RGBA32F or GL_RGBA16F; it may not be
 * color_texture). params: ddof_params_init'ed; solver (not REFERENCE_F64), precision,
 * substeps, beta_scale, pixel_aspect, jacobi_iterations and in_focus_threshold_px (a |CoC|
 * below it conducts as 0, as in ddof_diffuse) are used. stats may be NULL.
 * Returns DDOF_ERROR_BAD_PARAMETER / _BAD_SIZE / _UNSUPPORTED for bad arguments,
 * DDOF_ERROR_BACKEND_UNAVAILABLE for a host that adopted no context and
 * DDOF_ERROR_BACKEND_FAILED for GL failures; ddof_gl_host_last_error says why. */
DDOF_GL_API ddof_status ddof_gl_host_diffuse(ddof_gl_host *host, const ddof_params *params,
                                             unsigned color_texture, unsigned coc_texture,
                                             unsigned out_texture, uint32_t width,
                                             uint32_t height, ddof_stats *stats);

/* The same from a depth texture: the CoC is computed on the device from the first channel of
 * depth_texture (planar or radial depth in depth units, +inf for the sky) and the camera, by
 * ddof_coc_from_camera's formula (lens model, sensor fit, pixel aspect, crop window, the
 * aperture ratio: the CoC is the blur's width and params.pixel_aspect is multiplied by the
 * ratio for its height; blades are the highlight pass's, which this call has not), in float
 * where the CPU uses double (results within 1.2e-7 of the CPU's in the tests; a CoC within
 * float rounding of in_focus_threshold_px may fall on the other side of it). The camera is
 * checked as ddof_camera_check does: DDOF_ERROR_BAD_CAMERA. A depth that is NaN, zero or
 * negative is DDOF_ERROR_BAD_DEPTH naming the first such pixel, found before anything is
 * written: out_texture is left as it was. That check reads one uint back from the device. */
DDOF_GL_API ddof_status ddof_gl_host_diffuse_depth(ddof_gl_host *host,
                                                   const ddof_params *params,
                                                   const ddof_camera *camera,
                                                   unsigned color_texture,
                                                   unsigned depth_texture,
                                                   unsigned out_texture, uint32_t width,
                                                   uint32_t height, ddof_stats *stats);

/* Accepts NULL. */
DDOF_GL_API void ddof_gl_host_free(ddof_gl_host *host);

#ifdef __cplusplus
}
#endif

#endif
