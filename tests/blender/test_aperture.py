# SPDX-License-Identifier: GPL-3.0-or-later
"""The camera's aperture reaches the library with no knob of the add-on's own: Blades, Rotation
and Ratio are read from the camera (Camera properties > Depth of Field > Aperture), and a bright
point far behind the focus comes out as Cycles draws it: an anamorphic ratio of 2 makes its blur
half as wide as tall, six blades make it a hexagon (same light, another shape). The polygon is
turned as Cycles turns it (issue 41): a Cycles render of one highlight with lens depth of field
(5 blades at 90 degrees: a pentagon that points one way, and its mirror image the other) against
the add-on's render of the same highlight. Blender's images are bottom row first and the
library's top row first, so the library sees the frame upside down: the add-on hands it the
rotation negated (with the angle as it is, the add-on's pentagon is Cycles' upside down)."""

import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import blender_test_util as u  # noqa: E402

import bpy  # noqa: E402

checks = u.Checks("test_aperture")
addon = u.load_addon()
camera_mod = addon.camera

SIZE = 96
scene = u.clear_scene()
u.configure(scene, samples=1)
scene.render.resolution_x = scene.render.resolution_y = SIZE
scene.render.resolution_percentage = 100
cam = u.add_camera(scene, lens=50.0, fstop=0.25, focus=1.0)
settings = scene.diffusion_dof

# Blender's values, as the library takes them (rotation in degrees).
dof = cam.data.dof
dof.aperture_blades = 6
dof.aperture_rotation = math.radians(15.0)
dof.aperture_ratio = 2.0
camera, _info = camera_mod.camera_settings(scene, settings)
checks.check(camera["aperture_blades"] == 6 and abs(camera["aperture_rotation_deg"] - 15.0) < 1e-4
             and camera["aperture_ratio"] == 2.0, "camera read as %r" % (camera,))

# The panel's camera line says so.
line = camera_mod.describe(camera, _info)
checks.check("6 blades at 15 deg, ratio 2" in line, "camera line: %s" % line)
dof.aperture_blades, dof.aperture_ratio = 0, 1.0
line = camera_mod.describe(camera_mod.camera_settings(scene, settings)[0], _info)
checks.check("blades" not in line and "ratio" not in line, "round camera line: %s" % line)

# A point of light at 10 m, the camera focused at 1 m: a CoC of 24 px.
color = bpy.data.images.new("point color", SIZE, SIZE, float_buffer=True)
depth = bpy.data.images.new("point depth", SIZE, SIZE, float_buffer=True)
pixels = [0.0, 0.0, 0.0, 1.0] * (SIZE * SIZE)
centre = (SIZE // 2) * SIZE + SIZE // 2
pixels[centre * 4:centre * 4 + 3] = [500.0, 500.0, 500.0]
color.pixels.foreach_set(pixels)
depth.pixels.foreach_set([10.0] * (SIZE * SIZE * 4))


def spread(blades, ratio):
    """(energy, horizontal and vertical standard deviation) of the point's blur."""
    dof.aperture_blades = blades
    dof.aperture_ratio = ratio
    bpy.ops.diffusion_dof.apply_images(color="point color", depth="point depth")
    values = list(bpy.data.images["Diffusion DOF"].pixels)
    red = [values[i * 4] for i in range(SIZE * SIZE)]
    total = sum(red)
    mx = sum(v * (i % SIZE) for i, v in enumerate(red)) / total
    my = sum(v * (i // SIZE) for i, v in enumerate(red)) / total
    sx = math.sqrt(sum(v * (i % SIZE - mx) ** 2 for i, v in enumerate(red)) / total)
    sy = math.sqrt(sum(v * (i // SIZE - my) ** 2 for i, v in enumerate(red)) / total)
    return total, sx, sy, red


round_energy, round_sx, round_sy, round_red = spread(0, 1.0)
checks.check(abs(round_sx - round_sy) < 0.05 * round_sx and round_sx > 4.0,
             "round aperture: sd %.2f x %.2f px" % (round_sx, round_sy))
oval_energy, oval_sx, oval_sy, _ = spread(0, 2.0)
checks.check(abs(oval_sx / oval_sy - 0.5) < 0.05 and abs(oval_sy - round_sy) < 0.05 * round_sy,
             "ratio 2: sd %.2f x %.2f px, round %.2f x %.2f" % (oval_sx, oval_sy, round_sx,
                                                                 round_sy))
hex_energy, hex_sx, hex_sy, hex_red = spread(6, 1.0)
moved = sum(abs(a - b) for a, b in zip(hex_red, round_red)) / round_energy
# A hexagon inscribed in the disc: smaller, and its light elsewhere by a tenth or so.
checks.check(hex_sx < round_sx and moved > 0.05,
             "6 blades: sd %.2f px (round %.2f), %.3f of the light moved" % (hex_sx, round_sx,
                                                                             moved))
for name, energy in (("ratio 2", oval_energy), ("6 blades", hex_energy)):
    checks.check(abs(energy - round_energy) < 0.01 * round_energy,
                 "%s: energy %.2f, round %.2f" % (name, energy, round_energy))
print("round sd %.2f x %.2f; ratio 2 sd %.2f x %.2f; 6 blades sd %.2f x %.2f, %.3f moved"
      % (round_sx, round_sy, oval_sx, oval_sy, hex_sx, hex_sy, moved))


def blades_against_cycles():
    """(error of the add-on's highlight against Cycles', the same for its mirror image (what
    the unturned angle gives), centroid distance in px, the frame's report)."""
    import numpy as np
    for obj in [o for o in scene.objects if o.type != "CAMERA"]:
        bpy.data.objects.remove(obj, do_unlink=True)
    scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    # A 3 px light at 20 m, the camera (100 mm f/1) focused at 1 m: a 28 px pentagon.
    bpy.ops.mesh.primitive_uv_sphere_add(segments=16, ring_count=8, radius=0.12,
                                         location=(0.0, 20.0, 0.0))
    light = bpy.context.active_object
    mat = bpy.data.materials.new("Highlight")
    mat.use_nodes = True
    emission = mat.node_tree.nodes.new("ShaderNodeEmission")
    emission.inputs["Strength"].default_value = 50.0
    mat.node_tree.links.new(emission.outputs[0],
                            mat.node_tree.nodes["Material Output"].inputs["Surface"])
    light.data.materials.append(mat)
    data = cam.data
    data.lens, data.dof.aperture_fstop, data.dof.focus_distance = 100.0, 1.0, 1.0
    dof.aperture_blades, dof.aperture_rotation, dof.aperture_ratio = 5, math.radians(90.0), 1.0
    out_dir = u.scratch_dir("aperture")
    u.configure(scene, samples=1024)
    r = scene.render
    r.resolution_x = r.resolution_y = SIZE
    settings.enabled, data.dof.use_dof = False, True
    truth = u.render_still(scene, os.path.join(out_dir, "cycles.exr"))[0]
    scene.cycles.samples = 4
    settings.enabled, data.dof.use_dof = True, False
    settings.write_frames = False
    u.render_still(scene, os.path.join(out_dir, "ddof.exr"))
    ours = u.pixels(bpy.data.images["Diffusion DOF"])
    t = np.frombuffer(truth, np.float32).reshape(SIZE, SIZE, 4)[..., 0].astype(np.float64)
    d = np.frombuffer(ours, np.float32).reshape(SIZE, SIZE, 4)[..., 0].astype(np.float64)
    t, d = t / t.sum(), d / d.sum()
    rows = np.arange(SIZE, dtype=np.float64)
    cy = lambda a: float((a.sum(axis=1) * rows).sum())
    # d mirrored about its centroid row, interpolated between rows.
    source = 2.0 * cy(d) - rows
    mirror = np.stack([np.interp(source, rows, d[:, x], left=0.0, right=0.0)
                       for x in range(SIZE)], axis=1)
    return (float(((d - t) ** 2).sum()), float(((mirror - t) ** 2).sum()), abs(cy(d) - cy(t)),
            addon.report.reports.get(scene.name))


same, mirrored, offset, report = blades_against_cycles()
print("5 blades at 90 deg: error against Cycles %.3g, of the mirror image %.3g (ratio %.2f); "
      "centroids %.2f px apart" % (same, mirrored, same / mirrored, offset))
checks.check(report is not None and report["ok"] and "5 blades at 90 deg" in report["message"],
             "the frame's report: %r" % (report,))
checks.check(offset < 1.0 and same < 0.5 * mirrored,
             "5 blades at 90 deg: the add-on's pentagon against Cycles' %.3g, its mirror image "
             "%.3g (centroids %.2f px apart)" % (same, mirrored, offset))
u.unload_addon(addon)
checks.finish()
