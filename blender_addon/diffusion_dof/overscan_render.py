# SPDX-License-Identifier: GPL-3.0-or-later
"""Overscan in the scene (overscan.py computes the margin): the render and its camera grow by a
margin for the render's duration (main thread), and the frame is cut out of the grown passes
afterwards."""

import bpy

from . import camera as camera_mod
from . import compat, frame_region, overscan, report
from .errors import SetupError
from .frame_file import MOVIE_FORMATS


# On the scene while its render is grown: what to put back. Stored in the scene, not only in
# memory, so that a file saved mid-render (or an add-on reloaded) is put back on load.
OVERSCAN_KEY = "diffusion_dof_overscan_restore"
_SAVED_RENDER = ("resolution_x", "resolution_y", "resolution_percentage")
_SAVED_CAMERA = ("sensor_fit", "sensor_width", "sensor_height", "shift_x", "shift_y")


def overscan_plan(scene, settings):
    """(overscan.Plan or None, why there is none or ''): the margin this scene's render gets.
    Raises SetupError when the camera cannot drive depth of field."""
    if settings.overscan == "OFF":
        return None, "off"
    r = scene.render
    if r.use_border:
        return None, "not with a render border"
    # The files Blender writes are grown: only the add-on's replacement has the frame's size.
    if not settings.write_frames:
        return None, "Replace Written Frames is off, so Blender's files would keep the margin"
    if r.image_settings.file_format in MOVIE_FORMATS:
        return None, "not with a movie output, whose frames cannot be replaced"
    cam, _info = camera_mod.camera_settings(scene, settings)
    data = scene.camera.data
    width, height = frame_region.full_size(r.resolution_x, r.resolution_y,
                                           r.resolution_percentage)
    fit = data.sensor_fit
    thin = settings.lens_model == "THIN_LENS"
    focal, fstop, focus_m = max(_lenses_of_range(scene, settings, cam),
                                key=lambda lens: overscan.coc_infinity_mm(*lens, thin_lens=thin))
    plan = overscan.plan(
        width, height, fit, data.sensor_height if fit == "VERTICAL" else data.sensor_width,
        focal, fstop, focus_m, r.pixel_aspect_x, r.pixel_aspect_y,
        settings.overscan_margin if settings.overscan == "MANUAL" else None, thin)
    return plan, "" if plan is not None else "no margin needed"


MAX_SAMPLED_FRAMES = 1000


def _lenses_of_range(scene, settings, cam):
    """[(focal mm, f-stop, focus m)] of the camera over the scene's frame range, from the camera
    data's F-curves (a focus pull), so that one margin serves every frame of an animation; the
    panel's overrides win. A focus object is read at the current frame only (its motion would
    need the whole scene evaluated at every frame)."""
    lens = (cam["focal_length_mm"], cam["fstop"], cam["focus_distance_m"])
    curves = compat.fcurves(scene.camera.data)
    paths = {"lens": not settings.override_focal_length,
             "dof.aperture_fstop": not settings.override_fstop,
             "dof.focus_distance": not settings.override_focus
             and scene.camera.data.dof.focus_object is None}
    curves = {k: v for k, v in curves.items() if paths.get(k)}
    if not curves:
        return [lens]
    unit = scene.unit_settings.scale_length or 1.0
    step = max(1, scene.frame_step,
               (scene.frame_end - scene.frame_start + 1) // MAX_SAMPLED_FRAMES)
    lenses = [lens]
    for frame in range(scene.frame_start, scene.frame_end + 1, step):
        value = {k: fc.evaluate(frame) for k, fc in curves.items()}
        lenses.append((value.get("lens", lens[0]), value.get("dof.aperture_fstop", lens[1]),
                       value["dof.focus_distance"] * unit if "dof.focus_distance" in value
                       else lens[2]))
    return lenses


def apply_overscan(scene, plan):
    """Grows the render and its camera by the plan's margin (main thread); restore_overscan
    puts them back."""
    r, data = scene.render, scene.camera.data
    saved = {"camera": data.name}
    saved.update({"render." + k: getattr(r, k) for k in _SAVED_RENDER})
    saved.update({"camera." + k: getattr(data, k) for k in _SAVED_CAMERA})
    scene[OVERSCAN_KEY] = saved
    plan.source_fit = data.sensor_fit
    plan.source_sensor = data.sensor_height if data.sensor_fit == "VERTICAL" else \
        data.sensor_width
    try:
        r.resolution_percentage = 100
        r.resolution_x, r.resolution_y = plan.full_width, plan.full_height
        data.sensor_fit = plan.fit  # explicit: Auto could pick the other axis once grown
        if plan.fit == "HORIZONTAL":
            data.sensor_width = plan.sensor_mm
        else:
            data.sensor_height = plan.sensor_mm
        data.shift_x, data.shift_y = plan.shift(data.shift_x), plan.shift(data.shift_y)
    except (AttributeError, TypeError, ValueError) as err:  # e.g. a linked, read-only camera
        restore_overscan(scene)
        raise SetupError("cannot grow the render for overscan (%s): rendered without it; set "
                         "Diffusion DOF > Overscan to Off" % err) from None


def restore_overscan(scene):
    """Puts back what apply_overscan changed (main thread). Returns whether it did."""
    saved = scene.get(OVERSCAN_KEY)
    if saved is None:
        return False
    saved = saved.to_dict()
    del scene[OVERSCAN_KEY]
    data = bpy.data.cameras.get(saved.pop("camera"))
    for key, value in saved.items():
        kind, name = key.split(".", 1)
        target = scene.render if kind == "render" else data
        if target is not None and getattr(target, name) != value:
            setattr(target, name, value)
    return True


def start_overscan(scene, settings):
    """Grows the render when the scene asks for overscan (main thread only: with the UI the
    render has read the scene before its handlers run). Returns the overscan.Plan or None."""
    try:
        plan, why = overscan_plan(scene, settings)
        if plan is not None:
            apply_overscan(scene, plan)
            report.log("overscan: " + plan.describe())
        elif settings.overscan != "OFF":
            report.log("overscan: none (%s)" % why)
        return plan
    except SetupError as err:
        report.log("overscan: none: %s" % err)
        return None


def crop_frame(plan, buf, channels):
    """The frame's pixels of a grown render's buffer."""
    return frame_region.crop(buf, plan.full_width, channels, plan.margin_x, plan.margin_y,
                             plan.width, plan.height)



def crop_all(plan, out, color_cropped, depth, foreground):
    """The frame's part of a grown render's result, input (already cropped), depth and
    foreground element: (out, color, depth, foreground)."""
    if foreground is not None:
        foreground = {"color": crop_frame(plan, foreground["color"], 4),
                      "depth": crop_frame(plan, foreground["depth"],
                                          foreground["depth_channels"]),
                      "depth_channels": foreground["depth_channels"]}
    return (crop_frame(plan, *out), color_cropped, crop_frame(plan, *depth), foreground)


def overscan_camera(plan, settings, cam, width, height):
    """The camera of a grown render for the library: the frame's own sensor (the snapshot read
    the grown one) and the frame as the window's frame, so every pixel gets the CoC it has in
    the frame and the margin the CoC it would have outside it."""
    if (width, height) != (plan.full_width, plan.full_height):
        raise SetupError("the render is %dx%d, not the %dx%d overscan asked for (was the "
                         "resolution changed during the render?)"
                         % (width, height, plan.full_width, plan.full_height))
    cam = dict(cam, **plan.camera_fields())
    if not settings.override_sensor:
        cam["sensor_fit"], cam["sensor_width_mm"] = plan.source_fit, plan.source_sensor
    return cam
