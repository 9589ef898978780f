#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Lists the circles of dependence among the files of each product folder and exits 1 when
there is one that is not among KNOWN below (so no new one comes in while the known ones are
taken apart, issue 43).

    python3 scripts/circles.py [ROOT]

A file's unit is its name without the extension (x.h and x.c are one unit). C: unit A depends
on unit B when a file of A includes "B.h" of the same folder. Python: module A depends on B when
it imports B relatively (`from . import B`, `from .B import ...`), inside a function too: an
import put in a function to dodge a circle is still one. Includes and imports only: a circle of
calls through a shared header (libddof's context -> backend -> solvers -> context, issue 43)
is not seen."""
import ast
import os
import re
import sys

SKIP_DIRS = {".git", "build", "__pycache__", "tests", "study", "fuzz"}
PRODUCT_DIRS = ("libddof", "plugin", "blender_addon")

# Circles left to take apart (issue 43), by folder: sorted unit names.
KNOWN = {
    "libddof/src": [
        ["highlights", "highlights_classes"],
        ["internal", "thread_pool"],
        ["adi", "line_gather"],
        ["near_offsets", "near_offsets_internal"],
    ],
}


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


def main():
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
    if new:
        print("%d circle(s) not among the known ones: take them apart" % new)
    return 1 if new else 0


if __name__ == "__main__":
    sys.exit(main())
