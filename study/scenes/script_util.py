# SPDX-License-Identifier: MIT
"""What the study's Blender scripts (make_scenes.py, defocus_node.py) share: their argument
convention, a way to silence Blender's own output, and atomic JSON writes.

    args = script_util.parse("make_scenes.py", {"out": None, "size": "480x270"}, {"verbose"},
                             required=("out",))

parse reads everything after `--` on Blender's command line as `--key value` pairs and bare
`--flag`s. Values stay strings (flags become True); an unknown key, a missing value or a
missing required key ends the script with a message naming it."""

import contextlib
import json
import os
import sys


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
