# SPDX-License-Identifier: GPL-3.0-or-later
"""The object matte (Cryptomatte's CryptoObject pass) reaches the library bit for bit.

Scene: a strand (a bar 6 mm wide, about 0.75 px) in focus at 3 m before a checker wall at 20 m
(far out of focus), 85 mm f/1.4, Cycles, the view layer's Cryptomatte Object pass on (depth 6:
3 sub-layers). Checks:
- Object Matte Auto with the pass: the add-on calls ddof_render_frame_with_matte with 12
  channels (6 ranks); the floats it hands over are bit for bit those of the EXR files Blender
  wrote (read here by a reader of our own, not Blender's image loader), and the ids among them
  are Cryptomatte's hashes of the objects' names; the result equals the library's on the kept
  colour and depth with that matte, and differs from the matte-off result on the strand's edge.
- Object Matte Off, and Auto without the pass: ddof_render_frame, bit for bit the same result.
- Re-apply of the kept inputs takes the kept matte (the render's result bit for bit); overscan
  (the grown frame's matte) and a foreground collection take the matte too.
- The main File Output node keeps Combined and Depth only; turning Diffusion DOF off removes
  the matte's node.
With DDOF_MATTE_TRUTH=1 it also renders Cycles' lens DOF (1024 samples) and prints the PSNR of
the strand's edge band with and without the matte against it (the matte must not be worse).
"""

import array
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import blender_test_util as u  # noqa: E402

import bpy  # noqa: E402

EDGE_DIFFERENCE = 0.01  # the matte must change the bar's edge pixels by at least this
checks = u.Checks("test_object_matte")
addon = u.load_addon()
binding = addon.binding

scene = u.clear_scene()
u.add_plane(scene, "Wall", (40.0, 24.0), (0.0, 20.0, 0.0),
            u.emission_checker("WallMat", (0.95, 0.9, 0.8, 1), (0.2, 0.3, 0.6, 1), 2.0))
u.add_plane(scene, "Bar", (0.006, 0.9), (0.03, 3.0, 0.0),
            u.emission_checker("BarMat", (0.9, 0.25, 0.05, 1), (0.9, 0.25, 0.05, 1), 1.0))
u.add_camera(scene, lens=85.0, fstop=1.4, focus=3.0)
u.configure(scene, samples=16)
layer = scene.view_layers[0]
layer.use_pass_cryptomatte_object = True
s = scene.diffusion_dof
s.enabled = True
s.overscan = "OFF"
s.keep_inputs = True
W, H = u.WIDTH, u.HEIGHT


# ---------------------------------------------------------------------------------------------
# What Blender wrote, read without Blender: an uncompressed scanline OpenEXR (the managed File
# Output node's), and Cryptomatte's id of a name (MurmurHash3 x86 32, seed 0, as a float).


def read_exr_none(path):
    """{channel: array('I') of the float bits, rows bottom-up as Blender's} of an uncompressed
    single-part scanline EXR of 32-bit float channels."""
    with open(path, "rb") as f:
        data = f.read()
    pos, channels, window = 8, [], None
    while data[pos] != 0:
        end = data.index(b"\0", pos)
        name = data[pos:end].decode()
        end2 = data.index(b"\0", end + 1)
        size = struct.unpack_from("<i", data, end2 + 1)[0]
        value = data[end2 + 5:end2 + 5 + size]
        if name == "channels":
            p = 0
            while value[p] != 0:
                e = value.index(b"\0", p)
                channels.append((value[p:e].decode(), struct.unpack_from("<i", value, e + 1)[0]))
                p = e + 17
        elif name == "dataWindow":
            window = struct.unpack("<4i", value)
        elif name == "compression" and value[0] != 0:
            raise ValueError("%s is compressed" % path)
        pos = end2 + 5 + size
    width, height = window[2] - window[0] + 1, window[3] - window[1] + 1
    if any(kind != 2 for _, kind in channels):
        raise ValueError("%s has channels that are not 32-bit float: %r" % (path, channels))
    offsets = struct.unpack_from("<%dQ" % height, data, pos + 1)
    out = {name: array.array("I", bytes(4 * width * height)) for name, _ in channels}
    for offset in offsets:
        y = struct.unpack_from("<i", data, offset)[0] - window[1]
        row = (height - 1 - y) * width
        start = offset + 8
        for name, _ in channels:
            out[name][row:row + width] = array.array("I", data[start:start + 4 * width])
            start += 4 * width
    return out


def murmur3_32(key, seed=0):
    h, n = seed, len(key)
    for i in range(0, n - n % 4, 4):
        k = struct.unpack_from("<I", key, i)[0]
        k = (k * 0xcc9e2d51) & 0xffffffff
        k = ((k << 15) | (k >> 17)) * 0x1b873593 & 0xffffffff
        h ^= k
        h = ((h << 13) | (h >> 19)) & 0xffffffff
        h = (h * 5 + 0xe6546b64) & 0xffffffff
    k = 0
    for i, b in enumerate(key[n - n % 4:]):
        k |= b << (8 * i)
    if k:
        k = (k * 0xcc9e2d51) & 0xffffffff
        k = ((k << 15) | (k >> 17)) * 0x1b873593 & 0xffffffff
        h ^= k
    h ^= n
    h ^= h >> 16
    h = (h * 0x85ebca6b) & 0xffffffff
    h ^= h >> 13
    h = (h * 0xc2b2ae35) & 0xffffffff
    return h ^ (h >> 16)


def crypto_id_bits(name):
    """The bits of Cryptomatte's float id of a name (the exponent kept off 0 and 255)."""
    h = murmur3_32(name.encode("utf-8"))
    exponent = min(max((h >> 23) & 0xff, 1), 254)
    return (h & 0x807fffff) | (exponent << 23)


# ---------------------------------------------------------------------------------------------
# Rendering through the add-on, with its library call and the matte files it read recorded

calls = []
written = {}
original_call = binding.Session.depth_of_field
original_read = addon.images.read_exr


def recording_call(self, *args, **kwargs):
    calls.append((args, kwargs))
    return original_call(self, *args, **kwargs)


def recording_read(path, exact=False):
    if exact:  # an object matte's sub-layer: what Blender wrote, read here on our own
        written[os.path.basename(path)] = read_exr_none(path)
    return original_read(path, exact)


binding.Session.depth_of_field = recording_call
addon.images.read_exr = recording_read


def render(name):
    calls.clear()
    written.clear()
    bpy.ops.render.render()
    report = addon.report.reports.get(scene.name)
    checks.check(report is not None and report["ok"], "%s: no successful report: %r"
                 % (name, report))
    checks.check(len(calls) == 1, "%s: %d library calls" % (name, len(calls)))
    result = u.pixels(bpy.data.images[addon.images.RESULT_IMAGE])
    kept = (u.pixels(bpy.data.images[addon.images.INPUT_IMAGE]),
            u.pixels(bpy.data.images[addon.images.DEPTH_IMAGE]))
    return result, kept, (calls[0] if calls else ((), {})), dict(written)


def library(kept, call, matte):
    """The library's result on the kept colour and depth with the call's camera and params."""
    args, kwargs = call
    depth_channels = len(kept[1]) // (W * H)
    return binding.get_library().depth_of_field(
        W, H, kept[0], 4, kept[1], depth_channels, args[6], params=args[7],
        preset=kwargs.get("preset"), matte=matte)[0]


def bits(buf):
    return array.array("I", buf.tobytes())


# ---------------------------------------------------------------------------------------------

tree = u.compositor_tree(scene)
matte_node = tree.nodes.get(addon.passes.MATTE_OUTPUT_NODE)
checks.check(matte_node is not None, "no managed File Output node for the object matte")
checks.check(addon.passes.extra_slots(scene) == [], "the matte's slots are in the main node: %r"
             % addon.passes.extra_slots(scene))
if matte_node is not None:
    fmt = matte_node.format
    checks.check((fmt.file_format, fmt.color_depth, fmt.color_mode, fmt.exr_codec)
                 == ("OPEN_EXR", "32", "RGBA", "NONE"), "the matte is written as %r"
                 % ((fmt.file_format, fmt.color_depth, fmt.color_mode, fmt.exr_codec),))

on, on_kept, on_call, on_written = render("matte auto")
matte = on_call[1].get("matte")
checks.check(matte is not None and matte[1] == 12, "matte auto: the call's matte is %r"
             % ((None if matte is None else (len(matte[0]), matte[1])),))
report = addon.report.reports.get(scene.name) or {}
checks.check((report.get("stats") or {}).get("matte_ranks") == 6,
             "matte auto: the library was not called with 6 ranks")

# The matte the add-on handed over, bit for bit what Blender wrote (our own reader and packing).
if matte is not None and len(on_written) == 3:
    expected = array.array("I", bytes(4 * W * H * 12))
    for k in range(3):
        layer_bits = next(v for name, v in on_written.items() if name.startswith("matte%02d_" % k))
        for c, channel in enumerate("RGBA"):
            plane = next(v for n, v in layer_bits.items() if n.split(".")[-1].upper() == channel)
            for p in range(W * H):
                expected[12 * p + 4 * k + c] = plane[p]
    got = bits(matte[0])
    checks.check(got == expected, "the matte's floats are not the bits Blender wrote "
                 "(%d of %d differ)" % (sum(a != b for a, b in zip(got, expected)), len(got)))
else:
    checks.check(False, "matte auto: the sub-layers read: %r" % sorted(on_written))
    got = array.array("I", bytes(4 * W * H * 12))

# The ids are Cryptomatte's hashes of the objects' names.
ids = {"Bar": crypto_id_bits("Bar"), "Wall": crypto_id_bits("Wall")}
seen = {}
for p in range(W * H):
    for r in range(6):
        if matte is not None and matte[0][12 * p + 2 * r + 1] > 0.0:
            seen[got[12 * p + 2 * r]] = seen.get(got[12 * p + 2 * r], 0) + 1
print("ids with coverage: %s; Bar %08x, Wall %08x"
      % (", ".join("%08x: %d px" % kv for kv in sorted(seen.items())), ids["Bar"], ids["Wall"]))
checks.check(set(seen) == set(ids.values()), "the matte's ids %r are not Bar's and Wall's %r"
             % (sorted(seen), sorted(ids.values())))

# The bar's edge: pixels where the bar covers part of the pixel (any rank), and their row
# neighbours.
bar_cover = [0.0] * (W * H)
for p in range(W * H):
    for r in range(6):
        if got[12 * p + 2 * r] == ids["Bar"]:
            bar_cover[p] += matte[0][12 * p + 2 * r + 1] if matte else 0.0
edge = [False] * (W * H)
for p in range(W * H):
    if 0.02 < bar_cover[p] < 0.98:
        for q in (p - 1, p, p + 1):
            if 0 <= q < W * H:
                edge[q] = True
print("bar: %d pixels with coverage, %d in its edge band" % (sum(c > 0 for c in bar_cover),
                                                             sum(edge)))
checks.check(sum(edge) >= 50, "too few edge pixels: %d" % sum(edge))

if matte is not None:
    ref = library(on_kept, on_call, matte)
    worst = max(abs(a - b) for a, b in zip(on, ref))
    print("matte auto vs the library with the matte: largest difference %.3g" % worst)
    checks.check(worst <= 1e-6, "matte auto: the result differs from the library's with the "
                 "matte by %.3g" % worst)

# Re-apply of the kept inputs takes the kept matte: the render's result bit for bit.
bpy.ops.diffusion_dof.apply_images(color=addon.images.INPUT_IMAGE,
                                   depth=addon.images.DEPTH_IMAGE, output="Re-applied")
reapplied = u.pixels(bpy.data.images["Re-applied"])
checks.check(bits(reapplied) == bits(on), "Re-apply: not the render's result with the matte")

# Object Matte Off: today's call, today's result.
s.object_matte = "OFF"
checks.check(tree.nodes.get(addon.passes.MATTE_OUTPUT_NODE) is None,
             "Object Matte Off: the matte's node is still there")
off, off_kept, off_call, _ = render("matte off")
checks.check(off_call[1].get("matte") is None, "matte off: the call has a matte")
ref_off = library(off_kept, off_call, None)
checks.check(bits(off) == bits(ref_off), "matte off: the result is not the library's without a "
             "matte, bit for bit")
checks.check(bits(off_kept[0]) == bits(on_kept[0]), "the Combined pass changed with the matte")
edge_diff = max(max(abs(on[4 * p + c] - off[4 * p + c]) for c in range(3))
                for p in range(W * H) if edge[p])
print("bar's edge: largest change by the matte %.4f" % edge_diff)
checks.check(edge_diff >= EDGE_DIFFERENCE, "the matte changes the bar's edge by %.4f only"
             % edge_diff)

# Auto without the pass: the same as Off.
s.object_matte = "AUTO"
layer.use_pass_cryptomatte_object = False
absent, _, absent_call, _ = render("pass off")
checks.check(absent_call[1].get("matte") is None, "pass off: the call has a matte")
checks.check(bits(absent) == bits(off), "pass off: the result differs from Object Matte Off's")
checks.check(addon.passes.object_matte_hint(scene, s) != "", "pass off: no hint in the panel")
layer.use_pass_cryptomatte_object = True

if os.environ.get("DDOF_MATTE_TRUTH"):
    s.enabled = False
    scene.camera.data.dof.use_dof = True
    scene.cycles.samples = 1024
    truth = u.render_still(scene, os.path.join(u.scratch_dir("object_matte"), "truth.exr"))[0]
    print("edge band PSNR against Cycles lens DOF: matte off %.2f dB, matte %.2f dB; image "
          "%.2f -> %.2f dB" % (u.psnr(off, truth, edge), u.psnr(on, truth, edge),
                               u.psnr(off, truth), u.psnr(on, truth)))
    checks.check(u.psnr(on, truth, edge) >= u.psnr(off, truth, edge),
                 "the matte makes the strand's edge worse against Cycles")
    scene.camera.data.dof.use_dof = False
    scene.cycles.samples = 16
    s.enabled = True

# The other paths take the matte too: overscan (the grown frame's matte) and a foreground
# collection (the matte is the main view layer's, where the collection is indirect-only).
s.overscan = "AUTO"
grown, _, grown_call, _ = render("overscan")
gm, gw, gh = grown_call[1].get("matte"), grown_call[0][0], grown_call[0][1]
checks.check(gm is not None and (gw, gh) != (W, H) and len(gm[0]) == gw * gh * 12,
             "overscan: the matte of the %dx%d grown frame is %r" % (
                 gw, gh, None if gm is None else len(gm[0])))
checks.check(len(grown) == W * H * 4, "overscan: the result is not cropped to the frame")
s.overscan = "OFF"
near = bpy.data.collections.new("Near")
scene.collection.children.link(near)
u.add_plane(scene, "Leaf", (0.3, 0.3), (-0.15, 1.2, 0.1),
            u.emission_checker("LeafMat", (0.1, 0.7, 0.2, 1), (0.2, 0.9, 0.3, 1), 30.0), near)
s.foreground_collection = near
_, _, fg_call, _ = render("foreground")
checks.check(fg_call[1].get("matte") is not None and fg_call[1].get("foreground") is not None,
             "foreground: the call has no matte or no foreground element")
s.foreground_collection = None

# Teardown leaves none of the add-on's nodes.
s.enabled = False
tree = u.compositor_tree(scene)  # 5.x removes the node group the add-on made
left = [n.name for n in (tree.nodes if tree is not None else ())
        if n.name in addon.passes.MANAGED_NODES]
checks.check(not left, "turned off, the add-on left nodes: %r" % left)
binding.Session.depth_of_field = original_call
addon.images.read_exr = original_read
u.unload_addon(addon)
checks.finish()
