# SPDX-License-Identifier: GPL-3.0-or-later
"""Blender 5.x's compositor reading the render through its Group Input (issue 41), and 5.3's
compositor effects.

From 5.0 a compositor is a node group that Blender feeds the render into through its Group
Input: Compositor > New in 5.3 makes Group Input -> Group Output, with no Render Layers node.
Scene: a checker wall at 12 m behind a card in focus at 3 m (100 mm f/1.4). The depth-of-field
image D (the 'Diffusion DOF Raw' image) must reach the written frame through such a group:
Group Input -> Group Output writes D (before: the pinhole render P), Group Input -> Invert ->
Group Output writes 1 - D (before: 1 - P, and the report said the frame had depth of field).
A Render Layers node inside a node group the compositor uses would make the compositing run
render the scene again: the frame fails, never a success. 5.3's stack of effects applies them
all, in order, to D (two Invert effects: D). In 5.3 the add-on uses the effects API: its
nodes go into the effect the scene has (Compositor > New's), an effect it had to make goes
again when it is unticked or disabled, and Scene.compositing_node_group (deprecated for removal
in 6.0) is never read. 3.x/4.x have no Group Input compositing: a skip.
"""

import os
import sys
import warnings

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import blender_test_util as u  # noqa: E402

import bpy  # noqa: E402

if "compositing_node_group" not in bpy.types.Scene.bl_rna.properties:
    print("skipped: Blender %s has no node-group compositor (5.0+)" % bpy.app.version_string)
    sys.exit(77)

EFFECTS = "compositor_effects" in bpy.types.Scene.bl_rna.properties  # 5.3+
checks = u.Checks("test_group_input")
out_dir = u.scratch_dir("group_input")
addon = u.load_addon()
warnings.simplefilter("error", DeprecationWarning)  # the add-on must not use what 6.0 removes

scene = u.clear_scene()
u.add_plane(scene, "Wall", (24.0, 14.0), (0.0, 12.0, 0.0),
            u.emission_checker("WallMat", (0.95, 0.85, 0.6, 1), (0.08, 0.12, 0.3, 1), 4.0))
u.add_plane(scene, "Card", (0.5, 0.4), (0.2, 3.0, 0.0),
            u.emission_checker("CardMat", (0.9, 0.9, 0.9, 1), (0.1, 0.1, 0.1, 1), 40.0))
u.add_camera(scene, lens=100.0, fstop=1.4, focus=3.0)
u.configure(scene, samples=4)


def effects():
    """5.3: the scene's compositor effects as (name, node group name)."""
    return [(e.name, e.node_group and e.node_group.name) for e in scene.compositor_effects]


def new_group(name, invert):
    """A compositor node group: Group Input -> (Invert ->) Group Output, as a user makes it."""
    if EFFECTS and not invert:
        bpy.ops.scene.new_compositor_effect_node_group()  # Compositor > New
        return scene.compositor_effects.active.node_group
    group = bpy.data.node_groups.new(name, "CompositorNodeTree")
    group.interface.new_socket("Image", in_out="INPUT", socket_type="NodeSocketColor")
    group.interface.new_socket("Image", in_out="OUTPUT", socket_type="NodeSocketColor")
    gi, go = group.nodes.new("NodeGroupInput"), group.nodes.new("NodeGroupOutput")
    source = gi.outputs[0]
    if invert:
        node = group.nodes.new("CompositorNodeInvert")
        group.links.new(gi.outputs[0], node.inputs["Color"])
        source = node.outputs[0]
    group.links.new(source, go.inputs[0])
    if EFFECTS:
        scene.compositor_effects.new(name=name).node_group = group
    else:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DeprecationWarning)
            scene.compositing_node_group = group
    return group


def max_diff(a, b):
    return max(abs(a[i] - b[i]) for i in range(len(a)) if i % 4 != 3)


def render(name, composited):
    """(written frame, D, the frame's report) of a render with Diffusion DOF on; D is the
    result image, or with compositing the image the compositing ran on."""
    for image in [i for i in bpy.data.images if i.name.startswith("Diffusion DOF")]:
        bpy.data.images.remove(image)
    buf, _w, _h, _c = u.render_still(scene, os.path.join(out_dir, name + ".exr"))
    dof = bpy.data.images.get(addon.composite.RAW_IMAGE if composited else "Diffusion DOF")
    return buf, dof and u.pixels(dof), addon.report.reports.get(scene.name)


pinhole, W, H, _ = u.render_still(scene, os.path.join(out_dir, "pinhole.exr"))
before = effects() if EFFECTS else None

# Group Input -> Group Output (5.3: Compositor > New): the written frame is D.
plain = new_group("UA Plain", invert=False)
scene.diffusion_dof.enabled = True
scene.diffusion_dof.write_frames = True
written, dof, report = render("plain", False)
checks.check(report is not None and report["ok"], "plain group: report %r" % (report,))
blur = max_diff(dof, pinhole)
checks.check(blur > 0.1 and max_diff(written, dof) < 1e-3,
             "Group Input -> Group Output: written frame vs D %.4f (vs the pinhole render %.4f)"
             % (max_diff(written, dof), max_diff(written, pinhole)))
if EFFECTS:
    checks.check(len(scene.compositor_effects) == len(before) + 1,
                 "the add-on made an effect beside Compositor > New's: %r" % effects())
    checks.check(plain.nodes.get(addon.passes.OUTPUT_NODE) is not None,
                 "the managed nodes are not in the scene's effect: %r"
                 % [n.name for n in plain.nodes])

# Group Input -> Invert -> Group Output: the written frame is 1 - D.
scene.diffusion_dof.enabled = False
if EFFECTS:
    scene.compositor_effects.clear()
    bpy.data.node_groups.remove(plain)
    before = effects()
invert = new_group("UA Invert", invert=True)
scene.diffusion_dof.enabled = True
written, dof, report = render("invert", True)
inverted = [1.0 - v for v in dof]
checks.check(report is not None and report["ok"] and max_diff(written, inverted) < 1e-3,
             "Group Input -> Invert: written frame vs 1 - D %.4f (vs 1 - pinhole %.4f); "
             "report %r" % (max_diff(written, inverted),
                            max_diff(written, [1.0 - v for v in pinhole]), report))

# A node group in the compositor that reads the render itself (a Render Layers node inside):
# the copy would render the scene again and write that; the frame fails instead.
inner = bpy.data.node_groups.new("UA Inner", "CompositorNodeTree")
inner.interface.new_socket("Image", in_out="OUTPUT", socket_type="NodeSocketColor")
inner_rl, inner_out = inner.nodes.new("CompositorNodeRLayers"), inner.nodes.new("NodeGroupOutput")
inner.links.new(inner_rl.outputs["Image"], inner_out.inputs[0])
group_node = invert.nodes.new("CompositorNodeGroup")
group_node.node_tree = inner
invert_node = next(n for n in invert.nodes if n.bl_idname == "CompositorNodeInvert")
invert.links.new(group_node.outputs[0], invert_node.inputs["Color"])
written, dof, report = render("nested_render_layers", True)
checks.check(report is not None and not report["ok"] and "reads the render" in report["message"],
             "a Render Layers node inside a node group: report %r" % (report,))
invert.nodes.remove(group_node)
invert.links.new(next(n for n in invert.nodes if n.bl_idname == "NodeGroupInput").outputs[0],
                 invert_node.inputs["Color"])

if EFFECTS:
    # Two effects in the stack, applied in order: Invert twice gives D back.
    second = new_group("UA Invert 2", invert=True)
    written, dof, report = render("two_effects", True)
    checks.check(report is not None and report["ok"] and max_diff(written, dof) < 1e-3,
                 "two Invert effects: written frame vs D %.4f (vs the pinhole render %.4f); "
                 "report %r" % (max_diff(written, dof), max_diff(written, pinhole), report))
    left = [g.name for g in bpy.data.node_groups if g.get(addon.composite.COPY_KEY)] + \
        [s.name for s in bpy.data.scenes if addon.composite.is_copy(s)]
    checks.check(left == [], "the compositing copies left after the render: %r" % left)
    for effect in [e for e in scene.compositor_effects if e.node_group == second]:
        scene.compositor_effects.remove(effect)
    # No effect: the add-on makes one, and takes it away when unticked, or disabled.
    scene.diffusion_dof.enabled = False
    scene.compositor_effects.clear()
    checks.check(effects() == [], "effects not cleared: %r" % effects())
    scene.diffusion_dof.enabled = True
    written, dof, report = render("made_effect", False)
    checks.check(len(effects()) == 1 and report["ok"] and max_diff(written, dof) < 1e-3,
                 "no effect: %r, written frame vs D %.4f" % (effects(), max_diff(written, dof)))
    scene.diffusion_dof.enabled = False
    checks.check(effects() == [], "unticked: effects left %r" % effects())
    scene.diffusion_dof.enabled = True
    checks.check(len(effects()) == 1, "ticked: effects %r" % effects())
    u.unload_addon(addon)
    checks.check(effects() == [], "disabled: effects left %r" % effects())
else:
    u.unload_addon(addon)
checks.finish()
