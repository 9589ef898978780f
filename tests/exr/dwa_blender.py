# SPDX-License-Identifier: MIT
# dwa_blender.py - run by test_exr_dwa inside `blender -b`: Blender writes one image as ZIP,
# DWAA and DWAB (its own OpenEXR code, as a render would be saved), and reads files that exrio
# wrote (DWAA; ZIP, deflated by libdeflate) and saves what it read again as 32-bit ZIP, as
# OURS_read_by_blender.exr beside OUT_DIR's others, so that the test can compare.
#
#   blender -b --factory-startup --python-exit-code 1 --python dwa_blender.py -- OUT_DIR OURS.exr...
import os
import sys

import bpy

out_dir, *ours = sys.argv[sys.argv.index("--") + 1:]
W, H = 96, 64

scene = bpy.context.scene
# Linear EXR is written as stored; the view transform is kept neutral all the same.
scene.view_settings.view_transform = "Standard"
scene.view_settings.look = "None"
scene.view_settings.exposure = 0.0
scene.view_settings.gamma = 1.0
settings = scene.render.image_settings
settings.file_format = "OPEN_EXR"
settings.color_mode = "RGBA"

# The pattern test_exr_dwa.c's pattern() makes: smooth gradients, a hard-edged square and a
# highlight above 1, alpha 1 (Blender keeps straight and premultiplied alike then).
image = bpy.data.images.new("pattern", W, H, alpha=True, float_buffer=True)
pixels = []
for y in range(H):
    for x in range(W):
        inside = 30 <= x < 60 and 20 <= y < 44
        r = 0.1 + 0.8 * x / (W - 1)
        g = 0.9 if inside else 0.2 + 0.5 * y / (H - 1)
        b = 4.0 if (x - 75) ** 2 + (y - 15) ** 2 < 36 else 0.3
        pixels += [r, g, b, 1.0]
image.pixels[:] = pixels

settings.color_depth = "16"
for codec in ("ZIP", "DWAA", "DWAB"):
    settings.exr_codec = codec
    image.save_render(f"{out_dir}/blender_{codec.lower()}.exr", scene=scene)

settings.exr_codec = "ZIP"
settings.color_depth = "32"
for path in ours:
    read = bpy.data.images.load(path)
    stem = os.path.splitext(os.path.basename(path))[0]
    read.save_render(f"{out_dir}/{stem}_read_by_blender.exr", scene=scene)
