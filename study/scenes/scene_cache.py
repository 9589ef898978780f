# SPDX-License-Identifier: MIT
"""The study scenes' cache: the outputs a run wants, and whether an output on disk is up to date
(render.json records, per output, the settings and the code fingerprint it was made with)."""

import ast
import hashlib
import os

from scene_builders import TRUTH_SAMPLES

HERE = os.path.dirname(os.path.abspath(__file__))
# The modules a scene's renders depend on. Moving code between them leaves the fingerprint as it
# is; make_scenes.py and this file (arguments, the cache) are not among them, so what changes a
# render belongs in these.
RENDER_MODULES = ("materials.py", "objects.py", "camera.py", "scene_builders.py",
                  "render_output.py", "script_util.py")


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
    if "matte" in want:
        plan.append(("matte.exr", "matte", w, h, sp))
    if "1080" in want:
        plan.append(("pinhole_1080.exr", "pinhole", 1920, 1080, int(args["samples-1080"])))
    return plan


def code_fingerprint(name):
    """What a scene's renders depend on in the code: the top-level definitions of RENDER_MODULES
    as Python's syntax trees (comments, docstrings, imports and layout do not count), sorted (so
    moving a definition between the modules does not count either), less the other scenes'
    builders and the scene lists (SCENE_NAMES, TRUTH_SAMPLES: the samples are in the cache key,
    BUILDERS). Adding a scene, or editing another one, leaves a scene's cache valid."""
    skip = {"SCENE_NAMES", "TRUTH_SAMPLES", "BUILDERS"}
    parts = []
    for module in RENDER_MODULES:
        with open(os.path.join(HERE, module), encoding="utf-8") as f:
            tree = ast.parse(f.read())
        for node in tree.body:
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                continue
            if isinstance(node, ast.Expr) and isinstance(node.value, ast.Constant):
                continue  # a docstring
            if (isinstance(node, ast.FunctionDef) and node.name.startswith("build_") and
                    node.name != "build_" + name):
                continue
            if isinstance(node, ast.Assign) and any(
                    isinstance(t, ast.Name) and t.id in skip for t in node.targets):
                continue
            parts.append(ast.dump(node))
    return hashlib.sha256("\n".join(sorted(parts)).encode()).hexdigest()[:16]


def output_key(args, entry, blender, code):
    """What render.json records of an output: its kind, size, samples, seed, Blender version,
    aperture and code fingerprint (and, once rendered, its time and threads)."""
    fname, kind, w, h, samples = entry
    key = {"kind": kind, "size": [w, h], "samples": samples, "seed": int(args["seed"]),
           "blender": blender, "aperture": list(args["aperture_set"]), "code": code}
    if args.get("overscan_px"):  # absent at 0: the renders recorded before it stay valid
        key["overscan_px"] = args["overscan_px"]
    return key


def up_to_date(args, recorded, path, key):
    """Whether the output at path, recorded as `recorded` in render.json, is what key asks for
    (never with --force). --adopt takes it as made by the current code whatever fingerprint it
    records, for a change that leaves the renders the same."""
    if args["adopt"]:
        recorded = dict(recorded, code=key["code"])
    return (not args["force"] and os.path.exists(path) and
            all(recorded.get(k) == v for k, v in key.items()) and
            recorded.get("overscan_px", 0) == key.get("overscan_px", 0))
