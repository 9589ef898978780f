# SPDX-License-Identifier: GPL-3.0-or-later
"""One queued frame from its passes to its result: read on the main thread (frame_inputs.py),
the library call on a worker thread with the UI (library_call.py), the result stored, written
and reported on the main thread (frame_output.py)."""

import os
import traceback

import bpy

from . import binding, escape_watch, frame_inputs, frame_output, library_call, report
from . import settings as settings_mod
from .errors import SetupError


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
            frame = frame_inputs.read(job, scene, settings)
            fallback = frame.fallback
            call = library_call.Call(library_call.run_region, frame.call_args())
            if worker:
                call.start()
                escape_watch.start()
                while call.is_alive():
                    yield
                scene = bpy.data.scenes.get(job.scene_name)
                if scene is None:  # removed meanwhile
                    return
            else:
                call.run()
            out, stats = call.value()
            yield from frame_output.finish(job, scene, settings, frame, out, stats, worker)
        except binding.Cancelled:
            report.set_report(scene.name, False, "frame %d: cancelled (Esc): left as rendered, "
                              "without depth of field%s"
                              % (job.frame, frame_output.write_fallback(scene, job, fallback)),
                              job.frame)
        except (SetupError, binding.LibraryError, binding.DdofError) as err:
            report.set_report(scene.name, False, "frame %d not processed: %s%s" % (
                job.frame, err, frame_output.write_fallback(scene, job, fallback)), job.frame)
        except Exception as err:  # a bug: say so, keep Blender and the render going
            traceback.print_exc()
            report.set_report(scene.name, False, "frame %d not processed: internal error: %s"
                              % (job.frame, err), job.frame)
    finally:
        for path in job.files.values():
            try:
                os.remove(path)
            except OSError:
                pass
