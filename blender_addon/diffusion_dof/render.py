# SPDX-License-Identifier: GPL-3.0-or-later
"""Render handlers: every rendered frame of a scene with Diffusion DOF on goes through libddof.

Order of events in Blender 3.4 to 5.x, per frame (checked in background mode on 3.4.1, 4.2.23
and 5.0.1):
  render_init                     once per render, before the render is set up
  frame_change_pre/post           with the *render* depsgraph (mode 'RENDER'), evaluated for
                                  the frame: the only place where animated camera values are
                                  right during an animation render (the original datablocks
                                  are not updated by a render)
  (render, compositing)           the managed File Output node writes color_/depth_######.exr
  (the frame file is written)     animations, and stills with write_still
  render_post                     after compositing and after the frame file was written
  render_write                    only when a frame file was written
  render_complete / render_cancel once per render
In background mode all of these run on the main thread and a frame is processed right away.
With the UI, render handlers run on the render job's thread, where loading images or changing
data is not safe: the handlers only queue the frame and a timer on the main thread does the
work (while the next frame renders).
"""

import array
import os
import threading
import time
import traceback

import bpy
from bpy.app.handlers import persistent

from . import camera as camera_mod
from . import binding, compat, composite, frame_region, overscan, passes
from . import settings as settings_mod
from .errors import SetupError

RESULT_IMAGE = "Diffusion DOF"
INPUT_IMAGE = "Diffusion DOF Input"
DEPTH_IMAGE = "Diffusion DOF Depth"
FG_INPUT_IMAGE = "Diffusion DOF Foreground"
FG_DEPTH_IMAGE = "Diffusion DOF Foreground Depth"
FOCUS_MAP_IMAGE = "Diffusion DOF Focus Map"
MOVIE_FORMATS = {"FFMPEG", "AVI_JPEG", "AVI_RAW"}

_lock = threading.Lock()
_jobs = []          # Job, in the order frames were rendered
_snapshots = {}     # (scene name, frame) -> (camera dict, info) or SetupError
_render_state = {}  # scene name -> dict for the render in progress
reports = {}        # scene name -> the last result, for the panel
_session = None     # binding.Session: one ddof context for the frames of a render


class Job:
    def __init__(self, scene, frame, foreground, extra=(), plan=None):
        self.scene_name = scene.name
        self.frame = frame
        self.extra = list(extra)  # the passes the user's compositing reads (their slots)
        self.files = passes.frame_files(scene, frame, foreground, self.extra)
        self.foreground = foreground
        self.overscan = plan      # overscan.Plan of the render, or None
        self.camera = None
        self.error = None
        self.lens_dof_on = False
        self.write = False
        self.ready = False
        self.started = time.time()


def _is_main_thread():
    return threading.current_thread() is threading.main_thread()


def log(message):
    print("Diffusion DOF:", message, flush=True)


def _enabled(scene):
    s = settings_mod.get(scene)
    # The copy that runs the user's compositing (composite.py) carries the settings too.
    return s if s is not None and s.enabled and not composite.is_copy(scene) else None


def set_report(scene_name, ok, message, frame=None, stats=None, camera_line=None, path=None):
    reports[scene_name] = {"ok": ok, "message": message, "frame": frame, "stats": stats,
                           "camera": camera_line, "path": path, "time": time.time()}
    log(message)
    if not bpy.app.background:
        try:
            for window in bpy.context.window_manager.windows:
                for area in window.screen.areas:
                    if area.type in ("PROPERTIES", "NODE_EDITOR"):
                        area.tag_redraw()
        except AttributeError:
            pass


# ---------------------------------------------------------------------------------------------
# Moving pixels between Blender and the library


def read_image(image):
    """(buffer, width, height, channels) of an image datablock's float pixels."""
    width, height = image.size
    channels = image.channels
    if width == 0 or height == 0:
        raise SetupError("Image '%s' has no pixels (is its file missing?)." % image.name)
    buf = binding.new_buffer(width * height * channels)
    image.pixels.foreach_get(buf)
    return buf, width, height, channels


# Images the add-on is done with: their pixels are freed at once, the datablocks once no render
# runs. Blender 5.2+ re-evaluates an animation's render depsgraph between frames and crashes
# (deg_check_base_in_depsgraph, from RE_RenderAnim) when an image was removed meanwhile, so
# nothing is removed from bpy.data while a render runs; free_spent_images does it afterwards.
SPENT_IMAGE = ".Diffusion DOF spent"  # the leading dot hides them from image lists
SPENT_KEY = "diffusion_dof_spent"
_spent = []  # names of spent images (main thread only)


def retire_image(image):
    """Frees an image's pixels now and removes the datablock after the render (main thread)."""
    image.name = SPENT_IMAGE
    image[SPENT_KEY] = True
    image.buffers_free()
    _spent.append(image.name)


def free_spent_images():
    """Removes the retired images; only when no render runs (main thread)."""
    while _spent:
        image = bpy.data.images.get(_spent.pop())
        if image is not None and image.get(SPENT_KEY):
            bpy.data.images.remove(image)


def read_exr(path):
    """Loads a file the File Output node wrote, raw (no colour transform); None if missing."""
    if not os.path.isfile(path):
        return None
    image = bpy.data.images.load(path, check_existing=False)
    try:
        image.colorspace_settings.is_data = True
        return read_image(image)
    finally:
        retire_image(image)


def store_result(name, width, height, channels, pixels, data=False):
    """Puts pixels into a float image datablock (created or resized as needed); data=True marks
    them as non-colour values (depth)."""
    image = bpy.data.images.get(name)
    if image is not None and (not image.is_float or image.channels != channels):
        image.name = name + ".old"
        image = None
    if image is None:
        image = bpy.data.images.new(name, width, height, alpha=channels == 4, float_buffer=True)
    elif tuple(image.size) != (width, height):
        image.scale(width, height)
    if data and not image.colorspace_settings.is_data:
        image.colorspace_settings.is_data = True
    image.pixels.foreach_set(pixels)
    image.update()
    return image


def written_path(scene, frame, since):
    """The file this render just wrote for the frame. Animations (and `blender -f`) write
    frame_path(frame); a still with write_still writes the output path without a frame number.
    The candidate written since the render started is the one."""
    candidates = [scene.render.frame_path(frame=frame)]
    still = bpy.path.abspath(scene.render.filepath)
    candidates.append(still)
    if scene.render.use_file_extension:
        ext = scene.render.file_extension
        candidates += [still + ext, os.path.splitext(still)[0] + ext]
    found = [(os.path.getmtime(p), p) for p in candidates
             if os.path.isfile(p) and os.path.getmtime(p) >= since - 1.0]
    if not found:
        raise SetupError("Could not find the file this render wrote for frame %d (looked for "
                         "%s)." % (frame, ", ".join(sorted(set(candidates)))))
    return max(found)[1]


def write_frame(scene, image, frame, since):
    """Writes the result over the frame's output file, in the scene's format, atomically.
    Multilayer OpenEXR output is kept (it has the passes the user asked for) and the result is
    written beside it as <name>_dof.exr, a single-layer OpenEXR of the same depth and codec.
    Returns the path written."""
    settings = scene.render.image_settings
    fmt = settings.file_format
    if fmt in MOVIE_FORMATS:
        raise SetupError("the output is a movie (%s), which cannot be replaced frame by frame: "
                         "render to an image sequence (PNG, OpenEXR, ...) and encode it "
                         "afterwards" % fmt)
    path = written_path(scene, frame, since)
    if fmt == "OPEN_EXR_MULTILAYER":
        stem, ext = os.path.splitext(path)
        path = stem + "_dof" + (ext or ".exr")
    partial = path + ".ddof-partial"
    try:
        if fmt == "OPEN_EXR_MULTILAYER":
            compat.set_file_format(settings, "OPEN_EXR")
        image.save_render(partial, scene=scene)
        os.replace(partial, path)
    except RuntimeError as err:
        raise SetupError("Could not write %s: %s" % (path, str(err).strip())) from None
    finally:
        compat.set_file_format(settings, fmt)
        if os.path.exists(partial):
            os.remove(partial)
    return path


# ---------------------------------------------------------------------------------------------
# Overscan (overscan.py): the render grows by a margin for the render's duration

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


def _start_overscan(scene, settings, state):
    """Grows the render when the scene asks for overscan (main thread only: with the UI the
    render has read the scene before its handlers run)."""
    try:
        plan, why = overscan_plan(scene, settings)
        if plan is not None:
            apply_overscan(scene, plan)
            log("overscan: " + plan.describe())
        elif settings.overscan != "OFF":
            log("overscan: none (%s)" % why)
        state["overscan"] = plan
    except SetupError as err:
        log("overscan: none: %s" % err)


def crop_frame(plan, buf, channels):
    """The frame's pixels of a grown render's buffer."""
    return frame_region.crop(buf, plan.full_width, channels, plan.margin_x, plan.margin_y,
                             plan.width, plan.height)


# ---------------------------------------------------------------------------------------------
# One frame


# Set to stop the library call that runs (Esc, a cancelled render): its progress callback
# answers "stop" and the frame is left as rendered. Cleared when a render starts.
cancel_event = threading.Event()
# Run the library call on a worker thread while the main thread keeps handling events (Esc):
# with the UI; tests set it to run that path in background mode.
FORCE_WORKER = False


def request_cancel():
    cancel_event.set()


def library_options(settings):
    """The settings' preset (the library's values), overrides and backend, read on the main
    thread (a worker thread must not read Blender data)."""
    return {"params": settings.library_params(), "threads": settings.threads,
            "preset": settings.preset_name(), "backend": settings.library_backend()}


def session_for(threads, backend):
    """The ddof context of the render (threads, working memory, a GL backend's plugin and
    context): kept across its frames, made anew when the threads or backend change, freed by
    close_session once no frame is left to process. Used by one thread at a time (the main
    thread, or the worker of the frame that runs)."""
    global _session
    lib = binding.get_library()
    key = (max(0, int(threads)), backend, None)
    if _session is not None and (_session.key != key or _session.library is not lib):
        close_session()
    if _session is None:
        _session = lib.session(threads, backend)
        log("a ddof context for this render (%s backend, %s threads), kept for its frames"
            % (backend, threads or "all"))
    return _session


def close_session():
    global _session
    if _session is not None:
        _session.close()
        _session = None


def run(scene, settings, width, height, color, color_channels, depth, depth_channels,
        camera, foreground=None, options=None):
    """One frame in the render's session with the settings' library_options() (or `options`);
    returns (out, stats). Raises LibraryError, DdofError, binding.Cancelled (cancel_event
    set)."""
    o = options or library_options(settings)
    return session_for(o["threads"], o["backend"]).depth_of_field(
        width, height, color, color_channels, depth, depth_channels, camera, o["params"],
        foreground=foreground, preset=o["preset"], cancel=lambda _f: cancel_event.is_set())


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


def run_region(scene, settings, width, height, color, color_channels, depth, depth_channels,
               camera, foreground=None, region=None, options=None):
    """run() for a render that may be a render border's: the camera is the full frame's, and
    with a full-size image only the border's pixels go to the library; the rest of the frame is
    returned as rendered."""
    if region is None:
        return run(scene, settings, width, height, color, color_channels, depth, depth_channels,
                   camera, foreground, options)
    camera = dict(camera, **region.camera_fields())
    if region.cropped:
        return run(scene, settings, width, height, color, color_channels, depth, depth_channels,
                   camera, foreground, options)
    x, y, w, h = region.x, region.y, region.width, region.height

    def part(buf, channels):
        return frame_region.crop(buf, width, channels, x, y, w, h)
    fg = None
    if foreground is not None:
        fg_channels = foreground.get("depth_channels", depth_channels)
        fg = {"color": part(foreground["color"], 4),
              "depth": part(foreground["depth"], fg_channels), "depth_channels": fg_channels}
    out, stats = run(scene, settings, w, h, part(color, color_channels), color_channels,
                     part(depth, depth_channels), depth_channels, camera, fg, options)
    full = array.array("f", color)
    frame_region.paste(full, width, color_channels, x, y, w, h, out)
    return full, stats


def backend_line(stats):
    """'cpu (CPU, 2 threads)': where a frame ran."""
    return "%s (%s)" % (stats.get("backend_name", "?"), stats.get("renderer", ""))


def summary(stats):
    if stats.get("method_name") == "cod4":
        what = "CoD4 preview"
    elif stats["copied_only"]:
        what = "copied (nothing out of focus)"
    else:
        what = " + ".join(stats["effect_names"]) or "nothing"
    return "%.3f s on %s, largest CoC %.1f px, %s" % (
        stats["seconds_total"], backend_line(stats), stats["max_coc_px"], what)


class _Call(threading.Thread):
    """A function run on a worker thread; value() returns its result or raises its error."""

    def __init__(self, fn, args, kwargs):
        super().__init__(name="Diffusion DOF", daemon=True)
        self._fn, self._args, self._kwargs = fn, args, kwargs
        self._result = self._error = None

    def run(self):
        try:
            self._result = self._fn(*self._args, **self._kwargs)
        except BaseException as err:  # handed to the main thread
            self._error = err

    def value(self):
        if self._error is not None:
            raise self._error
        return self._result


def keep_inputs(width, height, color, depth, foreground):
    """Keeps a frame's passes ((buffer, channels) each) for Re-apply and the focus tools."""
    store_result(INPUT_IMAGE, width, height, color[1], color[0])
    store_result(DEPTH_IMAGE, width, height, depth[1], depth[0], data=True)
    if foreground is not None:
        store_result(FG_INPUT_IMAGE, width, height, 4, foreground["color"])
        store_result(FG_DEPTH_IMAGE, width, height, foreground["depth_channels"],
                     foreground["depth"], data=True)
    else:
        for name in (FG_INPUT_IMAGE, FG_DEPTH_IMAGE):
            if name in bpy.data.images:
                retire_image(bpy.data.images[name])


def _crop_all(plan, out, color_cropped, depth, foreground):
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


def composite_frame(scene, settings, job, out, width, height, channels):
    """The user's compositing run on the depth-of-field image `out` (composite.py), with the
    other passes it reads as rendered (cropped like the frame); returns its pixels."""
    images = {composite.DOF_KEY: store_result(composite.RAW_IMAGE, width, height, channels, out)}
    for slot in job.extra:
        data = read_exr(job.files[slot])
        if data is None:
            raise SetupError("a pass your compositing reads (%s) was not written: click Set Up "
                             "Passes and render again" % os.path.basename(job.files[slot]))
        buf, w, h, c = data
        if job.overscan is not None:
            buf, w, h = crop_frame(job.overscan, buf, c), job.overscan.width, \
                job.overscan.height
        images[slot] = store_result(composite.PASS_IMAGE % slot, w, h, c, buf)
    try:
        path = composite.run(scene, settings, job.frame, images, width, height)
    finally:
        for key, image in images.items():  # their pixels are in the composited frame now
            if key != composite.DOF_KEY:
                retire_image(image)
    try:
        result = read_exr(path)
    finally:
        if os.path.exists(path):
            os.remove(path)
    if result is None or result[1:] != (width, height, channels):
        raise SetupError("your compositing gave %s, not a %dx%d image"
                         % ("nothing" if result is None else "%dx%d with %d channels"
                            % result[1:], width, height))
    return result[0]


def _composited(job, settings, out, width, height, channels, worker):
    """composite_frame() as a step of job_steps(): with the UI it waits for a running render
    (Ctrl F12's next frame), since it is a render itself and two at once share the compositor.
    None when the scene is gone."""
    while worker and bpy.app.is_job_running("RENDER"):
        yield
    scene = bpy.data.scenes.get(job.scene_name)
    if scene is None:
        return None
    return composite_frame(scene, settings, job, out, width, height, channels)


def _write_fallback(scene, job, fallback):
    """A grown (overscan) frame that got no depth of field is still written at the frame's size:
    the frame as rendered, cropped (`fallback`, or the Combined pass read now when the frame
    failed before reading it). Returns what it did, as words for the report."""
    plan = job.overscan
    settings = settings_mod.get(scene)
    if plan is None or not job.write or settings is None or not settings.write_frames:
        return ""
    try:
        if fallback is None:
            color = read_exr(job.files[passes.SLOT_COLOR])
            if color is None or color[1:3] != (plan.full_width, plan.full_height):
                raise SetupError("no Combined pass of the grown size")
            fallback = (crop_frame(plan, color[0], color[3]), plan.width, plan.height, color[3])
        buf, width, height, channels = fallback
        image = store_result(RESULT_IMAGE, width, height, channels, buf)
        return " (written as rendered, cropped to the frame: %s)" % write_frame(
            scene, image, job.frame, job.started)
    except Exception as err:  # the report says what failed first; this is the aftermath
        return " (the overscan margin could not be cropped off the written file: %s)" % err


def process_job(job):
    """Processes one frame on this (the main) thread, start to end."""
    for _ in job_steps(job, worker=False):
        pass


def job_steps(job, worker):
    """Processes one frame: a generator that, with worker=True, runs the library call on a
    worker thread and yields while it runs (the main thread's timer resumes it)."""
    scene = bpy.data.scenes.get(job.scene_name)
    fallback = None  # with overscan: the frame as rendered, cropped, to write if this fails
    try:
        if scene is None:
            return
        settings = settings_mod.get(scene)
        if settings is None:
            return
        try:
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
            color = read_exr(job.files[passes.SLOT_COLOR])
            if color is None and scene.camera is None:
                # Blender refused to render: say why, not that the compositor did not run.
                camera_mod.camera_settings(scene, settings)  # raises: no active camera
            if color is None:
                raise SetupError("The Combined pass of frame %d did not reach the add-on: %s."
                                 % (job.frame, passes.missing_pass_reason(
                                     scene, settings, job.files[passes.SLOT_COLOR])))
            depth = read_exr(job.files[passes.SLOT_DEPTH])
            layer = passes.render_view_layer(scene, settings)
            if depth is None or not layer.use_pass_z:
                raise SetupError("No Depth pass was rendered for view layer '%s'. Enable View "
                                 "Layer properties > Passes > Data > Z (or click Set Up Passes "
                                 "in the Diffusion DOF panel) and render again." % layer.name)
            buf, width, height, channels = color
            depth_buf, dw, dh, dchannels = depth
            if (dw, dh) != (width, height):
                raise SetupError("The Depth pass is %dx%d but the Combined pass %dx%d."
                                 % (dw, dh, width, height))
            if isinstance(job.camera, SetupError):
                raise job.camera
            cam, info = job.camera or camera_mod.camera_settings(scene, settings)
            foreground = None
            if job.foreground:
                fg_color = read_exr(job.files[passes.SLOT_FG_COLOR])
                fg_depth = read_exr(job.files[passes.SLOT_FG_DEPTH])
                if fg_color is None or fg_depth is None or fg_color[1:3] != (width, height) \
                        or fg_depth[1:3] != (width, height) or fg_color[3] != 4:
                    raise SetupError("The foreground element of frame %d is missing or has "
                                     "another size: click Set Up Passes and render again."
                                     % job.frame)
                foreground = {"color": fg_color[0], "depth": fg_depth[0],
                              "depth_channels": fg_depth[3]}
            plan = job.overscan
            if plan is not None:
                cam = overscan_camera(plan, settings, cam, width, height)
                region = None
                fallback = (crop_frame(plan, buf, channels), plan.width, plan.height, channels)
            else:
                region = scene_region(scene, width, height)
            call = _Call(run_region, (scene, settings, width, height, buf, channels, depth_buf,
                                      dchannels, cam, foreground, region),
                         {"options": library_options(settings)})
            if worker:
                call.start()
                _start_escape_watch()
                while call.is_alive():
                    yield
                scene = bpy.data.scenes.get(job.scene_name)
                if scene is None:  # removed meanwhile
                    return
            else:
                call.run()
            out, stats = call.value()
            if plan is not None:  # the frame out of the grown render
                out, buf, depth_buf, foreground = _crop_all(
                    plan, (out, channels), fallback[0], (depth_buf, dchannels), foreground)
                width, height = plan.width, plan.height
            pixels = out
            if composite.has_compositing(scene, settings):
                pixels = yield from _composited(job, settings, out, width, height, channels,
                                                worker)
                if pixels is None:  # the scene was removed meanwhile
                    return
            image = store_result(RESULT_IMAGE, width, height, channels, pixels)
            if settings.keep_inputs:
                keep_inputs(width, height, (buf, channels), (depth_buf, dchannels), foreground)
            path = None
            if job.write and settings.write_frames:
                try:
                    path = write_frame(scene, image, job.frame, job.started)
                except SetupError as err:
                    raise SetupError("the result is in the '%s' image, but the frame file was "
                                     "not replaced: %s" % (image.name, err)) from None
            if not bpy.app.background and settings.show_result:
                _show_in_render_window(image)
            camera_line = camera_mod.describe(cam, info)
            set_report(scene.name, True, "frame %d: %s; %s%s" % (
                job.frame, summary(stats), camera_line, (" -> " + path) if path else ""),
                job.frame, stats, camera_line, path)
        except binding.Cancelled:
            set_report(scene.name, False, "frame %d: cancelled (Esc): left as rendered, without "
                       "depth of field%s" % (job.frame, _write_fallback(scene, job, fallback)),
                       job.frame)
        except (SetupError, binding.LibraryError, binding.DdofError) as err:
            set_report(scene.name, False, "frame %d not processed: %s%s" % (
                job.frame, err, _write_fallback(scene, job, fallback)), job.frame)
        except Exception as err:  # a bug: say so, keep Blender and the render going
            traceback.print_exc()
            set_report(scene.name, False, "frame %d not processed: internal error: %s"
                       % (job.frame, err), job.frame)
    finally:
        for path in job.files.values():
            try:
                os.remove(path)
            except OSError:
                pass


def show_image(image):
    """Shows an image in the first image editor of the screen (if there is one)."""
    for window in bpy.context.window_manager.windows:
        for area in window.screen.areas:
            if area.type == "IMAGE_EDITOR":
                area.spaces.active.image = image
                return


def _show_in_render_window(image):
    for window in bpy.context.window_manager.windows:
        for area in window.screen.areas:
            if area.type != "IMAGE_EDITOR":
                continue
            space = area.spaces.active
            if space.image is not None and space.image.type == "RENDER_RESULT":
                space.image = image


_active = None  # job_steps() of the frame whose library call runs on a worker thread
escape_watch = {"on": False}  # the Esc watcher (ops.DIFFUSION_DOF_OT_watch_escape) runs


def busy():
    """Whether a frame is being processed or waits to be."""
    with _lock:
        return _active is not None or bool(_jobs)


def _use_worker():
    return FORCE_WORKER or not bpy.app.background


def process_ready():
    """Processes every queued frame that is ready (main thread only). With a worker thread,
    returns while a frame's library call runs; the next call goes on with it. Frees the session
    once no render is running and no frame is queued or running."""
    global _active
    while True:
        if _active is not None:
            try:
                next(_active)
                return
            except StopIteration:
                _active = None
        with _lock:
            job = next((j for j in _jobs if j.ready), None)
            idle = not _jobs and not _render_state
            if job is None:
                break
            _jobs.remove(job)
        if _use_worker():
            _active = job_steps(job, worker=True)
        else:
            process_job(job)
    if idle:
        close_session()
        free_spent_images()
        composite.remove_copies()


def _start_escape_watch():
    """Esc cancels the frame's library call: a modal operator in the first window watches
    for it while the call runs (nothing to watch without a window)."""
    if bpy.app.background or escape_watch["on"]:
        return  # one watcher runs while there are frames
    try:
        wm = bpy.context.window_manager
        window = wm.windows[0] if wm is not None and len(wm.windows) else None
        if window is not None:
            with bpy.context.temp_override(window=window):
                bpy.ops.diffusion_dof.watch_escape("INVOKE_DEFAULT")
    except (AttributeError, RuntimeError, TypeError):
        pass  # no window to watch: the render's own Esc still cancels (render_cancel)


def _timer():
    try:
        process_ready()
    except Exception:
        traceback.print_exc()
    return 0.05 if _active is not None else 0.2 if busy() else 0.5


# ---------------------------------------------------------------------------------------------
# Handlers


@persistent
def on_render_init(scene, _depsgraph=None):
    if composite.running:  # the compositing pass's own render
        return
    settings = _enabled(scene)
    if settings is None:
        return
    cancel_event.clear()
    state = {"error": None, "restore_dof": None, "lens_dof_on": False, "started": time.time(),
             "overscan": None, "extra": []}
    main = _is_main_thread()
    try:
        if main:
            for line in passes.ensure_setup(scene):
                log(line)
        else:
            problem = passes.missing_setup(scene, settings)
            if problem:
                raise SetupError("this render cannot get depth of field (%s): click Set Up "
                                 "Passes in the Diffusion DOF panel and render again." % problem)
        state["extra"] = passes.extra_slots(scene)
    except SetupError as err:
        state["error"] = str(err)
        log(str(err))
    if main and state["error"] is None:
        _start_overscan(scene, settings, state)
    cam = scene.camera
    if cam is not None and cam.type == "CAMERA" and cam.data.dof.use_dof:
        if main:
            # The camera's settings drive Diffusion DOF; the render itself must be a pinhole.
            cam.data.dof.use_dof = False
            state["restore_dof"] = cam.data.name
            log("rendering camera '%s' without its lens blur (its depth-of-field settings "
                "drive Diffusion DOF; restored after the render)" % cam.name)
        else:
            state["lens_dof_on"] = True
    _render_state[scene.name] = state


@persistent
def on_frame_change_post(scene, depsgraph=None):
    if composite.running:  # the compositing pass's own render
        return
    if depsgraph is None or depsgraph.mode != "RENDER" or scene.name not in _render_state:
        return
    settings = _enabled(scene)
    if settings is None:
        return
    try:
        value = camera_mod.camera_settings(scene, settings, depsgraph)
    except SetupError as err:
        value = err
    with _lock:
        _snapshots[(scene.name, scene.frame_current)] = value


@persistent
def on_render_post(scene, _depsgraph=None):
    if composite.running:  # the compositing pass's own render
        return
    state = _render_state.get(scene.name)
    settings = _enabled(scene)
    if state is None or settings is None:
        return
    job = Job(scene, scene.frame_current, settings.foreground_collection is not None,
              state["extra"], state["overscan"])
    job.error = state["error"]
    job.lens_dof_on = state["lens_dof_on"]
    job.started = state["started"]
    with _lock:
        job.camera = _snapshots.pop((scene.name, job.frame), None)
        _jobs.append(job)


@persistent
def on_render_write(scene, _depsgraph=None):
    if composite.running:  # the compositing pass's own render
        return
    if scene.name not in _render_state:
        return
    with _lock:
        for job in _jobs:
            if job.scene_name == scene.name and job.frame == scene.frame_current:
                job.write = True
                job.ready = True
    if _is_main_thread():
        process_ready()


def _finish(scene, cancelled):
    state = _render_state.pop(scene.name, None)
    with _lock:
        for job in list(_jobs):
            if job.scene_name == scene.name:
                if cancelled:
                    _jobs.remove(job)
                    for path in job.files.values():
                        if os.path.exists(path):
                            os.remove(path)
                else:
                    job.ready = True
        for key in [k for k in _snapshots if k[0] == scene.name]:
            del _snapshots[key]
    if _is_main_thread() and restore_overscan(scene):
        log("overscan: the resolution and the camera are back as they were")
    if state and state["restore_dof"] and _is_main_thread():
        cam_data = bpy.data.cameras.get(state["restore_dof"])
        if cam_data is not None:
            cam_data.dof.use_dof = True
    if _is_main_thread():
        process_ready()


@persistent
def on_render_complete(scene, _depsgraph=None):
    if composite.running:  # the compositing pass's own render
        return
    _finish(scene, cancelled=False)


@persistent
def on_render_cancel(scene, _depsgraph=None):
    if composite.running:  # the compositing pass's own render
        return
    if scene.name in _render_state:
        request_cancel()  # Esc during the render: the frame being processed stops too
    _finish(scene, cancelled=True)


@persistent
def on_load_post(*_args):
    reports.clear()
    _spent.clear()  # the file they were in is gone
    composite.remove_copies()  # a file saved during a render may hold one
    for scene in bpy.data.scenes:
        if restore_overscan(scene):
            log("%s: put back the resolution and camera of an interrupted overscan render"
                % scene.name)
        if _enabled(scene) is None:
            continue
        try:
            for line in passes.ensure_setup(scene):
                log("%s: %s" % (scene.name, line))
        except SetupError as err:
            log("%s: %s" % (scene.name, err))


@persistent
def on_depsgraph_update_post(scene, _depsgraph=None):
    if composite.running:  # the compositing pass's own render
        return
    settings = _enabled(scene)
    if settings is None:
        return
    _sync_pass_slots(scene, settings)
    # Keeps the foreground companion scene in step with edits made in the UI.
    if settings.foreground_collection is None:
        return
    companion = passes.companion_scene(scene)
    if companion is not None:
        passes.sync_companion(scene, companion)


def _sync_pass_slots(scene, settings):
    """After an edit of the compositor in the UI: the managed File Output node writes the passes
    the user's compositing now reads (a render with the UI cannot set that up itself: its
    handlers run on the render thread). Only between renders, on the main thread."""
    if _render_state or not _is_main_thread():
        return
    try:
        tree = passes.node_tree(scene)
        wanted = [e[0] for e in composite.pass_slots(scene, settings, tree)] if tree else []
        if tree is not None and tree.nodes.get(passes.OUTPUT_NODE) is not None \
                and passes.extra_slots(scene) != wanted:
            for line in passes.ensure_setup(scene):
                log(line)
            log("the passes your compositing reads are written for the add-on now")
    except SetupError as err:
        log(str(err))


HANDLERS = (
    ("render_init", on_render_init),
    ("frame_change_post", on_frame_change_post),
    ("render_post", on_render_post),
    ("render_write", on_render_write),
    ("render_complete", on_render_complete),
    ("render_cancel", on_render_cancel),
    ("load_post", on_load_post),
    ("depsgraph_update_post", on_depsgraph_update_post),
)


def _ours(fn):
    return getattr(fn, "__module__", "") == __name__


def register():
    for name, fn in HANDLERS:
        handlers = getattr(bpy.app.handlers, name)
        for old in [h for h in handlers if _ours(h)]:  # left by an earlier load of this module
            handlers.remove(old)
        handlers.append(fn)
    if not bpy.app.background and not bpy.app.timers.is_registered(_timer):
        bpy.app.timers.register(_timer, first_interval=0.5, persistent=True)


def unregister():
    for name, _fn in HANDLERS:
        handlers = getattr(bpy.app.handlers, name)
        for old in [h for h in handlers if _ours(h)]:
            handlers.remove(old)
    if bpy.app.timers.is_registered(_timer):
        bpy.app.timers.unregister(_timer)
    global _active
    if _active is not None:  # a frame in progress: stop it and wait for the library
        request_cancel()
        try:
            for _ in _active:
                time.sleep(0.01)
        except Exception:
            traceback.print_exc()
        _active = None
    with _lock:
        _jobs.clear()
        _snapshots.clear()
    _render_state.clear()
    reports.clear()
    close_session()
    free_spent_images()
    try:
        for scene in bpy.data.scenes:
            restore_overscan(scene)
        composite.remove_copies()
    except AttributeError:  # bpy.data is not readable while Blender quits
        pass
    escape_watch["on"] = False
