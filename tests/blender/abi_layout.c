/* SPDX-License-Identifier: GPL-3.0-or-later */
/* abi_layout.c - prints the size and field offsets of every public ddof struct, one line each:
 *   <struct> <sizeof> <field>:<offset>:<size> ...
 * check_abi.py compares them with the ctypes mirror in blender_addon/diffusion_dof/ddof_abi.py,
 * and the enum values, so a field added to ddof.h without the add-on following fails a test. */
#ifndef DDOF_EXPERIMENTAL /* the cards' structs (the build may define it already) */
#define DDOF_EXPERIMENTAL
#endif
#include <ddof.h>

#include <stddef.h>
#include <stdio.h>

#define F(type, field) printf(" %s:%zu:%zu", #field, offsetof(type, field), sizeof(((type *)0)->field))
#define BEGIN(type) printf("%s %zu", #type, sizeof(type))
#define END() printf("\n")
#define E(name) printf("enum %s %d\n", #name, (int)(name))

int main(void)
{
    BEGIN(ddof_image);
    F(ddof_image, pixels); F(ddof_image, width); F(ddof_image, height);
    F(ddof_image, channels); F(ddof_image, row_stride);
    END();
    BEGIN(ddof_image_in);
    F(ddof_image_in, pixels); F(ddof_image_in, width); F(ddof_image_in, height);
    F(ddof_image_in, channels); F(ddof_image_in, row_stride);
    END();
    BEGIN(ddof_allocator);
    F(ddof_allocator, alloc); F(ddof_allocator, free); F(ddof_allocator, user);
    END();
    BEGIN(ddof_context_options);
    F(ddof_context_options, struct_size); F(ddof_context_options, thread_count);
    F(ddof_context_options, allocator);
    END();
    BEGIN(ddof_camera);
    F(ddof_camera, struct_size); F(ddof_camera, lens_model); F(ddof_camera, depth_kind);
    F(ddof_camera, sensor_fit); F(ddof_camera, focal_length_mm); F(ddof_camera, sensor_width_mm);
    F(ddof_camera, fstop); F(ddof_camera, focus_distance_m); F(ddof_camera, pixel_aspect);
    F(ddof_camera, depth_unit_m); F(ddof_camera, signed_coc);
    F(ddof_camera, frame_width); F(ddof_camera, frame_height); F(ddof_camera, window_x);
    F(ddof_camera, window_y);
    F(ddof_camera, aperture_blades);
    F(ddof_camera, aperture_rotation_deg);
    F(ddof_camera, aperture_ratio);
    F(ddof_camera, aperture_catseye);
    F(ddof_camera, aperture_image);
    F(ddof_camera, aperture_image_width);
    F(ddof_camera, aperture_image_height);
    END();
    BEGIN(ddof_curve);
    F(ddof_curve, struct_size); F(ddof_curve, near_blur_px); F(ddof_curve, near_start);
    F(ddof_curve, near_end); F(ddof_curve, far_start); F(ddof_curve, far_end);
    F(ddof_curve, far_blur_px); F(ddof_curve, signed_coc);
    END();
    BEGIN(ddof_params);
    F(ddof_params, struct_size); F(ddof_params, solver); F(ddof_params, substeps);
    F(ddof_params, beta_scale); F(ddof_params, pixel_aspect); F(ddof_params, jacobi_iterations);
    F(ddof_params, progress); F(ddof_params, progress_user); F(ddof_params, coc_signed);
    F(ddof_params, background); F(ddof_params, background_threshold_px);
    F(ddof_params, background_ramp_start_px); F(ddof_params, background_levels);
    F(ddof_params, near_spread); F(ddof_params, near_spread_threshold_px);
    F(ddof_params, method); F(ddof_params, precision); F(ddof_params, kernel);
    F(ddof_params, in_focus_threshold_px); F(ddof_params, highlights);
    F(ddof_params, highlight_threshold); F(ddof_params, near_layer);
    F(ddof_params, near_layer_threshold_px);
    F(ddof_params, far_field);
    F(ddof_params, silhouettes);
    F(ddof_params, blurred_edges);
    END();
    BEGIN(ddof_frame);
    F(ddof_frame, struct_size); F(ddof_frame, color); F(ddof_frame, depth);
    F(ddof_frame, camera); F(ddof_frame, curve); F(ddof_frame, coc);
    F(ddof_frame, foreground_color); F(ddof_frame, foreground_depth);
    F(ddof_frame, foreground_coc); F(ddof_frame, foreground_premultiplied);
    F(ddof_frame, coc_out);
    END();
    BEGIN(ddof_stats);
    F(ddof_stats, struct_size); F(ddof_stats, solver); F(ddof_stats, threads);
    F(ddof_stats, substeps); F(ddof_stats, lines_solved); F(ddof_stats, lines_skipped);
    F(ddof_stats, max_coc_px); F(ddof_stats, copied_only); F(ddof_stats, seconds_total);
    F(ddof_stats, seconds_coc); F(ddof_stats, seconds_rows); F(ddof_stats, seconds_columns);
    F(ddof_stats, effects); F(ddof_stats, seconds_plan); F(ddof_stats, seconds_background);
    F(ddof_stats, seconds_foreground); F(ddof_stats, plan); F(ddof_stats, backend);
    F(ddof_stats, method); F(ddof_stats, device_bytes); F(ddof_stats, host_bytes);
    F(ddof_stats, kernel); F(ddof_stats, device_uploads); F(ddof_stats, device_readbacks);
    F(ddof_stats, seconds_highlights); F(ddof_stats, seconds_near_layer);
    F(ddof_stats, seconds_far_field);
    F(ddof_stats, seconds_silhouettes);
    END();
    BEGIN(ddof_foreground);
    F(ddof_foreground, struct_size); F(ddof_foreground, color); F(ddof_foreground, coc);
    F(ddof_foreground, premultiplied);
    END();
    BEGIN(ddof_card);
    F(ddof_card, vertex_count); F(ddof_card, position); F(ddof_card, uv); F(ddof_card, texture);
    END();
    BEGIN(ddof_cards_params);
    F(ddof_cards_params, struct_size); F(ddof_cards_params, expansion);
    F(ddof_cards_params, strips);
    END();
    BEGIN(ddof_backend_info);
    F(ddof_backend_info, struct_size); F(ddof_backend_info, kind); F(ddof_backend_info, hardware);
    F(ddof_backend_info, renderer); F(ddof_backend_info, note);
    END();
    E(DDOF_OK); E(DDOF_ERROR_NULL_POINTER); E(DDOF_ERROR_BAD_PARAMETER); E(DDOF_ERROR_BAD_SIZE);
    E(DDOF_ERROR_BAD_STRIDE); E(DDOF_ERROR_BAD_CHANNELS); E(DDOF_ERROR_SIZE_MISMATCH);
    E(DDOF_ERROR_BAD_COLOR); E(DDOF_ERROR_BAD_DEPTH); E(DDOF_ERROR_BAD_COC);
    E(DDOF_ERROR_BAD_CAMERA); E(DDOF_ERROR_OUT_OF_MEMORY); E(DDOF_ERROR_THREADS);
    E(DDOF_ERROR_CANCELLED); E(DDOF_ERROR_BACKEND_UNAVAILABLE); E(DDOF_ERROR_UNSUPPORTED);
    E(DDOF_ERROR_BACKEND_FAILED); E(DDOF_ERROR_CONTEXT_BUSY); E(DDOF_STATUS_COUNT_);
    E(DDOF_BACKEND_CPU); E(DDOF_BACKEND_AUTO); E(DDOF_BACKEND_EGL); E(DDOF_BACKEND_OSMESA);
    E(DDOF_BACKEND_HOST_GL); E(DDOF_BACKEND_COUNT_);
    E(DDOF_LENS_CYCLES); E(DDOF_LENS_THIN_LENS);
    E(DDOF_DEPTH_PLANAR); E(DDOF_DEPTH_RADIAL);
    E(DDOF_SENSOR_FIT_AUTO); E(DDOF_SENSOR_FIT_HORIZONTAL); E(DDOF_SENSOR_FIT_VERTICAL);
    E(DDOF_SOLVER_THOMAS); E(DDOF_SOLVER_CYCLIC_REDUCTION); E(DDOF_SOLVER_PCR);
    E(DDOF_SOLVER_JACOBI); E(DDOF_SOLVER_REFERENCE_F64); E(DDOF_SOLVER_GRUEN);
    E(DDOF_SOLVER_COUNT_);
    E(DDOF_METHOD_DIFFUSION); E(DDOF_METHOD_COD4_PREVIEW);
    E(DDOF_PRECISION_FLOAT); E(DDOF_PRECISION_PACKED_HALF);
    E(DDOF_KERNEL_HEAT); E(DDOF_KERNEL_DISC_2X2); E(DDOF_KERNEL_DISC_2X3); E(DDOF_KERNEL_DISC_3X3);
    E(DDOF_PRESET_PREVIEW); E(DDOF_PRESET_DEFAULT); E(DDOF_PRESET_FINAL); E(DDOF_PRESET_COUNT_);
    E(DDOF_LAYER_AUTO); E(DDOF_LAYER_OFF); E(DDOF_LAYER_ON);
    E(DDOF_EFFECT_MIDGROUND); E(DDOF_EFFECT_BACKGROUND); E(DDOF_EFFECT_FOREGROUND);
    E(DDOF_EFFECT_NEAR_SPREAD);
    E(DDOF_EFFECT_HIGHLIGHTS); E(DDOF_EFFECT_NEAR_LAYER); E(DDOF_EFFECT_FAR_FIELD);
    E(DDOF_EFFECT_SILHOUETTES);
    E(DDOF_CARDS_EXPAND_OFFSET); E(DDOF_CARDS_EXPAND_CENTROID); E(DDOF_CARD_MAX_VERTICES);
    E(DDOF_MATTE_MAX_RANKS);
    printf("version %u\n", (unsigned)DDOF_VERSION_NUMBER);
    return 0;
}
