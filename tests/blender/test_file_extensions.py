# SPDX-License-Identifier: GPL-3.0-or-later
"""Output properties > File Extensions off: an animation still gets depth of field on every
frame. The add-on's own File Output node then writes its passes without ".exr"; an add-on that
looks only for names with it finds nothing, writes every frame as rendered and blames the
compositor. Also: when a pass is really missing, the message says what was found instead.

Scene: a checker wall at 12 m far behind the 3 m focus (100 mm f/1.4), 3 frames to OpenEXR
files named without extension.
"""

import os
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import blender_test_util as u  # noqa: E402

import bpy  # noqa: E402

FRAMES = (1, 2, 3)

checks = u.Checks("test_file_extensions")
out_dir = u.scratch_dir("file_extensions")
addon = u.load_addon()

scene = u.clear_scene()
u.add_plane(scene, "Wall", (24.0, 14.0), (0.0, 12.0, 0.0),
            u.emission_checker("WallMat", (0.95, 0.85, 0.6, 1), (0.08, 0.12, 0.3, 1), 4.0))
u.add_camera(scene, lens=100.0, fstop=1.4, focus=3.0)
u.configure(scene, samples=4)
scene.frame_start, scene.frame_end = FRAMES[0], FRAMES[-1]
pinhole, w, h, _ = u.render_still(scene, os.path.join(out_dir, "pinhole.exr"))

frames_dir = os.path.join(out_dir, "frames")
shutil.rmtree(frames_dir, ignore_errors=True)
scene.render.use_file_extension = False
scene.render.filepath = os.path.join(frames_dir, "dof_####")
scene.diffusion_dof.enabled = True
scene.diffusion_dof.write_frames = True
lines = []
real_log = addon.report.log
addon.report.log = lambda message: (lines.append(message), real_log(message))
try:
    bpy.ops.render.render(animation=True)
finally:
    addon.report.log = real_log
for frame in FRAMES:
    path = os.path.join(frames_dir, "dof_%04d" % frame)  # no extension, as the user asked
    if not checks.check(os.path.isfile(path), "frame %d: %s not written (%s)"
                        % (frame, path, sorted(os.listdir(frames_dir)))):
        continue
    reported = [l for l in lines if l.startswith("frame %d:" % frame)]
    checks.check(len(reported) == 1 and path in reported[0],
                 "frame %d: not processed: %r" % (frame, reported))
    buf, fw, fh, _ = u.load_file(path)
    # The far wall is blurred: its checker loses most of its detail against the pinhole.
    everywhere = [True] * (w * h)
    ratio = u.detail(buf, everywhere, w) / u.detail(pinhole, everywhere, w)
    checks.check((fw, fh) == (w, h) and ratio < 0.5,
                 "frame %d: %dx%d, detail kept %.2f (written without depth of field?)"
                 % (frame, fw, fh, ratio))
leftovers = [n for n in os.listdir(addon.passes.temp_dir(scene))]
checks.check(not leftovers, "pass files left behind: %s" % leftovers)

# A pass that does not arrive: the message names what the add-on found instead of blaming the
# compositor. Here the pass files are renamed away as soon as they are written (before the
# add-on reads them).
scene.render.use_file_extension = True


def hide_passes(scene_, *_args):
    folder = addon.passes.temp_dir(scene_)
    for name in os.listdir(folder):
        os.replace(os.path.join(folder, name), os.path.join(folder, "moved_" + name))


bpy.app.handlers.render_post.insert(0, hide_passes)
lines.clear()
addon.report.log = lambda message: (lines.append(message), real_log(message))
try:
    bpy.ops.render.render()
finally:
    addon.report.log = real_log
    bpy.app.handlers.render_post.remove(hide_passes)
report = addon.report.reports.get(scene.name)
checks.check(report is not None and not report["ok"] and "moved_color_" in report["message"]
             and "compositor did not run" not in report["message"],
             "missing pass: %r" % (report and report["message"]))
folder = addon.passes.temp_dir(scene)
for name in os.listdir(folder):
    os.remove(os.path.join(folder, name))
u.unload_addon(addon)
checks.finish()
