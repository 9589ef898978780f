# SPDX-License-Identifier: MIT
"""Ground-truth scenes for the accuracy-vs-cost study (issue 7), rendered with Blender Cycles.

    blender -b --factory-startup --python-exit-code 1 --python study/scenes/make_scenes.py -- \
        --out DIR [--scenes a,b,...] [--size WxH] [--samples-pinhole N] [--samples-truth N] \
        [--samples-1080 N] [--no-1080] [--smoke] [--force] [--seed N] \
        [--only pinhole,truth,fg,rest,matte,1080] [--threads N] [--aperture B,R,A] \
        [--overscan PX] [--adopt] [--verbose]

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
  matte.exr          the pinhole render with Blender's object matte beside it (Cryptomatte:
                     ViewLayer.CryptoObject00-02.r/g/b/a, 6 ranks of id and coverage, float;
                     its Combined pass is pinhole.exr's), for `ddof --matte`;
  pinhole_1080.exr   the pinhole render at 1920x1080 with few samples (for timings), and
  camera_1080.json   its sidecar (the same camera, resolution [1920, 1080]);
  render.json        what was rendered with which settings, and how long each render took.

Scenes: thin_bars, thin_strands, near_occluder, receding_plane, highlights, all_sharp,
near_railing, near_border, daylight (README.md beside this file says what each stresses;
daylight's sky is Blender's Nishita sky texture, the one background that is not a flat colour).
Every material is emission-only ("unlit": an albedo texture times a fixed fake-Lambert term
computed from the shading normal, no light sampling) and the renders use no bounces, so the only
noise in the truth is that of integrating the lens and the pixel footprint, which is what the
study measures against.

--smoke renders thin_bars alone at 96x54 with 4/16 samples and no 1080p pinhole (a few
seconds; the CI smoke test). Outputs whose settings and code fingerprint match render.json are
kept (a cache) unless --force: the fingerprint (scene_cache.code_fingerprint) covers what a
scene's renders depend on, the modules beside this file that build and render it less the other
scenes' builders. --adopt takes the outputs in DIR as made by the current code whatever
fingerprint they record (outputs made before the fingerprint existed, or after a change that
leaves every render the same, such as moving code between those modules), once, and records it.
Deterministic: fixed seed, no adaptive sampling, no denoiser; --threads (default 2) fixes the
thread count. --aperture BLADES,ROTATION_DEG,RATIO gives the camera Blender's Blades, Rotation
and Ratio (default 0,0,1: round; the truth then draws polygons or ovals, and camera.json carries
the aperture_* keys).

The work is split by job: scene_builders.py (the scenes), materials.py, objects.py, camera.py
(what they are made of), render_output.py (one output's render), scene_cache.py (which outputs
are up to date) and this file (the arguments and the loop over the scenes).
"""

import json
import os
import sys
import time

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from camera import camera_sidecar, coc_px, overscan_sensor_mm  # noqa: E402
from render_output import render_output  # noqa: E402
from scene_builders import BUILDERS, SCENE_NAMES  # noqa: E402
from scene_cache import code_fingerprint, output_key, plan_outputs, up_to_date  # noqa: E402
from script_util import parse, write_json  # noqa: E402


def parse_args():
    args = parse(
        "make_scenes.py",
        {"out": None, "scenes": ",".join(SCENE_NAMES), "size": "480x270",
         "samples-pinhole": "256", "samples-truth": None, "samples-1080": "16",
         "seed": "1", "only": "pinhole,truth,fg,rest,matte,1080", "threads": "2",
         "aperture": "0,0,1", "overscan": "0"},
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
    args["overscan_px"] = int(args["overscan"])
    if args["overscan_px"] and ("1080" in args["only_set"] or w < h):
        raise SystemExit("make_scenes.py: --overscan grows the scenes' own (landscape) frame: "
                         "add --no-1080")
    return args


def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    return bpy.context.scene


def read_manifest(path):
    """render.json of a scene folder ({"files": {}} when there is none yet)."""
    try:
        with open(path) as f:
            manifest = json.load(f)
    except (OSError, ValueError):
        manifest = {}
    manifest.setdefault("files", {})
    return manifest


def frame_sidecar(cam, args):
    """camera.json of the renders at the scenes' own size: with --overscan, of the grown frame
    (its resolution and its wider sensor, the same pixel pitch)."""
    m = args["overscan_px"]
    return camera_sidecar(cam, args["width"] + 2 * m, args["height"] + 2 * m,
                          args["aperture_set"], overscan_sensor_mm(args["width"], m))


def write_sidecars(out, args, cam):
    write_json(os.path.join(out, "camera.json"), frame_sidecar(cam, args))
    if "1080" in args["only_set"]:
        # The same camera with the 1080p frame's resolution (ddof warns when a sidecar's
        # resolution is not the frame's).
        write_json(os.path.join(out, "camera_1080.json"),
                   camera_sidecar(cam, 1920, 1080, args["aperture_set"]))


def make_scene(args, name, tag):
    """Builds the scene and renders the outputs of it that the cache lacks into its folder."""
    out = os.path.join(args["out"], name)
    os.makedirs(out, exist_ok=True)
    manifest_path = os.path.join(out, "render.json")
    manifest = read_manifest(manifest_path)

    scene = reset()
    cam, near = BUILDERS[name](scene)
    plan = plan_outputs(args, name, bool(near))
    code = code_fingerprint(name)

    todo = []
    for entry in plan:
        key = output_key(args, entry, bpy.app.version_string, code)
        if up_to_date(args, manifest["files"].get(entry[0], {}), os.path.join(out, entry[0]),
                      key):
            print("%s: %s is up to date (cached)" % (tag, entry[0]), flush=True)
            manifest["files"][entry[0]]["code"] = code
        else:
            todo.append((entry, key))

    manifest.update({
        "scene": name,
        "doc": BUILDERS[name].__doc__,
        "camera": frame_sidecar(cam, args),
        "near_objects": near,
        "max_coc_px_at_infinity": round(coc_px(cam, 1e10, args["width"]), 2),
        "threads": int(args["threads"]),
        "shading": "emission-only (albedo x fake Lambert), no bounces",
    })
    write_sidecars(out, args, cam)

    for (fname, kind, w, h, samples), key in todo:
        label = {"pinhole": "pinhole", "truth": "truth", "fg": "foreground element",
                 "rest": "rest (no near objects)", "matte": "pinhole with the object matte"}[kind]
        margin = args["overscan_px"] if (w, h) == (args["width"], args["height"]) else 0
        print("%s: %s %dx%d, %d samples ... " % (tag, label, w + 2 * margin, h + 2 * margin,
                                                 samples), end="", flush=True)
        seconds = render_output(scene, args, cam, near, os.path.join(out, fname), kind, w, h,
                                samples, margin)
        print("%.1f s" % seconds, flush=True)
        key["seconds"] = round(seconds, 2)
        key["threads"] = int(args["threads"])
        manifest["files"][fname] = key
        write_json(manifest_path, manifest)
    write_json(manifest_path, manifest)


def main():
    args = parse_args()
    total = len(args["scene_list"])
    t_all = time.perf_counter()
    for index, name in enumerate(args["scene_list"], 1):
        make_scene(args, name, "[%d/%d] %s" % (index, total, name))
    print("make_scenes.py: %d scene(s) in %.1f s -> %s"
          % (total, time.perf_counter() - t_all, args["out"]), flush=True)


main()
