#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Builds the installable add-on zip: the diffusion_dof package plus the built ddof shared
library, ready for Blender's Preferences > Add-ons > Install (the legacy add-on, Blender 3.x and
later), or with --extension the extension package for Blender 4.2 and later (Get Extensions >
Install from Disk, or `blender --command extension install-file`).

    python3 blender_addon/build_zip.py --library build/test/libddof/libddof.so [--output FILE]
    python3 blender_addon/build_zip.py --extension --library ... [--output-dir DIR]

The extension is one package per platform (its library is built for one): the manifest
(diffusion_dof/blender_manifest.toml) goes at the zip's root with `platforms` set to the
library's platform, and the file is named diffusion_dof-VERSION-PLATFORM.zip as Blender's
`extension build --split-platforms` names it.

The library is stored as diffusion_dof/libddof.so (symbolic links resolved), where the add-on
looks first. The GL backend plugin (libddof_gl.so: --gl-plugin, or the one built beside the
library when there is one) goes beside it, where libddof looks for it, so the add-on's
"Auto (GPU when available)" backend can find a GPU. The default output is diffusion_dof-<version>.zip in the current folder. The CMake
target ddof-blender-addon runs this with the library it built.
"""

import argparse
import ast
import os
import platform
import sys
import zipfile

HERE = os.path.dirname(os.path.abspath(__file__))
PACKAGE = "diffusion_dof"
MANIFEST = "blender_manifest.toml"


def addon_version():
    """bl_info['version'] of the package, read without importing it (it needs bpy)."""
    with open(os.path.join(HERE, PACKAGE, "__init__.py"), encoding="utf-8") as f:
        tree = ast.parse(f.read())
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(getattr(t, "id", "") == "bl_info"
                                                for t in node.targets):
            return ".".join(str(v) for v in ast.literal_eval(node.value)["version"])
    raise SystemExit("build_zip.py: no bl_info in %s/__init__.py" % PACKAGE)


def manifest_text():
    with open(os.path.join(HERE, PACKAGE, MANIFEST), encoding="utf-8") as f:
        return f.read()


def manifest_version():
    """The manifest's version = "...", read without a TOML parser (Python 3.11 has tomllib,
    Blender 3.4's 3.10 has not)."""
    for line in manifest_text().splitlines():
        key, _, value = line.partition("=")
        if key.strip() == "version":
            return value.strip().strip('"')
    raise SystemExit("build_zip.py: no version in %s/%s" % (PACKAGE, MANIFEST))


def platform_tag(library):
    """The extension platform of the library ('linux-x64', 'macos-arm64', 'windows-x64')."""
    machine = platform.machine().lower()
    arch = "arm64" if machine in ("arm64", "aarch64") else "x64"
    if library.endswith(".dll"):
        return "windows-" + arch
    if ".dylib" in library:
        return "macos-" + arch
    return "linux-" + arch


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


def build(library, output, gl_plugin=None, extension=False):
    """Writes the zip; gl_plugin: the libddof_gl file to carry, None for the one beside the
    library (if any), "" for none. extension: the extension package's layout (the package's
    files at the root, the manifest with the library's platform)."""
    library = os.path.realpath(library)
    if gl_plugin is None:
        gl_plugin = gl_plugin_beside(library)
    elif gl_plugin and not os.path.isfile(gl_plugin):
        raise SystemExit("build_zip.py: the GL plugin %s does not exist" % gl_plugin)
    if not os.path.isfile(library):
        raise SystemExit("build_zip.py: the library %s does not exist (build the `ddof` target "
                         "first)" % library)
    source = os.path.join(HERE, PACKAGE)
    prefix = "" if extension else PACKAGE
    files = []
    for root, dirs, names in os.walk(source):
        dirs[:] = sorted(d for d in dirs if d != "__pycache__")
        for name in sorted(names):
            if name.endswith((".py", ".md", ".txt")):
                full = os.path.join(root, name)
                files.append((full, os.path.join(prefix, os.path.relpath(full, source))))
    partial = output + ".partial"
    with zipfile.ZipFile(partial, "w", zipfile.ZIP_DEFLATED) as z:
        for full, arcname in files:
            z.write(full, arcname)
        if extension:
            text = manifest_text().rstrip("\n").split("\n")
            at = text.index("license = [\"SPDX:GPL-3.0-or-later\"]") + 1
            text[at:at] = ["", "platforms = [\"%s\"]" % platform_tag(library)]
            z.writestr(MANIFEST, "\n".join(text) + "\n")
        _add_binary(z, library, os.path.join(prefix, library_name(library)))
        if gl_plugin:
            _add_binary(z, os.path.realpath(gl_plugin), os.path.join(prefix, "libddof_gl.so"))
    os.replace(partial, output)
    return output, len(files) + 1 + (1 if gl_plugin else 0) + (1 if extension else 0)


def extension_name(library):
    return "%s-%s-%s.zip" % (PACKAGE, manifest_version(), platform_tag(library).replace("-", "_"))


def build_extension(library, output_dir, gl_plugin=None):
    """Writes the extension package into output_dir; returns (path, file count)."""
    os.makedirs(output_dir, exist_ok=True)
    output = os.path.join(os.path.abspath(output_dir), extension_name(os.path.realpath(library)))
    return build(library, output, gl_plugin, extension=True)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--library", required=True, help="the built libddof.so")
    parser.add_argument("--output", help="zip to write (default diffusion_dof-VERSION.zip)")
    parser.add_argument("--gl-plugin", help="the built libddof_gl.so to carry (default: the one "
                                            "beside --library, if any; '' for none)")
    parser.add_argument("--extension", action="store_true",
                        help="build the extension package (Blender 4.2+) instead")
    parser.add_argument("--output-dir", help="with --extension: the folder to write "
                                             "diffusion_dof-VERSION-PLATFORM.zip into (default .)")
    args = parser.parse_args(argv)
    if addon_version() != manifest_version():
        raise SystemExit("build_zip.py: bl_info's version %s and %s's %s differ"
                         % (addon_version(), MANIFEST, manifest_version()))
    if args.extension:
        path, count = build_extension(args.library, args.output_dir or ".", args.gl_plugin)
        print("build_zip.py: wrote %s (%d files)" % (path, count))
        return 0
    output = os.path.abspath(args.output or "%s-%s.zip" % (PACKAGE, addon_version()))
    os.makedirs(os.path.dirname(output), exist_ok=True)
    path, count = build(args.library, output, args.gl_plugin)
    print("build_zip.py: wrote %s (%d files)" % (path, count))
    return 0


if __name__ == "__main__":
    sys.exit(main())
