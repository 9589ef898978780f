# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs one of the add-on's background-mode test scripts (tests/blender/test_X.py) in Blender
as a Python module from PyPI: the venv python of bpy VERSION imports bpy and runs the script,
with DDOF_BLENDER_HOST=bpy so that the script installs the add-on as the extension package
(Blender's own extension tooling) instead of importing it from the source tree.

    python3 run_bpy.py VERSION tests/blender/test_X.py

The venvs are made by scripts/bpy_venv.sh (bash scripts/test.sh runs it) under $DDOF_BPY_CACHE
(default ~/.cache/ddof-bpy): venv-VERSION, or venv-VERSION.reason saying why there is none (no
wheel for this Python, no network). Without the venv this exits 77, which ctest reports as a
skip, printing the reason.
"""

import os
import shutil
import subprocess
import sys

SKIP = 77


def cache_dir():
    return os.environ.get("DDOF_BPY_CACHE") or os.path.join(os.path.expanduser("~"), ".cache",
                                                            "ddof-bpy")


def main(argv):
    if len(argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    version, script = argv
    venv = os.path.join(cache_dir(), "venv-" + version)
    python = os.path.join(venv, "bin", "python")
    if not os.path.isfile(os.path.join(venv, "ok")) or not os.path.isfile(python):
        reason_file = venv + ".reason"
        reason = "bpy %s is not installed in %s (bash scripts/test.sh or scripts/bpy_venv.sh " \
                 "%s installs it)" % (version, venv, version)
        if os.path.isfile(reason_file):
            with open(reason_file, encoding="utf-8") as f:
                reason = f.read().strip()
        print("skipped: " + reason)
        return SKIP
    env = dict(os.environ)
    env["DDOF_BLENDER_HOST"] = "bpy"
    # A user resources folder of the test's own (extensions, preferences), as
    # --factory-startup gives the executable a clean slate.
    scratch = env.get("DDOF_TEST_SCRATCH") or os.path.join(cache_dir(), "scratch")
    resources = os.path.join(scratch, "user_resources")
    shutil.rmtree(resources, ignore_errors=True)
    os.makedirs(resources)
    env["BLENDER_USER_RESOURCES"] = resources
    proc = subprocess.run([python, script], env=env)
    return proc.returncode


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
