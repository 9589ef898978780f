# SPDX-License-Identifier: GPL-3.0-or-later
"""Shared by the add-on's tests, with Blender or without (imported, not a test itself): the
add-on's folder, from which the bpy-free modules import as plain modules, and the checks'
record."""

import os
import sys

ADDON_PACKAGE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                             "blender_addon", "diffusion_dof")


def import_from_addon():
    """Makes the add-on's bpy-free modules importable as plain modules (binding, ddof_abi, ...)."""
    if ADDON_PACKAGE not in sys.path:
        sys.path.insert(0, ADDON_PACKAGE)


class Checks:
    """Collects failures; finish() prints them and exits non-zero if any."""

    def __init__(self, name):
        self.name = name
        self.failures = []
        self.count = 0

    def check(self, ok, message):
        self.count += 1
        if not ok:
            self.failures.append(message)
            print("FAIL: %s" % message, flush=True)
        return ok

    def finish(self):
        print("%s: %d checks, %d failures" % (self.name, self.count, len(self.failures)),
              flush=True)
        if self.failures:
            sys.exit(1)
