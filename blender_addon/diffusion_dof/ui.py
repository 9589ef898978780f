# SPDX-License-Identifier: GPL-3.0-or-later
"""The "Diffusion DOF" panel, in Properties > Render and in the compositor's sidebar (N panel,
"Diffusion DOF" tab). Both draw the same sub-panels."""

import textwrap

import bpy

from . import camera as camera_mod
from . import binding, images, overscan_render, passes, report
from . import settings as settings_mod
from .errors import SetupError


def _wrapped(layout, text, icon="NONE", width=52):
    col = layout.column(align=True)
    for i, line in enumerate(textwrap.wrap(text, width) or [""]):
        col.label(text=line, icon=icon if i == 0 else "BLANK1")
    return col


def _settings(context):
    return settings_mod.get(context.scene)


def _preset_line(s):
    """'thomas, disc-2x2 disc kernel, 1 background level' (or, for the heat kernel, 'thomas,
    4 sub-steps, ...') of the chosen preset: the library's values."""
    try:
        p = binding.get_library().preset_summary(s.preset_name())
    except (binding.LibraryError, ValueError) as err:
        return "preset values unknown: %s" % str(err).split(". ")[0]
    if p["method"] == "cod4":
        return "CoD4 preview (fast, approximate)"
    levels = "%d background level%s" % (p["background_levels"],
                                        "" if p["background_levels"] == 1 else "s")
    if p["kernel"] != "heat":
        return "%s, %s disc kernel, %s" % (p["solver"], p["kernel"], levels)
    return "%s, %d sub-step%s, %s" % (p["solver"], p["substeps"],
                                      "" if p["substeps"] == 1 else "s", levels)


def draw_main(layout, context):
    scene = context.scene
    s = _settings(context)
    layout.use_property_split = False
    ok, text = binding.library_status()
    if not ok:
        box = layout.box()
        box.alert = True
        _wrapped(box, text, icon="ERROR")
        box.operator("diffusion_dof.reload_library", icon="FILE_REFRESH")
    problems = passes.diagnose(scene)
    if problems:
        box = layout.box()
        for level, message in problems:
            _wrapped(box, message, icon="ERROR" if level == "ERROR" else "INFO")
        row = box.row()
        row.operator("diffusion_dof.setup", icon="NODE_COMPOSITING")
        cam = scene.camera
        if cam is not None and cam.type == "CAMERA" and cam.data.dof.use_dof:
            row.operator("diffusion_dof.pinhole", icon="CAMERA_DATA")
    col = layout.column()
    col.active = s.enabled
    col.row().prop(s, "quality", expand=True)
    if s.quality == "CUSTOM":
        row = col.row(align=True)
        row.prop(s, "substeps")
        row.prop(s, "background_levels")
    else:
        col.label(text=_preset_line(s))
    row = layout.row()
    row.operator("diffusion_dof.reapply", icon="FILE_REFRESH")
    last = report.reports.get(scene.name)
    if last:
        box = layout.box()
        _wrapped(box, last["message"], icon="CHECKMARK" if last["ok"] else "ERROR")
        stats = last.get("stats")
        if stats:
            sub = box.column(align=True)
            sub.scale_y = 0.8
            sub.label(text="Ran on: " + report.backend_line(stats),
                      icon="DESKTOP" if stats.get("hardware") else "MEMORY")
            for note in (stats.get("backend_note"), stats.get("method_note")):
                if note:
                    _wrapped(sub, note, icon="INFO")
            for line in stats.get("plan", "").strip().splitlines():
                sub.label(text=line)
            if "near layer" in stats.get("effect_names", ()) and not s.foreground_collection:
                _wrapped(sub, "Blurred near objects were made see-through from the image "
                         "alone, what they hide guessed from around them. For the exact "
                         "result put them in a Foreground collection (Expert).", icon="INFO")


def draw_camera(layout, context):
    scene = context.scene
    s = _settings(context)
    try:
        cam, info = camera_mod.camera_settings(scene, s)
        _wrapped(layout, camera_mod.describe(cam, info), icon="CAMERA_DATA")
    except SetupError as err:
        _wrapped(layout, str(err), icon="ERROR")
    row = layout.row(align=True)
    row.operator("diffusion_dof.pick_focus", icon="EYEDROPPER")
    row.operator("diffusion_dof.focus_map", icon="IMAGE_ZDEPTH")
    layout.prop(s, "lens_model")
    col = layout.column(align=True)
    for flag, value in (("override_focus", "focus_distance"), ("override_fstop", "fstop"),
                        ("override_focal_length", "focal_length"),
                        ("override_sensor", "sensor_width")):
        row = col.row(align=True)
        row.prop(s, flag, text="")
        sub = row.row(align=True)
        sub.active = getattr(s, flag)
        sub.prop(s, value)
    row = col.row(align=True)
    row.active = s.override_sensor
    row.prop(s, "sensor_fit", text="Fit")


def draw_expert(layout, context):
    scene = context.scene
    s = _settings(context)
    layout.use_property_split = True
    layout.use_property_decorate = False
    layout.prop(s, "method")
    layout.prop(s, "solver")
    layout.prop(s, "background")
    layout.prop(s, "near_spread")
    layout.prop(s, "foreground_collection")
    layout.prop(s, "object_matte")
    hint = passes.object_matte_hint(scene, s)
    if hint:
        _wrapped(layout, hint, icon="INFO")
    layout.prop_search(s, "view_layer", scene, "view_layers")
    layout.prop(s, "backend")
    last = report.reports.get(scene.name)
    stats = last.get("stats") if last else None
    if stats:
        row = layout.row()
        row.enabled = False
        row.label(text="Last frame: " + report.backend_line(stats))
    layout.prop(s, "threads")


def overscan_line(scene, s):
    """What overscan will do to this scene's render: the margin and its cost, or why none."""
    if s.overscan == "OFF":
        return "Off: light from outside the frame is missing"
    try:
        plan, why = overscan_render.overscan_plan(scene, s)
    except SetupError as err:
        return "None: %s" % err
    if plan is None:
        return "None (%s)" % why
    return plan.describe()


def draw_output(layout, context):
    s = _settings(context)
    layout.prop(s, "overscan")
    if s.overscan == "MANUAL":
        layout.prop(s, "overscan_margin")
    _wrapped(layout, overscan_line(context.scene, s), icon="FULLSCREEN_ENTER")
    if s.overscan != "OFF" and not bpy.app.background:
        _wrapped(layout, "Background renders and scripts only: an F12 or Ctrl F12 with the "
                 "interface renders the frame alone", icon="INFO")
    layout.prop(s, "write_frames")
    layout.prop(s, "show_result")
    layout.prop(s, "keep_inputs")
    layout.operator("diffusion_dof.apply_images_dialog", icon="IMAGE_DATA")
    layout.operator("diffusion_dof.render_cards", icon="IMAGE_PLANE")


class DIFFUSION_DOF_OT_apply_images_dialog(bpy.types.Operator):
    """Pick a colour and a depth image and apply Diffusion DOF with this scene's settings"""
    bl_idname = "diffusion_dof.apply_images_dialog"
    bl_label = "Apply to Images..."

    color: bpy.props.StringProperty(name="Colour")
    depth: bpy.props.StringProperty(name="Depth")
    output: bpy.props.StringProperty(name="Output", default=images.RESULT_IMAGE)

    def invoke(self, context, _event):
        return context.window_manager.invoke_props_dialog(self)

    def draw(self, _context):
        self.layout.prop_search(self, "color", bpy.data, "images")
        self.layout.prop_search(self, "depth", bpy.data, "images")
        self.layout.prop(self, "output")

    def execute(self, _context):
        try:
            return bpy.ops.diffusion_dof.apply_images(color=self.color, depth=self.depth,
                                                      output=self.output)
        except RuntimeError as err:  # the apply operator already reported the reason
            self.report({"ERROR"}, str(err))
            return {"CANCELLED"}


class _Main:
    bl_label = "Diffusion DOF"

    def draw_header(self, context):
        self.layout.prop(_settings(context), "enabled", text="")

    def draw(self, context):
        draw_main(self.layout, context)


class DIFFUSION_DOF_PT_render(_Main, bpy.types.Panel):
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"
    bl_options = {"DEFAULT_CLOSED"}

    @classmethod
    def poll(cls, context):
        return context.scene is not None


class DIFFUSION_DOF_PT_compositor(_Main, bpy.types.Panel):
    bl_space_type = "NODE_EDITOR"
    bl_region_type = "UI"
    bl_category = "Diffusion DOF"

    @classmethod
    def poll(cls, context):
        space = context.space_data
        return space is not None and getattr(space, "tree_type", "") == "CompositorNodeTree"


def _sub_panel(parent, suffix, label, draw_fn, closed=False):
    attrs = {
        "bl_idname": "%s_%s" % (parent.__name__, suffix),
        "bl_label": label,
        "bl_parent_id": parent.__name__,
        "bl_space_type": parent.bl_space_type,
        "bl_region_type": parent.bl_region_type,
        "bl_options": {"DEFAULT_CLOSED"} if closed else set(),
        "draw": lambda self, context: draw_fn(self.layout, context),
    }
    for key in ("bl_context", "bl_category"):
        if hasattr(parent, key):
            attrs[key] = getattr(parent, key)
    return type(attrs["bl_idname"], (bpy.types.Panel,), attrs)


CLASSES = [DIFFUSION_DOF_OT_apply_images_dialog]
for _parent in (DIFFUSION_DOF_PT_render, DIFFUSION_DOF_PT_compositor):
    CLASSES.append(_parent)
    CLASSES.append(_sub_panel(_parent, "camera", "Camera", draw_camera))
    CLASSES.append(_sub_panel(_parent, "expert", "Expert", draw_expert, closed=True))
    CLASSES.append(_sub_panel(_parent, "output", "Output", draw_output, closed=True))


# Registers CLASSES in order and unregisters them in reverse (Blender's own helper).
register, unregister = bpy.utils.register_classes_factory(CLASSES)
