# SPDX-License-Identifier: GPL-3.0-or-later
"""Disabling and enabling the add-on again, as Preferences > Add-ons does (addon_utils), sets a
scene with Diffusion DOF on up again for rendering (issue 41): the managed nodes are back and
nothing is missing (what an F12 with the UI checks before it renders). Blender 3.x runs
register() with bpy.data restricted there, where the add-on used to see no scene at all."""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import blender_test_util as u  # noqa: E402

import addon_utils  # noqa: E402
import bpy  # noqa: E402

checks = u.Checks("test_reenable")
if u.BPY_MODULE:
    u.load_addon()  # the extension, installed and enabled
    module = u.EXTENSION_MODULE
else:
    sys.path.insert(0, u.ADDON_DIR)
    module = "diffusion_dof"
    addon_utils.enable(module, default_set=True)
addon = sys.modules[module]
logged = []
addon.report.log = logged.append  # a failed set-up step is logged, not raised

scene = u.clear_scene()
u.configure(scene, samples=1)
u.add_plane(scene, "Card", (1.0, 1.0), (0.0, 3.0, 0.0),
            u.emission_checker("CardMat", (1, 1, 1, 1), (0, 0, 0, 1), 10.0))
u.add_camera(scene)
scene.diffusion_dof.enabled = True


def managed_nodes():
    tree = addon.passes.node_tree(scene)
    return sorted(n.name for n in tree.nodes if n.name in addon.passes.MANAGED_NODES) \
        if tree is not None else []


before = managed_nodes()
checks.check(addon.passes.OUTPUT_NODE in before, "not set up when ticked: %r" % before)
addon_utils.disable(module, default_set=True)
checks.check(managed_nodes() == [], "the managed nodes stay after disabling: %r"
             % managed_nodes())
addon_utils.enable(module, default_set=True)
addon = sys.modules[module]
checks.check(managed_nodes() == before, "after enabling again: %r, before %r"
             % (managed_nodes(), before))
missing = addon.passes.missing_setup(scene, scene.diffusion_dof)
checks.check(missing == "", "after enabling again, not set up: %s" % missing)
checks.check(not any("Could not set up" in line for line in logged), "logged: %r" % logged)
addon_utils.disable(module, default_set=True)
checks.finish()
