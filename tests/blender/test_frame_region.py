# SPDX-License-Identifier: GPL-3.0-or-later
"""The add-on's bpy-free frame_region helpers, from a plain python3: Blender's border rectangle
(float products, truncated), which image size means crop or no crop, and crop/paste."""

import array
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "blender_addon", "diffusion_dof"))
import frame_region as fr  # noqa: E402

failures = []


def check(ok, message):
    if not ok:
        failures.append(message)
        print("FAIL:", message)


check(fr.full_size(1920, 1080, 50) == (960, 540), "50%% of 1080p")
check(fr.full_size(481, 271, 33) == (158, 89), "integer percent")
check(fr.border_rect((0.2, 0.25, 0.7, 0.8), 160, 90) == (32, 22, 80, 50),
      "border rect %r" % (fr.border_rect((0.2, 0.25, 0.7, 0.8), 160, 90),))
# 0.7 as a C float is 0.699999988; times 10 in float rounds to 7.0 (a double product gives
# 6.99999988 and would truncate to 6): the float product is Blender's.
check(fr.border_rect((0.0, 0.0, 0.7, 1.0), 10, 10) == (0, 0, 7, 10),
      "float product: %r" % (fr.border_rect((0.0, 0.0, 0.7, 1.0), 10, 10),))
check(fr.region_of(False, False, (0.2, 0.2, 0.8, 0.8), (100, 50), (100, 50)) is None,
      "no border")
check(fr.region_of(True, True, (0.0, 0.0, 1.0, 1.0), (100, 50), (100, 50)) is None,
      "a border that is the frame")
r = fr.region_of(True, False, (0.2, 0.2, 0.8, 0.8), (100, 50), (100, 50))
check(r is not None and not r.cropped and (r.x, r.y, r.width, r.height) == (20, 10, 60, 30),
      "no crop region")
check(r.camera_fields() == {"frame_width": 100, "frame_height": 50, "window_x": 20,
                            "window_y": 10}, "camera fields %r" % r.camera_fields())
r = fr.region_of(True, True, (0.2, 0.2, 0.8, 0.8), (100, 50), (60, 30))
check(r is not None and r.cropped, "crop region")
try:
    fr.region_of(True, True, (0.2, 0.2, 0.8, 0.8), (100, 50), (61, 30))
    check(False, "a size that is neither the frame's nor the border's was accepted")
except ValueError as err:
    check("61x30" in str(err) and "60x30" in str(err), "size message: %s" % err)

w, h, ch = 7, 5, 2
buf = array.array("f", range(w * h * ch))
part = fr.crop(buf, w, ch, 2, 1, 3, 2)
check(list(part) == [18, 19, 20, 21, 22, 23, 32, 33, 34, 35, 36, 37], "crop %r" % list(part))
dst = array.array("f", [0.0]) * (w * h * ch)
fr.paste(dst, w, ch, 2, 1, 3, 2, part)
check(sum(1 for a, b in zip(dst, buf) if a == b and a != 0) == 12 and sum(dst) == sum(part),
      "paste")
print("test_frame_region: %d failures" % len(failures))
sys.exit(1 if failures else 0)
