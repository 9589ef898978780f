# SPDX-License-Identifier: GPL-3.0-or-later
"""Esc cancels a frame's library call while it runs on a worker thread: a modal operator in the
first window (ops.DIFFUSION_DOF_OT_watch_escape) watches for it (nothing to watch without a
window)."""

import bpy

watching = {"on": False}  # the watcher runs (set and cleared by the operator)


def start():
    """Starts the watcher unless one runs (main thread)."""
    if bpy.app.background or watching["on"]:
        return  # one watcher runs while there are frames
    try:
        wm = bpy.context.window_manager
        window = wm.windows[0] if wm is not None and len(wm.windows) else None
        if window is not None:
            with bpy.context.temp_override(window=window):
                bpy.ops.diffusion_dof.watch_escape("INVOKE_DEFAULT")
    except (AttributeError, RuntimeError, TypeError):
        pass  # no window to watch: the render's own Esc still cancels (render_cancel)
