# SPDX-License-Identifier: GPL-3.0-or-later
"""The add-on with Blender's UI (run under Xvfb with --enable-event-simulate, events simulated
through Window.event_simulate): F12 with the UI processes the frame on a worker thread while the
Esc watcher runs; Esc pressed while the library call runs cancels it (the frame is left as
rendered, the report says so); the next F12 is processed; Pick Focus, clicked on a pixel of the
kept Depth pass in an image editor, sets the camera's focus to that pixel's depth. An F12 with
an Invert node in the compositor gets the inverted depth-of-field image (the compositing run by
the main thread's timer); adding a node that reads Depth makes the add-on write that pass.

    xvfb-run blender --factory-startup --enable-event-simulate --python test_ui.py

Ends with exit status 1 on a failure (the UI's quit does not carry one)."""

import os
import sys
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import blender_test_util as u  # noqa: E402

import bpy  # noqa: E402

checks = u.Checks("test_ui")
addon = u.load_addon()
scene = u.clear_scene()
u.add_plane(scene, "Wall", (24.0, 14.0), (0.0, 12.0, 0.0),
            u.emission_checker("WallMat", (0.95, 0.85, 0.6, 1), (0.08, 0.12, 0.3, 1), 4.0))
u.add_plane(scene, "Card", (0.3, 0.3), (0.0, 3.0, 0.0),
            u.emission_checker("CardMat", (0.9, 0.3, 0.1, 1), (0.95, 0.95, 0.9, 1), 20.0))
cam = u.add_camera(scene, lens=100.0, fstop=1.4, focus=3.0)
u.configure(scene, samples=1)
# The image at 1:1 is wider than the editor Pick Focus clicks in.
scene.render.resolution_x, scene.render.resolution_y = 1920, 1080
scene.diffusion_dof.quality = "FINAL"
scene.diffusion_dof.enabled = True
state = {"step": "render1", "t0": time.time(), "esc": False, "watch": False}


class HeldCancel(threading.Event):
    """The first render's cancel flag. The library asks it from its progress callback on the
    worker thread; that first question waits until the Esc has set it (60 s at most), so the Esc
    always lands while the library call runs, however fast the frame is: a 1080p frame takes
    about 0.5 s here, which the simulated Esc's way through the event loop and the watcher can
    outlast."""

    held = False

    def is_set(self):
        if not self.held and threading.current_thread() is not threading.main_thread():
            self.held = True
            self.wait(60.0)
        return super().is_set()


plain_cancel = addon.library_call.cancel_event
addon.library_call.cancel_event = HeldCancel()


def window():
    return bpy.context.window_manager.windows[0]


def f12():
    with bpy.context.temp_override(window=window()):
        bpy.ops.render.render("INVOKE_DEFAULT")


def finish():
    checks.check(state["step"] == "done", "stopped at step %s" % state["step"])
    print("%s: %d checks, %d failures" % (checks.name, checks.count, len(checks.failures)),
          flush=True)
    os._exit(1 if checks.failures else 0)


def image_editor():
    """An area of the screen turned into an image editor showing the kept Depth pass."""
    area = max(window().screen.areas, key=lambda a: a.width * a.height)
    area.type = "IMAGE_EDITOR"
    area.spaces.active.image = bpy.data.images[addon.images.DEPTH_IMAGE]
    return area


def tick():
    step = state["step"]
    if time.time() - state["t0"] > 150:
        checks.check(False, "timed out at step %s" % step)
        finish()
    if step == "render1":
        addon.report.reports.clear()
        f12()
        state["step"] = "esc"
    elif step == "esc":
        if addon.escape_watch.watching["on"]:
            state["watch"] = True
        if addon.jobs.active is not None and addon.escape_watch.watching["on"] and not state["esc"]:
            window().event_simulate(type="ESC", value="PRESS")
            window().event_simulate(type="ESC", value="RELEASE")
            state["esc"] = True
        report = addon.report.reports.get(scene.name)
        if report is not None and not addon.jobs.busy():
            checks.check(state["watch"], "the Esc watcher did not run")
            checks.check(state["esc"], "Esc was not simulated while the call ran")
            checks.check(not report["ok"] and "cancelled (Esc)" in report["message"],
                         "Esc report: %r" % report)
            addon.library_call.cancel_event = plain_cancel  # the second render runs unheld
            addon.report.reports.clear()
            f12()
            state["step"] = "render2"
    elif step == "render2":
        report = addon.report.reports.get(scene.name)
        if report is not None and not addon.jobs.busy():
            checks.check(report["ok"], "the render after a cancel: %r" % report)
            # The user's compositing, run by the main thread's timer after the library call.
            rl = u.render_layers_node(scene)
            invert = u.compositor_tree(scene).nodes.new("CompositorNodeInvert")
            u.compositor_tree(scene).links.new(rl.outputs["Image"], invert.inputs["Color"])
            # A node reading Depth too: the edit makes the managed File Output node write it.
            math = u.compositor_tree(scene).nodes.new("CompositorNodeMath")
            u.compositor_tree(scene).links.new(rl.outputs["Depth"], math.inputs[0])
            u.composite_from(scene, invert.outputs[0])
            state["invert"], state["rl"], state["math"] = invert, rl, math
            state["step"] = "render3"
            return 0.5  # the edit's depsgraph update runs first, as after a user's edit
    elif step == "render3":
        slots = addon.passes.extra_slots(scene)
        checks.check(slots == [addon.composite.slot_name(state["rl"].name, "Depth")],
                     "the Depth pass the compositing reads is not written: %r" % slots)
        addon.report.reports.clear()
        f12()
        state["step"] = "composite"
    elif step == "composite":
        report = addon.report.reports.get(scene.name)
        if report is not None and not addon.jobs.busy():
            checks.check(report["ok"], "the render with compositing: %r" % report)
            raw = u.pixels(bpy.data.images[addon.composite.RAW_IMAGE])
            result = u.pixels(bpy.data.images[addon.images.RESULT_IMAGE])
            worst = max(abs(result[i + c] - (1.0 - raw[i + c]))
                        for i in range(0, len(raw), 4 * 97) for c in range(3)) \
                if len(raw) == len(result) else float("inf")
            checks.check(worst < 1e-4, "F12 with the UI: the result is not the inverted "
                         "depth-of-field image (max difference %.4g)" % worst)
            print("UI: compositing after the depth of field, max difference %.2g" % worst,
                  flush=True)
            u.compositor_tree(scene).nodes.remove(state["invert"])
            u.compositor_tree(scene).nodes.remove(state["math"])
            u.composite_from(scene, state["rl"].outputs["Image"])
            area = image_editor()
            state["area"] = area
            state["step"] = "pick"
            return 0.5  # let the editor draw once
    elif step == "pick":
        area = state["area"]
        region = next(r for r in area.regions if r.type == "WINDOW")
        with bpy.context.temp_override(window=window(), area=area, region=region):
            bpy.ops.diffusion_dof.pick_focus("INVOKE_DEFAULT")
        # A wall pixel: a tenth of the editor's width from its left, at mid height (the image
        # shows at 1:1, wider than the editor: the card is in the middle).
        rx, ry = int(region.width * 0.1), region.height // 2
        u_, v_ = region.view2d.region_to_view(rx, ry)
        checks.check(0.0 <= u_ < 0.3 and 0.3 < v_ < 0.7, "clicked at image (%.3f, %.3f)"
                     % (u_, v_))
        x, y = region.x + rx, region.y + ry
        window().event_simulate(type="MOUSEMOVE", value="NOTHING", x=x, y=y)
        window().event_simulate(type="LEFTMOUSE", value="PRESS", x=x, y=y)
        window().event_simulate(type="LEFTMOUSE", value="RELEASE", x=x, y=y)
        state["step"] = "picked"
        return 0.3
    elif step == "picked":
        checks.check(abs(cam.data.dof.focus_distance - 12.0) < 1e-3,
                     "picked focus %.4f, the wall is at 12" % cam.data.dof.focus_distance)
        print("UI: Esc cancelled the call; the focus picked from the wall: %.4f"
              % cam.data.dof.focus_distance, flush=True)
        state["step"] = "done"
        finish()
    return 0.02


bpy.app.timers.register(tick, first_interval=1.0)
