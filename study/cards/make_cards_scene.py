# SPDX-License-Identifier: MIT
"""The study's cards scene (issue 25): image planes from 0.5 m to 20 m, rendered by Cycles.

    blender -b --factory-startup --python-exit-code 1 --python study/cards/make_cards_scene.py \
        -- --out DIR [--size 480x270] [--samples-pinhole N] [--samples-truth N] [--seed N] \
        [--only pinhole,truth] [--truth-name truth.exr] [--threads N] [--force] [--verbose] \
        [--cards wall,text,checker,leaf,ring]

--cards renders a subset of the cards (the checks of a single card against Cycles).

Writes into DIR:
  tex_*.png / tex_*.exr  the cards' textures, generated here (pure Python, no numpy): PNGs are
                         8-bit sRGB RGBA, the EXR is linear float RGBA; row 0 is the top;
  scene.json             the scene for `ddof --cards` (the same corners, textures and camera);
  pinhole.exr            Blender multilayer, ViewLayer.Combined.R/G/B/A half +
                         ViewLayer.Depth.Z float (as study/scenes/make_scenes.py);
  truth.exr              the same camera with Cycles lens depth of field, R/G/B/A half;
  camera.json            the sidecar (AUTO fit, no shift, resolution of the frame);
  render.json            settings and seconds of each render (the cache key).

The camera sits at the origin with no rotation, so Blender's world space *is* ddof's camera
space (x right, y up, looking down -z): the cards' corners go to both unchanged. Each card is
a mesh quad built from its corners in the JSON order (the image's bottom-left, bottom-right,
top-right, top-left) with the UVs (0,0), (1,0), (1,1), (0,1): Blender's UV (0,0) is the
image's bottom-left, as in ddof. Materials are emission-only, strength 1: Emission(image colour)
mixed with a Transparent BSDF by the image's alpha, Closest interpolation (ddof's texels are
sharp squares), Clip extension. PNG textures are sRGB in Blender and in ddof; the EXR is Linear
in both. The one texture with holes (the ring) has alpha 0 or 1 only, so straight and
premultiplied alpha are the same image. Pixel filter: a 1 px box (ddof's pixel is the disc of
radius 0.5 px at least; Blender's default 1.5 px Blackman-Harris would blur the truth and the
pinhole alike). Cached: an output is kept when it is newer than this script and render.json
has the same settings.
"""

import json
import math
import os
import struct
import sys
import zlib

import bpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes"))
from script_util import film_and_file, parse, render_to, write_json  # noqa: E402

SCRIPT = os.path.abspath(__file__)
CAMERA = {"focal_length_mm": 50.0, "sensor_width_mm": 36.0, "sensor_fit": "AUTO",
          "fstop": 2.0, "focus_distance_m": 2.0}


# ---------------------------------------------------------------------------------------------
# Textures: lists of rows (row 0 at the top) of (r, g, b, a), values 0..1


def srgb_to_linear(c):
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


def write_png(path, w, h, px):
    """8-bit RGBA PNG; px[y][x] = (r, g, b, a) already sRGB-encoded, 0..1."""
    raw = bytearray()
    for row in px:
        raw.append(0)
        for r, g, b, a in row:
            raw.extend(int(round(max(0.0, min(1.0, v)) * 255)) for v in (r, g, b, a))

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    data = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0))
    data += chunk(b"IDAT", zlib.compress(bytes(raw), 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(data)


def write_exr(path, w, h, px):
    """Scanline, uncompressed, FLOAT R, G, B, A (linear, premultiplied); px[y][x] = (r,g,b,a)."""
    def attr(name, kind, data):
        return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(data)) + data
    chl = b"".join(c.encode() + b"\0" + struct.pack("<iB3xii", 2, 0, 1, 1) for c in "ABGR")
    chl += b"\0"
    box = struct.pack("<iiii", 0, 0, w - 1, h - 1)
    header = struct.pack("<ii", 20000630, 2)
    header += attr("channels", "chlist", chl) + attr("compression", "compression", b"\0")
    header += attr("dataWindow", "box2i", box) + attr("displayWindow", "box2i", box)
    header += attr("lineOrder", "lineOrder", b"\0")
    header += attr("pixelAspectRatio", "float", struct.pack("<f", 1.0))
    header += attr("screenWindowCenter", "v2f", struct.pack("<ff", 0.0, 0.0))
    header += attr("screenWindowWidth", "float", struct.pack("<f", 1.0)) + b"\0"
    line_bytes = 4 * 4 * w
    start = len(header) + 8 * h
    table = b"".join(struct.pack("<Q", start + y * (8 + line_bytes)) for y in range(h))
    blocks = bytearray()
    for y, row in enumerate(px):
        blocks += struct.pack("<ii", y, line_bytes)
        for c in (3, 2, 1, 0):  # A, B, G, R
            blocks += struct.pack("<%df" % w, *(p[c] for p in row))
    with open(path, "wb") as f:
        f.write(header + table + bytes(blocks))


def tex_bricks(w=256, h=160):
    """The far wall: bricks, sRGB colours (PNG)."""
    px = []
    for y in range(h):
        row = []
        course = y // 16
        for x in range(w):
            xs = x + (16 if course % 2 else 0)
            mortar = y % 16 < 2 or xs % 32 < 2
            shade = ((xs // 32) * 7 + course * 3) % 5 / 10.0
            row.append((0.8, 0.78, 0.72, 1.0) if mortar else (0.55 + shade * 0.4, 0.25 + shade * 0.2,
                                                                 0.18, 1.0))
        px.append(row)
    return w, h, px


def tex_text(w=192, h=128):
    """The slanted card: text-like lines of dark 'words' on paper (PNG)."""
    px = []
    for y in range(h):
        row = []
        line, in_line = y // 12, y % 12
        for x in range(w):
            word = ((x // 6) * 13 + line * 7) % 11
            ink = 2 <= in_line < 8 and word > 2 and 8 <= x < w - 8 and (x % 6) < 5 and 8 <= y < h - 8
            row.append((0.08, 0.1, 0.3, 1.0) if ink else (0.95, 0.93, 0.85, 1.0))
        px.append(row)
    return w, h, px


def tex_checker(w=64, h=48):
    """The card in focus: a linear-light checker with a colour ramp (EXR)."""
    px = []
    for y in range(h):
        row = []
        for x in range(w):
            on = ((x // 4) + (y // 4)) % 2
            t = x / (w - 1)
            row.append((0.9 * on + 0.05, (0.2 + 0.6 * t) * on + 0.05, (0.8 - 0.6 * t) * on + 0.05,
                        1.0))
        px.append(row)
    return w, h, px


def tex_ring(w=128, h=128):
    """The near card: an orange ring with dark spokes; alpha 0 in the hole and the corners (PNG)."""
    px = []
    for y in range(h):
        row = []
        for x in range(w):
            dx, dy = (x + 0.5) / w - 0.5, (y + 0.5) / h - 0.5
            r = math.hypot(dx, dy)
            if 0.25 <= r <= 0.48:
                spoke = int((math.atan2(dy, dx) + math.pi) / (2 * math.pi) * 12) % 2
                row.append((0.95, 0.55, 0.1, 1.0) if spoke else (0.3, 0.1, 0.05, 1.0))
            else:
                row.append((0.0, 0.0, 0.0, 0.0))
        px.append(row)
    return w, h, px


def tex_leaf(w=96, h=128):
    """A leaf: green ellipse with a vein, transparent around (PNG)."""
    px = []
    for y in range(h):
        row = []
        for x in range(w):
            u, v = (x + 0.5) / w * 2 - 1, (y + 0.5) / h * 2 - 1
            inside = u * u / (0.8 * 0.8 * (1 - v * v) + 1e-9) <= 1.0 and abs(v) < 0.97
            vein = abs(u) < 0.06
            row.append(((0.7, 0.9, 0.4, 1.0) if vein else (0.2, 0.6, 0.15, 1.0)) if inside
                       else (0.0, 0.0, 0.0, 0.0))
        px.append(row)
    return w, h, px


def rect(x0, x1, y0, y1, z0, z1=None):
    """Corners BL, BR, TR, TL of a card from x0..x1, y0..y1, at z0 (left) .. z1 (right)."""
    z1 = z0 if z1 is None else z1
    return [[x0, y0, -z0], [x1, y0, -z1], [x1, y1, -z1], [x0, y1, -z0]]


# name, file, texture builder, corners (camera space, metres)
CARDS = [
    ("wall", "tex_bricks.png", tex_bricks, rect(-8.5, 8.5, -5.0, 5.0, 20.0)),
    ("text", "tex_text.png", tex_text, rect(0.6, 3.2, -0.8, 0.9, 5.0, 11.0)),
    ("checker", "tex_checker.exr", tex_checker, rect(-0.62, -0.02, -0.3, 0.15, 2.0)),
    ("leaf", "tex_leaf.png", tex_leaf, rect(0.08, 0.42, -0.15, 0.12, 1.1, 1.5)),
    ("ring", "tex_ring.png", tex_ring, [[-0.16, -0.08, -0.5], [-0.02, -0.08, -0.56],
                                        [-0.02, 0.06, -0.56], [-0.16, 0.06, -0.5]]),
]


def write_textures(out):
    for _name, fname, build, _corners in CARDS:
        w, h, px = build()
        if fname.endswith(".png"):
            write_png(os.path.join(out, fname), w, h, px)
        else:
            write_exr(os.path.join(out, fname), w, h, px)


# ---------------------------------------------------------------------------------------------
# Blender scene


def card_material(name, path):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    img = bpy.data.images.load(path)
    img.colorspace_settings.name = "sRGB" if path.endswith(".png") else "Linear"
    tex = nodes.new("ShaderNodeTexImage")
    tex.image = img
    tex.interpolation = "Closest"
    tex.extension = "CLIP"
    uv = nodes.new("ShaderNodeTexCoord")
    links.new(uv.outputs["UV"], tex.inputs["Vector"])
    em = nodes.new("ShaderNodeEmission")
    em.inputs["Strength"].default_value = 1.0
    links.new(tex.outputs["Color"], em.inputs["Color"])
    tr = nodes.new("ShaderNodeBsdfTransparent")
    mix = nodes.new("ShaderNodeMixShader")
    links.new(tex.outputs["Alpha"], mix.inputs["Fac"])
    links.new(tr.outputs["BSDF"], mix.inputs[1])
    links.new(em.outputs["Emission"], mix.inputs[2])
    links.new(mix.outputs["Shader"], out.inputs["Surface"])
    return mat


def build(scene, out):
    world = bpy.data.worlds.new("World")
    scene.world = world
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    bg.inputs["Strength"].default_value = 0.0
    for name, fname, _build, corners in CARDS:
        mesh = bpy.data.meshes.new(name)
        mesh.from_pydata([tuple(c) for c in corners], [], [(0, 1, 2, 3)])
        uvl = mesh.uv_layers.new(name="UVMap")
        for loop, uv in zip(mesh.loops, [(0, 0), (1, 0), (1, 1), (0, 1)]):
            uvl.data[loop.index].uv = uv
        mesh.materials.append(card_material(name, os.path.join(out, fname)))
        obj = bpy.data.objects.new(name, mesh)
        scene.collection.objects.link(obj)


def add_camera(scene, lens_dof):
    data = bpy.data.cameras.new("Camera")
    data.lens = CAMERA["focal_length_mm"]
    data.sensor_width = CAMERA["sensor_width_mm"]
    data.sensor_fit = "AUTO"
    data.shift_x = data.shift_y = 0.0
    data.clip_start = 0.05
    data.clip_end = 1000.0
    data.dof.use_dof = lens_dof
    data.dof.focus_distance = CAMERA["focus_distance_m"]
    data.dof.aperture_fstop = CAMERA["fstop"]
    data.dof.aperture_blades = 0
    obj = bpy.data.objects.new("Camera", data)
    scene.collection.objects.link(obj)
    obj.location = (0.0, 0.0, 0.0)
    obj.rotation_euler = (0.0, 0.0, 0.0)  # looks down -z, y up: world = camera space
    scene.camera = obj


def configure(scene, args, samples, multilayer):
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = samples
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.seed = int(args["seed"])
    c.use_animated_seed = False
    c.max_bounces = 8
    c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = c.volume_bounces = 0
    c.transparent_max_bounces = 8  # the ring's and leaf's holes
    c.caustics_reflective = c.caustics_refractive = False
    c.filter_type = "BOX"
    c.filter_width = 1.0
    film_and_file(scene, args["width"], args["height"], args["threads"], multilayer)


def main():
    args = parse("make_cards_scene.py",
                 {"out": None, "size": "480x270", "samples-pinhole": "256",
                  "samples-truth": "1024", "seed": "1", "only": "pinhole,truth",
                  "truth-name": "truth.exr", "threads": "2",
                  "cards": ",".join(c[0] for c in CARDS)},
                 {"force", "verbose"}, required=("out",))
    args["width"], args["height"] = (int(v) for v in args["size"].lower().split("x"))
    keep = args["cards"].split(",")
    CARDS[:] = [c for c in CARDS if c[0] in keep]
    out = os.path.abspath(args["out"])
    os.makedirs(out, exist_ok=True)
    write_textures(out)
    cam = dict(CAMERA, resolution=[args["width"], args["height"]], pixel_aspect=1.0,
               depth="planar", unit_scale_m=1.0)
    write_json(os.path.join(out, "camera.json"), cam)
    write_json(os.path.join(out, "scene.json"),
               {"camera": {k: v for k, v in cam.items() if k not in ("depth", "unit_scale_m")},
                "cards": [{"image": f, "corners": c} for _n, f, _b, c in CARDS]})
    manifest_path = os.path.join(out, "render.json")
    try:
        with open(manifest_path) as f:
            manifest = json.load(f)
    except (OSError, ValueError):
        manifest = {}
    files = manifest.setdefault("files", {})
    mtime = os.path.getmtime(SCRIPT)
    scene = bpy.context.scene
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    build(scene, out)
    plan = []
    if "pinhole" in args["only"]:
        plan.append(("pinhole.exr", "pinhole", int(args["samples-pinhole"])))
    if "truth" in args["only"]:
        plan.append((args["truth-name"], "truth", int(args["samples-truth"])))
    for fname, kind, samples in plan:
        path = os.path.join(out, fname)
        key = {"kind": kind, "size": [args["width"], args["height"]], "samples": samples,
               "seed": int(args["seed"]), "blender": bpy.app.version_string,
               "cards": args["cards"]}
        old = files.get(fname, {})
        if (not args["force"] and os.path.exists(path) and os.path.getmtime(path) > mtime
                and all(old.get(k) == v for k, v in key.items())):
            print("cards scene: %s is up to date (cached)" % fname, flush=True)
            continue
        print("cards scene: %s %dx%d, %d samples, seed %s ... " % (
            fname, args["width"], args["height"], samples, args["seed"]), end="", flush=True)
        if scene.camera is not None:
            bpy.data.objects.remove(scene.camera, do_unlink=True)
        add_camera(scene, lens_dof=(kind == "truth"))
        configure(scene, args, samples, multilayer=(kind == "pinhole"))
        key["seconds"] = round(render_to(scene, path, args["verbose"], "make_cards_scene.py"), 2)
        print("%.1f s" % key["seconds"], flush=True)
        files[fname] = key
        write_json(manifest_path, manifest)
    write_json(manifest_path, manifest)


main()
