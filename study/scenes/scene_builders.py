# SPDX-License-Identifier: MIT
"""The study's scenes: each builder fills an empty Blender scene and returns (camera settings,
names of the near objects). README.md beside this file says what each stresses."""

import math

import bpy

from camera import SENSOR_MM, at
from materials import _rgb, bricks, checker, emission, multiply, ramp, texture, unlit, wave_z
from objects import box, monkey, plane, rod, set_world, sphere, strand, wall

SCENE_NAMES = ["thin_bars", "thin_strands", "near_occluder", "receding_plane", "highlights",
               "all_sharp", "near_railing", "near_border", "daylight", "park",
               "street", "night_lights", "orchard", "fence"]

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
    "park": 2048,
    "street": 2048,
    "night_lights": 4096,  # noise floor 41.5 dB (its lights' discs; README.md)
    "orchard": 2048,
    "fence": 1024,
}


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


def _park(scene):
    """What the park scenes share: the bright Nishita sky (no sun disc), the grass to the
    horizon, and the bark and leaves materials. Returns (bark, leaves)."""
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
    return bark, leaves


def _sign_post(cam):
    """The subject: a wooden post with a sign, in focus."""
    post = unlit("Post", ramp("ShaderNodeTexWave", [(0.35, 0.25, 0.15), (0.6, 0.45, 0.3)],
                              25.0))
    y = cam["focus_m"]
    rod("Post", post, (-0.1, y + 0.03, 0.0), (-0.1, y + 0.03, 1.32), 0.03)
    sign = unlit("Sign", checker((0.9, 0.88, 0.8, 1), (0.1, 0.3, 0.15, 1), 50.0))
    wall("Sign", sign, (0.2, 0.12), y - 0.002, 1.22, x_center=-0.1)


def build_daylight(scene):
    """A post in focus at 2.5 m (85 mm f/1.8, pitched 1.5 deg up) in a park: trees at 28-75 m,
    grass to the horizon and a bright Nishita sky (no sun disc) behind them, sun glints on the
    crowns and the grass."""
    import random
    cam = dict(focal_mm=85.0, fstop=1.8, focus_m=2.5, height=1.2, pitch=-1.5)
    bark, leaves = _park(scene)
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
    _sign_post(cam)
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


def build_park(scene):
    """Foliage against a bright sky, everything far but the subject: a post in focus at 2.5 m
    (85 mm f/1.8, pitched 3 deg up), tree crowns at 12-35 m (CoC 17-20 px) filling the upper
    frame with gaps of the sky (21 px) between and behind them, so that a fifth of the frame
    lies where two blurred surfaces meet."""
    import random
    cam = dict(focal_mm=85.0, fstop=1.8, focus_m=2.5, height=1.2, pitch=-3.0)
    bark, leaves = _park(scene)
    rng = random.Random(11)
    slope = math.tan(math.radians(3.0))
    # Crowns (centre x as a share of the half width, distance): each two or three spheres,
    # their centres at 62-88% up the frame at their distance, radii 3-5% of it.
    for i, (u, y) in enumerate([(-0.75, 12.0), (0.1, 14.0), (0.8, 17.0), (-0.35, 20.0),
                                (0.45, 24.0), (-0.9, 27.0), (0.0, 30.0), (0.85, 33.0),
                                (-0.55, 35.0)]):
        half_w = y * SENSOR_MM / 2.0 / cam["focal_mm"]
        half_h = half_w * 9.0 / 16.0
        x = u * half_w
        mid = cam["height"] + y * slope
        lobes = []
        for j in range(rng.choice((2, 3))):
            r = y * rng.uniform(0.03, 0.05)
            c = (x + rng.uniform(-1.5, 1.5) * r, y + rng.uniform(-0.3, 0.3) * r,
                 mid + half_h * rng.uniform(0.25, 0.75))
            sphere("Crown%d_%d" % (i, j), leaves, c, r, segments=32, rings=16)
            lobes.append(c)
        low = min(c[2] for c in lobes)
        rod("Trunk%d" % i, bark, (x, y, 0.0), (x, y, low), y * 0.008, vertices=16)
    _sign_post(cam)
    return cam, []



def build_street(scene):
    """A textured ball 0.9 m from the lens filling a fifth of the frame (CoC ~22 px), a crate in
    focus at 5 m on a receding paved street (50 mm f/1.4), house fronts at 25 m."""
    cam = dict(focal_mm=50.0, fstop=1.4, focus_m=5.0, height=1.3, pitch=3.0)
    set_world(scene, (0.6, 0.7, 0.85))
    paving = unlit("Paving", multiply(
        texture("ShaderNodeTexBrick", [(0.55, 0.5, 0.45, 1), (0.35, 0.33, 0.3, 1)], 1.0,
                bricks(0.3, 0.15, 0.015, (0.12, 0.11, 0.1, 1.0))),
        ramp("ShaderNodeTexNoise", [(0.7, 0.7, 0.7), (1.0, 1.0, 1.0)], 4.0)))
    plane("Street", paving, (60.0, 400.0), (0.0, 200.0, 0.0))
    fronts = unlit("Fronts", texture("ShaderNodeTexBrick", [(0.75, 0.45, 0.3, 1),
                                                           (0.85, 0.75, 0.6, 1)], 1.0,
                                     bricks(0.9, 0.35, 0.05, (0.3, 0.28, 0.25, 1.0))))
    wall("Fronts", fronts, (60.0, 24.0), 25.0, 12.0)
    crate = unlit("Box", checker((0.15, 0.35, 0.6, 1), (0.8, 0.85, 0.9, 1), 4.0))
    box("Crate", crate, (-0.3, 5.2, 0.4), (0.8, 0.8, 0.8), 25.0)
    ball = unlit("Ball", multiply(
        checker((0.85, 0.2, 0.1, 1), (0.95, 0.85, 0.3, 1), 40.0),
        ramp("ShaderNodeTexNoise", [(0.6, 0.6, 0.6), (1.0, 1.0, 1.0)], 8.0)))
    obj = sphere("Ball", ball, at(cam, 0.5, -0.35, 0.9), 0.125, segments=48, rings=24)
    return cam, [obj.name]


def build_night_lights(scene):
    """Night: thin twigs and a wire in focus at 3 m (85 mm f/1.4) before 55 small lights at
    12-30 m (CoC 18-20 px), 30 of them within about a disc of the frame's edges (their centres
    inside it: what lies past the frame no pinhole render shows), over a dark wall."""
    import random
    cam = dict(focal_mm=85.0, fstop=1.4, focus_m=3.0, height=1.2, pitch=0.0)
    set_world(scene, (0.004, 0.005, 0.01))
    back = unlit("Back", texture("ShaderNodeTexBrick", [(0.03, 0.025, 0.02, 1),
                                                        (0.015, 0.015, 0.02, 1)], 1.0,
                                 bricks(0.8, 0.3, 0.05, (0.005, 0.005, 0.006, 1.0))))
    wall("Back", back, (60.0, 30.0), 40.0, 1.2)
    rng = random.Random(5)
    warm = [(1.0, 0.7, 0.35), (1.0, 0.85, 0.55), (0.6, 0.8, 1.0), (1.0, 0.55, 0.3)]
    for i in range(55):
        if i < 30:  # along the edges: within about a disc of them, inside the frame
            side = i % 4
            t, e = rng.uniform(-0.98, 0.98), rng.uniform(0.86, 0.99)
            u, v = [(-e, t), (e, t), (t, -e), (t, e)][side]
        else:
            u, v = rng.uniform(-0.85, 0.85), rng.uniform(-0.85, 0.85)
        dist = rng.uniform(12.0, 30.0)
        strength = rng.choice((8.0, 20.0, 50.0))
        sphere("Light%d" % i, emission("Light%d" % i, warm[i % 4], strength),
               at(cam, u, v, dist), 0.0022 * dist)
    twig = unlit("Twig", (0.06, 0.045, 0.03))
    for i in range(7):
        p0 = at(cam, rng.uniform(-1.1, -0.2), rng.uniform(-0.9, 0.9), 3.0)
        p1 = at(cam, rng.uniform(0.2, 1.1), rng.uniform(-0.9, 0.9), 3.0)
        rod("Twig%d" % i, twig, p0, p1, rng.uniform(0.002, 0.005), vertices=8)
    wire = unlit("Wire", (0.02, 0.02, 0.02))
    rod("Wire", wire, at(cam, -1.2, 0.55, 3.05), at(cam, 1.2, 0.4, 3.05), 0.0012, vertices=8)
    return cam, []


def build_orchard(scene):
    """Foliage of a second kind, so that a preset chosen without park is judged on the same
    class: a lamp post in focus at 2.2 m (70 mm f/1.8, level), a near row of crowns at 7-10 m
    (CoC 11-13 px) overlapping a far row at 22-30 m (15 px) of another green, and the sky
    (16.5 px) between: crown against crown as well as crown against sky."""
    import random
    cam = dict(focal_mm=70.0, fstop=1.8, focus_m=2.2, height=1.2, pitch=0.0)
    bark, leaves = _park(scene)
    far_leaves = unlit("FarLeaves", multiply(
        ramp("ShaderNodeTexNoise", [(0.15, 0.2, 0.05), (0.4, 0.45, 0.1), (0.6, 0.55, 0.2)],
             2.5, detail=3.0),
        ramp("ShaderNodeTexVoronoi", [(0.6, 0.6, 0.5), (1.0, 1.0, 1.0)], 4.0)),
        ambient=0.6, key=0.6)
    rng = random.Random(23)
    rows = [(leaves, [(-0.8, 7.0), (-0.2, 9.0), (0.35, 8.0), (0.95, 10.0)]),
            (far_leaves, [(-0.95, 24.0), (-0.55, 28.0), (-0.05, 22.0), (0.2, 30.0),
                          (0.6, 26.0), (0.85, 23.0)])]
    for k, (mat, trees) in enumerate(rows):
        for i, (u, y) in enumerate(trees):
            half_w = y * SENSOR_MM / 2.0 / cam["focal_mm"]
            half_h = half_w * 9.0 / 16.0
            x = u * half_w
            lobes = []
            for j in range(rng.choice((2, 3))):
                r = y * rng.uniform(0.035, 0.06)
                c = (x + rng.uniform(-1.2, 1.2) * r, y + rng.uniform(-0.3, 0.3) * r,
                     cam["height"] + half_h * rng.uniform(0.25, 0.75))
                sphere("Crown%d_%d_%d" % (k, i, j), mat, c, r, segments=32, rings=16)
                lobes.append(c)
            low = min(c[2] for c in lobes)
            rod("Trunk%d_%d" % (k, i), bark, (x, y, 0.0), (x, y, low), y * 0.01, vertices=16)
    lamp = unlit("Lamp", (0.12, 0.13, 0.14))
    y = cam["focus_m"]
    rod("LampPost", lamp, (0.12, y + 0.025, 0.0), (0.12, y + 0.025, 1.25), 0.025)
    glass = unlit("LampGlass", checker((0.95, 0.9, 0.7, 1), (0.2, 0.2, 0.2, 1), 60.0))
    box("LampHead", glass, (0.12, y + 0.05, 1.31), (0.1, 0.1, 0.12), 20.0)
    return cam, []


def build_fence(scene):
    """Thin sharp insulators of a second kind, so that a preset chosen without thin_bars is
    judged on the same class: a picket fence in focus at 1.8 m (50 mm f/1.2, level, 1 m up):
    pickets 2-7 px wide, two rails, a slanted brace and a patch of wire mesh (0.6 px wires),
    before a receding paved ground (from 5 m: CoC 10 px), a brick facade at 15 m (14 px)
    with windows and the sky above its roofline (15.4 px)."""
    cam = dict(focal_mm=50.0, fstop=1.2, focus_m=1.8, height=1.0, pitch=0.0)
    set_world(scene, (0.55, 0.68, 0.9))
    paving = unlit("Paving", multiply(
        texture("ShaderNodeTexBrick", [(0.6, 0.55, 0.45, 1), (0.4, 0.36, 0.3, 1)], 1.0,
                bricks(0.4, 0.2, 0.02, (0.15, 0.14, 0.12, 1.0))),
        ramp("ShaderNodeTexNoise", [(0.7, 0.7, 0.7), (1.0, 1.0, 1.0)], 3.0)))
    plane("Ground", paving, (60.0, 200.0), (0.0, 100.0, 0.0))
    facade = unlit("Facade", multiply(
        texture("ShaderNodeTexBrick", [(0.8, 0.4, 0.25, 1), (0.65, 0.3, 0.2, 1)], 1.0,
                bricks(0.5, 0.18, 0.03, (0.85, 0.8, 0.7, 1.0))),
        checker((1.0, 1.0, 1.0, 1), (0.15, 0.2, 0.3, 1), 0.35), 0.7), ambient=0.7, key=0.4)
    wall("Facade", facade, (40.0, 3.6), 15.0, 1.8)
    y = cam["focus_m"]
    white = unlit("PaintWhite", (0.92, 0.92, 0.9))
    green = unlit("PaintGreen", (0.08, 0.25, 0.12))
    wood = unlit("Wood", ramp("ShaderNodeTexWave", [(0.3, 0.22, 0.14), (0.55, 0.42, 0.28)],
                              30.0))
    steel = unlit("Steel", (0.65, 0.67, 0.7))
    # Pickets (x, radius: 2.7 mm is 2 px at 1.8 m, 9.5 mm 7 px), left of the mesh.
    for i, (x, r, mat) in enumerate([(-0.62, 0.004, white), (-0.54, 0.0027, green),
                                     (-0.45, 0.0095, wood), (-0.37, 0.005, white),
                                     (-0.28, 0.003, green), (-0.2, 0.007, wood),
                                     (-0.12, 0.0035, white), (-0.05, 0.0027, green)]):
        rod("Picket%d" % i, mat, (x, y + r, 0.3), (x, y + r, 1.7), r, vertices=16)
    rod("RailTop", wood, (-0.7, y + 0.012, 1.22), (0.02, y + 0.012, 1.22), 0.006)
    rod("RailLow", wood, (-0.7, y + 0.012, 0.8), (0.02, y + 0.012, 0.8), 0.006)
    rod("Brace", green, (-0.62, y + 0.02, 0.8), (-0.05, y + 0.02, 1.22), 0.003)
    # Wire mesh on the right (pitch 2.5 cm, 0.8 mm wires: 0.6 px), its frame 4 px.
    for i in range(17):
        x = 0.1 + 0.025 * i
        rod("MeshV%d" % i, steel, (x, y, 0.7), (x, y, 1.3), 0.0008, vertices=8)
    for i in range(25):
        z = 0.7 + 0.025 * i
        rod("MeshH%d" % i, steel, (0.1, y, z), (0.5, y, z), 0.0008, vertices=8)
    rod("MeshPost", green, (0.52, y + 0.006, 0.3), (0.52, y + 0.006, 1.7), 0.006)
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
    "park": build_park,
    "street": build_street,
    "night_lights": build_night_lights,
    "orchard": build_orchard,
    "fence": build_fence,
}
