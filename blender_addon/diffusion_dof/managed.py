# SPDX-License-Identifier: GPL-3.0-or-later
"""What the add-on adds to a scene's compositor and where it writes: the managed nodes' names,
the session's temporary folder of a scene, and the view layer whose passes get depth of field.
passes.py adds and removes those nodes; composite.py leaves them out of the user's tree."""

import os
import re
import zlib

import bpy

from .errors import SetupError

FRAME_NODE = "DDOF Frame"
RLAYERS_NODE = "DDOF Render Layers"
FG_RLAYERS_NODE = "DDOF Foreground Render Layers"
OUTPUT_NODE = "DDOF Passes"
FG_OUTPUT_NODE = "DDOF Foreground Passes"
# The object matte's own File Output node: its slots are not the main node's, so they are never
# taken for passes the user's compositing reads (passes.extra_slots).
MATTE_OUTPUT_NODE = "DDOF Matte Passes"
MANAGED_NODES = (OUTPUT_NODE, FG_OUTPUT_NODE, MATTE_OUTPUT_NODE, RLAYERS_NODE, FG_RLAYERS_NODE,
                 FRAME_NODE)


def temp_dir(scene):
    """The folder the managed File Output node writes into: inside this Blender session's own
    temporary folder (removed when Blender quits), one sub-folder per scene."""
    base = bpy.app.tempdir or os.path.join(os.path.abspath(os.sep), "tmp")
    safe = re.sub(r"[^A-Za-z0-9_.-]", "_", scene.name)
    tag = zlib.crc32(scene.name.encode("utf-8")) & 0xffffff
    return os.path.join(base, "diffusion_dof", "%s_%06x" % (safe, tag))


def render_view_layer(scene, settings):
    """The view layer whose passes get depth of field."""
    if settings.view_layer:
        layer = scene.view_layers.get(settings.view_layer)
        if layer is None:
            raise SetupError("View layer '%s' (Diffusion DOF > Expert > View Layer) does not "
                             "exist in scene '%s'." % (settings.view_layer, scene.name))
        return layer
    for layer in scene.view_layers:
        if layer.use:
            return layer
    raise SetupError("Scene '%s' has no view layer that renders (View Layer properties > "
                     "Use for Rendering)." % scene.name)
