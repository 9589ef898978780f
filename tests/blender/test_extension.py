# SPDX-License-Identifier: GPL-3.0-or-later
"""The extension package (Blender 4.2+): built as the build builds it, validated by Blender's own
extension tool (bl_pkg's blender_ext.py, what `blender --command extension validate` runs),
installed with Blender's operator (Get Extensions > Install from Disk), enabled, and working
from its install folder: the library it carries is the one loaded (no DDOF_LIBRARY), a still
render gets depth of field, and it disables and uninstalls cleanly. Blender as a Python module
only (tests/bpy): Blender 3.x has no extensions."""

import os
import sys
import zipfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import blender_test_util as u  # noqa: E402

import addon_utils  # noqa: E402
import bpy  # noqa: E402

checks = u.Checks("test_extension")
work = u.scratch_dir("extension_test")
library = os.environ.pop("DDOF_LIBRARY", "")  # the package's own library must be found
checks.check(os.path.isfile(library), "DDOF_LIBRARY must name the built library")

path = u.build_extension(library, work)
checks.check(os.path.basename(path) == "diffusion_dof-0.4.0-linux_x64.zip" or
             path.endswith(("_x64.zip", "_arm64.zip")), "package name %s" % path)
with zipfile.ZipFile(path) as z:
    names = z.namelist()
    manifest = z.read("blender_manifest.toml").decode("utf-8")
checks.check("__init__.py" in names and "libddof.so" in names and "compat.py" in names,
             "package content: %s" % names)
import tomllib  # noqa: E402  (Python 3.11: every bpy wheel tested)
m = tomllib.loads(manifest)
sys.path.insert(0, u.ADDON_DIR)
import build_zip  # noqa: E402
checks.check(m["id"] == "diffusion_dof" and m["type"] == "add-on", "manifest id/type %r" % m)
checks.check(m["version"] == build_zip.addon_version(), "manifest version %s, bl_info %s"
             % (m["version"], build_zip.addon_version()))
checks.check(m["blender_version_min"] == "4.2.0", "blender_version_min %s"
             % m["blender_version_min"])
checks.check(m["license"] == ["SPDX:GPL-3.0-or-later"], "license %r" % m["license"])
checks.check(m.get("permissions", {}).get("files"), "no files permission with a reason")
checks.check(m.get("platforms") == ["linux-x64"], "platforms %r" % m.get("platforms"))

ok, text = u.validate_extension(path)
print("validate:", text)
checks.check(ok, "Blender's validator: %s" % text)
# The validator does refuse a bad manifest (so the check above can fail).
bad = os.path.join(work, "bad.zip")
with zipfile.ZipFile(path) as src, zipfile.ZipFile(bad, "w") as dst:
    for name in src.namelist():
        data = src.read(name)
        if name == "blender_manifest.toml":
            data = data.replace(b'blender_version_min = "4.2.0"', b'blender_version_min = "x"')
        dst.writestr(name, data)
ok_bad, text_bad = u.validate_extension(bad)
checks.check(not ok_bad, "the validator accepted a bad manifest: %s" % text_bad)

result = bpy.ops.extensions.package_install_files(filepath=path, repo=u.EXTENSION_REPO,
                                                  enable_on_install=True)
checks.check(result == {"FINISHED"}, "install: %r" % result)
installed = os.path.join(bpy.utils.user_resource("EXTENSIONS"), u.EXTENSION_REPO,
                         "diffusion_dof")
checks.check(os.path.isfile(os.path.join(installed, "blender_manifest.toml")),
             "not installed in %s" % installed)
checks.check(u.EXTENSION_MODULE in bpy.context.preferences.addons, "not enabled: %s"
             % list(bpy.context.preferences.addons.keys()))
addon = sys.modules[u.EXTENSION_MODULE]
ok, text = addon.binding.library_status(reload=True)
checks.check(ok and os.path.realpath(addon.binding.get_library().path).startswith(
    os.path.realpath(installed)), "library: %s" % text)

scene = u.clear_scene()
u.add_plane(scene, "Wall", (24.0, 14.0), (0.0, 12.0, 0.0),
            u.emission_checker("WallMat", (0.95, 0.85, 0.6, 1), (0.08, 0.12, 0.3, 1), 4.0))
u.add_camera(scene, lens=100.0, fstop=1.4, focus=3.0)
u.configure(scene, samples=4)
scene.diffusion_dof.enabled = True
bpy.ops.render.render()
report = addon.report.reports.get(scene.name)
checks.check(report is not None and report["ok"] and report["stats"]["max_coc_px"] > 5,
             "render with the installed extension: %r" % (report,))

addon_utils.disable(u.EXTENSION_MODULE, default_set=True)
checks.check(not hasattr(bpy.types.Scene, "diffusion_dof"), "still registered after disable")
result = bpy.ops.extensions.package_uninstall(repo_index=[r.module for r in
                                              bpy.context.preferences.extensions.repos]
                                              .index(u.EXTENSION_REPO), pkg_id="diffusion_dof")
checks.check(result == {"FINISHED"} and not os.path.isdir(installed),
             "uninstall: %r, folder left: %s" % (result, os.path.isdir(installed)))
if bpy.app.version < (5, 0, 0):
    # bpy 4.2.23 (the module) crashes at process exit after package_uninstall of this add-on
    # (SIGSEGV in bpy_class_free from ~SpaceType, in exit handlers after Python is finalized;
    # not with 5.0.1, nor after disable alone): leave before the exit handlers run.
    print("%s: %d checks, %d failures" % (checks.name, checks.count, len(checks.failures)),
          flush=True)
    sys.stderr.flush()
    os._exit(1 if checks.failures else 0)
checks.finish()
