#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Builds the installable add-on zip: the diffusion_dof package plus the built ddof shared
library, ready for Blender's Preferences > Add-ons > Install.

    python3 blender_addon/build_zip.py --library build/test/libddof/libddof.so [--output FILE]

The library is stored as diffusion_dof/libddof.so (symbolic links resolved), where the add-on
looks first. The GL backend plugin (libddof_gl.so: --gl-plugin, or the one built beside the
library when there is one) goes beside it, where libddof looks for it, so the add-on's
"Auto (GPU when available)" backend can find a GPU. The default output is diffusion_dof-<version>.zip in the current folder. The CMake
target ddof-blender-addon runs this with the library it built.
"""

import argparse
import ast
import os
import sys
import zipfile

HERE = os.path.dirname(os.path.abspath(__file__))
PACKAGE = "diffusion_dof"


def addon_version():
    """bl_info['version'] of the package, read without importing it (it needs bpy)."""
    with open(os.path.join(HERE, PACKAGE, "__init__.py"), encoding="utf-8") as f:
        tree = ast.parse(f.read())
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(getattr(t, "id", "") == "bl_info"
                                                for t in node.targets):
            return ".".join(str(v) for v in ast.literal_eval(node.value)["version"])
    raise SystemExit("build_zip.py: no bl_info in %s/__init__.py" % PACKAGE)


def library_name(path):
    if path.endswith(".dll"):
        return "ddof.dll"
    if ".dylib" in path:
        return "libddof.dylib"
    return "libddof.so"


def _add_binary(z, path, arcname):
    info = zipfile.ZipInfo(arcname, date_time=(2024, 1, 1, 0, 0, 0))
    info.external_attr = 0o755 << 16
    info.compress_type = zipfile.ZIP_DEFLATED
    with open(path, "rb") as f:
        z.writestr(info, f.read())


def gl_plugin_beside(library):
    """The GL plugin built beside the library (libddof_gl.so), or None."""
    path = os.path.join(os.path.dirname(os.path.realpath(library)), "libddof_gl.so")
    return path if os.path.isfile(path) else None


def build(library, output, gl_plugin=None):
    """Writes the zip; gl_plugin: the libddof_gl file to carry, None for the one beside the
    library (if any), "" for none."""
    library = os.path.realpath(library)
    if gl_plugin is None:
        gl_plugin = gl_plugin_beside(library)
    elif gl_plugin and not os.path.isfile(gl_plugin):
        raise SystemExit("build_zip.py: the GL plugin %s does not exist" % gl_plugin)
    if not os.path.isfile(library):
        raise SystemExit("build_zip.py: the library %s does not exist (build the `ddof` target "
                         "first)" % library)
    source = os.path.join(HERE, PACKAGE)
    files = []
    for root, dirs, names in os.walk(source):
        dirs[:] = sorted(d for d in dirs if d != "__pycache__")
        for name in sorted(names):
            if name.endswith((".py", ".md", ".txt")):
                full = os.path.join(root, name)
                files.append((full, os.path.join(PACKAGE, os.path.relpath(full, source))))
    partial = output + ".partial"
    with zipfile.ZipFile(partial, "w", zipfile.ZIP_DEFLATED) as z:
        for full, arcname in files:
            z.write(full, arcname)
        _add_binary(z, library, os.path.join(PACKAGE, library_name(library)))
        if gl_plugin:
            _add_binary(z, os.path.realpath(gl_plugin), os.path.join(PACKAGE, "libddof_gl.so"))
    os.replace(partial, output)
    return output, len(files) + 1 + (1 if gl_plugin else 0)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--library", required=True, help="the built libddof.so")
    parser.add_argument("--output", help="zip to write (default diffusion_dof-VERSION.zip)")
    parser.add_argument("--gl-plugin", help="the built libddof_gl.so to carry (default: the one "
                                            "beside --library, if any; '' for none)")
    args = parser.parse_args(argv)
    output = os.path.abspath(args.output or "%s-%s.zip" % (PACKAGE, addon_version()))
    os.makedirs(os.path.dirname(output), exist_ok=True)
    path, count = build(args.library, output, args.gl_plugin)
    print("build_zip.py: wrote %s (%d files)" % (path, count))
    return 0


if __name__ == "__main__":
    sys.exit(main())
