"""The argument convention of the study's Blender scripts: everything after `--` on Blender's
command line, as `--key value` pairs and bare `--flag`s.

    args = script_args.parse("make_scenes.py", {"out": None, "size": "480x270"}, {"verbose"},
                             required=("out",))

Values stay strings (flags become True); an unknown key, a missing value or a missing required
key ends the script with a message naming it."""

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
