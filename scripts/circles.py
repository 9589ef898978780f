#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Lists the circles of dependence among the files of each product folder and exits 1 when
there is one that is not among KNOWN below (so no new one comes in while the known ones are
taken apart, issue 43), or when a file of libddof/src breaks the order of its parts.

    python3 scripts/circles.py [ROOT]
    python3 scripts/circles.py --calls NAME OBJECTS... [--calls NAME OBJECTS...]

libddof/src's parts are the folders its README.md lists, bottom first: a file may include a
header of its own folder by bare name, or one of an earlier part as "part/name.h", and nothing
else of src/; no file stands outside the parts. Since C calls nothing it has not included a
declaration of, this also keeps the calls from forming a circle across the parts. A part's one
subfolder is gl/, its GL code, which the GL module (plugin/gl) builds with src/ off its include
path: it includes no part's header at all.

A file's unit is its name without the extension (x.h and x.c are one unit). C: unit A depends
on unit B when a file of A includes "B.h" of the same folder. Python: module A depends on B when
it imports B relatively (`from . import B`, `from .B import ...`), inside a function too: an
import put in a function to dodge a circle is still one. Includes and imports only: calls
through a table of function pointers (the backends') are not seen.

--calls reads the calls themselves from a built target's object files (nm: the symbols each
defines and the ones it needs), file by file, and exits 1 on any circle among them: what the
includes cannot show (files that share one header and call each other through it)."""
import ast
import os
import re
import subprocess
import sys

SKIP_DIRS = {".git", "build", "__pycache__", "tests", "study", "fuzz"}
PRODUCT_DIRS = ("libddof", "plugin", "blender_addon")

# Circles left to take apart (issue 43), by folder: sorted unit names.
KNOWN = {}
PARTS_ROOT = "libddof/src"
GL_FOLDER = "gl"  # a part's GL code (plugin/gl/CMakeLists.txt)


def c_edges(folder, names):
    edges = {}
    for name in names:
        unit = os.path.splitext(name)[0]
        with open(os.path.join(folder, name), encoding="utf-8", errors="replace") as f:
            text = f.read()
        for inc in re.findall(r'^\s*#\s*include\s+"([^"/]+)\.h"', text, re.M):
            if os.path.exists(os.path.join(folder, inc + ".h")) and inc != unit:
                edges.setdefault(unit, set()).add(inc)
        edges.setdefault(unit, set())
    return edges


def py_edges(folder, names):
    units = {os.path.splitext(n)[0] for n in names}
    edges = {}
    for name in names:
        unit = os.path.splitext(name)[0]
        with open(os.path.join(folder, name), encoding="utf-8") as f:
            tree = ast.parse(f.read())
        deps = edges.setdefault(unit, set())
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.level == 1:
                found = [node.module.split(".")[0]] if node.module else [a.name for a in node.names]
                deps.update(d for d in found if d in units and d != unit)
    edges.pop("__init__", None)  # the package's register() imports every module by design
    for deps in edges.values():
        deps.discard("__init__")
    return edges


def part_order(src):
    """The parts as src/README.md lists them, bottom first ("1. `runtime/`")."""
    with open(os.path.join(src, "README.md"), encoding="utf-8") as f:
        return re.findall(r"^\d+\. `([a-z_]+)/`", f.read(), re.M)


def part_breaks(root):
    """Each include in libddof/src that breaks the order of its parts, as a message."""
    src = os.path.join(root, PARTS_ROOT)
    order = part_order(src)
    rank = {part: i for i, part in enumerate(order)}
    found = []
    for name in sorted(os.listdir(src)):
        path = os.path.join(src, name)
        if os.path.isdir(path) and name not in rank:
            found.append("%s/%s/ is not a part listed in README.md" % (PARTS_ROOT, name))
        elif not os.path.isdir(path) and name != "README.md":
            found.append("%s/%s stands outside the parts" % (PARTS_ROOT, name))
    for part in order:
        folder = os.path.join(src, part)
        if not os.path.isdir(folder):
            found.append("%s/%s/ is listed in README.md but missing" % (PARTS_ROOT, part))
            continue
        found += gl_breaks(src, order, part)
        for name in sorted(os.listdir(folder)):
            if not name.endswith((".c", ".h", ".inc")):
                continue
            with open(os.path.join(folder, name), encoding="utf-8", errors="replace") as f:
                text = f.read()
            for inc in re.findall(r'^\s*#\s*include\s+"([^"]+)"', text, re.M):
                where = "%s/%s/%s includes \"%s\"" % (PARTS_ROOT, part, name, inc)
                head = inc.rpartition("/")[0]
                if not head:
                    if any(os.path.exists(os.path.join(src, p, inc)) for p in order) and \
                            not os.path.exists(os.path.join(folder, inc)):
                        found.append(where + ": another part's header needs its folder")
                elif head not in rank or not os.path.exists(os.path.join(src, inc)):
                    found.append(where + ": no such header of a part")
                elif rank[head] > rank[part]:
                    found.append(where + ": %s/ is above %s/" % (head, part))
                elif head == part:
                    found.append(where + ": its own folder's header by bare name")
    return found


def core_headers(src, order):
    """The names of the headers in the parts' own folders (not their gl/ folders)."""
    return {name for part in order if os.path.isdir(os.path.join(src, part))
            for name in os.listdir(os.path.join(src, part)) if name.endswith((".h", ".inc"))}


def gl_breaks(src, order, part):
    """A part's only subfolder is gl/: its GL code, built into the GL module (plugin/gl) with
    src/ off the include path, so it includes no header of a part, by path or by bare name."""
    found = []
    folder = os.path.join(src, part)
    for name in sorted(os.listdir(folder)):
        if os.path.isdir(os.path.join(folder, name)) and name != GL_FOLDER:
            found.append("%s/%s/%s/ is not a part's %s/ folder" % (PARTS_ROOT, part, name,
                                                                  GL_FOLDER))
    gl = os.path.join(folder, GL_FOLDER)
    if not os.path.isdir(gl):
        return found
    core = core_headers(src, order)
    for name in sorted(os.listdir(gl)):
        if not name.endswith((".c", ".h")):
            continue
        with open(os.path.join(gl, name), encoding="utf-8", errors="replace") as f:
            text = f.read()
        for inc in re.findall(r'^\s*#\s*include\s+"([^"]+)"', text, re.M):
            if "/" in inc or (inc in core and not os.path.exists(os.path.join(gl, inc))):
                found.append("%s/%s/%s/%s includes \"%s\": a part's GL code includes only "
                             "the GL module's headers, the seam and ddof.h" %
                             (PARTS_ROOT, part, GL_FOLDER, name, inc))
    return found


def circles(edges):
    """Strongly connected components of more than one unit (Tarjan), each sorted."""
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in edges.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(edges):
        if v not in index:
            visit(v)
    return sorted(out)


def object_edges(objects):
    """Object file (folder/name) -> the object files whose functions or data it uses."""
    defined, needed = {}, {}
    for path in objects:
        path = os.path.normpath(path)
        unit = "%s/%s" % (os.path.basename(os.path.dirname(path)),
                          os.path.basename(path).split(".")[0])
        needed[unit] = set()
        for line in subprocess.run(["nm", "-P", path], capture_output=True, text=True,
                                   check=True).stdout.splitlines():
            fields = line.split()
            if len(fields) >= 2 and fields[1] == "U":
                needed[unit].add(fields[0])
            elif len(fields) >= 2 and fields[1] in "TDRBCV":
                defined[fields[0]] = unit
    return {unit: {defined[s] for s in symbols if s in defined and defined[s] != unit}
            for unit, symbols in needed.items()}


def call_groups(args):
    """[(name, [objects])] from "--calls NAME OBJECTS... --calls NAME OBJECTS...", where the
    objects may also come as one ;-separated argument (a CMake list)."""
    groups = []
    for arg in args:
        if arg == "--calls":
            groups.append(None)
        elif groups and groups[-1] is None:
            groups[-1] = (arg, [])
        elif groups:
            groups[-1][1].extend(o for o in arg.split(";") if o)
    if not groups or any(g is None or not g[1] for g in groups):
        sys.exit("usage: circles.py --calls NAME OBJECTS... [--calls NAME OBJECTS...]")
    return groups


def call_circles(groups):
    failed = 0
    for name, objects in groups:
        found = circles(object_edges(objects))
        for comp in found:
            print("%s: a circle of calls among %s" % (name, ", ".join(comp)))
        failed += len(found)
        if not found:
            print("%s: no circle of calls among its %d files" % (name, len(objects)))
    return 1 if failed else 0


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--calls":
        return call_circles(call_groups(sys.argv[1:]))
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")
    sys.setrecursionlimit(10000)
    new = 0
    for top in PRODUCT_DIRS:
        for folder, dirs, files in os.walk(os.path.join(root, top)):
            dirs[:] = sorted(d for d in dirs if d not in SKIP_DIRS)
            rel = os.path.relpath(folder, root)
            found = circles(c_edges(folder, [f for f in files if f.endswith((".c", ".h", ".cpp"))]))
            found += circles(py_edges(folder, [f for f in files if f.endswith(".py")]))
            for comp in found:
                known = comp in KNOWN.get(rel, [])
                new += not known
                print("%s: a circle among %s%s" % (rel, ", ".join(comp),
                                                  " (known)" if known else ""))
    breaks = part_breaks(root)
    for message in breaks:
        print(message)
    if new:
        print("%d circle(s) not among the known ones: take them apart" % new)
    if breaks:
        print("%d include(s) against the order of libddof/src's parts (its README.md)" %
              len(breaks))
    return 1 if new or breaks else 0


if __name__ == "__main__":
    sys.exit(main())
