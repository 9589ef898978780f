# SPDX-License-Identifier: MIT
"""Ground-truth scenes for the accuracy-vs-cost study (issue 7), rendered with Blender Cycles.

    blender -b --factory-startup --python-exit-code 1 --python study/scenes/make_scenes.py -- \
        --out DIR [--scenes a,b,...] [--size WxH] [--samples-pinhole N] [--samples-truth N] \
        [--samples-1080 N] [--no-1080] [--smoke] [--force] [--seed N] \
        [--only pinhole,truth,fg,rest,1080] [--threads N] [--aperture B,R,A] [--adopt] [--verbose]

For each scene, into DIR/<scene>/:
  pinhole.exr        the input ddof gets: Blender multilayer EXR, ViewLayer.Combined.R/G/B/A
                     (half) and ViewLayer.Depth.Z (float, planar camera Z in metres), exactly as
                     samples/make_sample.py writes it;
  truth.exr          the same camera with Cycles lens depth of field (circular aperture):
                     single-layer R/G/B/A half, as samples/truth.exr;
  camera.json        the camera sidecar (docs/design.md section 1, as samples/camera.json);
  fg.exr             scenes with near objects only: the near objects alone (film transparent,
                     every other object invisible to the camera), premultiplied RGBA + Depth.Z,
                     in the layout of pinhole.exr: `ddof pinhole.exr --foreground fg.exr`;
  rest.exr           scenes with near objects only: the complement of fg.exr, everything but
                     the near objects (what lies behind them), layout of pinhole.exr;
  pinhole_1080.exr   the pinhole render at 1920x1080 with few samples (for timings), and
  camera_1080.json   its sidecar (the same camera, resolution [1920, 1080]);
  render.json        what was rendered with which settings, and how long each render took.

Scenes: thin_bars, near_occluder, receding_plane, highlights, all_sharp, near_railing,
near_border, daylight (README.md beside this
file says what each stresses; daylight's sky is Blender's Nishita sky texture, the one
background that is not a flat colour). Every material is emission-only ("unlit": an albedo texture
times a fixed fake-Lambert term computed from the shading normal, no light sampling) and the
renders use no bounces, so the only noise in the truth is that of integrating the lens and the
pixel footprint, which is what the study measures against.

--smoke renders thin_bars alone at 96x54 with 4/16 samples and no 1080p pinhole (a few
seconds; the CI smoke test). Outputs whose settings and code fingerprint (code_fingerprint: this
script less the other scenes' builders, and script_util.py) match render.json are kept (a
cache) unless --force; --adopt takes outputs recorded without a fingerprint (made before it
existed) as made by the current code, once, and records it. Deterministic: fixed seed, no
adaptive sampling, no denoiser; --threads (default 2) fixes the thread count. --aperture BLADES,ROTATION_DEG,RATIO
gives the camera Blender's Blades, Rotation and Ratio (default 0,0,1: round; the truth then
draws polygons or ovals, and camera.json carries the aperture_* keys).
"""

import ast
import hashlib
import json
import math
import os
import sys
import time

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from script_util import film_and_file, parse, render_to, write_json  # noqa: E402

SCRIPT = os.path.abspath(__file__)
UTIL = os.path.join(os.path.dirname(SCRIPT), "script_util.py")
SCENE_NAMES = ["thin_bars", "near_occluder", "receding_plane", "highlights", "all_sharp",
               "near_railing", "near_border", "daylight"]

SCENE_NAMES.insert(1, "thin_strands")  # issue 29, beside thin_bars

# Truth samples per scene at the default size: chosen so that two truth renders with
# different seeds are >= 40 dB apart (README.md, "Noise floor").
TRUTH_SAMPLES = {
    "thin_bars": 1024,
    "thin_strands": 8192,
    "near_occluder": 2048,
    "receding_plane": 2048,
    "highlights": 8192,
    "all_sharp": 512,
    "near_railing": 2048,
    "near_border": 2048,
    "daylight": 4096,
}
SENSOR_MM = 36.0
LIGHT_DIR = (0.42, -0.55, 0.72)  # the fake-Lambert light, world space (normalised below)


# ---------------------------------------------------------------------------------------------
# Arguments


def parse_args():
    args = parse(
        "make_scenes.py",
        {"out": None, "scenes": ",".join(SCENE_NAMES), "size": "480x270",
         "samples-pinhole": "256", "samples-truth": None, "samples-1080": "16",
         "seed": "1", "only": "pinhole,truth,fg,rest,1080", "threads": "2",
         "aperture": "0,0,1"},
        {"no-1080", "smoke", "force", "verbose", "adopt"}, required=("out",))
    if args["smoke"]:
        args.update({"scenes": "thin_bars", "size": "96x54", "samples-pinhole": "4",
                     "samples-truth": "16", "no-1080": True})
    w, h = (int(v) for v in args["size"].lower().split("x"))
    args["width"], args["height"] = w, h
    args["scene_list"] = [s for s in args["scenes"].split(",") if s]
    for s in args["scene_list"]:
        if s not in SCENE_NAMES:
            raise SystemExit("make_scenes.py: unknown scene %r (have: %s)"
                             % (s, ", ".join(SCENE_NAMES)))
    blades, rotation, ratio = args["aperture"].split(",")
    args["aperture_set"] = (int(blades), float(rotation), float(ratio))
    args["only_set"] = set(args["only"].split(","))
    if args["no-1080"]:
        args["only_set"].discard("1080")
    return args


# ---------------------------------------------------------------------------------------------
# Materials: emission-only


def _new_material(name):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    return mat, nodes, mat.node_tree.links, out


def unlit(name, albedo, ambient=0.45, key=0.6):
    """Emission = albedo * (ambient + key * max(0, N.L)): shaded, but noise-free.
    albedo(nodes, links) returns a colour socket, or is an RGB tuple."""
    mat, nodes, links, out = _new_material(name)
    geo = nodes.new("ShaderNodeNewGeometry")
    dot = nodes.new("ShaderNodeVectorMath")
    dot.operation = "DOT_PRODUCT"
    n = math.sqrt(sum(c * c for c in LIGHT_DIR))
    dot.inputs[1].default_value = tuple(c / n for c in LIGHT_DIR)
    links.new(geo.outputs["Normal"], dot.inputs[0])
    clamp = nodes.new("ShaderNodeMath")
    clamp.operation = "MAXIMUM"
    clamp.inputs[1].default_value = 0.0
    links.new(dot.outputs["Value"], clamp.inputs[0])
    shade = nodes.new("ShaderNodeMath")
    shade.operation = "MULTIPLY_ADD"
    shade.inputs[1].default_value = key
    shade.inputs[2].default_value = ambient
    links.new(clamp.outputs["Value"], shade.inputs[0])
    mix = nodes.new("ShaderNodeMixRGB")
    mix.blend_type = "MULTIPLY"
    mix.inputs["Fac"].default_value = 1.0
    if isinstance(albedo, tuple):
        mix.inputs["Color1"].default_value = albedo + (1.0,) if len(albedo) == 3 else albedo
    else:
        links.new(albedo(nodes, links), mix.inputs["Color1"])
    links.new(shade.outputs["Value"], mix.inputs["Color2"])
    em = nodes.new("ShaderNodeEmission")
    em.inputs["Strength"].default_value = 1.0
    links.new(mix.outputs["Color"], em.inputs["Color"])
    links.new(em.outputs["Emission"], out.inputs["Surface"])
    return mat


def texture(tex_type, colors=None, scale=1.0, setup=None, coords="Object"):
    """An albedo builder for unlit(): a procedural texture in object coordinates (metres once
    the object's scale is applied)."""
    def build(nodes, links):
        coord = nodes.new("ShaderNodeTexCoord")
        tex = nodes.new(tex_type)
        if "Scale" in tex.inputs:
            tex.inputs["Scale"].default_value = scale
        if colors and "Color1" in tex.inputs:
            tex.inputs["Color1"].default_value = colors[0]
            tex.inputs["Color2"].default_value = colors[1]
        if setup:
            setup(tex)
        links.new(coord.outputs[coords], tex.inputs["Vector"])
        return tex.outputs["Color"]
    return build


def multiply(a, b, fac=1.0):
    """Albedo builder: a * b (MixRGB multiply with factor fac)."""
    def build(nodes, links):
        mix = nodes.new("ShaderNodeMixRGB")
        mix.blend_type = "MULTIPLY"
        mix.inputs["Fac"].default_value = fac
        links.new(a(nodes, links), mix.inputs["Color1"])
        links.new(b(nodes, links), mix.inputs["Color2"])
        return mix.outputs["Color"]
    return build


def emission(name, color, strength):
    mat, nodes, links, out = _new_material(name)
    em = nodes.new("ShaderNodeEmission")
    em.inputs["Color"].default_value = tuple(color[:3]) + (1.0,)
    em.inputs["Strength"].default_value = strength
    links.new(em.outputs["Emission"], out.inputs["Surface"])
    return mat


def bricks(width, height, mortar, mortar_color, offset=0.5):
    def setup(tex):
        tex.inputs["Mortar Size"].default_value = mortar
        tex.inputs["Brick Width"].default_value = width
        tex.inputs["Row Height"].default_value = height
        tex.inputs["Mortar"].default_value = mortar_color
        tex.offset = offset
    return setup


def wave_z(tex):
    tex.bands_direction = "Z"


# ---------------------------------------------------------------------------------------------
# Objects


def set_world(scene, color, strength=1.0):
    world = bpy.data.worlds.new("World")
    scene.world = world
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = tuple(color) + (1.0,)
    bg.inputs["Strength"].default_value = strength


def _finish(obj, name, mat, smooth=False, apply_scale=False):
    obj.name = name
    if mat is not None:
        obj.data.materials.append(mat)
    if smooth:
        bpy.ops.object.shade_smooth()
    if apply_scale:
        bpy.ops.object.transform_apply(location=False, rotation=False, scale=True)
    return obj


def plane(name, mat, size, location, rotation=(0.0, 0.0, 0.0)):
    """A plane of size (sx, sy) metres; rotation in degrees. Scale applied, so object
    coordinates are metres."""
    bpy.ops.mesh.primitive_plane_add(size=1.0, location=location,
                                     rotation=tuple(math.radians(a) for a in rotation))
    obj = bpy.context.active_object
    obj.scale = (size[0], size[1], 1.0)
    return _finish(obj, name, mat, apply_scale=True)


def wall(name, mat, size, y, z_center, x_center=0.0):
    """A vertical plane facing the camera (normal -Y) at distance y."""
    return plane(name, mat, size, (x_center, y, z_center), (90.0, 0.0, 0.0))


def rod(name, mat, p0, p1, radius, vertices=24):
    """A cylinder from point p0 to p1."""
    d = [b - a for a, b in zip(p0, p1)]
    length = math.sqrt(sum(c * c for c in d))
    mid = [(a + b) / 2 for a, b in zip(p0, p1)]
    # Turn the +Z axis onto d: tilt by theta about X, then turn by phi + 90 deg about Z
    # (Euler XYZ: X first), which takes +Z to (sin t cos p, sin t sin p, cos t).
    theta = math.acos(max(-1.0, min(1.0, d[2] / length)))
    phi = math.atan2(d[1], d[0])
    bpy.ops.mesh.primitive_cylinder_add(vertices=vertices, radius=radius, depth=length,
                                        location=mid, rotation=(theta, 0.0, phi + math.pi / 2))
    obj = bpy.context.active_object
    return _finish(obj, name, mat, smooth=True)


def sphere(name, mat, location, radius, segments=24, rings=12):
    bpy.ops.mesh.primitive_uv_sphere_add(radius=radius, location=location, segments=segments,
                                         ring_count=rings)
    return _finish(bpy.context.active_object, name, mat, smooth=True)


def monkey(name, mat, location, size, rotation=(-10.0, 0.0, 195.0)):
    bpy.ops.mesh.primitive_monkey_add(size=size, location=location,
                                      rotation=tuple(math.radians(a) for a in rotation))
    obj = _finish(bpy.context.active_object, name, mat, smooth=True)
    mod = obj.modifiers.new("Subdivision", "SUBSURF")
    mod.levels = mod.render_levels = 2
    return obj


def box(name, mat, location, size, rotation_z=0.0):
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=location,
                                    rotation=(0.0, 0.0, math.radians(rotation_z)))
    obj = bpy.context.active_object
    obj.scale = size
    return _finish(obj, name, mat, apply_scale=True)


# ---------------------------------------------------------------------------------------------
# The scenes. Each returns (camera settings, names of the near objects).
# Camera: looking along +Y from `height` metres, pitched down `pitch` degrees.


def at(cam, u, v, dist):
    """The world point at normalised image position (u, v) (-1..1 across the frame's width
    and height, +v up) and planar distance dist, for a level camera (pitch 0) with the
    default 16:9 frame."""
    half_w = dist * SENSOR_MM / 2.0 / cam["focal_mm"]
    half_h = half_w * 9.0 / 16.0
    return (u * half_w, dist, cam["height"] + v * half_h)


def checker(c1, c2, scale):
    return texture("ShaderNodeTexChecker", [c1, c2], scale)


def build_thin_bars(scene):
    """Thin sharp poles, wires and a wire mesh in focus at 3 m over a brick wall at 25 m."""
    cam = dict(focal_mm=85.0, fstop=1.4, focus_m=3.0, height=1.2, pitch=0.0)
    set_world(scene, (0.5, 0.62, 0.85))
    wall_mat = unlit("Wall", multiply(
        texture("ShaderNodeTexBrick", [(0.95, 0.75, 0.25, 1), (0.75, 0.2, 0.1, 1)], 1.0,
                bricks(0.9, 0.3, 0.04, (0.05, 0.08, 0.2, 1.0))),
        checker((1.0, 1.0, 1.0, 1), (0.35, 0.55, 0.9, 1), 0.5), 0.6), ambient=0.7, key=0.4)
    wall("Wall", wall_mat, (40.0, 20.0), 25.0, 1.2)
    white = unlit("White", (0.9, 0.9, 0.88))
    dark = unlit("Dark", (0.03, 0.03, 0.035))
    red = unlit("Red", texture("ShaderNodeTexWave", None, 12.0, wave_z))
    yellow = unlit("Yellow", (0.95, 0.8, 0.1))
    steel = unlit("Steel", (0.7, 0.72, 0.75))
    y = cam["focus_m"]
    # Vertical poles, radius from 1.5 mm (about 1.1 px wide at 3 m) to 12 mm (9 px).
    for i, (x, r, mat) in enumerate([(-0.56, 0.0015, white), (-0.47, 0.0025, dark),
                                     (-0.37, 0.004, red), (-0.25, 0.007, white),
                                     (-0.10, 0.012, dark), (0.02, 0.002, yellow),
                                     (0.12, 0.0035, white), (0.20, 0.001, dark)]):
        rod("Pole%d" % i, mat, (x, y + r, 0.5), (x, y + r, 2.0), r)
    # Horizontal and slanted wires across the frame.
    rod("Wire0", dark, (-0.8, y, 1.42), (0.8, y, 1.42), 0.0015)
    rod("Wire1", white, (-0.8, y, 1.02), (0.8, y, 1.02), 0.003)
    rod("Wire2", yellow, (-0.8, y, 0.88), (0.8, y, 1.50), 0.002)
    # A wire mesh (pitch 4 cm, 1.2 mm wires: under one pixel wide) on the right.
    for i in range(10):
        x = 0.26 + 0.04 * i
        rod("MeshV%d" % i, steel, (x, y, 0.95), (x, y, 1.35), 0.0012, vertices=8)
    for i in range(11):
        z = 0.95 + 0.04 * i
        rod("MeshH%d" % i, steel, (0.26, y, z), (0.62, y, z), 0.0012, vertices=8)
    return cam, []


def strand(name, mat, points, radius):
    """A hair-like strand: a poly curve through points, bevelled to radius and turned into a
    mesh (the study's fg / rest passes switch meshes only)."""
    data = bpy.data.curves.new(name, "CURVE")
    data.dimensions = "3D"
    data.bevel_depth = radius
    data.bevel_resolution = 1
    data.use_fill_caps = True
    spline = data.splines.new("POLY")
    spline.points.add(len(points) - 1)
    for point, p in zip(spline.points, points):
        point.co = (p[0], p[1], p[2], 1.0)
    obj = bpy.data.objects.new(name, data)
    bpy.context.scene.collection.objects.link(obj)
    for other in bpy.context.selected_objects:
        other.select_set(False)
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
    bpy.ops.object.convert(target="MESH")
    obj = bpy.context.active_object
    return _finish(obj, name, mat, smooth=True)


def build_thin_strands(scene):
    """In-focus bars (2-6 px), hair-like strands (1-2 px) and a wire at 3 m before a dark
    brick wall at 25 m with 18 lights at 12-22 m (CoC 17-20 px), ten of them partly behind a
    bar or the strands; the thin structures are the foreground element (fg.exr)."""
    cam = dict(focal_mm=85.0, fstop=1.4, focus_m=3.0, height=1.2, pitch=0.0)
    set_world(scene, (0.02, 0.025, 0.04))
    back = unlit("Wall", multiply(
        texture("ShaderNodeTexBrick", [(0.2, 0.13, 0.08, 1), (0.11, 0.07, 0.05, 1)], 1.0,
                bricks(0.6, 0.22, 0.03, (0.03, 0.03, 0.035, 1.0))),
        checker((1.0, 1.0, 1.0, 1), (0.55, 0.65, 0.8, 1), 0.7), 0.6), ambient=0.7, key=0.4)
    wall("Wall", back, (40.0, 20.0), 25.0, 1.2)
    px = 2.0 / 480.0  # one pixel of the 480x270 frame in at()'s u
    d = cam["focus_m"]
    pitch = d * SENSOR_MM / cam["focal_mm"] / 480.0  # metres per pixel at the focus
    near = []
    # Vertical bars: u, width in pixels, material.
    bar_mats = [unlit("BarWhite", (0.85, 0.85, 0.82)), unlit("BarDark", (0.04, 0.04, 0.045)),
                unlit("BarRed", texture("ShaderNodeTexWave", None, 12.0, wave_z))]
    bars = [(-0.72, 3.0, 0), (-0.40, 2.0, 1), (-0.02, 4.0, 2), (0.62, 3.0, 0), (0.86, 6.0, 1)]
    for i, (u, w, m) in enumerate(bars):
        r = w * pitch / 2.0
        top, bottom = at(cam, u, 1.1, d + r), at(cam, u, -1.1, d + r)
        near.append(rod("Bar%d" % i, bar_mats[m], bottom, top, r, vertices=12).name)
    # A slanted wire, 1 px.
    wire_mat = unlit("Wire", (0.6, 0.62, 0.65))
    near.append(rod("Wire", wire_mat, at(cam, -1.1, 0.42, d), at(cam, 1.1, 0.2, d),
                    0.5 * pitch, vertices=8).name)
    # Hair: two hanks of strands hanging from the top edge with a gentle sway, radii of 0.5
    # to 1 pixel, blond and dark.
    hair = [unlit("HairBlond", (0.8, 0.62, 0.35)), unlit("HairDark", (0.09, 0.06, 0.04))]
    for hank, (u0, count, length) in enumerate([(-0.28, 14, 1.6), (0.28, 12, 1.3)]):
        for k in range(count):
            u = u0 + (k - count / 2.0) * 0.011
            depth = d + 0.01 * ((k * 7) % 5 - 2)
            amp, phase = 0.015 + 0.01 * (k % 3), 0.7 * k
            points = []
            for j in range(25):
                t = j / 24.0
                v = 1.1 - t * length * (0.85 + 0.15 * ((k * 3) % 4) / 3.0)
                du = amp * math.sin(3.0 * t + phase) + 0.04 * t * t * (1 if k % 2 else -1)
                points.append(at(cam, u + du, v, depth))
            r = pitch * (0.5 + 0.5 * ((k * 5) % 3) / 2.0)
            near.append(strand("Hair%d_%d" % (hank, k), hair[(k // 2) % 2], points, r).name)
    # Far lights (u, v, distance): behind a bar's middle, beside its edge, behind the hair,
    # and free (for the free highlights' neighbourhood).
    warm = [(1.0, 0.7, 0.35), (1.0, 0.85, 0.55), (0.6, 0.8, 1.0), (1.0, 0.55, 0.3)]
    lights = [(-0.72, 0.65, 14.0), (-0.72 + 2 * px, -0.25, 18.0), (-0.40 - 1.5 * px, 0.1, 12.0),
              (-0.02, -0.55, 20.0), (-0.02 + 3 * px, 0.75, 16.0), (0.62 - 2 * px, 0.0, 22.0),
              (0.86 + 4 * px, -0.7, 15.0), (-0.28, 0.25, 13.0), (0.27, 0.55, 17.0),
              (0.30, -0.05, 21.0),
              (-0.88, -0.3, 13.0), (-0.55, -0.75, 16.0), (-0.2, -0.82, 19.0),
              (0.12, 0.1, 14.0), (0.45, -0.45, 18.0), (0.16, -0.7, 12.0), (0.75, 0.6, 20.0),
              (-0.55, 0.5, 22.0)]
    for i, (u, v, dist) in enumerate(lights):
        strength = (60.0, 25.0, 10.0)[i % 3]
        sphere("Light%d" % i, emission("Light%d" % i, warm[i % 4], strength),
               at(cam, u, v, dist), 0.0022 * dist)
    return cam, near


def build_near_occluder(scene):
    """A chequered Suzanne in focus at 4 m behind a post at 1.2 m and a branch at 0.7 m."""
    cam = dict(focal_mm=85.0, fstop=1.4, focus_m=4.0, height=1.2, pitch=0.0)
    set_world(scene, (0.5, 0.62, 0.85))
    back = unlit("Back", texture("ShaderNodeTexBrick", [(0.3, 0.55, 0.25, 1),
                                                        (0.15, 0.3, 0.12, 1)], 1.0,
                                 bricks(0.5, 0.25, 0.03, (0.8, 0.8, 0.7, 1.0))))
    wall("Back", back, (12.0, 8.0), 9.0, 1.2)
    skin = unlit("Subject", checker((0.85, 0.45, 0.08, 1), (0.95, 0.9, 0.75, 1), 12.0))
    monkey("Subject", skin, (0.05, 4.0, 1.15), 0.6)
    card = unlit("Card", checker((0.1, 0.15, 0.5, 1), (0.95, 0.95, 0.9, 1), 40.0))
    wall("Card", card, (0.3, 0.4), 4.0, 1.25, x_center=0.48)
    bark = unlit("Bark", multiply(texture("ShaderNodeTexWave", None, 6.0, wave_z),
                                  (lambda n, l: _rgb(n, (0.45, 0.3, 0.18)))))
    # A post 1.2 m from the lens (CoC ~40 px, 64 px wide) and a branch at 0.9 m (CoC ~59 px,
    # 60 px wide, twigs 20 px wide: they nearly vanish in the truth).
    post = rod("Post", bark, (-0.14, 1.2, -0.5), (-0.14, 1.2, 2.5), 0.03)
    leafy = unlit("Branch", multiply(
        checker((0.25, 0.5, 0.12, 1), (0.5, 0.35, 0.15, 1), 60.0),
        (lambda n, l: _rgb(n, (0.8, 0.8, 0.8)))))
    d = 0.9
    branch = rod("Branch", leafy, at(cam, 1.1, -0.55, d), at(cam, -0.15, 0.25, d), 0.024)
    twig0 = rod("Twig0", leafy, at(cam, 0.55, -0.2, d), at(cam, 0.7, 0.6, d - 0.02), 0.008)
    twig1 = rod("Twig1", leafy, at(cam, 0.2, 0.02, d), at(cam, 0.05, 0.55, d + 0.03), 0.006)
    return cam, [post.name, branch.name, twig0.name, twig1.name]


def _rgb(nodes, color):
    node = nodes.new("ShaderNodeRGB")
    node.outputs["Color"].default_value = tuple(color) + (1.0,)
    return node.outputs["Color"]


def build_receding_plane(scene):
    """A tiled ground seen from 25 cm up: blurred near (CoC ~40 px), sharp at 4 m, blurred far."""
    cam = dict(focal_mm=85.0, fstop=1.4, focus_m=4.0, height=0.25, pitch=5.0)
    set_world(scene, (0.55, 0.68, 0.9))
    ground = unlit("Ground", multiply(
        texture("ShaderNodeTexBrick", [(0.8, 0.55, 0.3, 1), (0.35, 0.4, 0.5, 1)], 1.0,
                bricks(0.6, 0.3, 0.02, (0.08, 0.08, 0.08, 1.0))),
        checker((1.0, 1.0, 1.0, 1), (0.45, 0.45, 0.45, 1), 10.0)))
    # Object coordinates after the 90 degree turn: bricks run across (x) and recede (y).
    plane("Ground", ground, (120.0, 400.0), (0.0, 200.0, 0.0))
    return cam, []


def build_highlights(scene):
    """Small bright lights out of focus in front of (1.4-2 m) and behind (7-22 m) a dim
    Suzanne in focus at 3 m, over a dark wall."""
    cam = dict(focal_mm=85.0, fstop=1.4, focus_m=3.0, height=1.2, pitch=0.0)
    set_world(scene, (0.01, 0.012, 0.02))
    back = unlit("Back", texture("ShaderNodeTexBrick", [(0.05, 0.035, 0.03, 1),
                                                        (0.02, 0.02, 0.03, 1)], 1.0,
                                 bricks(0.8, 0.3, 0.05, (0.008, 0.008, 0.01, 1.0))))
    wall("Back", back, (30.0, 16.0), 30.0, 1.2)
    skin = unlit("Subject", checker((0.2, 0.16, 0.12, 1), (0.4, 0.38, 0.34, 1), 12.0))
    monkey("Subject", skin, (-0.22, 3.0, 1.12), 0.32)
    near = []
    warm = [(1.0, 0.7, 0.35), (1.0, 0.85, 0.55), (0.6, 0.8, 1.0), (1.0, 0.55, 0.3)]
    # Behind the focus: a slanted string of lights from 7 to 22 m (CoC 13 to 20 px), and a
    # few scattered ones; radius ~0.0022 * distance: about 5 px wide in the pinhole.
    far = [(-0.15 + 0.08 * i, 0.35 - 0.055 * i, 7.0 + 1.35 * i) for i in range(12)]
    far += [(-0.75, 0.55, 12.0), (0.8, -0.6, 9.0), (-0.5, -0.7, 15.0), (0.35, 0.7, 20.0)]
    for i, (u, v, dist) in enumerate(far):
        strength = (60.0, 25.0, 8.0)[i % 3]
        sphere("Far%d" % i, emission("Far%d" % i, warm[i % 4], strength),
               at(cam, u, v, dist), 0.0022 * dist)
    # In front of the focus: 1.4 to 2.2 m (CoC 25 to 11 px), two of them over the subject.
    for i, (u, v, dist, strength) in enumerate([(-0.42, 0.05, 1.45, 40.0),
                                                (-0.22, -0.25, 1.7, 12.0),
                                                (0.15, 0.45, 1.6, 30.0),
                                                (0.45, -0.4, 1.9, 20.0),
                                                (0.7, 0.2, 2.2, 6.0),
                                                (-0.8, -0.5, 1.5, 25.0)]):
        obj = sphere("Near%d" % i, emission("Near%d" % i, warm[(i + 1) % 4], strength),
                     at(cam, u, v, dist), 0.0024 * dist)
        near.append(obj.name)
    return cam, near


def build_near_railing(scene):
    """A railing 0.5 m from the lens (CoC ~90 px; balusters 2.4 cm, ~50 px, so the lens sees
    around them) over a chequered Suzanne in focus at 3 m and a hedge-like wall at 12 m."""
    cam = dict(focal_mm=85.0, fstop=1.8, focus_m=3.0, height=1.1, pitch=0.0)
    set_world(scene, (0.62, 0.7, 0.82))
    hedge = unlit("Hedge", multiply(
        checker((0.2, 0.45, 0.15, 1), (0.35, 0.6, 0.25, 1), 8.0),
        texture("ShaderNodeTexBrick", [(1.0, 1.0, 1.0, 1), (0.7, 0.8, 0.6, 1)], 1.0,
                bricks(0.35, 0.12, 0.02, (0.15, 0.25, 0.1, 1.0)))), ambient=0.6, key=0.4)
    wall("Hedge", hedge, (30.0, 12.0), 12.0, 1.1)
    skin = unlit("Subject", checker((0.2, 0.35, 0.8, 1), (0.95, 0.9, 0.8, 1), 12.0))
    monkey("Subject", skin, (0.1, 3.0, 1.05), 0.45)
    wood = unlit("Wood", multiply(texture("ShaderNodeTexWave", None, 20.0, wave_z),
                                  (lambda n, l: _rgb(n, (0.55, 0.33, 0.16)))))
    d = 0.5
    near = []
    # The top rail across the lower third, four balusters below it.
    near.append(rod("Rail", wood, at(cam, -1.3, -0.35, d), at(cam, 1.3, -0.35, d),
                    0.012).name)
    for i, u in enumerate([-0.75, -0.25, 0.25, 0.75]):
        near.append(rod("Baluster%d" % i, wood, at(cam, u, -1.3, d), at(cam, u, -0.35, d),
                        0.012).name)
    return cam, near


def build_near_border(scene):
    """A dark door frame at 0.8 m covering the frame's left edge (CoC ~45 px) and a ball at
    1 m cut by the top edge, over a subject in focus at 4 m and a brick wall at 10 m."""
    cam = dict(focal_mm=85.0, fstop=1.4, focus_m=4.0, height=1.2, pitch=0.0)
    set_world(scene, (0.5, 0.62, 0.85))
    brick = unlit("Wall", texture("ShaderNodeTexBrick", [(0.75, 0.4, 0.2, 1),
                                                         (0.5, 0.25, 0.12, 1)], 1.0,
                                  bricks(0.4, 0.2, 0.03, (0.85, 0.82, 0.75, 1.0))))
    wall("Wall", brick, (20.0, 10.0), 10.0, 1.2)
    skin = unlit("Subject", checker((0.85, 0.45, 0.08, 1), (0.95, 0.9, 0.75, 1), 12.0))
    monkey("Subject", skin, (-0.1, 4.0, 1.15), 0.6)
    paint = unlit("Frame", multiply(checker((0.12, 0.1, 0.1, 1), (0.3, 0.25, 0.22, 1), 30.0),
                                    (lambda n, l: _rgb(n, (0.9, 0.9, 0.9)))))
    left = at(cam, -1.25, 0.0, 0.8)
    door = box("Door", paint, (left[0] + 0.02, 0.8, cam["height"]), (0.12, 0.05, 3.0))
    ball_mat = unlit("Ball", checker((0.9, 0.85, 0.2, 1), (0.2, 0.45, 0.8, 1), 8.0))
    ball = sphere("Ball", ball_mat, at(cam, 0.45, 0.95, 1.0), 0.05)
    return cam, [door.name, ball.name]


def build_all_sharp(scene):
    """50 mm f/32 focused at 8 m: objects from 6 m to the sky all have CoC <= 0.13 px (0.52 px
    at 1080p)."""
    cam = dict(focal_mm=50.0, fstop=32.0, focus_m=8.0, height=1.6, pitch=3.0)
    set_world(scene, (0.5, 0.62, 0.85))
    ground = unlit("Ground", checker((0.55, 0.55, 0.5, 1), (0.15, 0.16, 0.14, 1), 1.0))
    plane("Ground", ground, (120.0, 200.0), (0.0, 100.0, 0.0))
    brick = unlit("Wall", texture("ShaderNodeTexBrick", [(0.55, 0.22, 0.12, 1),
                                                         (0.35, 0.13, 0.08, 1)], 1.0,
                                  bricks(0.5, 0.25, 0.03, (0.42, 0.4, 0.36, 1.0))))
    wall("Wall", brick, (40.0, 4.0), 40.0, 2.0)
    skin = unlit("Subject", checker((0.85, 0.45, 0.08, 1), (0.95, 0.9, 0.75, 1), 12.0))
    monkey("Subject", skin, (0.2, 8.0, 1.2), 1.0)
    crate = unlit("Box", checker((0.15, 0.35, 0.6, 1), (0.8, 0.85, 0.9, 1), 4.0))
    box("Box0", crate, (-1.6, 10.0, 0.5), (1.0, 1.0, 1.0), 30.0)
    box("Box1", crate, (2.6, 16.0, 0.8), (1.2, 1.6, 1.6), -20.0)
    striped = unlit("Post", texture("ShaderNodeTexWave", None, 3.0, wave_z))
    for i, (x, y) in enumerate([(-1.0, 7.0), (1.3, 12.0), (-3.0, 20.0), (4.0, 28.0)]):
        rod("Post%d" % i, striped, (x, y, 0.0), (x, y, 3.0), 0.04)
    thin = unlit("Wire", (0.05, 0.05, 0.05))
    rod("Wire", thin, (-6.0, 14.0, 2.6), (6.0, 14.0, 2.3), 0.006)
    return cam, []


def ramp(tex_type, colors, scale, setup=None, detail=None):
    """An albedo builder for unlit(): a procedural texture's Fac (object coordinates, metres)
    through a colour ramp of `colors` (RGB tuples, evenly spaced)."""
    def build(nodes, links):
        coord = nodes.new("ShaderNodeTexCoord")
        tex = nodes.new(tex_type)
        tex.inputs["Scale"].default_value = scale
        if detail is not None and "Detail" in tex.inputs:
            tex.inputs["Detail"].default_value = detail
        if setup:
            setup(tex)
        links.new(coord.outputs["Object"], tex.inputs["Vector"])
        cr = nodes.new("ShaderNodeValToRGB")
        elems = cr.color_ramp.elements
        while len(elems) < len(colors):
            elems.new(0.5)
        for i, c in enumerate(colors):
            elems[i].position = i / (len(colors) - 1)
            elems[i].color = tuple(c) + (1.0,)
        fac = tex.outputs["Fac"] if "Fac" in tex.outputs else tex.outputs["Distance"]
        links.new(fac, cr.inputs["Fac"])
        return cr.outputs["Color"]
    return build


def build_daylight(scene):
    """A post in focus at 2.5 m (85 mm f/1.8, pitched 1.5 deg up) in a park: trees at 28-75 m,
    grass to the horizon and a bright Nishita sky (no sun disc) behind them, sun glints on the
    crowns and the grass."""
    import random
    cam = dict(focal_mm=85.0, fstop=1.8, focus_m=2.5, height=1.2, pitch=-1.5)
    world = bpy.data.worlds.new("World")
    scene.world = world
    world.use_nodes = True
    nodes, links = world.node_tree.nodes, world.node_tree.links
    sky = nodes.new("ShaderNodeTexSky")
    sky.sky_type = "NISHITA"
    sky.sun_disc = False
    sky.sun_elevation = math.radians(35.0)
    sky.sun_rotation = math.radians(150.0)  # behind the camera's right (the camera looks +Y)
    sky.altitude = 100.0
    bg = nodes["Background"]
    bg.inputs["Strength"].default_value = 0.12  # sky 0.5-0.85 linear: bright, under 1
    links.new(sky.outputs["Color"], bg.inputs["Color"])

    grass = unlit("Grass", multiply(
        ramp("ShaderNodeTexNoise", [(0.12, 0.2, 0.05), (0.3, 0.45, 0.12), (0.5, 0.55, 0.2)],
             2.0, detail=3.0),
        ramp("ShaderNodeTexVoronoi", [(0.7, 0.75, 0.6), (1.0, 1.0, 1.0)], 6.0)),
        ambient=0.8, key=0.5)
    plane("Ground", grass, (800.0, 4000.0), (0.0, 2000.0, 0.0))
    bark = unlit("Bark", ramp("ShaderNodeTexNoise", [(0.08, 0.06, 0.05), (0.3, 0.22, 0.15),
                                                      (0.45, 0.38, 0.3)], 3.0, detail=3.0))
    leaves = unlit("Leaves", multiply(
        ramp("ShaderNodeTexNoise", [(0.05, 0.15, 0.03), (0.2, 0.4, 0.08), (0.45, 0.6, 0.15)],
             1.5, detail=3.0),
        ramp("ShaderNodeTexVoronoi", [(0.55, 0.6, 0.5), (1.0, 1.0, 1.0)], 3.0)),
        ambient=0.55, key=0.7)
    rng = random.Random(7)
    eye = (0.0, 0.0, cam["height"])
    crowns = []
    # Trees (x, distance): crowns of three overlapping spheres, gaps of sky between them.
    for i, (x, y) in enumerate([(-13.0, 42.0), (-6.5, 34.0), (-1.0, 58.0), (4.5, 38.0),
                                (10.5, 50.0), (-19.0, 70.0), (16.0, 66.0), (1.5, 28.0),
                                (-9.0, 75.0)]):
        top = rng.uniform(3.5, 5.0)
        rod("Trunk%d" % i, bark, (x, y, 0.0), (x, y, top + 1.0), rng.uniform(0.2, 0.35),
            vertices=16)
        for j in range(3):
            r = rng.uniform(1.8, 3.0)
            c = (x + rng.uniform(-2.0, 2.0), y + rng.uniform(-1.0, 1.0),
                 top + r * 0.7 + rng.uniform(0.0, 1.5))
            sphere("Crown%d_%d" % (i, j), leaves, c, r, segments=32, rings=16)
            crowns.append((c, r))
    # The subject: a wooden post with a sign, in focus at 2.5 m.
    post = unlit("Post", ramp("ShaderNodeTexWave", [(0.35, 0.25, 0.15), (0.6, 0.45, 0.3)],
                              25.0))
    y = cam["focus_m"]
    rod("Post", post, (-0.1, y + 0.03, 0.0), (-0.1, y + 0.03, 1.32), 0.03)
    sign = unlit("Sign", checker((0.9, 0.88, 0.8, 1), (0.1, 0.3, 0.15, 1), 50.0))
    wall("Sign", sign, (0.2, 0.12), y - 0.002, 1.22, x_center=-0.1)
    # Sun glints: small, very bright spots (what the highlight pass takes) where rays through
    # some image points (u, v in -1..1, +v up) hit a crown (28-75 m: CoC 19-21 px), 5 cm in
    # front of it, and on the grass; about 2 px wide in the pinhole.
    glint = emission("Glint", (1.0, 0.95, 0.85), 20.0)
    bpy.context.view_layer.update()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    p = math.radians(-cam["pitch"])
    tan_h = SENSOR_MM / 2.0 / cam["focal_mm"]
    spots = []
    for u, v in [(-0.62, 0.7), (-0.1, 0.5), (0.67, 0.6), (0.38, 0.85), (-0.75, 0.45)]:
        a, b = u * tan_h, v * tan_h * 9.0 / 16.0
        d = (a, math.cos(p) - b * math.sin(p), math.sin(p) + b * math.cos(p))
        n = math.sqrt(sum(c * c for c in d))
        d = tuple(c / n for c in d)
        hit, loc, _, _, obj, _ = scene.ray_cast(depsgraph, eye, d)
        if not hit or not obj.name.startswith("Crown"):
            raise RuntimeError("daylight: glint ray (%g, %g) hits %s"
                               % (u, v, obj.name if hit else "nothing"))
        spots.append(tuple(q - 0.05 * c for q, c in zip(loc, d)))
    spots += [(-1.6, 16.0, 0.05), (2.4, 22.0, 0.05)]
    for i, q in enumerate(spots):
        sphere("Glint%d" % i, glint, q, 0.0009 * q[1], segments=12, rings=6)
    return cam, []


BUILDERS = {
    "thin_bars": build_thin_bars,
    "thin_strands": build_thin_strands,
    "near_occluder": build_near_occluder,
    "receding_plane": build_receding_plane,
    "highlights": build_highlights,
    "all_sharp": build_all_sharp,
    "near_railing": build_near_railing,
    "near_border": build_near_border,
    "daylight": build_daylight,
}


# ---------------------------------------------------------------------------------------------
# Camera, render settings, output


def add_camera(scene, cam, lens_dof, aperture=(0, 0.0, 1.0)):
    data = bpy.data.cameras.new("Camera")
    data.lens = cam["focal_mm"]
    data.sensor_width = SENSOR_MM
    data.sensor_fit = "AUTO"
    data.clip_start = 0.05
    data.clip_end = 1000.0
    data.dof.use_dof = lens_dof
    data.dof.focus_distance = cam["focus_m"]
    data.dof.aperture_fstop = cam["fstop"]
    data.dof.aperture_blades = aperture[0]  # 0: circular
    data.dof.aperture_rotation = math.radians(aperture[1])
    data.dof.aperture_ratio = aperture[2]
    obj = bpy.data.objects.new("Camera", data)
    scene.collection.objects.link(obj)
    obj.location = (0.0, 0.0, cam["height"])
    obj.rotation_euler = (math.radians(90.0 - cam["pitch"]), 0.0, 0.0)
    scene.camera = obj
    return obj


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


def camera_sidecar(cam, width, height, aperture=(0, 0.0, 1.0)):
    sidecar = {
        "focal_length_mm": cam["focal_mm"],
        "sensor_width_mm": SENSOR_MM,
        "sensor_fit": "AUTO",
        "fstop": cam["fstop"],
        "focus_distance_m": cam["focus_m"],
        "resolution": [width, height],
        "pixel_aspect": 1.0,
        "depth": "planar",
        "unit_scale_m": 1.0,
    }
    if tuple(aperture) != (0, 0.0, 1.0):
        sidecar.update({"aperture_blades": aperture[0], "aperture_rotation_deg": aperture[1],
                        "aperture_ratio": aperture[2]})
    return sidecar


def coc_px(cam, z, width):
    """Blender's Cycles CoC (docs/design.md section 1) in pixels, AUTO fit on a landscape frame."""
    f = cam["focal_mm"] / 1000.0
    s1 = cam["focus_m"]
    return f * f / (cam["fstop"] * s1) * abs(z - s1) / z * width / (SENSOR_MM / 1000.0)


# ---------------------------------------------------------------------------------------------


def plan_outputs(args, name, has_near):
    """(file, kind, width, height, samples) of each output this run wants for a scene."""
    w, h = args["width"], args["height"]
    sp = int(args["samples-pinhole"])
    st = int(args["samples-truth"]) if args["samples-truth"] else TRUTH_SAMPLES[name]
    want = args["only_set"]
    plan = []
    if "pinhole" in want:
        plan.append(("pinhole.exr", "pinhole", w, h, sp))
    if "truth" in want:
        plan.append(("truth.exr", "truth", w, h, st))
    if has_near and "fg" in want:
        plan.append(("fg.exr", "fg", w, h, sp))
    if has_near and "rest" in want:
        plan.append(("rest.exr", "rest", w, h, sp))
    if "1080" in want:
        plan.append(("pinhole_1080.exr", "pinhole", 1920, 1080, int(args["samples-1080"])))
    return plan


def code_fingerprint(name):
    """What a scene's renders depend on in the code: this script without the other scenes'
    builders and the scene lists (SCENE_NAMES, TRUTH_SAMPLES: the samples are in the cache key,
    BUILDERS), and script_util.py, as Python's syntax trees (comments and layout do not count).
    Adding a scene, or editing another one, leaves a scene's cache valid."""
    skip = {"SCENE_NAMES", "TRUTH_SAMPLES", "BUILDERS"}
    parts = []
    for path in (SCRIPT, UTIL):
        with open(path, encoding="utf-8") as f:
            tree = ast.parse(f.read())
        for node in tree.body:
            if (isinstance(node, ast.FunctionDef) and node.name.startswith("build_") and
                    node.name != "build_" + name):
                continue
            if isinstance(node, ast.Assign) and any(
                    isinstance(t, ast.Name) and t.id in skip for t in node.targets):
                continue
            parts.append(ast.dump(node))
    return hashlib.sha256("\n".join(parts).encode()).hexdigest()[:16]


def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    return bpy.context.scene


def main():
    args = parse_args()
    total = len(args["scene_list"])
    t_all = time.perf_counter()
    for index, name in enumerate(args["scene_list"], 1):
        tag = "[%d/%d] %s" % (index, total, name)
        out = os.path.join(args["out"], name)
        os.makedirs(out, exist_ok=True)
        manifest_path = os.path.join(out, "render.json")
        try:
            with open(manifest_path) as f:
                manifest = json.load(f)
        except (OSError, ValueError):
            manifest = {}
        manifest.setdefault("files", {})

        scene = reset()
        cam, near = BUILDERS[name](scene)
        plan = plan_outputs(args, name, bool(near))
        code = code_fingerprint(name)

        def fresh(entry):
            fname, kind, w, h, samples = entry
            path = os.path.join(out, fname)
            key = {"kind": kind, "size": [w, h], "samples": samples, "seed": int(args["seed"]),
                   "blender": bpy.app.version_string, "aperture": list(args["aperture_set"]),
                   "code": code}
            old = manifest["files"].get(fname, {})
            if args["adopt"] and "code" not in old:
                old = dict(old, code=code)  # made by an earlier script: taken as this code's
            ok = (not args["force"] and os.path.exists(path) and
                  all(old.get(k) == v for k, v in key.items()))
            return ok, key

        todo = []
        for entry in plan:
            ok, key = fresh(entry)
            if ok:
                print("%s: %s is up to date (cached)" % (tag, entry[0]), flush=True)
                manifest["files"][entry[0]]["code"] = code
            else:
                todo.append((entry, key))

        manifest.update({
            "scene": name,
            "doc": BUILDERS[name].__doc__,
            "camera": camera_sidecar(cam, args["width"], args["height"], args["aperture_set"]),
            "near_objects": near,
            "max_coc_px_at_infinity": round(coc_px(cam, 1e10, args["width"]), 2),
            "threads": int(args["threads"]),
            "shading": "emission-only (albedo x fake Lambert), no bounces",
        })
        write_json(os.path.join(out, "camera.json"),
                   camera_sidecar(cam, args["width"], args["height"], args["aperture_set"]))
        if "1080" in args["only_set"]:
            # The same camera with the 1080p frame's resolution (ddof warns when a sidecar's
            # resolution is not the frame's).
            write_json(os.path.join(out, "camera_1080.json"),
                       camera_sidecar(cam, 1920, 1080, args["aperture_set"]))

        for (fname, kind, w, h, samples), key in todo:
            label = {"pinhole": "pinhole", "truth": "truth", "fg": "foreground element",
                     "rest": "rest (no near objects)"}[kind]
            print("%s: %s %dx%d, %d samples ... " % (tag, label, w, h, samples), end="",
                  flush=True)
            for obj in scene.objects:
                if obj.type == "MESH":
                    obj.visible_camera = (obj.name in near) if kind == "fg" else \
                        (obj.name not in near) if kind == "rest" else True
            if scene.camera is not None:
                bpy.data.objects.remove(scene.camera, do_unlink=True)
            add_camera(scene, cam, lens_dof=(kind == "truth"), aperture=args["aperture_set"])
            configure(scene, args, w, h, samples, multilayer=(kind != "truth"),
                      transparent=(kind == "fg"))
            seconds = render_to(scene, os.path.join(out, fname), args["verbose"], "make_scenes.py")
            print("%.1f s" % seconds, flush=True)
            key["seconds"] = round(seconds, 2)
            key["threads"] = int(args["threads"])
            manifest["files"][fname] = key
            write_json(manifest_path, manifest)
        write_json(manifest_path, manifest)
    print("make_scenes.py: %d scene(s) in %.1f s -> %s"
          % (total, time.perf_counter() - t_all, args["out"]), flush=True)


main()
