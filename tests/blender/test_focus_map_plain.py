# SPDX-License-Identifier: GPL-3.0-or-later
"""The add-on's bpy-free focus tools from a plain python3: the focal-plane view's colours (the
mapping `ddof --focus-map` uses, plugin/apps/cli/focus_map.h) on hand-computed pixels, and the
picker's pixel and depth look-ups."""

import math
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


def byte(v):
    return int(min(max(v, 0.0), 1.0) * 255.0 + 0.5)


# Four pixels: in focus, near at the largest blur, far at half of it, and far on black.
coc = [0.5, -9.0, 5.0, 9.0]
rgb = [1.0, 1.0, 1.0, 0.25, 0.25, 0.25, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0]
out = fm.focus_map_bytes(coc, rgb, 3, 4, 1)
shade_q = 0.35 + 0.65 * math.sqrt(0.25)
want = [byte(0.15), 255, byte(0.2),
        byte(1.0 * shade_q), byte(0.45 * shade_q), byte(0.1 * shade_q),
        byte(0.2 * (0.35 + 0.65 * 0.5)), byte(0.45 * (0.35 + 0.65 * 0.5)),
        byte(1.0 * (0.35 + 0.65 * 0.5)),
        byte(0.2 * 0.35), byte(0.45 * 0.35), byte(1.0 * 0.35)]
check(out == want, "focus map bytes %r, want %r" % (out, want))
check(fm.band_counts(coc) == (1, 1, 2), "bands %r" % (fm.band_counts(coc),))
check(fm.focus_map_bytes([0.0, 0.2], [0.5] * 6, 3, 2, 1)[1] > 200, "all in focus: green")
rgba = fm.focus_map_rgba(coc, rgb, 3, 4, 1)
check(len(rgba) == 16 and rgba[3] == 1.0 and abs(rgba[1] - 1.0) < 1e-6, "rgba %r" % list(rgba))

# A non-round aperture is the legend: the same white counts as `ddof --focus-map`'s
# (tests/exr/test_cli_results.c, case focus_map), white in the middle, black in the square's corner.
for cam, w, h, white in (({"aperture_blades": 6, "aperture_rotation_deg": 15.0}, 200, 120, 514),
                         ({"aperture_ratio": 2.0}, 200, 120, 312),
                         ({"aperture_blades": 5, "aperture_ratio": 0.5}, 320, 240, 990),
                         ({"aperture_blades": 0, "aperture_ratio": 1.0}, 200, 120, 0),
                         ({"aperture_blades": 6}, 47, 200, 0)):
    legend = fm.aperture_legend(cam, w, h)
    count = sum(1 for v in legend.values() if v == 255)
    check(count == white, "legend of %r: %d white pixels, want %d" % (cam, count, white))
    if white:
        s = min(64, min(w, h) // 4)
        middle = (2 + s // 2) * w + (w - 2 - s // 2)
        corner = 2 * w + (w - 3)
        check(legend[middle] == 255 and legend[corner] == 0, "legend of %r: middle %r, corner %r"
              % (cam, legend[middle], legend[corner]))
rgba = fm.focus_map_rgba([5.0] * (200 * 120), [0.5] * (200 * 120 * 3), 3, 200, 120,
                         {"aperture_blades": 6, "aperture_rotation_deg": 15.0})
check(rgba[4 * ((2 + 15) * 200 + (200 - 2 - 15))] == 1.0, "the legend is in the map")

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
