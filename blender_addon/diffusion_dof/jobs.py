# SPDX-License-Identifier: GPL-3.0-or-later
"""The queue of rendered frames waiting for depth of field. The render handlers (render.py)
queue a frame and mark it ready, on the render job's thread with the UI; process_ready, on the
main thread (called by the handlers in background mode, by a timer with the UI), takes the
ready ones in order, one frame's steps (frame_steps.py) at a time."""

import threading
import time
import traceback

import bpy

from . import composite, frame_steps, images, library_call, passes

lock = threading.Lock()  # guards queued and snapshots, which the render thread writes
queued = []              # Job, in the order frames were rendered
snapshots = {}           # (scene name, frame) -> (camera dict, info) or SetupError
render_state = {}        # scene name -> dict for the render in progress
active = None            # job_steps() of the frame whose library call runs on a worker thread
# Run the library call on a worker thread while the main thread keeps handling events (Esc):
# with the UI; tests set it to run that path in background mode.
FORCE_WORKER = False


class Job:
    """A rendered frame, as plain data: its scene's name, its pass files, what the render
    handlers found."""

    def __init__(self, scene, frame, foreground, extra=(), plan=None, matte=()):
        self.scene_name = scene.name
        self.frame = frame
        self.extra = list(extra)  # the passes the user's compositing reads (their slots)
        self.matte = list(matte)  # the object matte's sub-layers (their slots), in order
        self.files = passes.frame_files(scene, frame, foreground, self.extra, self.matte)
        self.foreground = foreground
        self.overscan = plan      # overscan.Plan of the render, or None
        self.camera = None
        self.error = None
        # Blender refused to render it (no camera): processed to report why, not dropped when
        # the render is cancelled.
        self.refused = False
        self.lens_dof_on = False
        self.write = False
        self.ready = False
        self.started = time.time()


def busy():
    """Whether a frame is being processed or waits to be."""
    with lock:
        return active is not None or bool(queued)


def use_worker():
    return FORCE_WORKER or not bpy.app.background


def process_ready():
    """Processes every queued frame that is ready (main thread only). With a worker thread,
    returns while a frame's library call runs; the next call goes on with it. Frees the session
    once no render is running and no frame is queued or running."""
    global active
    while True:
        if active is not None:
            try:
                next(active)
                return
            except StopIteration:
                active = None
        with lock:
            job = next((j for j in queued if j.ready), None)
            idle = not queued and not render_state
            if job is None:
                break
            queued.remove(job)
        if use_worker():
            active = frame_steps.job_steps(job, worker=True)
        else:
            frame_steps.process_job(job)
    if idle:
        library_call.close_session()
        images.free_spent_images()
        composite.remove_copies()


def timer():
    """bpy.app.timers' function with the UI: the next call's delay in seconds."""
    try:
        process_ready()
    except Exception:
        traceback.print_exc()
    return 0.05 if active is not None else 0.2 if busy() else 0.5


def stop():
    """Stops the frame in progress (cancels its library call and waits for it) and forgets the
    queue (main thread)."""
    global active
    if active is not None:
        library_call.request_cancel()
        try:
            for _ in active:
                time.sleep(0.01)
        except Exception:
            traceback.print_exc()
        active = None
    with lock:
        queued.clear()
        snapshots.clear()
    render_state.clear()
