# SPDX-License-Identifier: GPL-3.0-or-later
"""Depth of field before the user's compositing.

Depth of field is a lens effect: it belongs before glare, grading, a vignette or an Alpha Over
of view layers, not instead of them. The compositor runs inside the render, before the add-on
gets the passes, so the add-on runs it a second time on the depth-of-field image: a copy of the
scene whose compositor is the user's tree (3.x/4.x: the scene's embedded tree, copied with the
scene; 5.x: a copy of the scene's node group) with every Render Layers node replaced by Image
nodes: the depth-of-field image for the view layer's Combined (and Alpha), and for every other
pass the tree reads, that pass as rendered (written by the managed File Output node next to
Combined and Depth, see passes.py). Blender composites without rendering when a compositor
reads no Render Layers node, so rendering the copy costs a compositor run (about 15 ms at
160x90). Its Render Result is saved as a float OpenEXR and read back as pixels.

The user's scene and tree are never changed: the copy is made at the first frame that needs it
and removed once no render runs (Blender 5.2 crashes when data is removed during an animation
render). A scene whose compositor hands the view layer's image straight to its output has no
compositing: it keeps the path without this pass.
"""

import os
import zlib

import bpy

from . import compat, managed
from .errors import SetupError

COPY_KEY = "diffusion_dof_compositing_copy"  # on the copy (and its 5.x node group): the scene
RAW_IMAGE = "Diffusion DOF Raw"              # the depth-of-field image, before compositing
PASS_IMAGE = ".Diffusion DOF Pass %s"        # a pass as rendered, by its slot
IMAGE_NODE = "DDOF Image %s"
DOF_KEY = "dof"
RLAYERS = "CompositorNodeRLayers"
# True while the copy renders: that render's handlers must leave everything alone (it runs
# inside the processing of a frame, and it is not a render of the user's).
running = False


def is_copy(scene):
    return scene.get(COPY_KEY) is not None


def _user_render_layers(tree):
    return [n for n in tree.nodes if n.bl_idname == RLAYERS and n.name not in managed.MANAGED_NODES]


def _is_dof_layer(node, scene, layer_name, copy=None):
    """Whether a Render Layers node reads the view layer that gets depth of field (in a copy of
    the scene, its nodes may point at the copy)."""
    return node.scene in (None, scene, copy) and node.layer == layer_name


def _hands_on_render(tree, scene, layer_name):
    """Whether a compositor tree outputs the render as it is: its output fed straight from the
    depth-of-field view layer's Image (a Render Layers node, or 5.x's Group Input), or no
    output at all (5.x: the render layers' image then)."""
    out = compat.output_node(tree)
    if out is None or not out.inputs or not out.inputs[0].is_linked:
        return True
    link = out.inputs[0].links[0]
    source = link.from_node
    if source.mute:
        return False
    if compat.is_render_input(source):
        return link.from_socket == source.outputs[0]
    return (source.bl_idname == RLAYERS and source.name not in managed.MANAGED_NODES
            and link.from_socket.name == "Image" and _is_dof_layer(source, scene, layer_name))


def has_compositing(scene, settings):
    """Whether the compositor does more to the written image than hand on the depth-of-field
    view layer's Image (anything between it and the output, another view layer, ...)."""
    if not scene.render.use_compositing:
        return False
    layer = managed.render_view_layer(scene, settings).name
    return not all(_hands_on_render(tree, scene, layer)
                   for tree in compat.compositing_trees(scene))


def slot_name(node_name, socket_name):
    """The managed File Output slot of one pass of one Render Layers node: stable across runs
    and free of the characters a file name cannot hold."""
    tag = zlib.crc32(("%s\0%s" % (node_name, socket_name)).encode("utf-8")) & 0xffffffff
    return "pass%08x_" % tag


def _socket_kind(socket):
    return {"VALUE": "FLOAT", "VECTOR": "VECTOR"}.get(socket.type, "RGBA")


def pass_slots(scene, settings):
    """[(slot, node name, socket name, kind)] of the passes the user's compositing reads besides
    the depth-of-field image (the Alpha of another view layer comes with its Image): what the
    managed File Output node writes for it. Empty without compositing."""
    if not has_compositing(scene, settings):
        return []
    layer = managed.render_view_layer(scene, settings).name
    slots = {}
    for node in [n for tree in compat.compositing_trees(scene) for n in _user_render_layers(tree)]:
        if node.mute:
            continue
        dof = _is_dof_layer(node, scene, layer)
        for socket in node.outputs:
            if not socket.is_linked or not socket.enabled:
                continue
            name = "Image" if socket.name == "Alpha" else socket.name
            if dof and name == "Image":
                continue
            source = node.outputs[name]
            slots[slot_name(node.name, name)] = (node.name, name, _socket_kind(source))
    return [(slot,) + slots[slot] for slot in sorted(slots)]


# ---------------------------------------------------------------------------------------------
# The copy that composites


def _copy_tree(copy):
    return compat.compositor_tree(copy, even_off=True)


def _new_image_node(tree, key, image, location):
    node = tree.nodes.new("CompositorNodeImage")
    node.name = IMAGE_NODE % key
    node.image = image
    node.location = location
    return node


def _replace_render_layers(tree, node, dof, images):
    """Feeds every link out of a Render Layers node from Image nodes instead (the depth-of-field
    image for the view layer's Image and Alpha; the pass's image otherwise) and removes it."""
    for socket in node.outputs:
        if not socket.is_linked:
            continue
        name = "Image" if socket.name == "Alpha" else socket.name
        key = DOF_KEY if dof and name == "Image" else slot_name(node.name, name)
        if key not in images:
            raise SetupError("your compositor reads the pass '%s' of Render Layers node '%s', "
                             "which was not written for the add-on: click Set Up Passes and "
                             "render again" % (name, node.name))
        image_node = tree.nodes.get(IMAGE_NODE % key) or \
            _new_image_node(tree, key, images[key], node.location)
        out = image_node.outputs["Alpha" if socket.name == "Alpha" else "Image"]
        for link in list(socket.links):
            tree.links.new(out, link.to_socket)
    tree.nodes.remove(node)


def _replace_group_input(tree, node, images):
    """5.x: feeds the links out of the Group Input's first output (the render) from the
    depth-of-field image instead, and removes the node (with a Group Input Blender renders
    the scene again for the copy)."""
    for index, socket in enumerate(node.outputs):
        if not socket.is_linked:
            continue
        if index != 0:
            raise SetupError("your compositor reads its Group Input's '%s', which the add-on "
                             "cannot give it on the depth-of-field image" % socket.name)
        image_node = tree.nodes.get(IMAGE_NODE % DOF_KEY) or \
            _new_image_node(tree, DOF_KEY, images[DOF_KEY], node.location)
        for link in list(socket.links):
            tree.links.new(image_node.outputs["Image"], link.to_socket)
    tree.nodes.remove(node)


def _render_reader(tree, top=False, seen=()):
    """The name of a node in the tree (or in a node group it uses) through which the compositor
    still reads the render: a Render Layers node, or the top tree's Group Input (5.x); else
    None."""
    for node in tree.nodes:
        if node.bl_idname == RLAYERS or top and compat.is_render_input(node):
            return node.name
        group = getattr(node, "node_tree", None)
        if group is not None and group not in seen:
            inner = _render_reader(group, seen=seen + (group,))
            if inner is not None:
                return "%s > %s" % (node.name, inner)
    return None


def _own_copy(tree, scene):
    group = tree.copy()
    group[COPY_KEY] = scene.name
    return group


def _effect_chain(trees, scene):
    """5.3's stack of effects as one node group that applies them in order: a group node of a
    copy of each, the first fed from the Group Input (the render, replaced like a user's), each
    next one from the one before."""
    chain = bpy.data.node_groups.new("DDOF Compositing: " + scene.name, "CompositorNodeTree")
    chain[COPY_KEY] = scene.name
    chain.interface.new_socket("Image", in_out="INPUT", socket_type="NodeSocketColor")
    chain.interface.new_socket("Image", in_out="OUTPUT", socket_type="NodeSocketColor")
    source = chain.nodes.new("NodeGroupInput").outputs[0]
    for k, tree in enumerate(trees):
        node = chain.nodes.new("CompositorNodeGroup")
        node.node_tree = _own_copy(tree, scene)
        node.location = (200.0 * (k + 1), 0.0)
        if not node.inputs or not node.outputs:
            raise SetupError("compositor effect '%s' has no image input or output" % tree.name)
        chain.links.new(source, node.inputs[0])
        source = node.outputs[0]
    chain.links.new(source, chain.nodes.new("NodeGroupOutput").inputs[0])
    return chain


def _prepare(tree, scene, layer, copy, images):
    """The user's tree (a copy) made to read the images: without the managed nodes, every
    Render Layers node replaced."""
    for name in managed.MANAGED_NODES:
        node = tree.nodes.get(name)
        if node is not None:
            tree.nodes.remove(node)
    for node in _user_render_layers(tree):
        _replace_render_layers(tree, node, _is_dof_layer(node, scene, layer, copy), images)


def _make_copy(scene, settings, images):
    copy = scene.copy()
    copy[COPY_KEY] = scene.name
    for key in [k for k in copy.keys() if k.startswith("diffusion_dof_")]:
        if key != COPY_KEY:
            del copy[key]  # e.g. the overscan's restore record: the user's scene's alone
    copy.name = "DDOF Compositing: " + scene.name
    layer = managed.render_view_layer(scene, settings).name
    try:
        if compat.NODE_GROUP_COMPOSITOR:
            trees = compat.compositing_trees(scene)
            tree = _own_copy(trees[0], scene) if len(trees) == 1 else _effect_chain(trees,
                                                                                   scene)
            compat.set_compositor_tree(copy, tree)
            for node in tree.nodes if len(trees) > 1 else ():
                if node.bl_idname == "CompositorNodeGroup":
                    _prepare(node.node_tree, scene, layer, copy, images)
        tree = _copy_tree(copy)
        _prepare(tree, scene, layer, copy, images)
        for node in [n for n in tree.nodes if compat.is_render_input(n)]:
            _replace_group_input(tree, node, images)
    except SetupError:
        bpy.data.scenes.remove(copy)
        raise
    r = copy.render
    r.use_sequencer = False  # the compositor alone
    r.use_border = False
    r.resolution_percentage = 100
    fmt = r.image_settings
    compat.set_file_format(fmt, "OPEN_EXR")
    fmt.color_depth = "32"
    fmt.color_mode = "RGBA"
    fmt.exr_codec = "NONE"
    return copy


def _copy_of(scene):
    return next((s for s in bpy.data.scenes if s.get(COPY_KEY) == scene.name), None)


def run(scene, settings, frame, images, width, height):
    """Runs the user's compositing on the images {DOF_KEY: the depth-of-field image, slot: a
    pass} for `frame`; returns the path of the float OpenEXR it wrote (in the scene's
    temporary folder). Raises SetupError with what went wrong."""
    copy = _copy_of(scene)
    if copy is None:
        copy = _make_copy(scene, settings, images)
    tree = _copy_tree(copy)
    reader = _render_reader(tree, top=True)
    if reader is not None:
        # Rendering the copy would render the scene again and composite that, without the
        # depth of field.
        raise SetupError("your compositing reads the render through '%s', which the add-on "
                         "cannot give the depth-of-field image" % reader)
    for key, image in images.items():
        node = tree.nodes.get(IMAGE_NODE % key)
        if node is not None and node.image != image:
            node.image = image
    copy.render.resolution_x, copy.render.resolution_y = width, height
    copy.frame_current = frame
    global running
    running = True
    try:
        result = bpy.ops.render.render(scene=copy.name)
    except RuntimeError as err:
        raise SetupError("your compositing could not run on the depth-of-field image: %s"
                         % str(err).strip()) from None
    finally:
        running = False
    rendered = next((i for i in bpy.data.images if i.type == "RENDER_RESULT"), None)
    if "FINISHED" not in result or rendered is None:
        raise SetupError("your compositing did not run on the depth-of-field image (%s)"
                         % ", ".join(sorted(result)))
    path = os.path.join(managed.temp_dir(scene), "composited_%d.exr" % frame)
    try:
        rendered.save_render(path, scene=copy)
    except RuntimeError as err:
        raise SetupError("could not save the composited frame: %s" % str(err).strip()) from None
    return path


def remove_copies():
    """Removes the compositing copies and their node groups (only when no render runs)."""
    for copy in [s for s in bpy.data.scenes if is_copy(s)]:
        bpy.data.scenes.remove(copy, do_unlink=True)
    if compat.NODE_GROUP_COMPOSITOR:
        # A copy of a 5.3 effect is used by the group that chains them: removed after it.
        while True:
            spent = [g for g in bpy.data.node_groups
                     if g.get(COPY_KEY) is not None and g.users == 0]
            if not spent:
                break
            for group in spent:
                bpy.data.node_groups.remove(group)
