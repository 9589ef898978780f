# SPDX-License-Identifier: GPL-3.0-or-later
"""The UI path, simulated: with the UI, Blender calls render handlers on the render job's
thread, where the add-on must not load images or change data. Here the handlers are wrapped to
run on another thread (the main thread waits), so they queue the frame; the add-on's timer,
called on the main thread as Blender's event loop would, then does the work. Also: on that
thread the camera's lens DOF is not switched off, and the frame gets the clear message. As
with the UI, the library call runs on a worker thread while the timer keeps returning to the
event loop; Esc (here request_cancel, what the Esc watcher and render_cancel call) stops it
and the frame is left as rendered."""

import os
import sys
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import blender_test_util as u  # noqa: E402

import bpy  # noqa: E402

checks = u.Checks("test_render_thread")
addon = u.load_addon()
render = addon.render
jobs = addon.jobs

scene = u.clear_scene()
u.add_plane(scene, "Wall", (24.0, 14.0), (0.0, 12.0, 0.0),
            u.emission_checker("WallMat", (0.95, 0.85, 0.6, 1), (0.08, 0.12, 0.3, 1), 4.0))
cam = u.add_camera(scene, lens=100.0, fstop=1.4, focus=3.0)
u.configure(scene, samples=4)
scene.diffusion_dof.enabled = True  # sets up the passes on the main thread, as the UI does
scene.render.filepath = os.path.join(u.scratch_dir("render_thread"), "still.exr")

threads_seen = []


def on_other_thread(fn):
    def wrapper(*args):
        def run():
            threads_seen.append(threading.current_thread() is threading.main_thread())
            fn(*args)
        t = threading.Thread(target=run)
        t.start()
        t.join()
    return wrapper


jobs.FORCE_WORKER = True  # the library call on a worker thread, as with the UI
timer_calls = []
call_threads = []
_run_region = addon.library_call.run_region


def run_region_recorded(*args, **kwargs):
    call_threads.append(threading.current_thread() is threading.main_thread())
    return _run_region(*args, **kwargs)


addon.library_call.run_region = run_region_recorded


def drain():
    """Calls the timer as Blender's event loop would until the frames are done."""
    t0 = time.time()
    while True:
        timer_calls.append(jobs.timer())
        if not jobs.busy() or time.time() - t0 > 120:
            return
        time.sleep(0.005)


wrapped = {}
for name, fn in render.HANDLERS:
    if name.startswith("render_"):
        handlers = getattr(bpy.app.handlers, name)
        handlers.remove(fn)
        wrapped[name] = on_other_thread(fn)
        handlers.append(wrapped[name])

# A still with write_still: queued, not processed, until the timer runs.
bpy.ops.render.render(write_still=True)
checks.check(threads_seen and not any(threads_seen), "handlers did not run on another thread")
checks.check(len(jobs.queued) == 1 and jobs.queued[0].ready and jobs.queued[0].write,
             "expected one ready job to write, got %r" % [(j.frame, j.ready, j.write)
                                                          for j in jobs.queued])
checks.check("Diffusion DOF" not in bpy.data.images, "the render thread created the image")
drain()
checks.check(not jobs.queued, "the timer left jobs queued")
report = addon.report.reports.get(scene.name)
checks.check(report is not None and report["ok"] and report["path"], "timer report %r" % report)
checks.check("Diffusion DOF" in bpy.data.images, "no result image after the timer")

# Lens DOF on: left alone on the render thread, and the frame says why it was not processed.
cam.data.dof.use_dof = True
bpy.ops.render.render()
checks.check(cam.data.dof.use_dof, "the render thread changed the camera")
drain()
report = addon.report.reports.get(scene.name)
checks.check(report is not None and not report["ok"] and "lens depth of field was on"
             in report["message"], "lens DOF report %r" % report)
cam.data.dof.use_dof = False

# Setup missing (another session's temporary folder): the render thread does not fix it; the
# frame says to click Set Up Passes.
addon.compat.set_file_output_folder(u.compositor_tree(scene).nodes[addon.passes.OUTPUT_NODE],
                                    "/nonexistent/elsewhere/")
bpy.ops.render.render()
drain()
report = addon.report.reports.get(scene.name)
checks.check(report is not None and not report["ok"] and "Set Up Passes" in report["message"],
             "setup report %r" % report)

addon.compat.set_file_output_folder(u.compositor_tree(scene).nodes[addon.passes.OUTPUT_NODE],
                                    addon.passes.temp_dir(scene) + os.sep)

# Esc while the library call runs: the frame is left as rendered and the report says so.
bpy.ops.render.render(write_still=True)
written = scene.render.filepath
before = u.load_file(written)[0]
addon.library_call.request_cancel()  # after render_init, which clears it for a new render
drain()
report = addon.report.reports.get(scene.name)
checks.check(report is not None and not report["ok"] and "cancelled (Esc)" in report["message"]
             and "left as rendered" in report["message"], "cancel report %r" % (report,))
checks.check(u.load_file(written)[0] == before, "the cancelled frame's file was replaced")
# The next render is not cancelled.
bpy.ops.render.render(write_still=True)
drain()
report = addon.report.reports.get(scene.name)
checks.check(report is not None and report["ok"], "render after a cancel: %r" % (report,))
checks.check(call_threads and not any(call_threads),
             "the library call ran on the main thread: %r" % call_threads)

addon.library_call.run_region = _run_region
jobs.FORCE_WORKER = False
for name, fn in render.HANDLERS:
    if name in wrapped:
        handlers = getattr(bpy.app.handlers, name)
        handlers.remove(wrapped[name])
        handlers.append(fn)
u.unload_addon(addon)
checks.finish()
