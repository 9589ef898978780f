# SPDX-License-Identifier: GPL-3.0-or-later
"""register() / unregister() twice leaves no residue: handlers, timers, classes, the scene
property, the managed compositor nodes and the foreground companion scene all go, and a second
register() does not duplicate anything. Also draws every panel into a recording layout, which
catches a property name that does not exist.

Turning Diffusion DOF off, or disabling the add-on, leaves the compositor as it was (5.x: no
node group, where an empty one made Blender render nothing) and the render exactly as it was
before. A scene made with bpy.data.scenes.new (its view layer unsynced on 5.2+) sets up a
foreground collection, and a setup step failing with any error is a message: register() goes
on."""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import blender_test_util as u  # noqa: E402

import bpy  # noqa: E402

HANDLER_LISTS = [name for name in dir(bpy.app.handlers)
                 if not name.startswith("_") and isinstance(getattr(bpy.app.handlers, name),
                                                            list)]
checks = u.Checks("test_register")


def handler_snapshot():
    return {name: list(getattr(bpy.app.handlers, name)) for name in HANDLER_LISTS}


def ours(fn):  # diffusion_dof.render, or bl_ext.user_default.diffusion_dof.render
    return "diffusion_dof" in getattr(fn, "__module__", "").split(".")


def our_types():
    return sorted(name for name in dir(bpy.types) if name.startswith("DIFFUSION_DOF"))


def our_ops():
    return sorted(dir(getattr(bpy.ops, "diffusion_dof")))


def compositor_state(scene):
    """What decides whether and how the scene composites: its tree (5.x: node group) and that
    tree's nodes."""
    if hasattr(scene, "compositing_node_group"):
        tree = scene.compositing_node_group
        return (tree.name, sorted(n.name for n in tree.nodes)) if tree else None
    return (scene.use_nodes, sorted(n.name for n in scene.node_tree.nodes)
            if scene.use_nodes and scene.node_tree else None)


def managed_nodes(scene):
    tree = u.compositor_tree(scene)
    return sorted(n.name for n in tree.nodes if n.name.startswith("DDOF")) if tree else []


class RecordingLayout:
    """Stands in for bpy.types.UILayout: accepts every call, checks that prop() names exist."""

    def __init__(self, problems):
        self.problems = problems
        self.calls = 0

    def __getattr__(self, name):
        def call(*args, **kwargs):
            self.calls += 1
            if name in ("prop", "prop_search") and len(args) >= 2:
                data, prop = args[0], args[1]
                if prop not in data.bl_rna.properties:
                    self.problems.append("%s.%s does not exist" % (type(data).__name__, prop))
            if name == "operator":
                category, _, op = args[0].partition(".")
                if op not in dir(getattr(bpy.ops, category)):
                    self.problems.append("operator %s does not exist" % args[0])
            return self
        return call

    def __setattr__(self, name, value):
        object.__setattr__(self, name, value)


baseline_handlers = handler_snapshot()
baseline_types = our_types()
checks.check(baseline_types == [], "types before registering: %s" % baseline_types)

scene = u.clear_scene()
cam = u.add_camera(scene)
near = bpy.data.collections.new("NearObjects")
scene.collection.children.link(near)
u.add_plane(scene, "Post", (0.1, 1.0), (0.0, 1.5, 0.0),
            u.emission_checker("PostMat", (1, 1, 1, 1), (0, 0, 0, 1), 10.0), collection=near)
u.configure(scene, samples=7)
scenes_before = sorted(s.name for s in bpy.data.scenes)
collections_before = sorted(c.name for c in bpy.data.collections)
# The Cryptomatte Object pass on: the object matte's managed node is set up (and removed) too.
scene.view_layers[0].use_pass_cryptomatte_object = True
compositor_before = compositor_state(scene)
render_dir = u.scratch_dir("register")
render_before, _, _, _ = u.render_still(scene, os.path.join(render_dir, "before.exr"))

diffusion_dof = u.addon_module()  # imported, not registered

for round_ in (1, 2):
    diffusion_dof.register()
    added = {name: [h for h in getattr(bpy.app.handlers, name) if h not in
                    baseline_handlers[name]] for name in HANDLER_LISTS}
    added = {k: v for k, v in added.items() if v}
    checks.check(all(len(v) == 1 and ours(v[0]) for v in added.values()) and len(added) >= 6,
                 "round %d: handlers added: %r" % (round_, added))
    checks.check(hasattr(bpy.types.Scene, "diffusion_dof"), "no scene property")
    types = our_types()
    checks.check(len(types) >= 10, "round %d: registered types %s" % (round_, types))
    checks.check("apply_images" in our_ops() and "setup" in our_ops(), "operators missing")

    # Use it: on, foreground collection (companion scene), panels drawn.
    s = scene.diffusion_dof
    s.enabled = True
    s.foreground_collection = near
    companion = diffusion_dof.passes.companion_scene(scene)
    checks.check(companion is not None, "round %d: no companion scene" % round_)
    # It renders with the main scene's Cycles settings (5.0 no longer reads them through []).
    checks.check(companion is not None and companion.cycles.samples == scene.cycles.samples
                 and companion.cycles.max_bounces == scene.cycles.max_bounces,
                 "round %d: the companion's Cycles samples %s, the scene's %d" % (
                     round_, companion.cycles.samples if companion else None,
                     scene.cycles.samples))
    checks.check(managed_nodes(scene) == sorted(diffusion_dof.passes.MANAGED_NODES),
                 "round %d: managed nodes %s" % (round_, managed_nodes(scene)))
    layer_near = scene.view_layers[0].layer_collection.children["NearObjects"]
    checks.check(layer_near.indirect_only, "foreground collection not indirect-only")
    checks.check(diffusion_dof.passes.missing_setup(scene, s) == "",
                 "setup incomplete: %s" % diffusion_dof.passes.missing_setup(scene, s))
    problems = []
    layout = RecordingLayout(problems)

    class Ctx:
        pass
    ctx = Ctx()
    ctx.scene = scene
    for draw in (diffusion_dof.ui.draw_main, diffusion_dof.ui.draw_camera,
                 diffusion_dof.ui.draw_expert, diffusion_dof.ui.draw_output):
        draw(layout, ctx)
    checks.check(not problems and layout.calls > 20, "panel drawing: %s (%d calls)"
                 % (problems, layout.calls))
    # Again with a frame's report (backend, renderer, note, plan) and every quality and backend.
    diffusion_dof.report.reports[scene.name] = {
        "ok": True, "message": "frame 1: ...", "frame": 1, "path": None, "time": 0.0,
        "camera": "", "stats": {"backend_name": "cpu", "renderer": "CPU, 2 threads",
                                "hardware": False, "backend_note": "auto: the CPU, because ...",
                                "method_note": "", "plan": "midground: on: largest CoC 9 px"}}
    for quality in ("PREVIEW", "DEFAULT", "FINAL", "CUSTOM"):
        s.quality = quality
        s.backend = "AUTO" if quality == "FINAL" else "CPU"
        for draw in (diffusion_dof.ui.draw_main, diffusion_dof.ui.draw_expert):
            draw(layout, ctx)
    checks.check(not problems, "panel drawing with a report: %s" % problems)
    s.quality = "FINAL"
    final_line = diffusion_dof.ui._preset_line(s)
    lib = diffusion_dof.binding.get_library()
    final = lib.preset_summary("final")
    want = ("%s, %s disc kernel" % (final["solver"], final["kernel"]) if final["kernel"] != "heat"
            else "%s, %d sub-step" % (final["solver"], final["substeps"]))
    checks.check(final_line.startswith(want),
                 "the panel's final preset %r is not the library's %r" % (final_line, final))
    # Expert overrides: none by default (the preset's values), each one when set.
    s.quality = "DEFAULT"
    checks.check(s.library_params() == {} and s.preset_name() == "default" and
                 s.library_backend() == "cpu", "default overrides: %r" % s.library_params())
    s.solver, s.background, s.method, s.quality = "pcr", "OFF", "diffusion", "CUSTOM"
    checks.check(s.library_params() == {"solver": "pcr", "background": "OFF",
                                        "method": "diffusion", "kernel": "heat",
                                        "substeps": s.substeps,
                                        "background_levels": s.background_levels},
                 "overrides: %r" % s.library_params())
    s.solver = s.background = s.method = "PRESET"
    s.quality = "DEFAULT"
    diffusion_dof.report.reports.clear()
    # Unticked: the compositor is as it was before (and on again when ticked).
    s.enabled = False
    checks.check(compositor_state(scene) == compositor_before,
                 "round %d: unticked, the compositor is %r, before %r"
                 % (round_, compositor_state(scene), compositor_before))
    s.enabled = True
    checks.check(managed_nodes(scene) == sorted(diffusion_dof.passes.MANAGED_NODES),
                 "round %d: ticked again: managed nodes %s" % (round_, managed_nodes(scene)))

    diffusion_dof.unregister()
    after = handler_snapshot()
    checks.check(after == baseline_handlers,
                 "round %d: handlers left: %r" % (round_, {k: [h for h in v if ours(h)]
                                                           for k, v in after.items()}))
    checks.check(not hasattr(bpy.types.Scene, "diffusion_dof"), "scene property left")
    checks.check(our_types() == [], "round %d: types left: %s" % (round_, our_types()))
    checks.check(our_ops() == [], "round %d: operators left: %s" % (round_, our_ops()))
    checks.check(managed_nodes(scene) == [], "round %d: nodes left: %s"
                 % (round_, managed_nodes(scene)))
    checks.check(compositor_state(scene) == compositor_before,
                 "round %d: disabled, the compositor is %r, before %r"
                 % (round_, compositor_state(scene), compositor_before))
    checks.check(sorted(x.name for x in bpy.data.scenes) == scenes_before,
                 "round %d: scenes left: %s" % (round_, [x.name for x in bpy.data.scenes]))
    checks.check(sorted(c.name for c in bpy.data.collections) == collections_before,
                 "round %d: collections left: %s" % (round_,
                                                     [c.name for c in bpy.data.collections]))
    checks.check(not layer_near.indirect_only, "foreground collection still indirect-only")
    timer = diffusion_dof.jobs.timer
    checks.check(not bpy.app.timers.is_registered(timer), "timer left registered")
    checks.check(not diffusion_dof.jobs.queued and not diffusion_dof.report.reports,
                 "module state left")

# Registering twice in a row (a reload without unregister) still leaves one set of handlers.
diffusion_dof.register()
diffusion_dof.render.register()
counts = {name: sum(1 for h in getattr(bpy.app.handlers, name) if ours(h)) for name in
          HANDLER_LISTS}
checks.check(max(counts.values()) == 1, "duplicate handlers: %r" % counts)
diffusion_dof.unregister()
checks.check(handler_snapshot() == baseline_handlers, "handlers left after double register")

# The add-on enabled and disabled: the scene renders exactly as before (same samples and seed).
# (With an empty compositor node group, 5.x renders nothing and writes no file.)
try:
    render_after, _, _, _ = u.render_still(scene, os.path.join(render_dir, "after.exr"))
    checks.check(render_after == render_before, "the render after disabling the add-on "
                 "differs from the one before (largest difference %g)"
                 % max(abs(a - b) for a, b in zip(render_after, render_before)))
except RuntimeError as err:
    checks.check(False, "after disabling the add-on: %s" % err)

# A scene made by a script: its view layer is not synced yet on 5.2+ (layer_collection None).
fresh = bpy.data.scenes.new("Scripted")
fresh.collection.children.link(near)
diffusion_dof.register()
fresh.diffusion_dof.enabled = True
fresh.diffusion_dof.foreground_collection = near
problem = diffusion_dof.passes.missing_setup(fresh, fresh.diffusion_dof)
checks.check(problem == "" and diffusion_dof.passes.companion_scene(fresh) is not None,
             "a scene made by bpy.data.scenes.new is not set up: %s" % problem)
diffusion_dof.unregister()

# Registering with scenes to set up (Diffusion DOF on, stored): register() sets them up, and a
# setup step that fails with any error (here a RuntimeError) is a logged setup problem.
try:
    diffusion_dof.register()
    checks.check(diffusion_dof.passes.companion_scene(fresh) is not None,
                 "register() did not set up the scripted scene's foreground")
except Exception as err:  # noqa: BLE001 (what must not happen)
    checks.check(False, "register() raised %s: %s" % (type(err).__name__, err))
diffusion_dof.unregister()
logged = []
real_layer, real_log = diffusion_dof.passes.render_view_layer, diffusion_dof.report.log


def failing_step(*_args):
    raise RuntimeError("a setup step failed")


diffusion_dof.passes.render_view_layer = failing_step
diffusion_dof.report.log = logged.append
try:
    diffusion_dof.register()
    checks.check(hasattr(bpy.types.Scene, "diffusion_dof"), "not registered")
    checks.check(any("Scripted" in line and "RuntimeError: a setup step failed" in line
                     for line in logged), "the failed setup step was not reported: %r" % logged)
except Exception as err:  # noqa: BLE001
    checks.check(False, "register() let %s through: %s" % (type(err).__name__, err))
finally:
    diffusion_dof.passes.render_view_layer, diffusion_dof.report.log = real_layer, real_log
diffusion_dof.unregister()
checks.check(handler_snapshot() == baseline_handlers, "handlers left after a failed setup")
checks.finish()
