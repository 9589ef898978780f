# SPDX-License-Identifier: GPL-3.0-or-later
"""The add-on's bpy-free overscan helpers, from a plain python3: the Auto margin (the CoC at
infinity, capped), the grown sensor along the axis Blender fits, the shift that keeps the frame
in place, and the window the library gets."""

import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "blender_addon", "diffusion_dof"))
import overscan as ov  # noqa: E402

failures = []


def check(ok, message):
    if not ok:
        failures.append(message)
        print("FAIL:", message)


def close(a, b, tol=1e-9):
    return abs(a - b) <= tol * max(1.0, abs(b))


# 100 mm f/1.4 focused at 2 m: f^2 / (N (s - f)) = 10000 / (1.4 * 1900) = 3.7594 mm.
coc = ov.coc_infinity_mm(100.0, 1.4, 2.0)
check(close(coc, 10000.0 / (1.4 * 1900.0)), "CoC at infinity %r" % coc)
# The same CoC at half the focus distance (planar focus): A f |z - s| / (z (s - f)).
half = (100.0 / 1.4) * 100.0 * 1000.0 / (1000.0 * 1900.0)
check(close(coc, half), "CoC at s/2 %r != %r" % (half, coc))
check(ov.coc_infinity_mm(100.0, 1.4, 0.05) == 0.0, "focus within the focal length: no margin")
check(close(ov.coc_infinity_mm(100.0, 1.4, 2.0, thin_lens=True), coc * 2000.0 / 1900.0),
      "thin lens: larger by S1 / (S1 - f)")

# 160x90 on a 36 mm sensor (Auto fit: horizontal): 0.225 mm pixels; radius 8.35 px -> 9 + 1.
p = ov.plan(160, 90, "AUTO", 36.0, 100.0, 1.4, 2.0)
check(p is not None and (p.margin_x, p.margin_y) == (10, 10),
      "auto margin %r" % ((p.margin_x, p.margin_y) if p else None,))
check(p.fit == "HORIZONTAL" and close(p.sensor_mm, 36.0 * 180.0 / 160.0),
      "grown sensor %s %r" % (p.fit, p.sensor_mm))
check((p.full_width, p.full_height) == (180, 110), "grown size %r" % ((p.full_width,
                                                                        p.full_height),))
check(close(p.sensor_mm / p.full_width, 36.0 / 160.0), "pixel pitch kept")
check(close(p.shift(0.1), 0.1 * 160.0 / 180.0), "shift scaled %r" % p.shift(0.1))
check(p.camera_fields() == {"frame_width": 160, "frame_height": 90, "window_x": -10,
                            "window_y": -10}, "window %r" % p.camera_fields())
check(close(p.extra_pixels(), 180.0 * 110.0 / (160.0 * 90.0) - 1.0), "cost")
check("+38% pixels" in p.describe(), p.describe())

# A portrait frame with Auto fit spans its height: the sensor grows with the height.
p = ov.plan(90, 160, "AUTO", 36.0, 100.0, 1.4, 2.0)
check(p.fit == "VERTICAL" and close(p.sensor_mm, 36.0 * 180.0 / 160.0)
      and (p.margin_x, p.margin_y) == (10, 10), "portrait %s %r" % (p.fit, p.sensor_mm))
# Vertical fit on a landscape frame: pitch from the height (36 / 90 = 0.4 mm): 4.7 -> 5 + 1.
p = ov.plan(160, 90, "VERTICAL", 36.0, 100.0, 1.4, 2.0)
check(p.fit == "VERTICAL" and (p.margin_x, p.margin_y) == (6, 6)
      and close(p.sensor_mm, 36.0 * 102.0 / 90.0), "vertical fit %s %r %r"
      % (p.fit, (p.margin_x, p.margin_y), p.sensor_mm))
# Pixels twice as wide as tall (the width still spans the sensor: 0.225 mm wide, 0.1125 mm
# tall): twice the pixels in y for the same distance on the sensor.
p = ov.plan(160, 90, "HORIZONTAL", 36.0, 100.0, 1.4, 2.0, aspect_x=2.0, aspect_y=1.0)
check((p.margin_x, p.margin_y) == (10, 18), "pixel aspect 2 %r" % ((p.margin_x, p.margin_y),))
check(ov.effective_fit("AUTO", 100, 100, 1.0, 2.0) == "VERTICAL", "aspect decides Auto fit")

# A macro focus: the CoC is huge, the margin is capped at an eighth of the larger side.
p = ov.plan(1920, 1080, "AUTO", 36.0, 100.0, 1.4, 0.2)
check((p.margin_x, p.margin_y) == (240, 240), "capped %r" % ((p.margin_x, p.margin_y),))
# Manual: the margin as given along x, the same distance along y.
p = ov.plan(160, 90, "AUTO", 36.0, 100.0, 1.4, 2.0, manual=16)
check((p.margin_x, p.margin_y) == (16, 16), "manual %r" % ((p.margin_x, p.margin_y),))
check(ov.plan(160, 90, "AUTO", 36.0, 100.0, 1.4, 2.0, manual=0) is None, "manual 0: none")
check(ov.plan(160, 90, "AUTO", 36.0, 100.0, 0.0, 2.0) is None, "f/0: none")

print("test_overscan_plain: %d failures" % len(failures))
sys.exit(1 if failures else 0)
