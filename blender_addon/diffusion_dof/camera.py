# SPDX-License-Identifier: GPL-3.0-or-later
"""The camera of a frame as ddof_camera fields, read from Blender's camera (evaluated for the
frame being rendered when a depsgraph is given) with the panel's overrides on top."""

import math

from .errors import SetupError


def _dof_focus_units(cam_obj, data, depsgraph):
    """The focus distance in scene units and a description of where it came from, as Cycles
    computes it: with a focus object, the distance of its origin (or bone) from the camera along
    the camera's view axis."""
    dof = data.dof
    target = dof.focus_object
    if target is None:
        return dof.focus_distance, "camera focus distance"
    if depsgraph is not None:
        target = target.evaluated_get(depsgraph)
    point = target.matrix_world.translation
    subtarget = getattr(dof, "focus_subtarget", "")  # a bone of an armature
    if subtarget and target.pose is not None and subtarget in target.pose.bones:
        point = (target.matrix_world @ target.pose.bones[subtarget].matrix).translation
    cam_matrix = cam_obj.matrix_world
    view_axis = cam_matrix.col[2].xyz.normalized()
    distance = abs(view_axis.dot(cam_matrix.translation - point))
    return distance, "focus object '%s'" % dof.focus_object.name


def camera_object(scene, depsgraph=None):
    """The camera that renders the scene (the evaluated one with a depsgraph)."""
    if depsgraph is not None:
        cam = depsgraph.scene_eval.camera
        return cam.evaluated_get(depsgraph) if cam is not None else None
    return scene.camera


def check_lens(name, focal_mm, fstop, focus_m, settings):
    """Raises SetupError with what to change when the lens cannot give depth of field: an
    f-stop of 0 (Blender accepts it), a focus distance within the focal length (a focus
    distance of 0, a focus object at the camera), where a lens would focus behind itself."""
    where = "the Diffusion DOF panel's F-Stop" if settings.override_fstop else \
        "Camera properties > Depth of Field > Aperture > F-Stop"
    if not fstop > 0.0:
        raise SetupError("Camera '%s' has f/%g: depth of field needs an f-stop above 0 (%s)."
                         % (name, fstop, where))
    if not focus_m * 1000.0 > focal_mm:
        where = "the Diffusion DOF panel's Focus Distance" if settings.override_focus else \
            "Camera properties > Depth of Field > Focus Distance or Focus Object"
        raise SetupError("Camera '%s' focuses at %.3g m, within its focal length (%g mm): "
                         "a lens cannot focus there (the focus would be behind the lens). Set "
                         "a focus farther than the focal length (%s)."
                         % (name, focus_m, focal_mm, where))


def camera_settings(scene, settings, depsgraph=None, cam_obj=None):
    """(camera dict for Library.depth_of_field, description dict). Raises SetupError with a
    sentence that says what to do when the scene cannot drive depth of field."""
    if cam_obj is None:
        cam_obj = camera_object(scene, depsgraph)
    if cam_obj is None:
        raise SetupError("Scene '%s' has no active camera. Set one in Properties > Scene > "
                         "Camera (or select a camera and press Ctrl Numpad 0)." % scene.name)
    if cam_obj.type != "CAMERA":
        raise SetupError("The scene camera '%s' is not a camera object." % cam_obj.name)
    data = cam_obj.data
    if data.type != "PERSP":
        kind = {"ORTHO": "orthographic", "PANO": "panoramic"}.get(data.type, data.type.lower())
        raise SetupError("Camera '%s' is %s: depth of field needs a perspective camera "
                         "(Camera properties > Lens > Type)." % (cam_obj.name, kind))
    render = scene.render
    unit = scene.unit_settings.scale_length or 1.0

    if settings.override_focus:
        focus_units, focus_source = settings.focus_distance, "panel override"
    else:
        focus_units, focus_source = _dof_focus_units(cam_obj, data, depsgraph)
    focal = settings.focal_length if settings.override_focal_length else data.lens
    fstop = settings.fstop if settings.override_fstop else data.dof.aperture_fstop
    if settings.override_sensor:
        fit, sensor = settings.sensor_fit, settings.sensor_width
    else:
        fit = data.sensor_fit
        # Blender's vertical fit spans the image height with the sensor *height*.
        sensor = data.sensor_height if fit == "VERTICAL" else data.sensor_width

    check_lens(cam_obj.name, focal, fstop, float(focus_units) * unit, settings)

    camera = {
        "lens_model": settings.lens_model,
        "sensor_fit": fit,
        "focal_length_mm": float(focal),
        "sensor_width_mm": float(sensor),
        "fstop": float(fstop),
        "focus_distance_m": float(focus_units) * unit,
        "pixel_aspect": float(render.pixel_aspect_x) / float(render.pixel_aspect_y),
        "depth_unit_m": float(unit),
        # Cycles' aperture: polygonal highlights and anamorphic (stretched) blur.
        "aperture_blades": int(data.dof.aperture_blades),
        "aperture_rotation_deg": math.degrees(float(data.dof.aperture_rotation)),
        "aperture_ratio": float(data.dof.aperture_ratio),
    }
    info = {"camera": cam_obj.name, "focus_source": focus_source, "focus_units": focus_units,
            "lens_dof_on": bool(data.dof.use_dof)}
    return camera, info


def for_blender_rows(camera):
    """The camera for images handed to the library in Blender's row order (bottom row first):
    the library takes row 0 as the top, so it sees the frame upside down, and an upside-down
    polygon is turned the other way: the aperture's rotation is negated, so that the blades
    turn as Cycles turns them. Images flipped to the library's order first (the cards) take
    the camera as it is."""
    return dict(camera, aperture_rotation_deg=-camera.get("aperture_rotation_deg", 0.0))


def aperture_words(camera):
    """The aperture when it is not round and plain: "6 blades at 15 deg, ratio 2", or ""."""
    words = []
    if camera.get("aperture_blades", 0) >= 3:
        words.append("%d blades at %.3g deg" % (camera["aperture_blades"],
                                               camera.get("aperture_rotation_deg", 0.0)))
    if camera.get("aperture_ratio", 1.0) != 1.0:
        words.append("ratio %.3g" % camera["aperture_ratio"])
    return ", ".join(words)


def describe(camera, info):
    """One line for the panel and the log."""
    aperture = aperture_words(camera)
    return "%s: %.0f mm f/%.3g%s, focus %.3g m (%s)" % (
        info["camera"], camera["focal_length_mm"], camera["fstop"],
        " (%s)" % aperture if aperture else "", camera["focus_distance_m"], info["focus_source"])
