# SPDX-License-Identifier: GPL-3.0-or-later
"""The add-on's bpy-free focus tools from a plain python3: the focal-plane view's bytes (the
library's ddof_focus_map, checked in tests/test_focus_map.c and through the binding in
check_abi.py) turned into a Blender image's floats and pasted into a frame, and the picker's
pixel and depth look-ups."""

import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "blender_addon", "diffusion_dof"))
import focus_map as fm  # noqa: E402

failures = []


def check(ok, message):
    if not ok:
        failures.append(message)
        print("FAIL:", message)


# Two pixels of RGB bytes: floats of bytes / 255, alpha 1.
rgba = fm.rgba_of(bytearray([0, 255, 51, 255, 128, 0]), 2, 1)
check(len(rgba) == 8 and rgba.dtype.name == "float32", "rgba %r" % (rgba,))
want = [0.0, 1.0, 51 / 255, 1.0, 1.0, 128 / 255, 0.0, 1.0]
check(all(abs(float(v) - w) < 1e-7 for v, w in zip(rgba, want)), "rgba values %r" % list(rgba))

# A 2x1 part pasted at (1, 1) of a 3x2 frame: only its two pixels change.
frame = bytearray(3 * 2 * 3)
fm.paste_rgb(frame, 3, 1, 1, bytearray([1, 2, 3, 4, 5, 6]), 2, 1)
check(list(frame) == [0] * 9 + [0, 0, 0, 1, 2, 3, 4, 5, 6], "pasted %r" % list(frame))

check(fm.pixel_of(0.0, 0.0, 10, 5) == (0, 0), "pixel of (0, 0)")
check(fm.pixel_of(0.999, 0.5, 10, 5) == (9, 2), "pixel of (0.999, 0.5)")
check(fm.pixel_of(1.0, 0.5, 10, 5) is None and fm.pixel_of(-0.1, 0.5, 10, 5) is None,
      "outside the image")
depth = [1.0, 2.0, float("inf"), 1e10, 3.0, 4.0]  # 3x2, one channel
check(fm.depth_at(depth, 3, 2, 1, 1, 0) == 2.0, "depth at (1, 0)")
check(fm.depth_at(depth, 3, 2, 1, 2, 0) is None and fm.depth_at(depth, 3, 2, 1, 0, 1) is None,
      "the sky (inf, 1e10) is no surface")
check(fm.depth_at(depth, 3, 2, 1, 3, 0) is None, "outside")
print("test_focus_map_plain: %d failures" % len(failures))
sys.exit(1 if failures else 0)
