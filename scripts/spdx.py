#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Every source file carries an SPDX licence line: MIT for the library, the command, the GL
module, the shaders, the tests, the study and the scripts (LICENSE); GPL-3.0-or-later for the
Blender add-on and the tests that run inside Blender, which import bpy
(blender_addon/LICENSE).

    python3 scripts/spdx.py          lists the files without the right line; exit 1 if any
    python3 scripts/spdx.py --fix    adds the line where it is missing"""
import os
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
TOP_DIRS = ("libddof", "plugin", "blender_addon", "tests", "study", "scripts",
            "fuzz", ".ci")
GPL_DIRS = ("blender_addon", "tests/blender", "tests/bpy")
SKIP_DIRS = {".git", "build", "__pycache__", "corpus", "known"}
HASH = (".py", ".sh", ".cmake", ".txt", ".toml")
SLASH = (".c", ".h", ".glsl", ".comp")  # not .inc: the fitted and measured tables are written by scripts


def licence(rel):
    return "GPL-3.0-or-later" if rel.startswith(GPL_DIRS) else "MIT"


def comment_style(rel, name):
    if name.endswith(SLASH):
        return "/* %s */"
    if name.endswith(HASH) or name in ("CMakeLists.txt", "run"):
        return "# %s"
    return None


def sources():
    for top in TOP_DIRS:
        for folder, dirs, files in os.walk(os.path.join(ROOT, top)):
            dirs[:] = sorted(d for d in dirs if d not in SKIP_DIRS)
            for name in sorted(files):
                path = os.path.join(folder, name)
                rel = os.path.relpath(path, ROOT)
                style = comment_style(rel, name)
                if style and not (name.endswith(".txt") and name != "CMakeLists.txt"):
                    yield path, rel, style
    yield os.path.join(ROOT, "CMakeLists.txt"), "CMakeLists.txt", "# %s"


def main():
    fix = "--fix" in sys.argv[1:]
    missing = 0
    for path, rel, style in sources():
        with open(path, encoding="utf-8") as f:
            text = f.read()
        line = style % ("SPDX-License-Identifier: " + licence(rel))
        head = text.split("\n", 3)[:3]
        if any(line == h for h in head):
            continue
        missing += 1
        if not fix:
            print("%s: no '%s'" % (rel, line))
            continue
        if text.startswith("#!"):
            first, rest = text.split("\n", 1)
            text = first + "\n" + line + "\n" + rest
        else:
            text = line + "\n" + text
        with open(path, "w", encoding="utf-8") as f:
            f.write(text)
    print("spdx: %d file%s %s" % (missing, "" if missing == 1 else "s",
                                  "fixed" if fix else "without their licence line"))
    return 0 if fix or not missing else 1


if __name__ == "__main__":
    sys.exit(main())
