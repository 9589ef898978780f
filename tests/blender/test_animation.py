# SPDX-License-Identifier: GPL-3.0-or-later
"""A 5-frame focus pull rendered the way users render animations, `blender -b scene.blend -a`,
with the add-on installed from the zip that build_zip.py makes (so the library is found next to
the add-on, not through DDOF_LIBRARY): five DOF frames are written in the scene's format (PNG),
and in each the card at the focus object's distance is the sharp one.

Three checker cards at 2 m (left), 4 m (middle) and 10 m (right); the camera's focus object is
an empty that jumps 2, 4, 10, 4, 2 m on frames 1 to 5. A bar at 1.2 m along the bottom is in a
foreground collection (rendered by the companion scene, blurred over what is behind it) on every
frame: Blender 5.2+ crashed between such frames when the add-on removed an image then.
"""

import os
import shutil
import subprocess
import sys
import time
import zipfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import blender_test_util as u  # noqa: E402

import bpy  # noqa: E402

CARDS = (("Near", 2.0, -0.24, 0.2, 44.0), ("Mid", 4.0, 0.0, 0.36, 22.0),
         ("Far", 10.0, 1.2, 0.9, 9.0))  # name, distance, x, size, checker scale (~5 px squares)
FOCUS_ON = ("Near", "Mid", "Far", "Mid", "Near")  # the card in focus, frames 1 to 5
FRAMES = tuple(range(1, len(FOCUS_ON) + 1))
BAR_DISTANCE = 1.2  # the foreground bar: nearer than every focus, so always blurred
BAR_ROWS = 8  # the frame's bottom rows, where the bar is
BAR_GREEN_MIN = 0.1  # their mean green - blue (PNG values) with the bar; the sky's is negative

checks = u.Checks("test_animation")
work = u.scratch_dir("animation")
t_start = time.time()
library = os.environ.get("DDOF_LIBRARY", "")
checks.check(os.path.isfile(library), "DDOF_LIBRARY must name the built library")

# The add-on as a user installs it: the zip, extracted into a user scripts folder.
zip_path = os.path.join(work, "diffusion_dof.zip")
addon = u.load_addon()  # also puts blender_addon/ on sys.path, where build_zip.py is
import build_zip  # noqa: E402
build_zip.build(library, zip_path)
user_scripts = os.path.join(work, "user_scripts")
addons = os.path.join(user_scripts, "addons")
os.makedirs(addons, exist_ok=True)
with zipfile.ZipFile(zip_path) as z:
    names = z.namelist()
    checks.check("diffusion_dof/libddof.so" in names and "diffusion_dof/__init__.py" in names,
                 "zip content: %s" % names)
    z.extractall(addons)
# With Blender as a module the add-on is the extension load_addon() installed (in the user
# resources folder run_bpy.py gives this test, which the render below shares).
addon_name = u.EXTENSION_MODULE if u.BPY_MODULE else "diffusion_dof"

# The scene, saved with Diffusion DOF on (the add-on is registered here to set it).
scene = u.clear_scene()
for name, dist, x, size, scale in CARDS:
    u.add_plane(scene, name, (size, size), (x, dist, 0.0),
                u.emission_checker(name + "Mat", (0.9, 0.9, 0.85, 1), (0.1, 0.1, 0.15, 1), scale))
near_collection = bpy.data.collections.new("Foreground")
scene.collection.children.link(near_collection)
# Across the frame's bottom rows, below the cards (they reach 0.5 of the half-height, the bar's
# top 0.77 of it): ~10 px tall in the frame, green-yellow against the blue sky.
u.add_plane(scene, "Bar", (1.0, 0.03), (0.0, BAR_DISTANCE, -0.09 * BAR_DISTANCE),
            u.emission_checker("BarMat", (0.2, 0.8, 0.3, 1), (0.9, 0.9, 0.2, 1), 60.0),
            collection=near_collection)
cam = u.add_camera(scene, lens=100.0, fstop=1.4, focus=5.0)
target = bpy.data.objects.new("FocusTarget", None)
scene.collection.objects.link(target)
cam.data.dof.focus_object = target
# Constant keys (set as new keys' interpolation: 5.0's layered actions have no .fcurves).
bpy.context.preferences.edit.keyframe_new_interpolation_type = "CONSTANT"
DISTANCE = {name: dist for name, dist, *_ in CARDS}
for frame, focused in zip(FRAMES, FOCUS_ON):
    target.location = (0.0, DISTANCE[focused], 0.0)
    target.keyframe_insert("location", frame=frame)
u.configure(scene, samples=16)
scene.frame_start, scene.frame_end = FRAMES[0], FRAMES[-1]
settings = scene.render.image_settings
addon.compat.set_file_format(settings, "PNG")
settings.color_mode = "RGBA"
settings.color_depth = "16"
frames_dir = os.path.join(work, "frames")
shutil.rmtree(frames_dir, ignore_errors=True)  # an earlier run's frames must not pass for these
scene.render.filepath = os.path.join(frames_dir, "dof_####")

# Reference: the pinhole frame (static scene), through the same PNG path, and the card masks.
pinhole_png = os.path.join(work, "pinhole.png")
pinhole, w, h, ch = u.render_still(scene, pinhole_png)
scene.render.filepath = os.path.join(frames_dir, "dof_####")
scene.diffusion_dof.enabled = True
scene.diffusion_dof.quality = "PREVIEW"
scene.diffusion_dof.write_frames = True
scene.diffusion_dof.foreground_collection = near_collection
blend = os.path.join(work, "focus_pull.blend")
bpy.ops.wm.save_as_mainfile(filepath=blend)
u.unload_addon(addon)

# Masks: which pixels each card covers (its depth), from a depth render of the same scene.
depth_dir = os.path.join(work, "depth")
u.composite_from(scene, u.render_layers_node(scene).outputs["Depth"])
addon.compat.set_file_format(scene.render.image_settings, "OPEN_EXR")
scene.render.image_settings.color_depth = "32"
depth, _, _, _ = u.render_still(scene, os.path.join(depth_dir, "depth.exr"))
masks = {}
for name, dist, _, _, _ in CARDS:
    inside = [abs(depth[4 * i] - dist) < 1e-3 for i in range(w * h)]
    masks[name] = u.erode(inside, w, h, 2)
    checks.check(sum(masks[name]) > 200, "card %s covers %d px" % (name, sum(masks[name])))

# The animation render, as a user runs it.
env = dict(os.environ)
env.pop("DDOF_LIBRARY", None)
env["BLENDER_USER_SCRIPTS"] = user_scripts
t0 = time.time()
proc = subprocess.run(u.blender_command("-b", "--factory-startup", "--addons", addon_name, blend,
                                        "-a"), env=env, capture_output=True, text=True,
                      timeout=300)
t_anim = time.time() - t0
log = proc.stdout + proc.stderr
lines = [l for l in log.splitlines() if "Diffusion DOF" in l or "Error" in l or "Traceback" in l]
print("\n".join(lines))
checks.check(proc.returncode == 0, "blender -a exited with %d" % proc.returncode)
checks.check("Traceback" not in log, "a traceback in the animation render's output")
contexts = sum("a ddof context for this render" in l for l in lines)
checks.check(contexts == 1, "%d ddof contexts for a %d-frame render (one, kept, expected)"
             % (contexts, len(FRAMES)))

ref = {name: u.detail(pinhole, masks[name], w) for name, *_ in CARDS}
pinhole_bar_green = sum(pinhole[4 * i + 1] - pinhole[4 * i + 2]
                        for i in range(BAR_ROWS * w)) / (BAR_ROWS * w)
montage = [pinhole]
for frame, focused in zip(FRAMES, FOCUS_ON):
    dist = DISTANCE[focused]
    path = os.path.join(frames_dir, "dof_%04d.png" % frame)
    if not checks.check(os.path.isfile(path), "frame %d not written" % frame):
        continue
    checks.check(any(("frame %d:" % frame) in l and path in l for l in lines),
                 "no Diffusion DOF report for frame %d" % frame)
    checks.check(any(("frame %d:" % frame) in l and "foreground" in l for l in lines),
                 "frame %d: the foreground element was not used" % frame)
    checks.check(any(("frame %d:" % frame) in l and ("focus %g m (focus object" % dist) in l
                     for l in lines), "frame %d: focus is not %g m from the focus object"
                 % (frame, dist))
    with open(path, "rb") as f:
        checks.check(f.read(8) == b"\x89PNG\r\n\x1a\n", "frame %d is not a PNG" % frame)
    buf, fw, fh, _ = u.load_file(path)
    checks.check((fw, fh) == (w, h), "frame %d is %dx%d" % (frame, fw, fh))
    montage.append(buf)
    ratios = {name: u.detail(buf, masks[name], w) / ref[name] for name, *_ in CARDS}
    print("frame %d (focus %g m): detail kept %s" % (
        frame, dist, ", ".join("%s %.2f" % (n, r) for n, r in ratios.items())))
    for name, ratio in ratios.items():
        if name == focused:
            checks.check(ratio > 0.95, "frame %d: the focused card %s lost detail (%.2f)"
                         % (frame, name, ratio))
        else:
            checks.check(ratio < 0.5, "frame %d: card %s is not blurred (%.2f)"
                         % (frame, name, ratio))
    # The foreground bar is in the frame, blurred: its bottom rows are green more than blue,
    # where the sky alone (the main render, in which the bar only lights) is blue.
    bar_green = sum(buf[4 * i + 1] - buf[4 * i + 2] for i in range(BAR_ROWS * w)) / (BAR_ROWS * w)
    print("frame %d: bottom rows' green - blue %.3f (pinhole %.3f)" % (frame, bar_green,
                                                                      pinhole_bar_green))
    checks.check(bar_green > BAR_GREEN_MIN, "frame %d: no foreground bar in the bottom rows "
                 "(green - blue %.3f)" % (frame, bar_green))
u.save_montage(montage, w, h, 2, os.path.join(work, "montage.png"), scale=2)
print("times: animation render (%d frames + start-up) %.1f s, test total %.1f s"
      % (len(FRAMES), t_anim, time.time() - t_start))
checks.finish()
