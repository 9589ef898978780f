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
                  "overscan", "scene_settings", "managed", "camera", "object_matte",
                  "composite", "passes", "settings", "report", "images",
                  "frame_file", "overscan_render", "library_call", "escape_watch",
                  "frame_inputs", "frame_output", "frame_steps", "jobs", "render", "ops",
                  "cards", "ui"):
        if _name in locals():
            importlib.reload(locals()[_name])

import bpy  # noqa: E402

from . import errors, ddof_abi, binding, compat, frame_region, focus_map  # noqa: E402,F401
from . import overscan, scene_settings, managed, camera, object_matte  # noqa: E402,F401
from . import composite, passes, settings, report, images  # noqa: E402,F401
from . import frame_file, overscan_render, library_call, escape_watch  # noqa: E402,F401
from . import frame_inputs, frame_output, frame_steps, jobs  # noqa: E402,F401
from . import render, ops, cards, ui  # noqa: E402,F401

_MODULES = (settings, ops, cards, ui, render)


class _FileData:
    """While register() runs: the open file's data readable through bpy.data. Blender 3.x runs
    register() with bpy.data restricted (bpy_restrict_state: enabling the add-on in a session
    as well as at start-up; 4.2+ restricts only the import), so a re-enabled add-on would leave
    its scenes not set up. The C module's handle on the data is not restricted: bpy.data points
    at it for the set-up, as 4.2+ allows, and back at the restricted one after."""

    def __enter__(self):
        self.saved = bpy.data
        if not hasattr(bpy.data, "scenes"):
            import _bpy
            bpy.data = _bpy.data
        return bpy.data

    def __exit__(self, *_exc):
        bpy.data = self.saved


def register():
    for module in _MODULES:
        module.register()
    # Scenes already open (enabling the add-on in a session, or a script's register()): make
    # the ones with Diffusion DOF on ready. At start-up these are the startup file's; load_post
    # sets up the file loaded then.
    with _FileData() as data:
        for scene in list(getattr(data, "scenes", ())):
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
