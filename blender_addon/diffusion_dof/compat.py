# SPDX-License-Identifier: GPL-3.0-or-later
"""Where Blender's Python API differs between the versions the add-on supports (3.4 to 5.x), and
only there: the rest of the add-on has one code path.

- The compositor tree: scene.use_nodes + scene.node_tree up to 4.x; from 5.0 a node group in
  scene.compositing_node_group, which a scene does not get by itself; 5.3 makes it a stack of
  effects (scene.compositor_effects, each with its node group, applied in order) and deprecates
  compositing_node_group (the active effect's group; setting it makes an effect) for removal.
- The render's image in a 5.x node group: its Group Input's first output (Blender feeds the
  render into it), besides any Render Layers node.
- The Composite node: a render needs one up to 4.x; 5.0 removed it (a render's image is the
  render layers' unless the group has an output).
- The File Output node: base_path + file_slots[].path + use_node_format up to 4.x; 5.0:
  directory + file_name + file_output_items (name, socket type) and a media type in its format.
- Image settings: 5.0 splits the file format by a media type (OPEN_EXR is an IMAGE format,
  OPEN_EXR_MULTILAYER a MULTI_LAYER_IMAGE one).
- Settings groups registered with bpy.props (scene.cycles): readable as ID properties through
  scene["cycles"] up to 4.x; 5.0 no longer exposes them through [], only through RNA.
- A view layer's collections: 5.2 syncs them lazily, so a scene made with bpy.data.scenes.new
  has view_layers[0].layer_collection None until something syncs it.
- The File Output node's file names: up to 5.0 they end in ".exr" only while the scene's
  Output > File Extensions is on; 5.2 always adds it.
- F-curves: an action's own `fcurves` up to 4.x; 4.4 put them in channel bags (per action slot)
  and 5.0 removed `Action.fcurves`.
- Removing an ID while an animation renders: 5.2 re-evaluates the render's depsgraph between
  frames and crashes on a removed image (images.py frees images after the render instead).
"""

import bpy

VERSION = tuple(bpy.app.version)
NODE_GROUP_COMPOSITOR = "compositing_node_group" in bpy.types.Scene.bl_rna.properties  # 5.0+
COMPOSITOR_EFFECTS = "compositor_effects" in bpy.types.Scene.bl_rna.properties  # 5.3+
COMPOSITOR_TREE_NAME = "Compositing"  # the name Blender 5.0's UI gives a new one too
BPY_PROPS_AS_ID_PROPERTIES = VERSION < (5, 0, 0)
# Marks, on the scene, a compositor the add-on made, so that release_compositor_tree undoes just
# that: the name of the 5.x node group it created and assigned, or (3.x/4.x, where it turned
# compositing nodes on) the names of the nodes the tree held then.
MADE_TREE_KEY = "diffusion_dof_made_compositor"
# 5.3: marks the effect node group that holds the add-on's nodes (the active effect's when they
# were added), so that they stay in one group when another effect becomes the active one.
HOLDS_NODES_KEY = "diffusion_dof_holds_nodes"


def layer_collection(view_layer):
    """The view layer's root LayerCollection, synced first: on 5.2+ it is None on a new scene's
    view layer until synced. Reading active_layer_collection syncs it (cheap; ViewLayer.update()
    would also evaluate the whole scene); update() is the fallback."""
    root = view_layer.layer_collection
    if root is None:
        view_layer.active_layer_collection  # noqa: B018 (read for its sync)
        root = view_layer.layer_collection
    if root is None:
        view_layer.update()
        root = view_layer.layer_collection
    return root


def _effect_groups(scene, for_render=False):
    """5.3: the node groups of the scene's compositor effects, in the order they apply."""
    return [e.node_group for e in scene.compositor_effects
            if e.node_group is not None and (e.enable_for_render or not for_render)]


def compositor_tree(scene, even_off=False):
    """The scene's compositor tree, the one that holds (or is to hold) the add-on's nodes, or
    None when it has none (or compositing nodes are off, unless even_off). 5.3: the effect
    group marked as holding them, else the active effect's."""
    if COMPOSITOR_EFFECTS:
        marked = [g for g in _effect_groups(scene) if g.get(HOLDS_NODES_KEY)]
        if marked:
            return marked[0]
        active = scene.compositor_effects.active
        return active.node_group if active is not None else None
    if NODE_GROUP_COMPOSITOR:
        return scene.compositing_node_group
    return scene.node_tree if scene.use_nodes or even_off else None


def compositing_trees(scene):
    """The compositor trees a render applies to the render, in order ([] without compositing
    nodes): 5.3 the node groups of the effects enabled for rendering; else the one tree."""
    if COMPOSITOR_EFFECTS:
        return _effect_groups(scene, for_render=True)
    tree = compositor_tree(scene)
    return [tree] if tree is not None else []


def _new_effect_group(scene, name):
    """5.3: a new compositor effect whose node group hands the render on unchanged (Group
    Input -> Group Output, as Compositor > New makes it)."""
    tree = bpy.data.node_groups.new(name, "CompositorNodeTree")
    tree.interface.new_socket("Image", in_out="INPUT", socket_type="NodeSocketColor")
    tree.interface.new_socket("Image", in_out="OUTPUT", socket_type="NodeSocketColor")
    gi = tree.nodes.new("NodeGroupInput")
    go = tree.nodes.new("NodeGroupOutput")
    gi.location, go.location = (-200.0, 0.0), (200.0, 0.0)
    tree.links.new(gi.outputs[0], go.inputs[0])
    effect = scene.compositor_effects.new(name=name)
    effect.node_group = tree
    return tree


def set_compositor_tree(scene, tree):
    """Makes `tree` the scene's compositor (the copy that runs the user's compositing): 5.3 its
    only effect; 5.0 its node group."""
    if COMPOSITOR_EFFECTS:
        scene.compositor_effects.clear()
        scene.compositor_effects.new(name=tree.name).node_group = tree
    else:
        scene.compositing_node_group = tree


def ensure_compositor_tree(scene):
    """(tree, changed): the scene's compositor tree, made (and turned on) when it has none."""
    if COMPOSITOR_EFFECTS:
        tree = compositor_tree(scene)
        made = tree is None
        if made:
            tree = _new_effect_group(scene, COMPOSITOR_TREE_NAME)
            scene[MADE_TREE_KEY] = tree.name
        if not tree.get(HOLDS_NODES_KEY):
            tree[HOLDS_NODES_KEY] = True
        return tree, made
    if NODE_GROUP_COMPOSITOR:
        tree = scene.compositing_node_group
        if tree is not None:
            return tree, False
        tree = bpy.data.node_groups.new(COMPOSITOR_TREE_NAME, "CompositorNodeTree")
        scene.compositing_node_group = tree
        scene[MADE_TREE_KEY] = tree.name
        return tree, True
    if scene.use_nodes and scene.node_tree is not None:
        return scene.node_tree, False
    scene.use_nodes = True  # a new tree gets Render Layers -> Composite: the same image
    # The nodes it holds now (a new tree's, or those of a tree the user had switched off).
    scene[MADE_TREE_KEY] = [n.name for n in scene.node_tree.nodes]
    return scene.node_tree, True


# Nodes the add-on may add to a 3.x/4.x tree besides its managed ones (a Composite node when
# there is none, with a Render Layers node feeding it): they do nothing to the image.
_PLAIN_NODES = {"CompositorNodeRLayers", "CompositorNodeComposite"}


def release_compositor_tree(scene):
    """Leaves the compositor as it was before ensure_compositor_tree made one, once the add-on's
    nodes are gone: 5.3 removes the effect it made (and its group, when nothing else uses it);
    5.0 unassigns the node group it created (an empty group makes Blender 5.x render nothing)
    and removes it when nothing else uses it; 3.x/4.x turns compositing nodes off again. A tree
    the user has since put nodes of their own into is left as it is. 5.3's mark on the group
    that held the nodes goes too. Returns what it did, as a sentence, or ''."""
    if COMPOSITOR_EFFECTS:
        for tree in _effect_groups(scene):
            if tree.get(HOLDS_NODES_KEY) is not None:
                del tree[HOLDS_NODES_KEY]
    made = scene.get(MADE_TREE_KEY)
    if made is None:
        return ""
    del scene[MADE_TREE_KEY]
    if COMPOSITOR_EFFECTS:
        effect = next((e for e in scene.compositor_effects
                       if e.node_group is not None and e.node_group.name == str(made)), None)
        tree = effect.node_group if effect is not None else None
        if tree is None or any(n.bl_idname not in ("NodeGroupInput", "NodeGroupOutput")
                               for n in tree.nodes):
            return ""
        scene.compositor_effects.remove(effect)
        if tree.users == 0:
            bpy.data.node_groups.remove(tree)
        return "removed the compositor effect it had made"
    if NODE_GROUP_COMPOSITOR:
        tree = scene.compositing_node_group
        if tree is None or tree.name != str(made) or len(tree.nodes):
            return ""
        scene.compositing_node_group = None
        if tree.users == 0:
            bpy.data.node_groups.remove(tree)
        return "removed the empty compositor node group it had made"
    tree = scene.node_tree
    if not scene.use_nodes or tree is None or \
            any(n.name not in made and n.bl_idname not in _PLAIN_NODES for n in tree.nodes):
        return ""
    scene.use_nodes = False
    return "turned compositing nodes off again"


def needs_composite_node():
    """Whether a render needs a Composite node in the tree (up to 4.x)."""
    return not NODE_GROUP_COMPOSITOR


def output_node(tree):
    """The node whose image the compositor outputs: the Composite node up to 4.x, the group
    output from 5.0; None when there is none."""
    kind = "NodeGroupOutput" if NODE_GROUP_COMPOSITOR else "CompositorNodeComposite"
    return next((n for n in tree.nodes if n.bl_idname == kind), None)


def is_render_input(node):
    """Whether the node is a 5.x node group's Group Input, whose first output Blender feeds
    the render into."""
    return NODE_GROUP_COMPOSITOR and node.bl_idname == "NodeGroupInput"


# -- the File Output node --------------------------------------------------------------------


def file_output_paths(node):
    """The file names (without the folder) the node's inputs write, in input order."""
    if hasattr(node, "file_output_items"):
        return [item.name for item in node.file_output_items]
    return [slot.path for slot in node.file_slots]


def set_file_output_paths(node, paths, socket_types):
    """Makes a new File Output node write `paths` (one per input, socket_types: 'RGBA' or
    'FLOAT') with the node's own format. Only ever adds (Blender 3.4 leaks memory when a file
    slot is removed): a node with other paths is to be replaced as a whole by the caller."""
    if hasattr(node, "file_output_items"):
        for path, kind in zip(paths[len(node.file_output_items):],
                              socket_types[len(node.file_output_items):]):
            node.file_output_items.new(kind, path)
        for item in node.file_output_items:
            if item.override_node_format:
                item.override_node_format = False
        if node.file_name:
            node.file_name = ""
        return
    node.file_slots[0].path = paths[0]  # a new node has one slot, "Image"
    for path in paths[1:]:
        node.file_slots.new(path)
    for slot in node.file_slots:
        slot.use_node_format = True


def file_output_folder(node):
    return node.directory if hasattr(node, "directory") else node.base_path


def file_output_extension(scene):
    """The ending a File Output node gives its OpenEXR files: up to 5.0 ".exr" only while the
    scene's Output properties > File Extensions is on; 5.2 always (5.1 not checked)."""
    if VERSION >= (5, 2, 0) or scene.render.use_file_extension:
        return ".exr"
    return ""


def set_file_output_folder(node, folder):
    if hasattr(node, "directory"):
        if node.directory != folder:
            node.directory = folder
    elif node.base_path != folder:
        node.base_path = folder


def set_file_format(image_settings, file_format):
    """Sets an ImageFormatSettings' file format; 5.0 needs the media type of the format first."""
    if hasattr(image_settings, "media_type"):
        media = "MULTI_LAYER_IMAGE" if file_format == "OPEN_EXR_MULTILAYER" else "IMAGE"
        if image_settings.media_type != media:
            image_settings.media_type = media
    if image_settings.file_format != file_format:
        image_settings.file_format = file_format


# -- settings groups ---------------------------------------------------------------------------


def _rna_values(group):
    """{identifier: value} of a property group's writable, plain values (nested groups too)."""
    values = {}
    for prop in group.bl_rna.properties:
        key = prop.identifier
        if key == "rna_type" or prop.is_readonly and prop.type != "POINTER":
            continue
        if prop.type == "POINTER":
            value = getattr(group, key)
            if value is not None and isinstance(value, bpy.types.PropertyGroup):
                values[key] = _rna_values(value)
            continue
        if prop.type == "COLLECTION":
            continue
        value = getattr(group, key)
        if getattr(prop, "is_array", False):
            value = tuple(value)
        values[key] = value
    return values


def _set_rna_values(group, values):
    for key, value in values.items():
        if isinstance(value, dict):
            _set_rna_values(getattr(group, key), value)
        elif getattr(group, key) != value and not isinstance(getattr(group, key), bpy.types.ID):
            try:
                setattr(group, key, value)
            except (AttributeError, TypeError, ValueError):
                pass  # a value this property takes only in some states: left as it is


def copy_settings_group(source, target, key):
    """Copies an add-on settings group (e.g. scene.cycles) from one ID to another, writing only
    changes. Up to 4.x as raw ID properties (exact, and without reading enum values this build
    may not know); 5.0 exposes them only through RNA, so there property by property."""
    if BPY_PROPS_AS_ID_PROPERTIES:
        data = source.get(key)
        data = data.to_dict() if data is not None else None
        current = target.get(key)
        current = current.to_dict() if current is not None else None
        if data != current:
            if data is None:
                del target[key]
            else:
                target[key] = data
        return
    group = getattr(source, key, None)
    if group is None:
        return
    _set_rna_values(getattr(target, key), _rna_values(group))


# -- animation -----------------------------------------------------------------------------


def fcurves(id_data):
    """The F-curves animating an ID ({data_path: FCurve}); empty when it has none."""
    ad = getattr(id_data, "animation_data", None)
    action = ad.action if ad is not None else None
    if action is None:
        return {}
    slot = getattr(ad, "action_slot", None)
    curves = None
    if slot is not None:  # 4.4+: slotted actions
        try:
            from bpy_extras import anim_utils
            bag = anim_utils.action_get_channelbag_for_slot(action, slot)
            curves = bag.fcurves if bag is not None else []
        except (ImportError, AttributeError):
            curves = None
    if curves is None:
        curves = getattr(action, "fcurves", [])
    return {fc.data_path: fc for fc in curves if fc.array_index == 0}
