#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Lists the functions longer than a limit (default 120 lines) in the product's C and Python
sources (libddof, plugin, blender_addon, scripts) and exits 1 when there is one; --all lists
the tests', study's and fuzz targets' too, for information (a test case reads best whole).

    python3 scripts/long_functions.py [--limit N] [--all] [ROOT]

C functions are found the way this tree writes them: a line at column 0 ending a signature,
a '{' alone at column 0, and the matching '}' at column 0. Python functions by their ast."""
import argparse
import ast
import os
import re
import sys

SKIP_DIRS = {".git", "build", "__pycache__"}
PRODUCT_DIRS = ("libddof", "plugin", "blender_addon", "scripts")
OTHER_DIRS = ("tests", "study", "fuzz")


def c_functions(text):
    lines = text.split("\n")
    start = None
    for i, line in enumerate(lines):
        if line == "{" and i > 0:
            j = i - 1  # the signature's first line: back to a line starting at column 0
            while j > 0 and lines[j][:1] in (" ", "\t"):
                j -= 1
            m = re.search(r"(\w+)\s*\(", lines[j])
            start = (m.group(1) if m else "?", j)
        elif line.startswith("}") and start is not None:
            yield start[0], start[1] + 1, i - start[1] + 1
            start = None


def py_functions(text):
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            yield node.name, node.lineno, node.end_lineno - node.lineno + 1


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--limit", type=int, default=120)
    parser.add_argument("--all", action="store_true")
    parser.add_argument("root", nargs="?", default=os.path.join(os.path.dirname(__file__), ".."))
    args = parser.parse_args()
    root = os.path.abspath(args.root)
    bad = 0
    for top in PRODUCT_DIRS + (OTHER_DIRS if args.all else ()):
        for folder, dirs, files in os.walk(os.path.join(root, top)):
            dirs[:] = [d for d in dirs if d not in SKIP_DIRS]
            for name in sorted(files):
                path = os.path.join(folder, name)
                rel = os.path.relpath(path, root)
                if name.endswith(".c"):
                    found = c_functions(open(path, encoding="utf-8").read())
                elif name.endswith(".py"):
                    found = py_functions(open(path, encoding="utf-8").read())
                else:
                    continue
                for fn, line, length in found:
                    if length > args.limit:
                        product = top in PRODUCT_DIRS
                        bad += product
                        print("%s:%d: %s is %d lines%s" % (rel, line, fn, length,
                                                           "" if product else " (not enforced)"))
    print("long_functions: %d product functions over %d lines" % (bad, args.limit))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
