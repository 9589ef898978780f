# SPDX-License-Identifier: GPL-3.0-or-later
"""What a user is told, with no traceback and Blender still working, when: the scene has no
camera; the camera is orthographic; the Depth pass is off (and that enabling Diffusion DOF turns
it on); the camera's lens DOF is on; a depth image is 8-bit; the library is missing, is not a
ddof library, or has an incompatible version (DDOF_FAKE_LIBRARY, a library built by the tests
that claims to be 1.2.0)."""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import blender_test_util as u  # noqa: E402

import bpy  # noqa: E402

checks = u.Checks("test_messages")
real_library = os.environ.get("DDOF_LIBRARY", "")
addon = u.load_addon()
binding, passes, render = addon.binding, addon.passes, addon.render


def problems(scene):
    return " | ".join(text for _, text in passes.diagnose(scene))


def operator_error(**kwargs):
    """The message the apply operator reports (it raises RuntimeError when called from Python),
    or '' when it succeeds."""
    try:
        bpy.ops.diffusion_dof.apply_images(**kwargs)
    except RuntimeError as err:
        return str(err)
    return ""


scene = u.clear_scene()
u.configure(scene, samples=1)
u.add_plane(scene, "Card", (1.0, 1.0), (0.0, 3.0, 0.0),
            u.emission_checker("CardMat", (1, 1, 1, 1), (0, 0, 0, 1), 10.0))
color = bpy.data.images.new("color", 16, 8, float_buffer=True)
depth = bpy.data.images.new("depth", 16, 8, float_buffer=True)
depth.pixels.foreach_set([3.0] * (16 * 8 * 4))
byte_depth = bpy.data.images.new("byte depth", 16, 8)

# No camera.
text = problems(scene)
checks.check("has no active camera" in text and "Scene > Camera" in text,
             "no-camera diagnosis: %s" % text)
err = operator_error(color="color", depth="depth")
checks.check("has no active camera" in err, "no-camera operator message: %s" % err)

# Orthographic camera.
cam = u.add_camera(scene)
cam.data.type = "ORTHO"
err = operator_error(color="color", depth="depth")
checks.check("perspective camera" in err, "orthographic camera message: %s" % err)
cam.data.type = "PERSP"
checks.check(operator_error(color="color", depth="depth") == "", "operator failed on good input")
checks.check("Diffusion DOF" in bpy.data.images, "operator made no result image")

# An 8-bit depth image, a missing image, sizes that differ.
err = operator_error(color="color", depth="byte depth")
checks.check("8-bit" in err and "OpenEXR" in err, "8-bit depth message: %s" % err)
err = operator_error(color="color", depth="no such image")
checks.check("no depth image named 'no such image'" in err, "missing image message: %s" % err)
small = bpy.data.images.new("small depth", 8, 8, float_buffer=True)
err = operator_error(color="color", depth="small depth")
checks.check("16x8" in err and "8x8" in err, "size mismatch message: %s" % err)

# Bad depth values: the library's own message names the pixel.
bad = list(depth.pixels)
bad[4 * 5] = -1.0
depth.pixels.foreach_set(bad)
err = operator_error(color="color", depth="depth")
checks.check("(5, 0)" in err and "depth" in err.lower(), "bad depth message: %s" % err)

# Depth pass off: diagnosed, and turned on by enabling Diffusion DOF.
layer = scene.view_layers[0]
layer.use_pass_z = False
text = problems(scene)
checks.check("has no Depth pass" in text and "Passes > Data > Z" in text,
             "depth-pass diagnosis: %s" % text)
scene.diffusion_dof.enabled = True
checks.check(layer.use_pass_z, "enabling Diffusion DOF did not turn on the Depth pass")
checks.check("Depth pass" not in problems(scene), "still diagnosed: %s" % problems(scene))

# Lens DOF on: a warning that says what to do.
cam.data.dof.use_dof = True
text = problems(scene)
checks.check("lens depth of field on" in text and "Use Pinhole Render" in text,
             "lens DOF diagnosis: %s" % text)
bpy.ops.diffusion_dof.pinhole()
checks.check(not cam.data.dof.use_dof, "Use Pinhole Render did not turn lens DOF off")

# The library: missing, not ddof, incompatible. The render goes on; the report says why.
cases = [("/nonexistent/libddof.so", "DDOF_LIBRARY is set to '/nonexistent/libddof.so'"),
         ("/bin/sh", "Could not load the ddof library")]
libm = "/lib/x86_64-linux-gnu/libm.so.6"
if os.path.isfile(libm):
    cases.append((libm, "is not a ddof library: it has no function ddof_version_number"))
fake = os.environ.get("DDOF_FAKE_LIBRARY", "")
if checks.check(os.path.isfile(fake), "DDOF_FAKE_LIBRARY not given"):
    cases.append((fake, "is version 1.2.0, but this add-on was written for %d.%d"
                  % addon.ddof_abi.BINDING_VERSION[:2]))
scene.render.filepath = os.path.join(u.scratch_dir("messages"), "frame.exr")
for path, expected in cases:
    os.environ["DDOF_LIBRARY"] = path
    ok, text = binding.library_status(reload=True)
    checks.check(not ok and expected in text, "library %s: %s" % (path, text))
    err = operator_error(color="color", depth="depth")
    checks.check(expected in err, "operator with library %s: %s" % (path, err))
    bpy.ops.render.render(write_still=True)  # must not raise
    report = addon.report.reports.get(scene.name)
    checks.check(report is not None and not report["ok"] and expected in report["message"],
                 "render report with library %s: %r" % (path, report))

# And back: with the real library everything works again after Reload Library.
os.environ["DDOF_LIBRARY"] = real_library
bpy.ops.diffusion_dof.reload_library()
bpy.ops.render.render(write_still=True)
report = addon.report.reports.get(scene.name)
checks.check(report is not None and report["ok"], "render after reload: %r" % (report,))

# Invalid cameras, shown by the panel before rendering: panoramic, f/0 (Blender accepts it),
# a focus within the focal length; each also leaves a rendered frame with the same reason.
cam.data.type = "PANO"
checks.check("is panoramic" in problems(scene) and "perspective camera" in problems(scene),
             "panoramic camera diagnosis: %s" % problems(scene))
cam.data.type = "ORTHO"
checks.check("is orthographic" in problems(scene), "ortho diagnosis: %s" % problems(scene))
cam.data.type = "PERSP"
cam.data.dof.use_dof = False
cam.data.dof.aperture_fstop = 0.0
text = problems(scene)
checks.check(cam.data.dof.aperture_fstop == 0.0 and "has f/0" in text and "F-Stop" in text,
             "f/0 diagnosis: %s" % text)
bpy.ops.render.render()
report = addon.report.reports.get(scene.name)
checks.check(report is not None and not report["ok"] and "has f/0" in report["message"],
             "f/0 render report: %r" % (report,))
cam.data.dof.aperture_fstop = 1.4
cam.data.dof.focus_distance = 0.0
text = problems(scene)
checks.check("focuses at 0 m, within its focal length" in text and "Focus Distance" in text,
             "focus-within-the-lens diagnosis: %s" % text)
scene.diffusion_dof.override_focus = True
scene.diffusion_dof.focus_distance = 0.05
text = problems(scene)
checks.check("focuses at 0.05 m" in text and "panel's Focus Distance" in text,
             "override focus diagnosis: %s" % text)
scene.diffusion_dof.override_focus = False
cam.data.dof.focus_distance = 3.0
checks.check(problems(scene) == "", "a good camera still diagnosed: %s" % problems(scene))

# No camera at render time: Blender refuses to render (here without calling the handlers; in
# other runs after render_init) and nothing reaches the compositor. The frame's report says
# there is no camera, not that the compositor did not run: the handlers' path, called here.
scene.camera = None
addon.report.reports.clear()
try:
    bpy.ops.render.render()
except RuntimeError as err:
    print("Blender: %s" % str(err).strip())
render.on_render_init(scene)
render.on_render_post(scene)
render.on_render_complete(scene)
report = addon.report.reports.get(scene.name)
checks.check(report is not None and not report["ok"] and
             "has no active camera" in report["message"] and
             "compositor" not in report["message"], "no-camera render report: %r" % (report,))
scene.camera = cam

# The same through Blender's own handlers (render_init, render_post, then render_cancel), after
# a frame that got depth of field: the frame's report says there is no camera, not the last
# frame's success line; also when the frame file was to be written.
for write_still in (False, True):
    bpy.ops.render.render()
    last = dict(addon.report.reports.get(scene.name) or {})
    scene.camera = None
    scene.render.filepath = os.path.join(u.scratch_dir("messages"), "no_camera_")
    try:
        bpy.ops.render.render(write_still=write_still)
    except RuntimeError as err:
        print("Blender: %s" % str(err).strip())
    report = addon.report.reports.get(scene.name)
    checks.check(last.get("ok") and report is not None and not report["ok"] and
                 "has no active camera" in report["message"],
                 "no-camera render after a good one (write_still %s): %r, before %r"
                 % (write_still, report, last.get("message")))
    scene.camera = cam

# Another resolution: the result image follows.
scene.render.resolution_percentage = 50
bpy.ops.render.render()
checks.check(tuple(bpy.data.images["Diffusion DOF"].size) == (80, 45),
             "result size after a 50%% render: %r" % (tuple(bpy.data.images["Diffusion DOF"].size),))
u.unload_addon(addon)
checks.finish()
