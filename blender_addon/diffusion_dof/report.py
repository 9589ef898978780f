# SPDX-License-Identifier: GPL-3.0-or-later
"""What the add-on says about a frame: the log line, and each scene's last result for the panel
(main thread; the log line from any thread)."""

import time

import bpy

reports = {}  # scene name -> the last result, for the panel


def log(message):
    print("Diffusion DOF:", message, flush=True)


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
        if stats.get("matte_ranks"):
            what += " (object matte, %d ranks)" % stats["matte_ranks"]
    return "%.3f s on %s, largest CoC %.1f px, %s" % (
        stats["seconds_total"], backend_line(stats), stats["max_coc_px"], what)
