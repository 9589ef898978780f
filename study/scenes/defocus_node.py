# SPDX-License-Identifier: MIT
"""The baseline users already have: Blender's compositor Defocus node on a scene's pinhole input.

    blender -b --factory-startup --python-exit-code 1 --python study/scenes/defocus_node.py -- \
        --scene-dir DIR/<scene> [--size-tag 1080] [--fstop-scale S] [--threshold T] \
        [--blur-max PX] [--execution-mode TILED|FULL_FRAME] [--repeats N] [--long S] \
        [--threads N] \
        [--out-dir DIR] [--out-name NAME] [--write-image] [--verbose]

    VENV/bin/python study/scenes/defocus_node.py -- --scene-dir ...   (PyPI's bpy 4.2 / 5.0)

Under Blender 4.2 or 5.0 the outputs are named defocus-4.2 / defocus-5.0 (node_rules.node_tag),
the f-stop follows that node's thin-lens CoC (node_rules.node_fstop), blur_max is the scene's
largest CoC (node_rules.auto_blur_max), and 5.0's tree is a node group with a group output;
scenes/README.md, "Blender 4.2 LTS's and 5.0's nodes", has what differs and why.

Reads DIR/<scene>/pinhole.exr (with --size-tag 1080: pinhole_1080.exr) and camera.json, and
composites Image node (ViewLayer: Combined -> Image, Depth -> Z) -> Defocus -> Composite, with
no Render Layers node, so `bpy.ops.render.render()` runs the compositor alone (Blender renders
nothing when no Render Layers node is in the tree). The Defocus node gets the camera of the
sidecar (focal length, sensor, AUTO fit, focus distance) as its scene camera, use_zbuffer on,
the bokeh of the camera's blades (circular for 0; the sidecar's aperture_blades and
aperture_rotation_deg as a user would set the node's Bokeh Type and Angle), no gamma correction, use_preview off (full quality), blur_max 512 px radius
(so that nothing is clipped; 3.4), threshold 1 (Blender's default), and the f-stop (3.4)
N * 1000 / sensor_mm * fstop-scale: docs/design.md section 1 says the node blurs 1000/sensor_mm
times more than the physical lens at the same f-number (README.md, "Defocus node f-stop",
checks it).

Timing: one untimed warm-up composite (it loads and decodes the EXR into Blender's image cache
and is reported as seconds_first), then --repeats (default 5) timed composites, each
time.perf_counter() around bpy.ops.render.render() (write_still off): the compositor tree's
conversion and execution and the render result's bookkeeping, not the EXR decoding and not
writing a file. seconds is the best of those (the machine is shared: the minimum is the least
disturbed), seconds_median their median. When the warm-up alone takes more than --long
seconds (default 20: the 1080p frames with large blur take minutes), it is the one measurement
(seconds_runs is empty; the EXR decoding it includes is under a second). Then the result is
written, untimed.

Writes DIR/<scene>/defocus.exr (plain single-layer R, G, B, A, 32-bit float, ZIP) and
defocus.json; with --size-tag 1080, defocus_1080.json only (the image too with --write-image).
--out-dir writes them elsewhere, --out-name under another name (the f-stop check of README.md).
"""

import json
import math
import os
import statistics
import struct
import sys
import time

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from node_rules import auto_blur_max, node_fstop, node_tag  # noqa: E402
from script_util import parse, quiet, write_json  # noqa: E402


BOKEH_OF_BLADES = {3: "TRIANGLE", 4: "SQUARE", 5: "PENTAGON", 6: "HEXAGON", 7: "HEPTAGON",
                   8: "OCTAGON"}


def parse_args():
    return parse(
        "defocus_node.py",
        {"scene-dir": None, "size-tag": "", "fstop-scale": "1.0", "threshold": "1.0",
         "blur-max": "auto", "execution-mode": "TILED", "repeats": "5", "threads": "2",
         "long": "20", "out-dir": None, "out-name": None},
        {"write-image", "verbose"}, required=("scene-dir",))


def exr_size(path):
    """(width, height) of an EXR's display window, read from its header."""
    with open(path, "rb") as f:
        data = f.read(65536)
    if data[:4] != b"\x76\x2f\x31\x01":
        raise SystemExit("defocus_node.py: %s is not an OpenEXR file" % path)
    pos = 8
    while data[pos] != 0:
        end = data.index(b"\0", pos)
        name = data[pos:end]
        pos = data.index(b"\0", end + 1) + 1
        size = struct.unpack_from("<i", data, pos)[0]
        pos += 4
        if name == b"displayWindow":
            x0, y0, x1, y1 = struct.unpack_from("<4i", data, pos)
            return x1 - x0 + 1, y1 - y0 + 1
        pos += size
    raise SystemExit("defocus_node.py: %s has no displayWindow" % path)


VERSION = tuple(bpy.app.version)


NODE_GROUP_COMPOSITOR = "compositing_node_group" in bpy.types.Scene.bl_rna.properties  # 5.0+


def compositor_tree(scene):
    """A new compositor tree for the scene: scene.node_tree up to 4.x, a node group in
    scene.compositing_node_group from 5.0 (as blender_addon/diffusion_dof/compat.py)."""
    if NODE_GROUP_COMPOSITOR:
        tree = bpy.data.node_groups.new("Compositing", "CompositorNodeTree")
        scene.compositing_node_group = tree
        return tree
    scene.use_nodes = True
    return scene.node_tree


def output_socket(tree):
    """The socket whose image the render keeps: a Composite node's (with use_alpha where it
    has one) up to 4.x; from 5.0, which has no Composite node, the group output's "Image"."""
    if NODE_GROUP_COMPOSITOR:
        tree.interface.new_socket(name="Image", in_out="OUTPUT", socket_type="NodeSocketColor")
        return tree.nodes.new("NodeGroupOutput").inputs["Image"]
    composite = tree.nodes.new("CompositorNodeComposite")
    if hasattr(composite, "use_alpha"):
        composite.use_alpha = True
    return composite.inputs["Image"]

def main():
    args = parse_args()
    scene_dir = os.path.abspath(args["scene-dir"])
    tag = args["size-tag"]
    suffix = "_" + tag if tag else ""
    source = os.path.join(scene_dir, "pinhole%s.exr" % suffix)
    with open(os.path.join(scene_dir, "camera.json")) as f:
        cam = json.load(f)
    if not os.path.exists(source):
        raise SystemExit("defocus_node.py: no %s" % source)
    width, height = exr_size(source)
    base = args["out-name"] or node_tag(VERSION) + suffix
    out_dir = os.path.abspath(args["out-dir"]) if args["out-dir"] else scene_dir
    os.makedirs(out_dir, exist_ok=True)
    write_image = args["write-image"] or not tag
    sensor = float(cam["sensor_width_mm"])
    fstop_node, fstop_rule = node_fstop(cam, float(args["fstop-scale"]), VERSION)
    threads = int(args["threads"])

    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"  # never runs: there is no Render Layers node
    render = scene.render
    render.resolution_x, render.resolution_y = width, height
    render.resolution_percentage = 100
    render.pixel_aspect_x = render.pixel_aspect_y = float(cam.get("pixel_aspect", 1.0))
    render.use_compositing = True
    render.use_sequencer = False
    render.threads_mode = "FIXED"
    render.threads = threads
    render.film_transparent = False
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"

    cam_data = bpy.data.cameras.new("Camera")
    cam_data.lens = float(cam["focal_length_mm"])
    cam_data.sensor_width = sensor
    cam_data.sensor_fit = cam.get("sensor_fit", "AUTO")
    cam_data.dof.use_dof = False  # the Defocus node reads focus_distance either way
    cam_data.dof.focus_distance = float(cam["focus_distance_m"]) / float(
        cam.get("unit_scale_m", 1.0))
    cam_obj = bpy.data.objects.new("Camera", cam_data)
    scene.collection.objects.link(cam_obj)
    scene.camera = cam_obj

    tree = compositor_tree(scene)
    if hasattr(tree, "execution_mode"):  # 3.x to 4.1; 4.2 has one (full-frame) compositor
        tree.execution_mode = args["execution-mode"]
    tree.nodes.clear()
    image = bpy.data.images.load(source)
    image_node = tree.nodes.new("CompositorNodeImage")
    image_node.image = image
    image_node.layer = "ViewLayer"
    defocus = tree.nodes.new("CompositorNodeDefocus")
    defocus.scene = scene
    defocus.use_zbuffer = True
    # The camera's blades as a user would give them to the node (it has no anamorphic ratio).
    blades = int(cam.get("aperture_blades", 0))
    defocus.bokeh = BOKEH_OF_BLADES.get(blades, "CIRCLE")
    defocus.angle = math.radians(float(cam.get("aperture_rotation_deg", 0.0)))
    # 5.0 dropped these three (no threshold, no gamma option, always full quality).
    for name, value in (("use_gamma_correction", False), ("use_preview", False),
                        ("threshold", float(args["threshold"]))):
        if hasattr(defocus, name):
            setattr(defocus, name, value)
    defocus.f_stop = fstop_node
    defocus.blur_max = (auto_blur_max(cam, source, width, float(args["fstop-scale"]), VERSION)
                        if args["blur-max"] == "auto"
                        else float(args["blur-max"]))
    tree.links.new(image_node.outputs["Combined"], defocus.inputs["Image"])
    tree.links.new(image_node.outputs["Depth"], defocus.inputs["Z"])
    tree.links.new(defocus.outputs["Image"], output_socket(tree))

    settings = render.image_settings
    if hasattr(settings, "media_type"):  # 5.0: the format's media type first
        settings.media_type = "IMAGE"
    settings.file_format = "OPEN_EXR"
    settings.color_mode = "RGBA"
    settings.color_depth = "32"
    settings.exr_codec = "ZIP"

    def composite_once():
        t0 = time.perf_counter()
        with quiet(not args["verbose"]):
            bpy.ops.render.render(write_still=False)
        return time.perf_counter() - t0

    print("defocus_node.py: Blender %s, %s %dx%d, f-stop %.4g (N %.4g: %s, scale %.4g), "
          "threshold %s, blur_max %g, %s, %d threads ..."
          % (bpy.app.version_string, os.path.basename(scene_dir), width, height, fstop_node,
             cam["fstop"], fstop_rule.split(" * fstop_scale")[0], float(args["fstop-scale"]),
             getattr(defocus, "threshold", "-"), defocus.blur_max,
             getattr(tree, "execution_mode", "FULL_FRAME"), threads), end=" ", flush=True)
    first = composite_once()
    if first > float(args["long"]):
        # Minutes per composite (large blur at 1080p): the warm-up is the measurement; the
        # EXR decoding it includes is well under a second.
        runs = []
        seconds = first
        print("%.3f s (one run, EXR load included)" % seconds, flush=True)
    else:
        runs = [composite_once() for _ in range(int(args["repeats"]))]
        seconds = min(runs)
        print("%.3f s best of %d, median %.3f s (first, with the EXR load: %.3f s)"
              % (seconds, len(runs), statistics.median(runs), first), flush=True)

    result = {
        "scene": os.path.basename(scene_dir),
        "input": os.path.basename(source),
        "size": [width, height],
        "fstop_camera": cam["fstop"],
        "fstop_node": round(fstop_node, 6),
        "fstop_scale": float(args["fstop-scale"]),
        "fstop_rule": fstop_rule,
        "blur_max": defocus.blur_max,
        "threshold": getattr(defocus, "threshold", None),
        "bokeh": defocus.bokeh,
        "use_zbuffer": True,
        "use_preview": getattr(defocus, "use_preview", None),
        "use_gamma_correction": getattr(defocus, "use_gamma_correction", None),
        "execution_mode": getattr(tree, "execution_mode", "FULL_FRAME"),
        "threads": threads,
        "seconds": round(seconds, 4),
        "seconds_median": round(statistics.median(runs), 4) if runs else round(seconds, 4),
        "seconds_runs": [round(t, 4) for t in runs],
        "seconds_first": round(first, 4),
        "timing": ("best (minimum) of the timed runs of bpy.ops.render.render() on a tree "
                   "with no "
                   "Render Layers node (compositor only: Image -> Defocus -> Composite), after "
                   "one untimed warm-up that loads the EXR (seconds_first); excludes EXR "
                   "decoding and file writing") if runs else (
                   "one bpy.ops.render.render() on a tree with no Render Layers node "
                   "(compositor only), longer than --long s, so not repeated; includes "
                   "decoding the EXR on first use (well under a second), not file writing"),
        "blender": bpy.app.version_string,
        "node": node_tag(VERSION),
    }
    if write_image:
        out_path = os.path.join(out_dir, base + ".exr")
        tmp = os.path.join(out_dir, "." + base + ".tmp.exr")
        with quiet(not args["verbose"]):
            bpy.data.images["Render Result"].save_render(tmp, scene=scene)
        if not os.path.exists(tmp):
            raise SystemExit("defocus_node.py: Blender did not write %s" % tmp)
        os.replace(tmp, out_path)
        result["output"] = os.path.basename(out_path)
        result["output_layout"] = "single-layer R, G, B, A, 32-bit float, ZIP"
    write_json(os.path.join(out_dir, base + ".json"), result)


main()
