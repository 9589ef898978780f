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

import os
import threading
import time

import bpy
from bpy.app.handlers import persistent

from . import camera as camera_mod
from . import composite, escape_watch, images, jobs, library_call, object_matte, passes, report
from . import settings as settings_mod
from .errors import SetupError
from .overscan_render import restore_overscan, start_overscan


def _is_main_thread():
    return threading.current_thread() is threading.main_thread()


def _enabled(scene):
    s = settings_mod.get(scene)
    # The copy that runs the user's compositing (composite.py) carries the settings too.
    return s if s is not None and s.enabled and not composite.is_copy(scene) else None


# ---------------------------------------------------------------------------------------------
# Handlers


@persistent
def on_render_init(scene, _depsgraph=None):
    if composite.running:  # the compositing pass's own render
        return
    settings = _enabled(scene)
    if settings is None:
        return
    library_call.cancel_event.clear()
    state = {"error": None, "restore_dof": None, "lens_dof_on": False, "started": time.time(),
             "overscan": None, "extra": [], "matte": []}
    main = _is_main_thread()
    try:
        if main:
            for line in passes.ensure_setup(scene):
                report.log(line)
        else:
            problem = passes.missing_setup(scene, settings)
            if problem:
                raise SetupError("this render cannot get depth of field (%s): click Set Up "
                                 "Passes in the Diffusion DOF panel and render again." % problem)
        state["extra"] = passes.extra_slots(scene)
        state["matte"] = passes.matte_slots(scene)
    except SetupError as err:
        state["error"] = str(err)
        report.log(str(err))
    if main and state["error"] is None:
        state["overscan"] = start_overscan(scene, settings)
    cam = scene.camera
    if cam is not None and cam.type == "CAMERA" and cam.data.dof.use_dof:
        if main:
            # The camera's settings drive Diffusion DOF; the render itself must be a pinhole.
            cam.data.dof.use_dof = False
            state["restore_dof"] = cam.data.name
            report.log("rendering camera '%s' without its lens blur (its depth-of-field settings "
                "drive Diffusion DOF; restored after the render)" % cam.name)
        else:
            state["lens_dof_on"] = True
    jobs.render_state[scene.name] = state


@persistent
def on_frame_change_post(scene, depsgraph=None):
    if composite.running:  # the compositing pass's own render
        return
    if depsgraph is None or depsgraph.mode != "RENDER" or scene.name not in jobs.render_state:
        return
    settings = _enabled(scene)
    if settings is None:
        return
    try:
        value = camera_mod.camera_settings(scene, settings, depsgraph)
    except SetupError as err:
        value = err
    with jobs.lock:
        jobs.snapshots[(scene.name, scene.frame_current)] = value


@persistent
def on_render_post(scene, _depsgraph=None):
    if composite.running:  # the compositing pass's own render
        return
    state = jobs.render_state.get(scene.name)
    settings = _enabled(scene)
    if state is None or settings is None:
        return
    job = jobs.Job(scene, scene.frame_current, settings.foreground_collection is not None,
              state["extra"], state["overscan"], state["matte"])
    job.error = state["error"]
    if scene.camera is None:  # Blender refuses to render the frame (render_cancel follows)
        try:
            camera_mod.camera_settings(scene, settings)
        except SetupError as err:
            job.error, job.refused = str(err), True
    job.lens_dof_on = state["lens_dof_on"]
    job.started = state["started"]
    with jobs.lock:
        job.camera = jobs.snapshots.pop((scene.name, job.frame), None)
        jobs.queued.append(job)


@persistent
def on_render_write(scene, _depsgraph=None):
    if composite.running:  # the compositing pass's own render
        return
    if scene.name not in jobs.render_state:
        return
    with jobs.lock:
        for job in jobs.queued:
            if job.scene_name == scene.name and job.frame == scene.frame_current:
                job.write = True
                job.ready = True
    if _is_main_thread():
        jobs.process_ready()


def _finish(scene, cancelled):
    state = jobs.render_state.pop(scene.name, None)
    with jobs.lock:
        for job in list(jobs.queued):
            if job.scene_name == scene.name:
                if cancelled and not job.refused:
                    jobs.queued.remove(job)
                    for path in job.files.values():
                        if os.path.exists(path):
                            os.remove(path)
                else:
                    job.ready = True
        for key in [k for k in jobs.snapshots if k[0] == scene.name]:
            del jobs.snapshots[key]
    if _is_main_thread() and restore_overscan(scene):
        report.log("overscan: the resolution and the camera are back as they were")
    if state and state["restore_dof"] and _is_main_thread():
        cam_data = bpy.data.cameras.get(state["restore_dof"])
        if cam_data is not None:
            cam_data.dof.use_dof = True
    if _is_main_thread():
        jobs.process_ready()


@persistent
def on_render_complete(scene, _depsgraph=None):
    if composite.running:  # the compositing pass's own render
        return
    _finish(scene, cancelled=False)


@persistent
def on_render_cancel(scene, _depsgraph=None):
    if composite.running:  # the compositing pass's own render
        return
    if scene.name in jobs.render_state:
        library_call.request_cancel()  # Esc during the render: the frame being processed stops too
    _finish(scene, cancelled=True)


@persistent
def on_load_post(*_args):
    report.reports.clear()
    images.forget_spent_images()  # the file they were in is gone
    composite.remove_copies()  # a file saved during a render may hold one
    for scene in bpy.data.scenes:
        if restore_overscan(scene):
            report.log("%s: put back the resolution and camera of an interrupted overscan render"
                % scene.name)
        if _enabled(scene) is None:
            continue
        try:
            for line in passes.ensure_setup(scene):
                report.log("%s: %s" % (scene.name, line))
        except SetupError as err:
            report.log("%s: %s" % (scene.name, err))


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
    """After an edit in the UI: the managed File Output nodes write the passes the user's
    compositing now reads and the object matte the view layer now renders (a render with the UI
    cannot set that up itself: its handlers run on the render thread). Only between renders, on
    the main thread."""
    if jobs.render_state or not _is_main_thread():
        return
    try:
        tree = passes.node_tree(scene)
        if tree is None or tree.nodes.get(passes.OUTPUT_NODE) is None:
            return
        wanted = [e[0] for e in composite.pass_slots(scene, settings)]
        matte = object_matte.slots(passes.matte_layers(scene, settings))
        changed = [what for what, now, want in (
            ("the passes your compositing reads", passes.extra_slots(scene), wanted),
            ("the object matte (Cryptomatte)", passes.matte_slots(scene), matte)) if now != want]
        if changed:
            for line in passes.ensure_setup(scene):
                report.log(line)
            report.log("%s: written for the add-on now" % " and ".join(changed))
    except SetupError as err:
        report.log(str(err))


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
    if not bpy.app.background and not bpy.app.timers.is_registered(jobs.timer):
        bpy.app.timers.register(jobs.timer, first_interval=0.5, persistent=True)


def unregister():
    for name, _fn in HANDLERS:
        handlers = getattr(bpy.app.handlers, name)
        for old in [h for h in handlers if _ours(h)]:
            handlers.remove(old)
    if bpy.app.timers.is_registered(jobs.timer):
        bpy.app.timers.unregister(jobs.timer)
    jobs.stop()
    report.reports.clear()
    library_call.close_session()
    images.free_spent_images()
    try:
        for scene in bpy.data.scenes:
            restore_overscan(scene)
        composite.remove_copies()
    except AttributeError:  # bpy.data is not readable while Blender quits
        pass
    escape_watch.watching["on"] = False
