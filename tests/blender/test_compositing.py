# SPDX-License-Identifier: GPL-3.0-or-later
"""The user's compositing survives, applied after the depth of field (issue 31).

Scene: a checker wall at 12 m behind a card in focus at 3 m (100 mm f/1.4). The frames written
with the compositor plain (Render Layers -> output) are the depth-of-field image D; with an
Invert node between, every written frame must be 1 - D (before: D, the inversion dropped), still
and animation; with the tree reading the Depth pass (times 0.05) the written frame is that pass
as rendered (before: D); an Alpha Over of a second view layer at factor 0.5 is half the
depth-of-field image and half that layer as rendered. The user's tree, the scene's resolution and camera are exactly as
before each render, and no helper scene is left.
"""

import os
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import blender_test_util as u  # noqa: E402

import bpy  # noqa: E402

checks = u.Checks("test_compositing")
out_dir = u.scratch_dir("compositing")
addon = u.load_addon()

scene = u.clear_scene()
u.add_plane(scene, "Wall", (24.0, 14.0), (0.0, 12.0, 0.0),
            u.emission_checker("WallMat", (0.95, 0.85, 0.6, 1), (0.08, 0.12, 0.3, 1), 4.0))
u.add_plane(scene, "Card", (0.5, 0.4), (0.2, 3.0, 0.0),
            u.emission_checker("CardMat", (0.9, 0.9, 0.9, 1), (0.1, 0.1, 0.1, 1), 40.0))
cam = u.add_camera(scene, lens=100.0, fstop=1.4, focus=3.0)
u.configure(scene, samples=4)
pinhole, W, H, _ = u.render_still(scene, os.path.join(out_dir, "pinhole.exr"))
rl = u.render_layers_node(scene)
u.composite_from(scene, rl.outputs["Image"])
scene.diffusion_dof.enabled = True
scene.diffusion_dof.write_frames = True
tree = u.compositor_tree(scene)


def new_node(*kinds):
    """The first of these node types this Blender's compositor has (5.x renamed some)."""
    for kind in kinds:
        try:
            return tree.nodes.new(kind)
        except RuntimeError:
            continue
    raise RuntimeError("none of %s in this Blender" % (kinds,))


def tree_state():
    """The user's nodes and links (the add-on's managed nodes are its own)."""
    nodes = sorted((n.name, n.bl_idname, tuple(n.location)) for n in tree.nodes
                   if not n.name.startswith("DDOF"))
    links = sorted((l.from_node.name, l.from_socket.identifier, l.to_node.name,
                    l.to_socket.identifier) for l in tree.links
                   if not l.to_node.name.startswith("DDOF"))
    return nodes, links


def scene_state():
    r, d = scene.render, cam.data
    return ((r.resolution_x, r.resolution_y, r.resolution_percentage),
            (d.sensor_fit, d.sensor_width, d.sensor_height, d.shift_x, d.shift_y),
            sorted(s.name for s in bpy.data.scenes), sorted(g.name for g in bpy.data.node_groups),
            tree_state())


def max_diff(a, b, channels=3):
    return max(abs(a[i * 4 + c] - b[i * 4 + c]) for i in range(len(a) // 4)
               for c in range(channels))


def inverted(buf):
    out = list(buf)
    for i in range(0, len(out), 4):
        out[i:i + 3] = [1.0 - v for v in out[i:i + 3]]
    return out


def render(name):
    before = scene_state()
    result = u.render_still(scene, os.path.join(out_dir, name + ".exr"))
    after = scene_state()
    checks.check(after == before, "%s: the scene or its tree changed: %r -> %r"
                 % (name, before, after))
    report = addon.report.reports.get(scene.name)
    checks.check(report is not None and report["ok"], "%s: not processed: %r"
                 % (name, report and report["message"]))
    return result


everywhere = [True] * (W * H)
for mode in ("OFF", "AUTO"):
    scene.diffusion_dof.overscan = mode
    u.composite_from(scene, rl.outputs["Image"])
    plain, w, h, _ = render("plain_" + mode)
    checks.check((w, h) == (W, H), "%s: written %dx%d" % (mode, w, h))
    ratio = u.detail(plain, everywhere, W) / u.detail(pinhole, everywhere, W)
    checks.check(ratio < 0.6, "%s: no depth of field (detail kept %.2f)" % (mode, ratio))

    invert = new_node("CompositorNodeInvert")
    tree.links.new(rl.outputs["Image"], invert.inputs["Color"])
    u.composite_from(scene, invert.outputs[0])
    inv, w, h, _ = render("invert_" + mode)
    d = max_diff(inv, inverted(plain)) if (w, h) == (W, H) else float("inf")
    # Before: the written frame was the plain depth-of-field image (d about 0.9).
    checks.check(d < 1e-4, "%s: the written frame is not the inverted depth-of-field image "
                 "(max difference %.4g)" % (mode, d))
    result = u.pixels(bpy.data.images[addon.images.RESULT_IMAGE])
    checks.check(len(result) == len(inv) and max_diff(result, inv) < 1e-6,
                 "%s: the Diffusion DOF image is not the written frame" % mode)
    tree.nodes.remove(invert)

# The other passes as rendered: the frame is Depth x 0.05 (the wall at 12 m: 0.6).
scene.diffusion_dof.overscan = "AUTO"
math = new_node("CompositorNodeMath", "ShaderNodeMath")
math.operation = "MULTIPLY"
math.inputs[1].default_value = 0.05
tree.links.new(rl.outputs["Depth"], math.inputs[0])
u.composite_from(scene, math.outputs[0])
depth_frame, w, h, _ = render("depth")
kept = u.pixels(bpy.data.images[addon.images.DEPTH_IMAGE])
channels = bpy.data.images[addon.images.DEPTH_IMAGE].channels
err = max(abs(depth_frame[i * 4] - 0.05 * kept[i * channels]) for i in range(W * H)) \
    if (w, h) == (W, H) else float("inf")
checks.check(err < 1e-5, "the Depth pass did not reach the compositing as rendered (max error "
             "%.4g; wall pixel %.4f, expected 0.6)" % (err, depth_frame[4 * (W * 5 + 5)]))
tree.nodes.remove(math)

# An Alpha Over of view layers at factor 0.5: the depth-of-field layer's image under a second
# view layer's, which stays as rendered (it renders the same scene: the pinhole input).
overlay_layer = scene.view_layers.new("Overlay")
overlay = tree.nodes.new("CompositorNodeRLayers")
overlay.layer = overlay_layer.name
over = new_node("CompositorNodeAlphaOver")
background = over.inputs.get("Background") or over.inputs[1]
foreground = over.inputs.get("Foreground") or over.inputs[2]
next(i for i in over.inputs if i.identifier == "Fac").default_value = 0.5
tree.links.new(rl.outputs["Image"], background)
tree.links.new(overlay.outputs["Image"], foreground)
u.composite_from(scene, over.outputs[0])
layered, w, h, _ = render("view_layers")
raw = u.pixels(bpy.data.images[addon.composite.RAW_IMAGE])
kept_input = u.pixels(bpy.data.images[addon.images.INPUT_IMAGE])
expected = [0.5 * a + 0.5 * b for a, b in zip(raw, kept_input)]
d = max_diff(layered, expected) if (w, h) == (W, H) else float("inf")
checks.check(d < 1e-3, "Alpha Over of view layers: not half the depth-of-field image and half "
             "the other layer as rendered (max difference %.4g; half the depth-of-field image "
             "alone: %.4g)" % (d, max_diff(layered, raw)))
for node in (over, overlay):
    tree.nodes.remove(node)
scene.view_layers.remove(overlay_layer)

# An animation: every frame written with depth of field, then inverted (focus pulled so that
# the frames differ).
cam.data.dof.focus_distance = 3.0
cam.data.dof.keyframe_insert("focus_distance", frame=1)
cam.data.dof.focus_distance = 12.0
cam.data.dof.keyframe_insert("focus_distance", frame=2)
scene.frame_start, scene.frame_end = 1, 2


def animation(name):
    folder = os.path.join(out_dir, name)
    shutil.rmtree(folder, ignore_errors=True)
    scene.render.filepath = os.path.join(folder, "f_####")
    scene.frame_set(2)  # the Auto margin serves the whole range, whatever the current frame
    before = scene_state()
    lines = []
    real_log = addon.report.log
    addon.report.log = lambda message: (lines.append(message), real_log(message))
    try:
        bpy.ops.render.render(animation=True)
    finally:
        addon.report.log = real_log
    checks.check(scene_state() == before, "%s: the scene or its tree changed" % name)
    # The margin is frame 1's (focus 3 m: 7 px), the larger blur, though the render starts
    # at frame 2 (focus 12 m alone would give 3 px).
    margins = [l for l in lines if "px margin" in l]
    checks.check(len(margins) == 1 and "7 x 7 px margin" in margins[0],
                 "%s: the margin does not serve the whole focus pull: %r" % (name, margins))
    return [u.load_file(os.path.join(folder, "f_%04d.exr" % f))[0] for f in (1, 2)]


u.composite_from(scene, rl.outputs["Image"])
plain_frames = animation("anim_plain")
invert = new_node("CompositorNodeInvert")
tree.links.new(rl.outputs["Image"], invert.inputs["Color"])
u.composite_from(scene, invert.outputs[0])
inv_frames = animation("anim_invert")
checks.check(max_diff(plain_frames[0], plain_frames[1]) > 0.1, "the two frames are the same")
for f, (p, i) in enumerate(zip(plain_frames, inv_frames), 1):
    d = max_diff(i, inverted(p)) if len(i) == len(p) == W * H * 4 else float("inf")
    checks.check(d < 1e-4, "animation frame %d: not the inverted depth-of-field image (max "
                 "difference %.4g)" % (f, d))
tree.nodes.remove(invert)
u.composite_from(scene, rl.outputs["Image"])
u.unload_addon(addon)
checks.check(not [s for s in bpy.data.scenes if s.get("diffusion_dof_compositing_copy")],
             "a compositing copy is left")
checks.finish()
