# SPDX-License-Identifier: MIT
"""What the study's Blender scripts (make_scenes.py, defocus_node.py, cards/make_cards_scene.py)
share: their argument convention, a way to silence Blender's own output, atomic JSON writes,
and the film and file settings of a study render with its atomic write.

    args = script_util.parse("make_scenes.py", {"out": None, "size": "480x270"}, {"verbose"},
                             required=("out",))

parse reads everything after `--` on Blender's command line as `--key value` pairs and bare
`--flag`s. Values stay strings (flags become True); an unknown key, a missing value or a
missing required key ends the script with a message naming it."""

import contextlib
import json
import os
import sys
import time


def parse(script, defaults, flags, required=()):
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    args = dict(defaults)
    for flag in flags:
        args.setdefault(flag, False)
    i = 0
    while i < len(argv):
        key = argv[i][2:] if argv[i].startswith("--") else None
        if key in flags:
            args[key] = True
            i += 1
            continue
        if key not in args or i + 1 >= len(argv):
            raise SystemExit("%s: unknown or incomplete argument %r" % (script, argv[i]))
        args[key] = argv[i + 1]
        i += 2
    for key in required:
        if not args[key]:
            raise SystemExit("%s: --%s is required" % (script, key))
    return args


@contextlib.contextmanager
def quiet(enabled):
    """Sends Blender's own stdout (render progress, 'Saved:' lines) to /dev/null."""
    if not enabled:
        yield
        return
    sys.stdout.flush()
    saved = os.dup(1)
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, 1)
        yield
    finally:
        sys.stdout.flush()
        os.dup2(saved, 1)
        os.close(saved)
        os.close(devnull)


def write_json(path, data):
    """Writes data as indented JSON to a temporary file and renames it over path."""
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        json.dump(data, f, indent=2)
        f.write("\n")
    os.replace(tmp, path)


def film_and_file(scene, width, height, threads, multilayer, transparent=False):
    """The study's render output: width x height at 100 %, square pixels, a fixed thread count,
    Standard view with no look (the EXR holds the scene-linear values), no compositing (else
    Blender adds a "Composite" layer to the EXR), and RGBA half OpenEXR, ZIP: multilayer with
    the Depth pass (Blender keeps it in float) for a pinhole, single-layer for a truth."""
    render = scene.render
    render.resolution_x, render.resolution_y = width, height
    render.resolution_percentage = 100
    render.pixel_aspect_x = render.pixel_aspect_y = 1.0
    render.film_transparent = transparent
    render.use_compositing = False
    render.use_sequencer = False
    render.threads_mode = "FIXED"
    render.threads = int(threads)
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    layer = scene.view_layers[0]
    layer.name = "ViewLayer"
    layer.use_pass_combined = True
    layer.use_pass_z = multilayer
    settings = render.image_settings
    settings.file_format = "OPEN_EXR_MULTILAYER" if multilayer else "OPEN_EXR"
    settings.color_mode = "RGBA"
    settings.color_depth = "16"
    settings.exr_codec = "ZIP"


def render_to(scene, path, verbose, script):
    """Renders the scene's still into path (a temporary name first: never a half-written file
    under the final one); returns the seconds it took. `script` names the caller in errors."""
    import bpy  # only Blender's python has it; the rest of this module does not need it

    tmp = os.path.join(os.path.dirname(path), "." + os.path.basename(path) + ".tmp.exr")
    scene.render.filepath = tmp
    scene.render.use_file_extension = False
    t0 = time.perf_counter()
    with quiet(not verbose):
        bpy.ops.render.render(write_still=True)
    seconds = time.perf_counter() - t0
    if not os.path.exists(tmp):
        raise SystemExit("%s: Blender did not write %s" % (script, tmp))
    os.replace(tmp, path)
    return seconds
