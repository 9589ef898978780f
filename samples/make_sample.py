"""Renders ddof's bundled sample with Blender (Cycles, CPU), or a tiny test scene.

    blender -b --factory-startup --python-exit-code 1 --python samples/make_sample.py -- \
        [--out DIR] [--scene sample|flat] [--size WxH] [--samples-pinhole N] \
        [--samples-truth N] [--seed N] [--only pinhole|truth|both] [--threads N]

Writes into DIR (default: this script's directory):
  pinhole.exr   pinhole render (no lens blur): Blender multilayer EXR, ViewLayer.Combined.R/G/B/A
                as half and ViewLayer.Depth.Z (planar camera Z in metres) as float - the input
                ddof gets;
  truth.exr     the same camera with Cycles lens depth of field on (circular aperture): single-
                layer R/G/B/A half - the ground truth;
  camera.json   the camera sidecar of docs/design.md section 1.

Scene "sample" (the bundled one): a textured Suzanne in focus at 4 m, a striped post 1.6 m from
the lens, a chequered ground running from the camera to a brick wall at 25 m, a strip of sky
above it, small bright emissive beads in front of the wall (they become bokeh discs), an 85 mm
lens at f/1.4 on a 36 mm sensor. 320x180 keeps the committed files small.

Scene "flat" (for tests): one emissive plane of colour (0.25, 0.5, 0.75) facing the camera at
5 m, nothing else: every pixel's colour and planar depth are known exactly.

Everything is deterministic for a given Blender version: fixed seed, no denoiser, no adaptive
sampling.
"""

import json
import math
import os
import sys

import bpy

FOCAL_MM = 85.0
SENSOR_MM = 36.0
FSTOP = 1.4
FOCUS_M = 4.0


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    args = {
        "out": os.path.dirname(os.path.abspath(__file__)),
        "scene": "sample",
        "size": "320x180",
        "samples-pinhole": "256",
        "samples-truth": "4096",
        "seed": "1",
        "only": "both",
        "threads": "0",
    }
    i = 0
    while i < len(argv):
        key = argv[i].lstrip("-")
        if key not in args or i + 1 >= len(argv):
            raise SystemExit("make_sample.py: unknown or incomplete argument %r" % argv[i])
        args[key] = argv[i + 1]
        i += 2
    w, h = (int(v) for v in args["size"].lower().split("x"))
    args["width"], args["height"] = w, h
    return args


def clear_scene():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    for collection in (bpy.data.meshes, bpy.data.materials, bpy.data.lights, bpy.data.cameras):
        for block in list(collection):
            collection.remove(block)


def material(name, build):
    """A node material; build(nodes, links, output) wires the surface."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    build(nodes, links, out)
    return mat


def diffuse_with(texture_node_type, colors, scale, setup=None, coords="Object"):
    def build(nodes, links, out):
        coord = nodes.new("ShaderNodeTexCoord")
        tex = nodes.new(texture_node_type)
        bsdf = nodes.new("ShaderNodeBsdfDiffuse")
        if "Scale" in tex.inputs:
            tex.inputs["Scale"].default_value = scale
        if "Color1" in tex.inputs:
            tex.inputs["Color1"].default_value = colors[0]
            tex.inputs["Color2"].default_value = colors[1]
        if setup:
            setup(tex)
        links.new(coord.outputs[coords], tex.inputs["Vector"])
        links.new(tex.outputs["Color"], bsdf.inputs["Color"])
        links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    return build


def emission(color, strength):
    def build(nodes, links, out):
        em = nodes.new("ShaderNodeEmission")
        em.inputs["Color"].default_value = color
        em.inputs["Strength"].default_value = strength
        links.new(em.outputs["Emission"], out.inputs["Surface"])
    return build


def add_camera(scene, width, height, lens_dof):
    cam_data = bpy.data.cameras.new("Camera")
    cam_data.lens = FOCAL_MM
    cam_data.sensor_width = SENSOR_MM
    cam_data.sensor_fit = "AUTO"
    cam_data.clip_start = 0.05
    cam_data.clip_end = 1000.0
    cam_data.dof.use_dof = lens_dof
    cam_data.dof.focus_distance = FOCUS_M
    cam_data.dof.aperture_fstop = FSTOP
    cam_data.dof.aperture_blades = 0  # circular
    cam_data.dof.aperture_ratio = 1.0
    cam = bpy.data.objects.new("Camera", cam_data)
    scene.collection.objects.link(cam)
    # Looking along +Y from 1.2 m above the ground, level.
    cam.location = (0.0, 0.0, 1.2)
    cam.rotation_euler = (math.radians(90.0), 0.0, 0.0)
    scene.camera = cam
    return cam


def mesh_object(scene, name, op, mat, **kwargs):
    op(**kwargs)
    obj = bpy.context.active_object
    obj.name = name
    if mat is not None:
        obj.data.materials.append(mat)
    return obj


def build_sample(scene):
    world = bpy.data.worlds.new("World") if not scene.world else scene.world
    scene.world = world
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.45, 0.62, 0.9, 1.0)
    bg.inputs["Strength"].default_value = 0.9

    sun_data = bpy.data.lights.new("Sun", "SUN")
    sun_data.energy = 3.5
    sun_data.angle = math.radians(2.0)
    sun = bpy.data.objects.new("Sun", sun_data)
    sun.rotation_euler = (math.radians(50.0), math.radians(-20.0), math.radians(-30.0))
    scene.collection.objects.link(sun)

    ground = material("Ground", diffuse_with(
        "ShaderNodeTexChecker", [(0.55, 0.55, 0.5, 1), (0.12, 0.13, 0.12, 1)], 1.0))
    mesh_object(scene, "Ground", bpy.ops.mesh.primitive_plane_add, ground,
                size=120.0, location=(0.0, 40.0, 0.0))

    def bricks(tex):
        tex.inputs["Mortar Size"].default_value = 0.03
        tex.inputs["Brick Width"].default_value = 0.5
        tex.inputs["Row Height"].default_value = 0.25
        tex.inputs["Mortar"].default_value = (0.42, 0.4, 0.36, 1.0)
    wall = material("Wall", diffuse_with(
        "ShaderNodeTexBrick", [(0.5, 0.2, 0.12, 1), (0.32, 0.12, 0.08, 1)], 1.0, bricks))
    wall_obj = mesh_object(scene, "Wall", bpy.ops.mesh.primitive_plane_add, wall,
                           size=1.0, location=(0.0, 25.0, 1.6),
                           rotation=(math.radians(90.0), 0.0, 0.0))
    wall_obj.scale = (40.0, 3.2, 1.0)  # 40 m wide, 0..3.2 m high: sky shows above it
    # Applied, so that object coordinates (and the bricks) are in metres.
    bpy.ops.object.transform_apply(location=False, rotation=False, scale=True)

    # Suzanne in focus: a fine chequer makes sharpness (and its loss) visible.
    skin = material("Subject", diffuse_with(
        "ShaderNodeTexChecker", [(0.85, 0.45, 0.08, 1), (0.95, 0.9, 0.75, 1)], 12.0))
    monkey = mesh_object(scene, "Subject", bpy.ops.mesh.primitive_monkey_add, skin,
                         size=0.7, location=(0.15, FOCUS_M, 1.1),
                         rotation=(math.radians(-10.0), 0.0, math.radians(180.0 + 15.0)))
    bpy.ops.object.shade_smooth()
    mod = monkey.modifiers.new("Subdivision", "SUBSURF")
    mod.levels = mod.render_levels = 2

    # A post 1.6 m away: the near field.
    def stripes(tex):
        tex.bands_direction = "Z"
    post_mat = material("Post", diffuse_with(
        "ShaderNodeTexWave", None, 3.0, stripes))
    post = mesh_object(scene, "Post", bpy.ops.mesh.primitive_cylinder_add, post_mat,
                       radius=0.06, depth=3.0, location=(-0.26, 1.6, 1.5))
    bpy.ops.object.shade_smooth()
    post.name = "Post"

    # A box in the midground, 8 m.
    box = material("Box", diffuse_with(
        "ShaderNodeTexChecker", [(0.15, 0.35, 0.6, 1), (0.8, 0.85, 0.9, 1)], 4.0))
    mesh_object(scene, "Box", bpy.ops.mesh.primitive_cube_add, box,
                size=0.8, location=(1.05, 8.0, 0.4), rotation=(0.0, 0.0, math.radians(30.0)))

    # Small bright beads in front of the wall: highlights that turn into bokeh discs.
    beads = [(-2.6, 22.5, 1.9, (1.0, 0.75, 0.4)), (-1.7, 23.0, 2.6, (0.5, 0.8, 1.0)),
             (-0.9, 22.0, 1.4, (1.0, 0.55, 0.3)), (-0.2, 23.5, 3.0, (1.0, 0.9, 0.6)),
             (0.7, 22.8, 2.2, (0.6, 1.0, 0.7)), (1.6, 23.2, 2.9, (1.0, 0.7, 0.5)),
             (2.4, 22.2, 1.6, (0.7, 0.8, 1.0)), (3.1, 23.6, 2.5, (1.0, 0.85, 0.5))]
    for i, (x, y, z, c) in enumerate(beads):
        mat = material("Bead%d" % i, emission((c[0], c[1], c[2], 1.0), 60.0))
        mesh_object(scene, "Bead%d" % i, bpy.ops.mesh.primitive_uv_sphere_add, mat,
                    radius=0.05, location=(x, y, z), segments=16, ring_count=8)


def build_flat(scene):
    world = bpy.data.worlds.new("World") if not scene.world else scene.world
    scene.world = world
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    mat = material("Flat", emission((0.25, 0.5, 0.75, 1.0), 1.0))
    mesh_object(scene, "Flat", bpy.ops.mesh.primitive_plane_add, mat,
                size=40.0, location=(0.0, 5.0, 1.2), rotation=(math.radians(90.0), 0.0, 0.0))


def configure_render(scene, args, samples, pinhole):
    scene.render.engine = "CYCLES"
    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.samples = samples
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    cycles.seed = int(args["seed"])
    cycles.max_bounces = 4
    cycles.diffuse_bounces = 2
    cycles.glossy_bounces = 1
    cycles.transmission_bounces = 0
    cycles.transparent_max_bounces = 2
    cycles.caustics_reflective = False
    cycles.caustics_refractive = False
    render = scene.render
    render.resolution_x = args["width"]
    render.resolution_y = args["height"]
    render.resolution_percentage = 100
    render.pixel_aspect_x = render.pixel_aspect_y = 1.0
    render.film_transparent = False
    render.use_compositing = False  # else Blender adds a "Composite" layer to the EXR
    render.use_sequencer = False
    threads = int(args["threads"])
    render.threads_mode = "FIXED" if threads > 0 else "AUTO"
    if threads > 0:
        render.threads = threads
    scene.view_settings.view_transform = "Standard"
    layer = scene.view_layers[0]
    layer.use_pass_combined = True
    layer.use_pass_z = pinhole
    settings = render.image_settings
    settings.file_format = "OPEN_EXR_MULTILAYER" if pinhole else "OPEN_EXR"
    settings.color_mode = "RGBA"
    settings.color_depth = "16"  # half; Blender keeps the Depth pass in float
    settings.exr_codec = "ZIP"


def render_to(scene, path):
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    if not os.path.exists(path):
        raise SystemExit("make_sample.py: Blender did not write %s" % path)


def write_camera_json(path, width, height):
    sidecar = {
        "focal_length_mm": FOCAL_MM,
        "sensor_width_mm": SENSOR_MM,
        "sensor_fit": "AUTO",
        "fstop": FSTOP,
        "focus_distance_m": FOCUS_M,
        "resolution": [width, height],
        "pixel_aspect": 1.0,
        "depth": "planar",
        "unit_scale_m": 1.0,
    }
    with open(path, "w") as f:
        json.dump(sidecar, f, indent=2)
        f.write("\n")


def main():
    args = parse_args()
    os.makedirs(args["out"], exist_ok=True)
    scene = bpy.context.scene
    clear_scene()
    if args["scene"] == "flat":
        build_flat(scene)
    else:
        build_sample(scene)

    if args["only"] in ("pinhole", "both"):
        add_camera(scene, args["width"], args["height"], lens_dof=False)
        configure_render(scene, args, int(args["samples-pinhole"]), pinhole=True)
        render_to(scene, os.path.join(args["out"], "pinhole.exr"))
        bpy.data.objects.remove(scene.camera, do_unlink=True)
    if args["only"] in ("truth", "both"):
        add_camera(scene, args["width"], args["height"], lens_dof=True)
        configure_render(scene, args, int(args["samples-truth"]), pinhole=False)
        render_to(scene, os.path.join(args["out"], "truth.exr"))
    write_camera_json(os.path.join(args["out"], "camera.json"), args["width"], args["height"])


main()
