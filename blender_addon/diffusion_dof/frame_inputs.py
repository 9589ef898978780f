# SPDX-License-Identifier: GPL-3.0-or-later
"""Everything a queued frame's library call needs, read on the main thread into plain data:
the passes the File Output node wrote, the camera, the render border's region, the overscan
plan and the library options. The call itself (library_call.py) then runs on a worker thread
without touching Blender data."""

from . import binding, frame_region, images, library_call, object_matte, passes
from . import camera as camera_mod
from .errors import SetupError
from .overscan_render import crop_frame, overscan_camera


def scene_region(scene, width, height, strict=True):
    """The frame_region.Region of a width x height render of the scene (None without a render
    border). strict: an image that is neither the frame's nor the border's size raises
    SetupError; else it is taken as a frame of its own (None)."""
    r = scene.render
    try:
        return frame_region.region_of(
            r.use_border, r.use_crop_to_border,
            (r.border_min_x, r.border_min_y, r.border_max_x, r.border_max_y),
            frame_region.full_size(r.resolution_x, r.resolution_y, r.resolution_percentage),
            (width, height))
    except ValueError as err:
        if strict:
            raise SetupError("Cannot place the render in its frame: %s." % err) from None
        return None


class FrameInputs:
    """A frame's passes and settings as plain data. color, depth: (buffer, channels);
    foreground: None or the dict binding.Session.depth_of_field takes; region: the render
    border's frame_region.Region or None; fallback: with overscan, the frame as rendered and
    cropped, (buffer, width, height, channels), to write if the call fails; matte: None or the
    object matte (buffer, channels), object_matte.pack of the CryptoObject sub-layers."""

    def __init__(self, width, height, color, depth, camera, camera_info, foreground):
        self.width, self.height = width, height
        self.color, self.depth = color, depth
        self.camera, self.camera_info = camera, camera_info
        self.foreground = foreground
        self.matte = None
        self.region = None
        self.fallback = None
        self.options = None

    def call_args(self):
        """The arguments of library_call.run_region for this frame."""
        return (self.width, self.height, self.color[0], self.color[1], self.depth[0],
                self.depth[1], self.camera, self.foreground, self.region, self.options,
                self.matte)


def _check_setup(job):
    if job.error:
        raise SetupError(job.error)
    lib_ok, lib_text = binding.library_status()
    if not lib_ok:
        raise SetupError(lib_text)
    if job.lens_dof_on:
        raise SetupError("The camera's lens depth of field was on, so the render is "
                         "already blurred: Diffusion DOF was not applied. Turn off "
                         "Camera properties > Depth of Field (its focus and f-stop still "
                         "drive Diffusion DOF) and render again.")


def _read_passes(job, scene, settings):
    """(color, depth) as read_exr gives them, the Combined and Depth passes of the same size."""
    color = images.read_exr(job.files[passes.SLOT_COLOR])
    if color is None and scene.camera is None:
        # Blender refused to render: say why, not that the compositor did not run.
        camera_mod.camera_settings(scene, settings)  # raises: no active camera
    if color is None:
        raise SetupError("The Combined pass of frame %d did not reach the add-on: %s."
                         % (job.frame, passes.missing_pass_reason(
                             scene, settings, job.files[passes.SLOT_COLOR])))
    depth = images.read_exr(job.files[passes.SLOT_DEPTH])
    layer = passes.render_view_layer(scene, settings)
    if depth is None or not layer.use_pass_z:
        raise SetupError("No Depth pass was rendered for view layer '%s'. Enable View "
                         "Layer properties > Passes > Data > Z (or click Set Up Passes "
                         "in the Diffusion DOF panel) and render again." % layer.name)
    if depth[1:3] != color[1:3]:
        raise SetupError("The Depth pass is %dx%d but the Combined pass %dx%d."
                         % (depth[1], depth[2], color[1], color[2]))
    return color, depth


def _read_foreground(job, width, height):
    fg_color = images.read_exr(job.files[passes.SLOT_FG_COLOR])
    fg_depth = images.read_exr(job.files[passes.SLOT_FG_DEPTH])
    if fg_color is None or fg_depth is None or fg_color[1:3] != (width, height) \
            or fg_depth[1:3] != (width, height) or fg_color[3] != 4:
        raise SetupError("The foreground element of frame %d is missing or has "
                         "another size: click Set Up Passes and render again."
                         % job.frame)
    return {"color": fg_color[0], "depth": fg_depth[0], "depth_channels": fg_depth[3]}


def _read_matte(job, width, height):
    """The object matte of the frame (object_matte.pack), or None without one. The sub-layers
    are read bit for bit (images.read_exr exact) in the same row order as the colour."""
    if not job.matte:
        return None
    layers = []
    for slot in job.matte:
        data = images.read_exr(job.files[slot], exact=True)
        if data is None or data[1:] != (width, height, 4):
            raise SetupError("The object matte (%s) of frame %d is missing or has another "
                             "size: click Set Up Passes and render again, or set Object Matte "
                             "to Off." % (slot.rstrip("_"), job.frame))
        layers.append(data[0])
    return object_matte.pack(layers, width * height)


def read(job, scene, settings):
    """The FrameInputs of a queued frame (main thread). Raises SetupError."""
    _check_setup(job)
    color, depth = _read_passes(job, scene, settings)
    buf, width, height, channels = color
    if isinstance(job.camera, SetupError):
        raise job.camera
    cam, info = job.camera or camera_mod.camera_settings(scene, settings)
    foreground = _read_foreground(job, width, height) if job.foreground else None
    frame = FrameInputs(width, height, (buf, channels), (depth[0], depth[3]), cam, info,
                        foreground)
    frame.matte = _read_matte(job, width, height)
    plan = job.overscan
    if plan is not None:
        frame.camera = overscan_camera(plan, settings, cam, width, height)
        frame.fallback = (crop_frame(plan, buf, channels), plan.width, plan.height, channels)
    else:
        frame.region = scene_region(scene, width, height)
    frame.options = library_call.library_options(settings)
    return frame
