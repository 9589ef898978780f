# SPDX-License-Identifier: GPL-3.0-or-later
"""One frame's library call, on plain data only: it runs on a worker thread with the UI, where
no Blender data may be read, so everything it takes (buffers, camera and option dicts, the
region) was read on the main thread first. Also the render's ddof context, kept across its
frames, and the cancel flag that stops a running call."""

import threading

from . import binding, report
from .camera import for_blender_rows

# Set to stop the library call that runs (Esc, a cancelled render): its progress callback
# answers "stop" and the frame is left as rendered. Cleared when a render starts.
cancel_event = threading.Event()
_session = None  # binding.Session: one ddof context for the frames of a render


def request_cancel():
    cancel_event.set()


def library_options(settings):
    """The settings' preset (the library's values), overrides and backend as plain data, read
    on the main thread (a worker thread must not read Blender data)."""
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
        report.log("a ddof context for this render (%s backend, %s threads), kept for its "
                   "frames" % (backend, threads or "all"))
    return _session


def close_session():
    global _session
    if _session is not None:
        _session.close()
        _session = None


def run(width, height, color, color_channels, depth, depth_channels, camera, foreground,
        options, window=None, matte=None):
    """One frame in the render's session with library_options() `options` (window, matte: as
    binding.Session.depth_of_field takes them); the buffers in Blender's row order (bottom
    first). Returns (out, stats). Raises LibraryError, DdofError, binding.Cancelled
    (cancel_event set)."""
    return session_for(options["threads"], options["backend"]).depth_of_field(
        width, height, color, color_channels, depth, depth_channels, for_blender_rows(camera),
        options["params"], foreground=foreground, preset=options["preset"],
        cancel=lambda _f: cancel_event.is_set(), window=window, matte=matte)


def run_region(width, height, color, color_channels, depth, depth_channels, camera,
               foreground, region, options, matte=None):
    """run() for a render that may be a render border's (region: a frame_region.Region or
    None): the camera is the full frame's, and with a full-size image only the border's pixels
    go to the library (through its row stride, the matte's too); the rest of the frame is
    returned as rendered."""
    if region is None:
        return run(width, height, color, color_channels, depth, depth_channels, camera,
                   foreground, options, matte=matte)
    camera = dict(camera, **region.camera_fields())
    if region.cropped:
        return run(width, height, color, color_channels, depth, depth_channels, camera,
                   foreground, options, matte=matte)
    return run(region.width, region.height, color, color_channels, depth, depth_channels,
               camera, foreground, options, window=(region.x, region.y, width, height),
               matte=matte)


class Call(threading.Thread):
    """A function run on a worker thread; value() returns its result or raises its error."""

    def __init__(self, fn, args):
        super().__init__(name="Diffusion DOF", daemon=True)
        self._fn, self._args = fn, args
        self._result = self._error = None

    def run(self):
        try:
            self._result = self._fn(*self._args)
        except BaseException as err:  # handed to the main thread
            self._error = err

    def value(self):
        if self._error is not None:
            raise self._error
        return self._result
