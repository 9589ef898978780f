# SPDX-License-Identifier: MIT
"""The study scenes' camera: looking along +Y from `height` metres, pitched down `pitch` degrees
(the scenes' camera settings: focal_mm, fstop, focus_m, height, pitch); the Blender camera, its
sidecar (camera.json) and the CoC it gives."""

import math

import bpy

SENSOR_MM = 36.0


def at(cam, u, v, dist):
    """The world point at normalised image position (u, v) (-1..1 across the frame's width
    and height, +v up) and planar distance dist, for a level camera (pitch 0) with the
    default 16:9 frame."""
    half_w = dist * SENSOR_MM / 2.0 / cam["focal_mm"]
    half_h = half_w * 9.0 / 16.0
    return (u * half_w, dist, cam["height"] + v * half_h)


def add_camera(scene, cam, lens_dof, aperture=(0, 0.0, 1.0), sensor_mm=SENSOR_MM):
    """The scene's camera; sensor_mm wider than SENSOR_MM for an overscanned render (the frame
    grown by a margin at the same pixel pitch: overscan_sensor_mm)."""
    data = bpy.data.cameras.new("Camera")
    data.lens = cam["focal_mm"]
    data.sensor_width = sensor_mm
    data.sensor_fit = "AUTO"
    data.clip_start = 0.05
    data.clip_end = 1000.0
    data.dof.use_dof = lens_dof
    data.dof.focus_distance = cam["focus_m"]
    data.dof.aperture_fstop = cam["fstop"]
    data.dof.aperture_blades = aperture[0]  # 0: circular
    data.dof.aperture_rotation = math.radians(aperture[1])
    data.dof.aperture_ratio = aperture[2]
    obj = bpy.data.objects.new("Camera", data)
    scene.collection.objects.link(obj)
    obj.location = (0.0, 0.0, cam["height"])
    obj.rotation_euler = (math.radians(90.0 - cam["pitch"]), 0.0, 0.0)
    scene.camera = obj
    return obj


def overscan_sensor_mm(width, margin):
    """The sensor width that keeps the pixel pitch of a width-pixel frame (landscape, AUTO fit:
    the sensor spans the width) when margin pixels are rendered on each side."""
    return SENSOR_MM * (width + 2 * margin) / width


def camera_sidecar(cam, width, height, aperture=(0, 0.0, 1.0), sensor_mm=SENSOR_MM):
    sidecar = {
        "focal_length_mm": cam["focal_mm"],
        "sensor_width_mm": sensor_mm,
        "sensor_fit": "AUTO",
        "fstop": cam["fstop"],
        "focus_distance_m": cam["focus_m"],
        "resolution": [width, height],
        "pixel_aspect": 1.0,
        "depth": "planar",
        "unit_scale_m": 1.0,
    }
    if tuple(aperture) != (0, 0.0, 1.0):
        sidecar.update({"aperture_blades": aperture[0], "aperture_rotation_deg": aperture[1],
                        "aperture_ratio": aperture[2]})
    return sidecar


def coc_px(cam, z, width):
    """Blender's Cycles CoC (docs/design.md section 1) in pixels, AUTO fit on a landscape frame."""
    f = cam["focal_mm"] / 1000.0
    s1 = cam["focus_m"]
    return f * f / (cam["fstop"] * s1) * abs(z - s1) / z * width / (SENSOR_MM / 1000.0)
