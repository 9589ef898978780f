# SPDX-License-Identifier: GPL-3.0-or-later
"""The per-scene settings (scene.diffusion_dof) and what they mean for the library."""

import bpy
from bpy.props import (BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty,
                       StringProperty)

from . import binding, passes
from .scene_settings import PROPERTY, get  # noqa: F401 (get: the settings' reader for callers)

# Quality presets are the library's (ddof_params_init_preset): their values are chosen by the
# accuracy study from measured data, so the add-on holds none of its own. Quality -> the name of
# the library preset; CUSTOM starts from the default preset with the heat kernel (the one the
# sub-steps are for) and the sub-steps and background levels below.
QUALITY_PRESETS = {"PREVIEW": "preview", "DEFAULT": "default", "FINAL": "final"}

# Expert overrides: "PRESET" keeps the preset's value. Enum items carry explicit numbers (Blender
# stores the number), so scenes saved by 0.2 keep their choices.
PRESET = "PRESET"


def _on_setup_change(self, context):
    scene = self.id_data
    if not isinstance(scene, bpy.types.Scene):
        return
    try:
        if self.enabled:
            for line in passes.ensure_setup(scene):
                print("Diffusion DOF:", line)
        else:
            for line in passes.teardown(scene):
                print("Diffusion DOF:", line)
    except passes.SetupError as err:
        print("Diffusion DOF:", err)


class DiffusionDOFSettings(bpy.types.PropertyGroup):
    enabled: BoolProperty(
        name="Diffusion DOF",
        description="Apply diffusion depth of field to every render of this scene: the Combined "
                    "and Depth passes go through libddof, the result goes to the 'Diffusion DOF' "
                    "image and, for animations, replaces the written frames",
        default=False, update=_on_setup_change)

    quality: EnumProperty(
        name="Quality",
        items=[("PREVIEW", "Preview", "The library's preview preset: fastest"),
               ("DEFAULT", "Default", "The library's default preset"),
               ("FINAL", "Final", "The library's final preset: closest to a lens"),
               ("CUSTOM", "Custom", "The default preset with the heat kernel (soft blur) and "
                                    "the sub-steps and background levels set below")],
        default="DEFAULT",
        description="The library's presets (ddof_params_init_preset), measured by its accuracy "
                    "study; the Expert settings override them")
    substeps: IntProperty(
        name="Sub-steps", min=1, max=64, default=2,
        description="ADI steps of beta/n each: more approach a Gaussian kernel, at linear cost")
    background_levels: IntProperty(
        name="Background Levels", min=1, max=8, default=1,
        description="Blurring-underneath layers at thresholds t, 2t, 4t, ...")

    # Camera: by default everything comes from the active camera, read at every frame.
    lens_model: EnumProperty(
        name="Lens Model",
        items=[("CYCLES", "Cycles", "Fixed pinhole projection and a planar focus plane: matches "
                                    "Cycles and EEVEE renders"),
               ("THIN_LENS", "Thin Lens", "Textbook thin lens (larger CoC by S1 / (S1 - f))")],
        default="CYCLES")
    override_focus: BoolProperty(name="Focus Distance", default=False,
                                 description="Use this focus distance, not the camera's")
    focus_distance: FloatProperty(name="Focus Distance", subtype="DISTANCE", unit="LENGTH",
                                  min=0.0, default=10.0,
                                  description="Distance of the focus plane, in scene units")
    override_fstop: BoolProperty(name="F-Stop", default=False,
                                 description="Use this f-number, not the camera's")
    fstop: FloatProperty(name="F-Stop", min=0.01, soft_max=128.0, default=2.8, precision=2,
                         description="Aperture f-number: lower blurs more")
    override_focal_length: BoolProperty(name="Focal Length", default=False,
                                        description="Use this focal length, not the camera's")
    focal_length: FloatProperty(name="Focal Length", subtype="DISTANCE_CAMERA", min=1.0,
                                default=50.0, unit="CAMERA",
                                description="Focal length in millimetres")
    override_sensor: BoolProperty(name="Sensor", default=False,
                                  description="Use this sensor size and fit, not the camera's")
    sensor_width: FloatProperty(name="Sensor Size", subtype="DISTANCE_CAMERA", min=1.0,
                                default=36.0, unit="CAMERA",
                                description="Sensor size in millimetres along the fitted axis")
    sensor_fit: EnumProperty(
        name="Sensor Fit",
        items=[("AUTO", "Auto", "The sensor size spans the larger image dimension"),
               ("HORIZONTAL", "Horizontal", "The sensor size spans the image width"),
               ("VERTICAL", "Vertical", "The sensor size spans the image height")],
        default="AUTO")

    # Expert knobs.
    method: EnumProperty(
        name="Method",
        items=[(PRESET, "Preset's", "As the quality preset says", 2),
               ("diffusion", "Diffusion", "The heat-diffusion solve with its layers", 0),
               ("cod4", "CoD4 Preview", "The fast, approximate post-process depth of field of "
                                        "Call of Duty 4 (GPU Gems 3 ch. 28); CPU only; not with "
                                        "a foreground collection", 1)],
        default=PRESET)
    solver: EnumProperty(
        name="Solver",
        items=[(PRESET, "Preset's", "As the quality preset says", 6),
               ("thomas", "Thomas", "LU forward/back substitution: the CPU workhorse", 0),
               ("cr", "Cyclic Reduction", "Odd/even reduction (Kass et al. fig. 5)", 1),
               ("pcr", "Parallel Cyclic Reduction", "Zhang, Cohen, Owens 2010", 2),
               ("jacobi", "Jacobi", "Approximate: a fixed number of sweeps", 3),
               ("reference", "Reference", "Double precision, one thread: for comparisons", 4)],
        default=PRESET)
    background: EnumProperty(
        name="Background Layer",
        items=[(PRESET, "Preset's", "As the quality preset says", 3),
               ("AUTO", "Auto", "The planner decides from the CoC field", 0),
               ("ON", "On", "Always blur the background underneath in-focus objects", 1),
               ("OFF", "Off", "Never", 2)],
        default=PRESET,
        description="Blurring underneath (Kass et al. 3.1): lets a far background blur behind "
                    "thin in-focus objects")
    near_spread: EnumProperty(
        name="Near Spread",
        items=[(PRESET, "Preset's", "As the quality preset says", 3),
               ("AUTO", "Auto", "The planner decides from the CoC field", 0),
               ("ON", "On", "Always spread blurred near objects over what is behind them", 1),
               ("OFF", "Off", "Never", 2)],
        default=PRESET,
        description="Soft silhouettes for blurred near objects from one image (GPU Gems 3 "
                    "ch. 28); not used with a foreground collection")
    foreground_collection: PointerProperty(
        name="Foreground", type=bpy.types.Collection, update=_on_setup_change,
        description="Near objects rendered separately with alpha and blurred on top (Kass et "
                    "al. 3.2), so that they turn partly transparent. Cycles only; the objects "
                    "stay in the lighting of the main render as indirect-only objects")
    object_matte: EnumProperty(
        name="Object Matte",
        items=[("AUTO", "Auto", "Use the view layer's Cryptomatte Object pass when it renders "
                                "one (View Layer > Passes > Cryptomatte > Object)", 0),
               ("OFF", "Off", "Split mixed edge pixels by their colours only", 1)],
        default="AUTO", update=_on_setup_change,
        description="Which object covers how much of a pixel at the edge of a sharp object "
                    "over a blurred background, from Cryptomatte: sharpens thin in-focus edges "
                    "and strands. The pass is not turned on for you")
    view_layer: StringProperty(
        name="View Layer", default="", update=_on_setup_change,
        description="The view layer whose passes get depth of field (empty: the first view "
                    "layer that renders)")
    backend: EnumProperty(
        name="Backend",
        items=[("CPU", "CPU", "libddof's multi-threaded CPU solvers", 1),
               ("AUTO", "Auto (GPU when available)",
                "A hardware GPU through libddof's GL plugin when one is found, else the CPU "
                "(the panel shows which ran)", 0)],
        default="CPU",
        description="Where the diffusion runs")
    threads: IntProperty(name="Threads", min=0, max=1024, default=0,
                         description="Worker threads (0: one per core)")

    # Overscan: a margin rendered around the frame (overscan.py).
    overscan: EnumProperty(
        name="Overscan",
        items=[("AUTO", "Auto", "A margin as wide as the largest blur a pixel at the frame's "
                                "edge can get (capped at an eighth of the frame)"),
               ("MANUAL", "Manual", "The margin set below"),
               ("OFF", "Off", "Render the frame only: no light from outside the frame, and "
                              "the light spread out of it stays inside")],
        default="AUTO",
        description="Render a margin around the frame (resolution and sensor grown together), "
                    "run depth of field on the whole and crop the frame out: light from just "
                    "outside the frame spreads in, as through a lens. Background renders and "
                    "scripts; not with a render border")
    overscan_margin: IntProperty(
        name="Margin", min=0, max=4096, default=32, subtype="PIXEL",
        description="The margin on each side, in rendered pixels along x (Manual)")

    # Output.
    write_frames: BoolProperty(
        name="Replace Written Frames", default=True,
        description="When a render writes a file (animation, or a still with 'write still'), "
                    "overwrite it with the depth-of-field result in the scene's output format")
    keep_inputs: BoolProperty(
        name="Keep Inputs", default=True,
        description="Keep the last frame's Combined and Depth passes as the images 'Diffusion "
                    "DOF Input' and 'Diffusion DOF Depth', so Re-apply can try other settings "
                    "without rendering again")
    show_result: BoolProperty(
        name="Show Result", default=True,
        description="After F12, show the 'Diffusion DOF' image in the render window")

    def preset_name(self):
        """The library preset the quality starts from."""
        return QUALITY_PRESETS.get(self.quality, "default")

    def quality_steps(self):
        """(sub-steps, background levels) of the chosen quality: for a preset, the library's
        values. Raises binding.LibraryError when the library cannot be loaded."""
        if self.quality == "CUSTOM":
            return self.substeps, self.background_levels
        summary = binding.get_library().preset_summary(self.preset_name())
        return summary["substeps"], summary["background_levels"]

    def library_params(self):
        """The ddof_params fields these settings override on top of preset_name()'s."""
        params = {}
        if self.quality == "CUSTOM":
            params["kernel"] = "heat"  # a disc kernel has no sub-steps
            params["substeps"] = self.substeps
            params["background_levels"] = self.background_levels
        for key in ("method", "solver", "background", "near_spread"):
            value = getattr(self, key)
            if value != PRESET:
                params[key] = value
        return params

    def library_backend(self):
        """The binding's backend name: 'cpu' or 'auto'."""
        return "auto" if self.backend == "AUTO" else "cpu"


def register():
    bpy.utils.register_class(DiffusionDOFSettings)
    setattr(bpy.types.Scene, PROPERTY, PointerProperty(type=DiffusionDOFSettings))


def unregister():
    delattr(bpy.types.Scene, PROPERTY)
    bpy.utils.unregister_class(DiffusionDOFSettings)
