# SPDX-License-Identifier: GPL-3.0-or-later
"""The focus tools: Pick Focus sets the focus distance from the kept Depth pass at a pixel (the
camera's, or the panel's override when the camera has a focus object), refuses the sky; the
Focal-Plane View shows the in-focus band green, near blur orange, far blur blue, and follows
the new focus. Scene: a wall at 12 m (smaller than the view: sky around it), a card at 3 m, a
post at 1.5 m; 85 mm f/1.4 focused at 6 m."""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import blender_test_util as u  # noqa: E402

import bpy  # noqa: E402

checks = u.Checks("test_focus_tools")
addon = u.load_addon()

scene = u.clear_scene()
u.add_plane(scene, "Wall", (5.0, 2.2), (0.0, 12.0, 0.0),
            u.emission_checker("WallMat", (0.9, 0.9, 0.85, 1), (0.4, 0.4, 0.45, 1), 4.0))
u.add_plane(scene, "Card", (0.3, 0.3), (-0.15, 3.0, 0.0),
            u.emission_checker("CardMat", (0.9, 0.3, 0.1, 1), (0.95, 0.95, 0.9, 1), 20.0))
u.add_plane(scene, "Post", (0.05, 2.0), (0.12, 1.5, 0.0),
            u.emission_checker("PostMat", (0.2, 0.7, 0.3, 1), (0.9, 0.9, 0.2, 1), 30.0))
cam = u.add_camera(scene, lens=85.0, fstop=1.4, focus=6.0)
u.configure(scene, samples=4)
scene.diffusion_dof.enabled = True

# Before any render: the tools say what to do.
try:
    bpy.ops.diffusion_dof.focus_map()
    checks.check(False, "focal-plane view without a render succeeded")
except RuntimeError as err:
    checks.check("Keep Inputs" in str(err), "focal-plane view message: %s" % err)

bpy.ops.render.render()
depth_img = bpy.data.images[addon.images.DEPTH_IMAGE]
w, h = depth_img.size
depth = u.pixels(depth_img)
ch = depth_img.channels


def find(pred):
    """The pixel nearest the frame's middle row whose depth satisfies pred."""
    best = None
    for y in range(h):
        for x in range(w):
            if pred(depth[(y * w + x) * ch]) and (best is None or
                                                   abs(y - h // 2) < abs(best[1] - h // 2)):
                best = (x, y)
    return best


card = find(lambda z: abs(z - 3.0) < 1e-3)
post = find(lambda z: abs(z - 1.5) < 1e-3)
wall = find(lambda z: abs(z - 12.0) < 1e-3)
sky = find(lambda z: z > 1e6)
checks.check(None not in (card, post, wall, sky), "pixels card %r post %r wall %r sky %r"
             % (card, post, wall, sky))

bpy.ops.diffusion_dof.pick_focus(x=card[0], y=card[1])
checks.check(abs(cam.data.dof.focus_distance - 3.0) < 1e-3 and
             not scene.diffusion_dof.override_focus,
             "picked focus %.4f (want 3)" % cam.data.dof.focus_distance)
try:
    bpy.ops.diffusion_dof.pick_focus(x=sky[0], y=sky[1])
    checks.check(False, "picking the sky succeeded")
except RuntimeError as err:
    checks.check("No surface" in str(err), "sky message: %s" % err)
checks.check(abs(cam.data.dof.focus_distance - 3.0) < 1e-3, "the sky pick changed the focus")

bpy.ops.diffusion_dof.focus_map()
fm_img = bpy.data.images.get(addon.images.FOCUS_MAP_IMAGE)
checks.check(fm_img is not None and tuple(fm_img.size) == (w, h), "no focus map image")
fm = u.pixels(fm_img)


def rgb(p):
    k = (p[1] * w + p[0]) * 4
    return fm[k], fm[k + 1], fm[k + 2]


r, g, b = rgb(card)
checks.check(g > r and g > b, "the card (in focus) is not green: %.2f %.2f %.2f" % (r, g, b))
r, g, b = rgb(post)
checks.check(r > g and r > b, "the post (near) is not orange: %.2f %.2f %.2f" % (r, g, b))
r, g, b = rgb(wall)
checks.check(b > r and b > g, "the wall (far) is not blue: %.2f %.2f %.2f" % (r, g, b))
print("focus map: card %s, post %s, wall %s" % (rgb(card), rgb(post), rgb(wall)))

# With a focus object the camera's distance is not used: the pick goes to the override, and
# the view follows it (the wall now in focus, the card near).
target = bpy.data.objects.new("Target", None)
scene.collection.objects.link(target)
cam.data.dof.focus_object = target
bpy.ops.diffusion_dof.pick_focus(x=wall[0], y=wall[1])
s = scene.diffusion_dof
checks.check(s.override_focus and abs(s.focus_distance - 12.0) < 1e-3,
             "focus-object pick: override %s %.4f" % (s.override_focus, s.focus_distance))
bpy.ops.diffusion_dof.focus_map()
fm = u.pixels(bpy.data.images[addon.images.FOCUS_MAP_IMAGE])
r, g, b = rgb(wall)
checks.check(g > r and g > b, "refocused: the wall is not green: %.2f %.2f %.2f" % (r, g, b))
r, g, b = rgb(card)
checks.check(r > g and r > b, "refocused: the card is not orange: %.2f %.2f %.2f" % (r, g, b))

# A render border kept in its frame: the view maps the border's pixels only (the rest black),
# and a hexagonal aperture's legend is drawn in the whole frame's corner (rows 2.., as the map's
# rows are stored), white in its middle and black at its edge.
scene.render.use_border, scene.render.use_crop_to_border = True, False
scene.render.border_min_x, scene.render.border_max_x = 0.25, 0.75
scene.render.border_min_y, scene.render.border_max_y = 0.25, 0.75
cam.data.dof.aperture_blades = 6
bpy.ops.diffusion_dof.focus_map()
fm = u.pixels(bpy.data.images[addon.images.FOCUS_MAP_IMAGE])
side = min(64, min(w, h) // 4)
checks.check(rgb((w // 8, h // 2)) == (0.0, 0.0, 0.0), "outside the border: %r"
             % (rgb((w // 8, h // 2)),))
checks.check(max(rgb((w // 2, h // 2))) > 0.1, "inside the border: %r" % (rgb((w // 2, h // 2)),))
checks.check(rgb((w - 2 - side // 2, 2 + side // 2)) == (1.0, 1.0, 1.0) and
             rgb((w - 3, 2)) == (0.0, 0.0, 0.0), "legend: middle %r, corner %r"
             % (rgb((w - 2 - side // 2, 2 + side // 2)), rgb((w - 3, 2))))
u.unload_addon(addon)
checks.finish()
