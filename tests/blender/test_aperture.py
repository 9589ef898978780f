# SPDX-License-Identifier: GPL-3.0-or-later
"""The camera's aperture reaches the library with no knob of the add-on's own: Blades, Rotation
and Ratio are read from the camera (Camera properties > Depth of Field > Aperture), and a bright
point far behind the focus comes out as Cycles draws it: an anamorphic ratio of 2 makes its blur
half as wide as tall, six blades make it a hexagon (same light, another shape)."""

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
u.unload_addon(addon)
checks.finish()
