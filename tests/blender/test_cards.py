# SPDX-License-Identifier: GPL-3.0-or-later
"""Render Image Planes as Cards (issue 25): the scene's image planes become ddof cards seen by
the scene camera. Scene: a camera at the origin looking along +Y, 50 mm f/1.4 focused at 3 m;
a 0.6 m plane at 3 m (in focus) whose 2x2 image is green on top and red below; a 24 x 14 m blue
plane at 12 m behind it; a plane behind the camera (skipped). Checks: the in-focus plane shows
its image the right way up at the right place, the far plane fills the corner, the whole
image equals ddof_render_cards called through the binding with the camera-space corners
written here by hand (camera space of this camera: (x, y, z) -> (x, z, -y)), and the render
engine (the render option) renders the same image."""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import blender_test_util as u  # noqa: E402

import bpy  # noqa: E402

checks = u.Checks("test_cards")
addon = u.load_addon()
cards_mod = addon.cards
binding = addon.binding

GREEN, RED, BLUE = (0.1, 0.8, 0.2, 1.0), (0.8, 0.1, 0.1, 1.0), (0.1, 0.2, 0.9, 1.0)


def float_image(name, width, height, rows):
    """A float image; rows[0] is the bottom row (Blender's order), each a list of RGBA."""
    image = bpy.data.images.new(name, width, height, alpha=True, float_buffer=True)
    image.pixels.foreach_set([c for row in rows for px in row for c in px])
    return image


def image_material(name, image):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    tex = nodes.new("ShaderNodeTexImage")
    tex.image = image
    emission = nodes.new("ShaderNodeEmission")
    out = nodes.new("ShaderNodeOutputMaterial")
    links.new(tex.outputs["Color"], emission.inputs["Color"])
    links.new(emission.outputs["Emission"], out.inputs["Surface"])
    return mat


def image_plane(scene, name, size, location, image):
    obj = u.add_plane(scene, name, size, location, image_material(name + "Mat", image))
    layer = obj.data.uv_layers.new()
    for loop, uv in zip(obj.data.loops, [(0, 0), (1, 0), (1, 1), (0, 1)]):
        layer.data[loop.index].uv = uv
    return obj


scene = u.clear_scene()
near_img = float_image("Near", 2, 2, [[RED, RED], [GREEN, GREEN]])
far_img = float_image("Far", 1, 1, [[BLUE]])
image_plane(scene, "Near", (0.6, 0.6), (0.0, 3.0, 0.0), near_img)
image_plane(scene, "Far", (24.0, 14.0), (0.0, 12.0, 0.0), far_img)
image_plane(scene, "Behind", (1.0, 1.0), (0.0, -2.0, 0.0), far_img)
u.add_camera(scene, lens=50.0, fstop=1.4, focus=3.0)
r = scene.render
r.resolution_x, r.resolution_y, r.resolution_percentage = u.WIDTH, u.HEIGHT, 100
r.pixel_aspect_x = r.pixel_aspect_y = 1.0

result = bpy.ops.diffusion_dof.render_cards()
checks.check(result == {"FINISHED"}, "render_cards returned %r" % (result,))
image = bpy.data.images.get(cards_mod.RESULT_IMAGE)
checks.check(image is not None and tuple(image.size) == (u.WIDTH, u.HEIGHT),
             "result image %r" % (image and tuple(image.size),))
got = u.pixels(image)
w, h = u.WIDTH, u.HEIGHT


def at(x, y_from_top):
    i = ((h - 1 - y_from_top) * w + x) * 4
    return tuple(got[i:i + 4])


def near(a, b, tol=1e-4):
    return all(abs(p - q) <= tol for p, q in zip(a, b))


# The near plane is 0.6 / 3 * 50 / 36 * 160 = 44 px wide, centred: 8 px above the middle is
# its green half, 8 px below its red half; the corner is the far plane.
checks.check(near(at(w // 2, h // 2 - 8), GREEN), "above the middle %r" % (at(w // 2, h // 2 - 8),))
checks.check(near(at(w // 2, h // 2 + 8), RED), "below the middle %r" % (at(w // 2, h // 2 + 8),))
checks.check(near(at(8, 8), BLUE), "corner %r" % (at(8, 8),))

# The same through the binding, corners by hand: bottom-left, bottom-right, top-right, top-left.


def corners(size, y_world):
    hx, hz = 0.5 * size[0], 0.5 * size[1]
    return [(-hx, -hz, -y_world), (hx, -hz, -y_world), (hx, hz, -y_world), (-hx, hz, -y_world)]


def top_first(rows):
    return binding.array.array("f", [c for row in reversed(rows) for px in row for c in px])


square = [(0, 0), (1, 0), (1, 1), (0, 1)]
by_hand = [{"positions": corners((0.6, 0.6), 3.0), "uv": square, "width": 2, "height": 2,
            "texture": top_first([[RED, RED], [GREEN, GREEN]])},
           {"positions": corners((24.0, 14.0), 12.0), "uv": square, "width": 1, "height": 1,
            "texture": top_first([[BLUE]])}]
camera = {"lens_model": "CYCLES", "sensor_fit": "AUTO", "focal_length_mm": 50.0,
          "sensor_width_mm": 36.0, "fstop": 1.4, "focus_distance_m": 3.0, "pixel_aspect": 1.0}
with binding.get_library().session() as session:
    direct = cards_mod.flipped_rows(session.render_cards(w, h, camera, by_hand), w, h)
worst = max(abs(a - b) for a, b in zip(direct, got))
checks.check(worst <= 1e-5, "the operator and the binding by hand differ by %g" % worst)

# The render option: the same image as the scene's render, through the engine (an EXR keeps
# the linear, premultiplied values).
scene.render.engine = "DIFFUSION_DOF_CARDS"
settings = scene.render.image_settings
settings.file_format, settings.color_mode, settings.color_depth = "OPEN_EXR", "RGBA", "32"
scene.render.filepath = os.path.join(u.scratch_dir("cards"), "engine.exr")
bpy.ops.render.render(write_still=True)
rendered, rw, rh, rc = u.load_file(scene.render.filepath)
checks.check((rw, rh, rc) == (w, h, 4), "engine render %dx%d, %d channels" % (rw, rh, rc))
worst = max(abs(a - b) for a, b in zip(rendered, got)) if len(rendered) == len(got) else 1.0
checks.check(worst <= 1e-5, "the engine's render and the operator's differ by %g" % worst)

u.unload_addon(addon)
checks.finish()
