# SPDX-License-Identifier: MIT
"""Rendering one output of a study scene: the pinhole input (multilayer, with depth), the lens
truth, the near objects alone (fg) or everything but them (rest), with Cycles settings that make
the render deterministic and noise-free but for the lens and the pixel footprint."""

import bpy

from camera import add_camera
from script_util import film_and_file, render_to


def configure(scene, args, width, height, samples, multilayer, transparent=False):
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


def render_output(scene, args, cam, near, path, kind, width, height, samples):
    """Renders the built scene's output of this kind into path; returns the seconds it took."""
    for obj in scene.objects:
        if obj.type == "MESH":
            obj.visible_camera = (obj.name in near) if kind == "fg" else \
                (obj.name not in near) if kind == "rest" else True
    if scene.camera is not None:
        bpy.data.objects.remove(scene.camera, do_unlink=True)
    add_camera(scene, cam, lens_dof=(kind == "truth"), aperture=args["aperture_set"])
    configure(scene, args, width, height, samples, multilayer=(kind != "truth"),
              transparent=(kind == "fg"))
    return render_to(scene, path, args["verbose"], "make_scenes.py")
