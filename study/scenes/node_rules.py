# SPDX-License-Identifier: MIT
"""How study/scenes/defocus_node.py sets up Blender's Defocus node per Blender version, without
bpy (so that system python3 tests it: tests/study/test_node_rules.py): the f-stop that makes
the node blur as Cycles' lens, the study's name for the node, and blur_max.

`version` is bpy.app.version, a tuple (major, minor, patch).
"""

import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from exr_io import depth_of, read_exr  # noqa: E402

# Up to 4.1 the node's f-stop is a blur amount (docs/design.md section 1: 1000 / sensor_mm times
# the physical lens's). From 4.2 the node computes a thin lens's CoC itself, and the old mapping
# leaves it nearly sharp; f-stop N S1 / (S1 - f) (S1 the focus distance, f the focal length)
# is meant to match Cycles. Measured with fstop_check.py on the highlights scene (6 isolated
# lights, median blur diameter over the truth's; README.md, "Defocus node f-stop"): 5.0 at
# this rule 1.049 (x0.5 1.736, x2 0.615; PSNR 26.72 dB, the best of the scales); 4.2 at this
# rule 1.067 (x0.8 1.277, x2 0.611; 26.63 dB, the best) with blur_max auto (below); the 3.x
# mapping on either: 0.381 (nearly sharp).
RULE_BLUR_AMOUNT = "N * 1000 / sensor_width_mm * fstop_scale"
RULE_THIN_LENS = "N * S1 / (S1 - f) * fstop_scale (S1 focus distance, f focal length, m)"


def node_fstop(cam, scale, version):
    """(f-stop to give the node, the rule's text): the node of `version` blurs as Cycles' lens
    of the camera sidecar `cam` at scale 1."""
    n = float(cam["fstop"])
    if version < (4, 2, 0):
        return n * 1000.0 / float(cam["sensor_width_mm"]) * scale, RULE_BLUR_AMOUNT
    f = float(cam["focal_length_mm"]) / 1000.0
    s1 = float(cam["focus_distance_m"])
    if s1 <= f:
        raise ValueError("focus distance %g m is not beyond the focal length "
                         "%g m" % (s1, f))
    return n * s1 / (s1 - f) * scale, RULE_THIN_LENS


def max_coc_radius_px(cam, depth, width):
    """The largest CoC radius (pixels) Cycles' lens gives on the planar depth map `depth`
    (numpy), at `width` pixels across the sensor width."""
    f = float(cam["focal_length_mm"]) / 1000.0
    s1 = float(cam["focus_distance_m"])
    z = depth[np.isfinite(depth) & (depth > 0)].astype(np.float64)
    if z.size == 0:
        return 0.0
    z = np.array([z.min(), z.max()])
    coc = f * f / (float(cam["fstop"]) * s1) * np.abs(z - s1) / z
    return float(coc.max()) * width / (float(cam["sensor_width_mm"]) / 1000.0) / 2.0


def auto_blur_max(cam, source, width, scale, version):
    """blur_max for --blur-max auto: 512 px (nothing clipped) up to 4.1, whose cost does not
    grow with it; from 4.2 the scene's largest CoC radius plus 10 % and 2 px, so that nothing
    is clipped either: 5.0's CPU defocus searches blur_max pixels around every pixel (thin_bars
    480x270: 2.6 s at 16 px, 14.9 s at 64 px, not done after 10 minutes at 512), and 4.2's
    blurs wrong with a blur_max far above the CoC (thin_bars: 21.49 dB at 512, smeared
    sideways; 32.31 dB at 16)."""
    if version < (4, 2, 0):
        return 512.0
    radius = max_coc_radius_px(cam, depth_of(read_exr(source)), width) / scale
    return float(min(512, math.ceil(radius * 1.1 + 2.0)))


def node_tag(version):
    """The name the study gives this Blender's node: "defocus" for 3.x (the study's first
    baseline, Debian's Blender 3.4), "defocus-MAJOR.MINOR" from 4.0."""
    return "defocus" if version < (4, 0, 0) else "defocus-%d.%d" % version[:2]
