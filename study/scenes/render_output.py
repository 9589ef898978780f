# SPDX-License-Identifier: MIT
"""Rendering one output of a study scene: the pinhole input (multilayer, with depth), the lens
truth, the near objects alone (fg) or everything but them (rest), the pinhole with the object
matte (Cryptomatte) beside it, with Cycles settings that make
the render deterministic and noise-free but for the lens and the pixel footprint."""

import bpy

from camera import add_camera, overscan_sensor_mm
from script_util import film_and_file, render_to


def configure(scene, args, width, height, samples, multilayer, transparent=False, matte=False):
    scene.render.engine = "CYCLES"
    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.samples = samples
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    cycles.seed = int(args["seed"])
    cycles.use_animated_seed = False
    # Emission-only materials: nothing scatters, so no bounces are needed.
    cycles.max_bounces = 0
    cycles.diffuse_bounces = cycles.glossy_bounces = 0
    cycles.transmission_bounces = cycles.volume_bounces = 0
    cycles.transparent_max_bounces = 0
    cycles.caustics_reflective = cycles.caustics_refractive = False
    film_and_file(scene, width, height, args["threads"], multilayer, transparent)
    # The object matte as Blender writes it by default (6 ranks: CryptoObject00-02, 32-bit
    # float whatever the file's depth); it leaves the Combined pass as it is.
    layer = scene.view_layers[0]
    layer.use_pass_cryptomatte_object = matte
    layer.pass_cryptomatte_depth = 6


def render_output(scene, args, cam, near, path, kind, width, height, samples, margin=0):
    """Renders the built scene's output of this kind into path; returns the seconds it took.
    margin: pixels rendered beyond each side of the width x height frame (overscan: the
    sensor grows with them, the pixel pitch stays)."""
    for obj in scene.objects:
        if obj.type == "MESH":
            obj.visible_camera = (obj.name in near) if kind == "fg" else \
                (obj.name not in near) if kind == "rest" else True
    if scene.camera is not None:
        bpy.data.objects.remove(scene.camera, do_unlink=True)
    add_camera(scene, cam, lens_dof=(kind == "truth"), aperture=args["aperture_set"],
               sensor_mm=overscan_sensor_mm(width, margin))
    configure(scene, args, width + 2 * margin, height + 2 * margin, samples, multilayer=(kind != "truth"),
              transparent=(kind == "fg"), matte=(kind == "matte"))
    return render_to(scene, path, args["verbose"], "make_scenes.py")
