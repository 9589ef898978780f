# SPDX-License-Identifier: GPL-3.0-or-later
"""F12 on a scene with Diffusion DOF on: the result keeps in-focus pixels, blurs the far wall,
and is closer to a Cycles lens-DOF render of the same camera (the ground truth) than the pinhole
input is. Also: the camera's lens DOF is switched off for the render and restored; the written
file (write_still, OpenEXR) holds the result. Prints the Defocus node's PSNR for comparison."""

import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import blender_test_util as u  # noqa: E402

import bpy  # noqa: E402

FOCUS = 3.0
FSTOP = 1.4
LENS = 100.0
SENSOR = 36.0
PSNR_MARGIN_DB = 6.0  # measured 11.3 dB (Blender 3.4.1): see docs/blender-addon.md

checks = u.Checks("test_still_accuracy")
out_dir = u.scratch_dir("still_accuracy")
t_start = time.time()
addon = u.load_addon()

scene = u.clear_scene()
u.add_plane(scene, "Wall", (24.0, 14.0), (0.0, 12.0, 0.0),
            u.emission_checker("WallMat", (0.95, 0.85, 0.6, 1), (0.08, 0.12, 0.3, 1), 4.0))
u.add_plane(scene, "Card", (0.35, 0.3), (-0.2, FOCUS, 0.05),
            u.emission_checker("CardMat", (0.9, 0.3, 0.1, 1), (0.95, 0.95, 0.9, 1), 20.0))
near_collection = bpy.data.collections.new("Near")
scene.collection.children.link(near_collection)
u.add_plane(scene, "Post", (0.06, 2.0), (0.15, 1.5, 0.0),
            u.emission_checker("PostMat", (0.2, 0.7, 0.3, 1), (0.9, 0.9, 0.2, 1), 30.0),
            collection=near_collection)
cam = u.add_camera(scene, lens=LENS, fstop=FSTOP, focus=FOCUS, sensor=SENSOR, lens_dof=True)

# 1. Ground truth: Cycles with lens depth of field, Diffusion DOF off.
u.configure(scene, samples=512)
truth, w, h, ch = u.render_still(scene, os.path.join(out_dir, "truth.exr"))
t_truth = time.time()

# 2. Diffusion DOF on, camera DOF left on: the add-on renders a pinhole and blurs it.
u.configure(scene, samples=32)
s = scene.diffusion_dof
s.enabled = True
s.quality = "FINAL"
result_file, _, _, _ = u.render_still(scene, os.path.join(out_dir, "ddof.exr"))
t_ddof = time.time()
checks.check(cam.data.dof.use_dof, "the camera's lens DOF was not restored after the render")
report = addon.report.reports.get(scene.name)
checks.check(report is not None and report["ok"], "no successful report: %r" % (report,))
result_img = bpy.data.images.get("Diffusion DOF")
input_img = bpy.data.images.get("Diffusion DOF Input")
depth_img = bpy.data.images.get("Diffusion DOF Depth")
checks.check(result_img is not None and input_img is not None and depth_img is not None,
             "result or kept input images missing")
result = u.pixels(result_img)
pinhole = u.pixels(input_img)
depth = u.pixels(depth_img)
checks.check(tuple(result_img.size) == (w, h), "result size %r" % (tuple(result_img.size),))
checks.check(max(abs(a - b) for a, b in zip(result, result_file)) < 1e-6,
             "the written file is not the result")
# The quality is the library's preset (ddof_params_init_preset), and the report says where the
# frame ran (the default backend: the CPU).
lib = addon.binding.get_library()
final = lib.preset_summary("final")
stats = report["stats"] if report else {}
checks.check(s.quality_steps() == (final["substeps"], final["background_levels"]) and
             stats.get("kernel_name") == final["kernel"],
             "Final is not the library's final preset: %r, %r" % (s.quality_steps(), final))
checks.check(s.backend == "CPU" and stats.get("backend_name") == "cpu" and
             stats.get("renderer", "").startswith("CPU, ") and
             "on cpu (CPU, " in report["message"],
             "backend in the report: %r" % (report,))

# Masks from the depth pass.
n = w * h
d = [depth[4 * i] for i in range(n)]
checks.check(min(d) > 1.4 and max(d) < 13.0, "depth range %g..%g" % (min(d), max(d)))
in_focus = [abs(v - FOCUS) < 1e-3 for v in d]
far = [v > 11.0 for v in d]
near = [v < 2.0 for v in d]
near_columns = [i % w for i in range(n) if near[i]]
near_x0, near_x1 = min(near_columns), max(near_columns)
core = u.erode(in_focus, w, h, 1)
core = [c and not (near_x0 - 14 <= i % w <= near_x1 + 14) for i, c in enumerate(core)]
checks.check(sum(core) > 500, "in-focus test region too small (%d px)" % sum(core))
diff_in_focus = max(abs(result[4 * i + c] - pinhole[4 * i + c])
                    for i in range(n) if core[i] for c in range(4))
checks.check(diff_in_focus < 1e-5, "in-focus pixels changed by up to %g" % diff_in_focus)
far_core = u.erode(far, w, h, 3)
detail_in, detail_out = u.detail(pinhole, far_core, w), u.detail(result, far_core, w)
checks.check(detail_out < 0.25 * detail_in,
             "far wall not blurred: neighbour difference %g -> %g" % (detail_in, detail_out))
near_core = u.erode(near, w, h, 2)
detail_near_in, detail_near_out = u.detail(pinhole, near_core, w), u.detail(result, near_core, w)
checks.check(detail_near_out < 0.5 * detail_near_in,
             "near post not blurred: %g -> %g" % (detail_near_in, detail_near_out))

# 3. Closer to the truth than the input.
psnr_pinhole = u.psnr(pinhole, truth)
psnr_ddof = u.psnr(result, truth)
print("PSNR vs Cycles lens DOF: pinhole %.2f dB, ddof %.2f dB (margin %.2f dB)"
      % (psnr_pinhole, psnr_ddof, psnr_ddof - psnr_pinhole))
checks.check(psnr_ddof >= psnr_pinhole + PSNR_MARGIN_DB,
             "ddof %.2f dB is not %.1f dB above the pinhole's %.2f dB"
             % (psnr_ddof, PSNR_MARGIN_DB, psnr_pinhole))
for quality in ("PREVIEW", "DEFAULT"):
    s.quality = quality
    bpy.ops.diffusion_dof.reapply()
    print("PSNR %s quality: %.2f dB" % (quality.lower(),
                                         u.psnr(u.pixels(bpy.data.images["Diffusion DOF"]), truth)))
    summary = lib.preset_summary(quality.lower())
    report = addon.report.reports.get(scene.name)
    # The preset ran as the library defines it: its method, and for the diffusion its
    # sub-steps (the CoD4 preview runs no ADI step).
    ran = report["stats"]
    # sub-steps (the CoD4 preview runs no ADI step; a disc kernel runs one complex step chain).
    expect_substeps = (0 if summary["method"] == "cod4" else
                       1 if summary["kernel"] != "heat" else summary["substeps"])
    checks.check(ran["method_name"] == summary["method"] and ran["substeps"] == expect_substeps,
                 "%s: ran %s with %r sub-steps, the library's preset %r"
                 % (quality, ran["method_name"], ran["substeps"], summary))

# Backend Auto: a GPU when the GL plugin finds one, else the CPU, with the same pixels; the
# report says which ran, its renderer and why.
s.quality = "FINAL"
bpy.ops.diffusion_dof.reapply()
cpu_result = u.pixels(bpy.data.images["Diffusion DOF"])
s.backend = "AUTO"
bpy.ops.diffusion_dof.reapply()
report = addon.report.reports.get(scene.name)
stats = report["stats"]
print("backend auto ran on %s (%s): %s" % (stats["backend_name"], stats["renderer"],
                                           stats["backend_note"]))
checks.check(stats["backend_note"].startswith("auto: ") and stats["renderer"] and
             ("on %s (%s)" % (stats["backend_name"], stats["renderer"])) in report["message"],
             "auto report: %r" % (report,))
auto_result = u.pixels(bpy.data.images["Diffusion DOF"])
if stats["backend_name"] == "cpu":
    checks.check(auto_result == cpu_result, "auto on the CPU differs from CPU")
else:
    checks.check(max(abs(a - b) for a, b in zip(auto_result, cpu_result)) < 1e-3,
                 "auto on the GPU differs from the CPU")
s.backend = "CPU"

# 4. The post as a separately rendered foreground element (companion scene, Kass et al. 3.2).
s.quality = "FINAL"
s.foreground_collection = near_collection
# Re-apply runs on the kept frame, without the overscan margin the render had: compared with a
# render without overscan (overscan itself: test_overscan).
s.overscan = "OFF"
t0 = time.time()
u.render_still(scene, os.path.join(out_dir, "ddof_fg.exr"))
t_fg = time.time() - t0
report = addon.report.reports.get(scene.name)
ok = checks.check(report is not None and report["ok"] and "foreground" in
                  report["stats"]["effect_names"], "foreground render: %r" % (report,))
result_fg = u.pixels(bpy.data.images["Diffusion DOF"])
psnr_fg = u.psnr(result_fg, truth)
print("PSNR with the post as foreground element: %.2f dB (render + ddof %.1f s)"
      % (psnr_fg, t_fg))
checks.check(psnr_fg >= psnr_pinhole + PSNR_MARGIN_DB,
             "foreground: %.2f dB is not %.1f dB above the pinhole's %.2f dB"
             % (psnr_fg, PSNR_MARGIN_DB, psnr_pinhole))
pinhole_fg = u.pixels(bpy.data.images["Diffusion DOF Input"])  # this render's own input
checks.check(max(abs(result_fg[4 * i + c] - pinhole_fg[4 * i + c]) for i in range(n)
                 if core[i] for c in range(4)) < 1e-5, "foreground: in-focus pixels changed")
bpy.ops.diffusion_dof.reapply()  # with the kept foreground element
psnr_fg_again = u.psnr(u.pixels(bpy.data.images["Diffusion DOF"]), truth)
checks.check(abs(psnr_fg_again - psnr_fg) < 1e-3, "re-apply with the foreground element: "
             "%.2f dB, render %.2f dB" % (psnr_fg_again, psnr_fg))
s.foreground_collection = None
checks.check(not any(x.name.startswith("DDOF Foreground") for x in bpy.data.scenes),
             "companion scene left after clearing the foreground collection")


# 5. The baseline users already have: the compositor's Defocus node on the same pinhole render
# (f-stop scaled by 1000 / sensor mm to match the physical lens, docs/design.md section 1).
# (Blender 3.4's node; with the module from PyPI, 4.2+, the baseline is left out.)
if os.environ.get("DDOF_TEST_DEFOCUS", "0" if u.BPY_MODULE else "1") == "1":
    s.enabled = False
    cam.data.dof.use_dof = False
    tree = u.ensure_compositor_tree(scene)  # the add-on turned off the nodes it turned on
    rl = next(n for n in tree.nodes if n.bl_idname == "CompositorNodeRLayers")
    comp = next(n for n in tree.nodes if n.bl_idname == "CompositorNodeComposite")
    defocus = tree.nodes.new("CompositorNodeDefocus")
    defocus.use_zbuffer = True
    defocus.use_preview = False
    defocus.bokeh = "CIRCLE"
    defocus.f_stop = FSTOP * 1000.0 / SENSOR
    defocus.blur_max = 200.0
    defocus.threshold = 0.0
    tree.links.new(rl.outputs["Image"], defocus.inputs["Image"])
    tree.links.new(rl.outputs["Depth"], defocus.inputs["Z"])
    tree.links.new(defocus.outputs["Image"], comp.inputs["Image"])
    t0 = time.time()
    defocused, _, _, _ = u.render_still(scene, os.path.join(out_dir, "defocus.exr"))
    print("PSNR Defocus node: %.2f dB (render + composite %.2f s)"
          % (u.psnr(defocused, truth), time.time() - t0))
else:
    defocused = truth
# Pinhole input, Cycles lens DOF; ddof, Defocus node; ddof with the foreground element.
u.save_montage([pinhole, truth, result, defocused, result_fg], w, h, 2,
               os.path.join(out_dir, "montage.png"), scale=3)
print("times: truth render %.1f s, pinhole render + ddof %.1f s, total %.1f s"
      % (t_truth - t_start, t_ddof - t_truth, time.time() - t_start))
u.unload_addon(addon)
checks.finish()
