# SPDX-License-Identifier: GPL-3.0-or-later
"""Getting the passes out of a render.

Blender cannot run Python inside the compositor, and a render result's pixels are not readable
from Python. What does work, in the UI and in background mode, for stills and animations: a
File Output node in the scene's compositor writes the Combined and Depth passes of every
rendered frame as float OpenEXR files into the session's temporary folder, and the queued
frame (frame_inputs.py, images.py) loads them as images and reads their pixels. This module adds
and removes those managed nodes (inside a frame labelled "Diffusion DOF"), turns on what they
need (the Depth pass, compositing) and, for a foreground collection, keeps a companion scene
that renders just that collection with a transparent film.
"""

import os
import traceback

import bpy

from . import compat, composite, object_matte, scene_settings
from . import camera as camera_mod
from .errors import SetupError
# The managed nodes' names and folders live in managed.py (composite.py reads them too); they are
# this module's vocabulary, so they are named here as well.
from .managed import (FG_OUTPUT_NODE, FG_RLAYERS_NODE, FRAME_NODE,  # noqa: F401
                      MANAGED_NODES, MATTE_OUTPUT_NODE, OUTPUT_NODE, RLAYERS_NODE,
                      render_view_layer, temp_dir)

SLOT_COLOR = "color_"
SLOT_DEPTH = "depth_"
SLOT_FG_COLOR = "fg_color_"
SLOT_FG_DEPTH = "fg_depth_"
FRAME_DIGITS = 6
COMPANION_PREFIX = "DDOF Foreground"
COMPANION_LOOSE = "DDOF Loose Objects"
# Marks data the add-on owns (custom property on the companion scene and its collection).
OWNER_KEY = "diffusion_dof_owner"


# ---------------------------------------------------------------------------------------------
# Paths


def frame_files(scene, frame, foreground=False, extra=(), matte=()):
    """{slot: path} of the files the File Output node wrote for a frame (called once they are
    written). Whether their names end in ".exr" depends on the Blender version and the scene's
    Output properties > File Extensions (compat.file_output_extension): the name that exists
    is taken, else the one expected."""
    folder = temp_dir(scene)
    if frame < 0:  # as Blender fills '#' for negative frames: the sign takes one digit
        number = "-%0*d" % (FRAME_DIGITS - 1, -frame)
    else:
        number = "%0*d" % (FRAME_DIGITS, frame)
    expected = compat.file_output_extension(scene)
    slots = [SLOT_COLOR, SLOT_DEPTH] + ([SLOT_FG_COLOR, SLOT_FG_DEPTH] if foreground else []) \
        + list(extra) + list(matte)
    files = {}
    for slot in slots:
        stem = os.path.join(folder, slot + number)
        files[slot] = next((p for p in (stem + expected, stem + ".exr", stem)
                            if os.path.isfile(p)), stem + expected)
    return files


def missing_pass_reason(scene, settings, path):
    """Why the pass file `path` is not there, as a phrase: what is not set up, or what the
    folder holds instead."""
    if not scene.render.use_compositing:
        return "Output properties > Post Processing > Compositing is off"
    problem = missing_setup(scene, settings)
    if problem:
        return problem + " (click Set Up Passes)"
    tree = node_tree(scene)
    out = tree.nodes.get(OUTPUT_NODE) if tree is not None else None
    if out is not None and out.mute:
        return "the managed File Output node '%s' is muted" % OUTPUT_NODE
    folder = os.path.dirname(path)
    try:
        found = sorted(os.listdir(folder))
    except OSError:
        found = []
    if found:
        shown = ", ".join(found[:4]) + (", ..." if len(found) > 4 else "")
        return ("there is no %s in %s, which holds %s"
                % (os.path.basename(path), folder, shown))
    return "the compositor did not write it to %s (did the compositor run?)" % folder


# ---------------------------------------------------------------------------------------------
# Looking things up


def node_tree(scene):
    """The scene's compositor tree (None while it has none or compositing nodes are off)."""
    return compat.compositor_tree(scene)


def _find_layer_collection(layer_collection, collection):
    if layer_collection.collection == collection:
        return layer_collection
    for child in layer_collection.children:
        found = _find_layer_collection(child, collection)
        if found is not None:
            return found
    return None


def companion_scene(scene):
    """The companion scene that renders the foreground collection, or None."""
    for other in bpy.data.scenes:
        if other.get(OWNER_KEY) == scene.name and other != scene:
            return other
    return None


# ---------------------------------------------------------------------------------------------
# Problems the panel shows before a render


def diagnose(scene):
    """[(level, text)] of what stops or degrades depth of field now: level 'ERROR' or 'WARNING'.
    Never raises."""
    settings = scene_settings.get(scene)
    problems = []
    if settings is None:
        return problems
    try:
        camera_mod.camera_settings(scene, settings)
    except SetupError as err:
        problems.append(("ERROR", str(err)))
    cam = scene.camera
    if cam is not None and cam.type == "CAMERA" and cam.data.dof.use_dof:
        problems.append(("WARNING", "Camera '%s' has lens depth of field on, so the render is "
                         "already blurred and Diffusion DOF would blur it twice. Turn off Camera "
                         "properties > Depth of Field (its focus and f-stop still drive "
                         "Diffusion DOF), or click Use Pinhole Render. Background renders do "
                         "this for you." % cam.name))
    try:
        layer = render_view_layer(scene, settings)
        if not layer.use_pass_z:
            problems.append(("ERROR", "View layer '%s' has no Depth pass. Enable View Layer "
                             "properties > Passes > Data > Z, or click Set Up Passes."
                             % layer.name))
        problem = missing_setup(scene, settings) if settings.enabled else ""
        if problem and layer.use_pass_z:
            problems.append(("ERROR", "Not set up for rendering (%s): click Set Up Passes."
                             % problem))
    except SetupError as err:
        problems.append(("ERROR", str(err)))
    if settings.foreground_collection is not None and scene.render.engine != "CYCLES":
        problems.append(("WARNING", "The foreground collection needs Cycles (indirect-only "
                         "collections); with %s it is rendered but also stays in the main "
                         "render." % scene.render.engine.title()))
    return problems


def missing_setup(scene, settings):
    """What is not set up for a render, as a short phrase, or '' when all is in place."""
    try:
        tree = node_tree(scene)
        layer = render_view_layer(scene, settings)
    except SetupError as err:
        return str(err)
    if not layer.use_pass_z:
        return "the Depth pass of view layer '%s' is off" % layer.name
    if tree is None:
        return "compositing nodes are off"
    if not scene.render.use_compositing:
        return "Output properties > Post Processing > Compositing is off"
    out = tree.nodes.get(OUTPUT_NODE)
    rl = tree.nodes.get(RLAYERS_NODE)
    if out is None or rl is None or rl.layer != layer.name:
        return "the managed compositor nodes are missing"
    if os.path.normpath(bpy.path.abspath(compat.file_output_folder(out))) != \
            os.path.normpath(temp_dir(scene)):
        return ("the managed File Output node writes to another folder (another Blender "
                "session or scene name)")
    if compat.file_output_paths(out) != _slot_paths(_main_slots(scene, settings)[0]):
        return "the passes your compositing reads are not all written for the add-on"
    if matte_slots(scene) != object_matte.slots(matte_layers(scene, settings)):
        return "the object matte's passes are not set up as the view layer renders them"
    want_fg = settings.foreground_collection is not None
    if want_fg != (tree.nodes.get(FG_OUTPUT_NODE) is not None):
        return "the foreground setup is out of date"
    if want_fg and companion_scene(scene) is None:
        return "the foreground companion scene is missing"
    return ""


# ---------------------------------------------------------------------------------------------
# Setting up and tearing down


def _new_node(tree, kind, name, label, location, parent):
    node = tree.nodes.get(name)
    if node is not None and node.bl_idname != kind:
        tree.nodes.remove(node)
        node = None
    if node is None:
        node = tree.nodes.new(kind)
        node.name = name
        node.location = location
    node.label = label
    if parent is not None and node != parent:
        node.parent = parent
    return node


def _configure_format(fmt):
    compat.set_file_format(fmt, "OPEN_EXR")
    fmt.color_depth = "32"
    fmt.color_mode = "RGBA"
    fmt.exr_codec = "NONE"  # temporary files: no time spent compressing


def ensure_setup(scene):
    """Makes the scene ready for Diffusion DOF renders; returns what it changed, as sentences.
    Raises SetupError when it cannot (the message says why), and nothing else: any other error
    of a setup step (a Blender API that changed, a bug) becomes a SetupError too, so that no
    caller (register(), a handler, a property update) lets it through half-way."""
    try:
        return _ensure_setup(scene)
    except SetupError:
        raise
    except Exception as err:
        traceback.print_exc()
        raise SetupError("Could not set up scene '%s' for Diffusion DOF (an error in the add-on "
                         "with this Blender %s: %s: %s). Please report it."
                         % (scene.name, bpy.app.version_string, type(err).__name__, err)) \
            from err


def _ensure_setup(scene):
    settings = scene_settings.get(scene)
    changes = []
    tree = node_tree(scene)
    layer = render_view_layer(scene, settings)
    if not layer.use_pass_z:
        layer.use_pass_z = True
        changes.append("enabled the Depth pass of view layer '%s'" % layer.name)
    tree, made = compat.ensure_compositor_tree(scene)
    if made:
        changes.append("turned on compositing nodes")
    if not scene.render.use_compositing:
        scene.render.use_compositing = True
        changes.append("turned on Post Processing > Compositing")
    if compat.needs_composite_node() and compat.output_node(tree) is None:
        composite = tree.nodes.new("CompositorNodeComposite")
        source = next((n for n in tree.nodes if n.bl_idname == "CompositorNodeRLayers"
                       and n.name not in MANAGED_NODES), None)
        if source is not None:
            tree.links.new(source.outputs["Image"], composite.inputs["Image"])
        changes.append("added a Composite node (a render needs one)")

    lowest = min((n.location.y - n.dimensions.y for n in tree.nodes
                  if n.name not in MANAGED_NODES), default=0.0)
    x0, y0 = -300.0, lowest - 120.0
    frame = _new_node(tree, "NodeFrame", FRAME_NODE, "Diffusion DOF (managed by the add-on)",
                      (x0 - 20.0, y0 + 40.0), None)
    frame.label_size = 16
    rl = _new_node(tree, "CompositorNodeRLayers", RLAYERS_NODE, "Diffusion DOF: main passes",
                   (x0, y0), frame)
    rl.scene = scene
    rl.layer = layer.name
    folder = temp_dir(scene)
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError as err:  # a setup problem the user can fix: a message, not a traceback
        raise SetupError(f"Diffusion DOF cannot create its folder for the render passes "
                         f"({folder}): {err.strerror}. Check the temporary folder in "
                         f"Preferences > File Paths.") from err
    slots, kinds, sources = _main_slots(scene, settings)
    out = _output_node(tree, OUTPUT_NODE, "Diffusion DOF: passes to the add-on",
                       (x0 + 320.0, y0), frame, folder, slots, kinds)
    depth_socket = _depth_socket(rl)
    links = [(rl.outputs["Image"], out.inputs[0]), (depth_socket, out.inputs[1])]
    # The other passes the user's compositing reads, as rendered (composite.py).
    links += [(tree.nodes[node].outputs[socket], out.inputs[2 + i])
              for i, (node, socket) in enumerate(sources)]
    links += _matte_links(tree, rl, matte_layers(scene, settings), frame, folder,
                          (x0 + 320.0, y0 - 220.0))

    fg_collection = settings.foreground_collection
    if fg_collection is not None:
        companion, fg_changes = ensure_companion(scene, layer, fg_collection)
        changes.extend(fg_changes)
        fg_rl = _new_node(tree, "CompositorNodeRLayers", FG_RLAYERS_NODE,
                          "Diffusion DOF: foreground passes", (x0, y0 - 420.0), frame)
        fg_rl.scene = companion
        fg_rl.layer = companion.view_layers[0].name
        fg_out = _output_node(tree, FG_OUTPUT_NODE, "Diffusion DOF: foreground to the add-on",
                              (x0 + 320.0, y0 - 420.0), frame, folder,
                              (SLOT_FG_COLOR, SLOT_FG_DEPTH), ("RGBA", "FLOAT"))
        fg_depth = _depth_socket(fg_rl)
        links += [(fg_rl.outputs["Image"], fg_out.inputs[0]), (fg_depth, fg_out.inputs[1])]
    else:
        for name in (FG_RLAYERS_NODE, FG_OUTPUT_NODE):
            node = tree.nodes.get(name)
            if node is not None:
                tree.nodes.remove(node)
        changes.extend(remove_companion(scene))
    for source, target in links:
        if not any(l.from_socket == source for l in target.links):
            for old in list(target.links):
                tree.links.remove(old)
            tree.links.new(source, target)
    return changes


def matte_layers(scene, settings):
    """The CryptoObject sub-layers to write for the add-on: none with Object Matte off or
    without the view layer's Cryptomatte Object pass (never turned on for the user)."""
    layer = render_view_layer(scene, settings)
    if settings.object_matte == "OFF" or not layer.use_pass_cryptomatte_object:
        return 0
    return object_matte.layer_count(layer.pass_cryptomatte_depth)


def object_matte_hint(scene, settings):
    """A sentence for the panel when Object Matte is Auto but the pass is off, else ''."""
    try:
        layer = render_view_layer(scene, settings)
    except SetupError:
        return ""
    if settings.object_matte == "OFF" or layer.use_pass_cryptomatte_object:
        return ""
    return ("View Layer > Passes > Cryptomatte > Object is off: turning it on sharpens thin "
            "in-focus edges over a blurred background.")


def _matte_links(tree, rl, count, frame, folder, location):
    """The managed File Output node of the CryptoObject sub-layers (32-bit float RGBA, as
    data: the ids' bits must survive) and its links; the node removed when count is 0."""
    if count == 0:
        node = tree.nodes.get(MATTE_OUTPUT_NODE)
        if node is not None:
            tree.nodes.remove(node)
        return []
    names = [object_matte.SOCKET % k for k in range(count)]
    missing = [name for name in names if rl.outputs.get(name) is None]
    if missing:
        raise SetupError("The Render Layers node of view layer '%s' has no %s output in this "
                         "Blender version." % (rl.layer, missing[0]))
    out = _output_node(tree, MATTE_OUTPUT_NODE, "Diffusion DOF: object matte to the add-on",
                       location, frame, folder, object_matte.slots(count), ("RGBA",) * count)
    return [(rl.outputs[name], out.inputs[k]) for k, name in enumerate(names)]


def matte_slots(scene):
    """The slots of the object matte's File Output node, as it is set up now ([] without it);
    read-only, so safe on the render thread."""
    tree = node_tree(scene)
    out = tree.nodes.get(MATTE_OUTPUT_NODE) if tree is not None else None
    if out is None:
        return []
    return [p[:-FRAME_DIGITS] for p in compat.file_output_paths(out)]


def _depth_socket(node):
    socket = node.outputs.get("Depth") or node.outputs.get("Z")  # "Z" before Blender 2.8x
    if socket is None:
        raise SetupError("The Render Layers node of view layer '%s' has no Depth output in this "
                         "Blender version." % node.layer)
    return socket


def _slot_paths(slots):
    return [slot + "#" * FRAME_DIGITS for slot in slots]


def _main_slots(scene, settings):
    """(slots, socket kinds, [(node, socket)] of the extra passes) of the main File Output node:
    Combined and Depth, then the passes the user's compositing reads (composite.pass_slots)."""
    extra = composite.pass_slots(scene, settings)
    return ((SLOT_COLOR, SLOT_DEPTH) + tuple(e[0] for e in extra),
            ("RGBA", "FLOAT") + tuple(e[3] for e in extra), [(e[1], e[2]) for e in extra])


def extra_slots(scene):
    """The slots of the main File Output node beyond Combined and Depth (the passes the user's
    compositing reads), as it is set up now; read-only, so safe on the render thread."""
    tree = node_tree(scene)
    out = tree.nodes.get(OUTPUT_NODE) if tree is not None else None
    if out is None:
        return []
    return [p[:-FRAME_DIGITS] for p in compat.file_output_paths(out)[2:]]


def _output_node(tree, name, label, location, parent, folder, slots, kinds):
    """A File Output node writing float EXRs of `slots` (socket kinds `kinds`) into folder.
    Slots are only ever added (Blender 3.4 leaks memory when a file slot is removed): a node
    with other slots is replaced as a whole."""
    wanted = _slot_paths(slots)
    node = tree.nodes.get(name)
    if node is not None and (node.bl_idname != "CompositorNodeOutputFile"
                             or compat.file_output_paths(node) != wanted):
        tree.nodes.remove(node)
    node = _new_node(tree, "CompositorNodeOutputFile", name, label, location, parent)
    if compat.file_output_paths(node) != wanted:
        compat.set_file_output_paths(node, wanted, list(kinds))
    compat.set_file_output_folder(node, folder + os.sep)
    _configure_format(node.format)
    return node


def teardown(scene):
    """Removes the managed nodes and the companion scene, and a compositor tree the add-on made
    (so the scene renders as before: the Depth pass stays on). Returns what it changed."""
    tree = compat.compositor_tree(scene, even_off=True)
    if tree is not None:
        for name in MANAGED_NODES:
            node = tree.nodes.get(name)
            if node is not None:
                tree.nodes.remove(node)
    changes = remove_companion(scene)
    released = compat.release_compositor_tree(scene)
    return changes + ([released] if released else [])


# ---------------------------------------------------------------------------------------------
# The foreground companion scene
#
# Cycles makes the film transparent per scene, not per view layer (a view layer with the
# world switched off still has alpha 1), so the foreground element, which needs a real alpha,
# is rendered by a companion scene: it links the same collections and camera, renders the
# foreground collection normally and everything else as indirect-only (invisible to the camera
# but in the lighting), with a transparent film. The main scene's compositor renders it through
# a Render Layers node. In the main view layer the foreground collection becomes indirect-only,
# so the main passes show what is behind it.

_SYNCED_RENDER = ("engine", "resolution_x", "resolution_y", "resolution_percentage",
                  "pixel_aspect_x", "pixel_aspect_y", "use_border", "border_min_x",
                  "border_min_y", "border_max_x", "border_max_y", "use_crop_to_border",
                  "use_motion_blur", "motion_blur_shutter", "threads_mode", "threads")


def sync_companion(scene, companion):
    """Copies what decides the picture from the main scene (idempotent: writes only changes)."""
    for name in _SYNCED_RENDER:
        value = getattr(scene.render, name)
        if getattr(companion.render, name) != value:
            setattr(companion.render, name, value)
    if not companion.render.film_transparent:
        companion.render.film_transparent = True
    if companion.render.use_compositing:
        companion.render.use_compositing = False
    if companion.camera != scene.camera:
        companion.camera = scene.camera
    if companion.world != scene.world:
        companion.world = scene.world
    if companion.unit_settings.scale_length != scene.unit_settings.scale_length:
        companion.unit_settings.scale_length = scene.unit_settings.scale_length
    compat.copy_settings_group(scene, companion, "cycles")


def _contains(collection, target):
    return collection == target or any(_contains(c, target) for c in collection.children)


def _mark_indirect(lc, fg_collection, inside=False):
    """Everything indirect-only except the foreground collection (with its children) and the
    collections on the way to it. Indirect-only passes down to children, and an object reached
    through any indirect-only path is indirect-only: objects placed directly in a parent of the
    foreground collection are therefore visible too (keep the foreground collection top-level)."""
    inside = inside or lc.collection == fg_collection
    want = not inside and not _contains(lc.collection, fg_collection)
    if lc.indirect_only != want:
        lc.indirect_only = want
    if not want:
        for child in lc.children:
            _mark_indirect(child, fg_collection, inside)


def ensure_companion(scene, layer, fg_collection):
    changes = []
    companion = companion_scene(scene)
    if companion is None:
        companion = bpy.data.scenes.new("%s: %s" % (COMPANION_PREFIX, scene.name))
        companion[OWNER_KEY] = scene.name
        changes.append("created the companion scene '%s' that renders the foreground "
                       "collection" % companion.name)
    loose = next((c for c in companion.collection.children
                  if c.get(OWNER_KEY) == scene.name), None)
    if loose is None:
        loose = bpy.data.collections.new("%s: %s" % (COMPANION_LOOSE, scene.name))
        loose[OWNER_KEY] = scene.name
        companion.collection.children.link(loose)
    # The same top-level collections and loose objects as the main scene (and the foreground
    # collection itself, when it is not in the scene's tree).
    top = list(scene.collection.children)
    if not any(_contains(c, fg_collection) for c in top):
        top.append(fg_collection)
    for child in top:
        if child.name not in companion.collection.children:
            companion.collection.children.link(child)
    for child in list(companion.collection.children):
        if child != loose and child not in top:
            companion.collection.children.unlink(child)
    for obj in scene.collection.objects:
        if obj.name not in loose.objects:
            loose.objects.link(obj)
    for obj in list(loose.objects):
        if obj.name not in scene.collection.objects:
            loose.objects.unlink(obj)
    fg_layer = companion.view_layers[0]
    fg_layer.use_pass_z = True
    for lc in compat.layer_collection(fg_layer).children:
        _mark_indirect(lc, fg_collection)
    sync_companion(scene, companion)
    # In the main view layer the foreground objects only light and shadow.
    main_lc = _find_layer_collection(compat.layer_collection(layer), fg_collection)
    if main_lc is not None and not main_lc.indirect_only:
        main_lc.indirect_only = True
        scene[OWNER_KEY + "_indirect"] = fg_collection.name
        changes.append("made collection '%s' indirect-only in view layer '%s' (it is rendered "
                       "as the foreground element)" % (fg_collection.name, layer.name))
    return companion, changes


def remove_companion(scene):
    changes = []
    companion = companion_scene(scene)
    if companion is not None:
        for child in list(companion.collection.children):
            if child.get(OWNER_KEY) == scene.name:
                bpy.data.collections.remove(child)
        name = companion.name
        bpy.data.scenes.remove(companion)
        changes.append("removed the companion scene '%s'" % name)
    restored = scene.get(OWNER_KEY + "_indirect")
    if restored:
        collection = bpy.data.collections.get(restored)
        for layer in scene.view_layers:
            lc = (_find_layer_collection(compat.layer_collection(layer), collection)
                  if collection else None)
            if lc is not None and lc.indirect_only:
                lc.indirect_only = False
        del scene[OWNER_KEY + "_indirect"]
        changes.append("made collection '%s' visible to the camera again" % restored)
    return changes
