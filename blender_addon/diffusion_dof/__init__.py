# SPDX-License-Identifier: GPL-3.0-or-later
"""Diffusion DOF: depth of field by simulated heat diffusion (Kass, Lefohn, Owens 2006) on the
render's Combined and Depth passes, through the ddof shared library (ctypes, no pixel math in
Python). See docs/blender-addon.md."""

bl_info = {
    "name": "Diffusion DOF",
    "author": "ddof",
    "version": (0, 9, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Render > Diffusion DOF; Compositor > Sidebar > Diffusion DOF",
    "description": "Depth of field by simulated diffusion on the Combined and Depth passes",
    "category": "Render",
}

if "bpy" in locals():  # "Reload Scripts": pick up edited modules in dependency order
    import importlib
    for _name in ("errors", "ddof_abi", "binding", "compat", "frame_region", "focus_map",
                  "overscan", "settings", "camera", "passes", "composite", "report", "images",
                  "frame_file", "overscan_render", "library_call", "escape_watch",
                  "frame_inputs", "frame_output", "frame_steps", "jobs", "render", "ops",
                  "cards", "ui"):
        if _name in locals():
            importlib.reload(locals()[_name])

import bpy  # noqa: E402

from . import errors, ddof_abi, binding, compat, frame_region, focus_map  # noqa: E402,F401
from . import overscan, settings, camera, passes, composite, report, images  # noqa: E402,F401
from . import frame_file, overscan_render, library_call, escape_watch  # noqa: E402,F401
from . import frame_inputs, frame_output, frame_steps, jobs  # noqa: E402,F401
from . import render, ops, cards, ui  # noqa: E402,F401

_MODULES = (settings, ops, cards, ui, render)


def register():
    for module in _MODULES:
        module.register()
    # Scenes already open (enabling the add-on in a session, or a script's register()): make
    # the ones with Diffusion DOF on ready. bpy.data is not readable while Blender starts up;
    # load_post does it for the file that is loaded then.
    try:
        scenes = list(bpy.data.scenes)
    except AttributeError:
        scenes = []
    for scene in scenes:
        if scene.diffusion_dof.enabled:
            try:
                passes.ensure_setup(scene)
            except errors.SetupError as err:
                report.log("%s: %s" % (scene.name, err))


def unregister():
    # Managed compositor nodes and companion scenes go with the add-on: they would keep
    # writing temporary files at every render. The settings stay stored in the scenes.
    try:
        scenes = list(bpy.data.scenes)
    except AttributeError:
        scenes = []
    for scene in [s for s in scenes if s.get(passes.OWNER_KEY) is None]:
        try:
            passes.teardown(scene)  # also removes its companion scene, never iterated itself
        except Exception as err:  # the add-on is going: it must still unregister what it can
            report.log("%s: could not remove the add-on's nodes: %s: %s"
                       % (scene.name, type(err).__name__, err))
    for module in reversed(_MODULES):
        module.unregister()
    binding.forget_library()
