# SPDX-License-Identifier: MIT
"""ctest `study_node_rules`: study/scenes/node_rules.py, the per-version setup of Blender's
Defocus node (the f-stop rule, the node's name, blur_max), against values worked by hand.
System python3 + numpy (exit 77 without numpy)."""

import math
import os
import sys

try:
    import numpy as np
except ImportError:
    print("skipped: no numpy for %s" % sys.executable)
    sys.exit(77)

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
sys.path.insert(0, os.path.join(ROOT, "study", "scenes"))
import node_rules  # noqa: E402

CAM = {"focal_length_mm": 85.0, "sensor_width_mm": 36.0, "fstop": 1.4, "focus_distance_m": 3.0}
failures = []


def check(name, got, want, tol=1e-9):
    if not (abs(got - want) <= tol * max(1.0, abs(want))):
        failures.append("%s: got %r, want %r" % (name, got, want))


# 3.x: N * 1000 / sensor_mm (docs/design.md section 1): 1.4 * 1000 / 36 = 38.888...
f, rule = node_rules.node_fstop(CAM, 1.0, (3, 4, 1))
check("3.4 f-stop", f, 1.4 * 1000.0 / 36.0)
assert "1000" in rule, rule
# 4.2 and 5.0: N * S1 / (S1 - f) = 1.4 * 3 / 2.915 = 1.440823...
for version in ((4, 2, 23), (5, 0, 1)):
    f, rule = node_rules.node_fstop(CAM, 1.0, version)
    check("%s f-stop" % (version,), f, 1.4 * 3.0 / (3.0 - 0.085))
    assert "S1" in rule, rule
    check("%s f-stop x2" % (version,), node_rules.node_fstop(CAM, 2.0, version)[0],
          2 * 1.4 * 3.0 / 2.915)
try:
    node_rules.node_fstop(dict(CAM, focus_distance_m=0.05), 1.0, (4, 2, 0))
    failures.append("focus inside the focal length: no error")
except ValueError:
    pass

# The names ddof-study reads (study_node_names in study/configs.c).
for version, tag in (((3, 4, 1), "defocus"), ((4, 2, 23), "defocus-4.2"),
                     ((5, 0, 1), "defocus-5.0"), ((5, 3, 0), "defocus-5.3")):
    if node_rules.node_tag(version) != tag:
        failures.append("node_tag(%s) = %r, want %r" % (version, node_rules.node_tag(version), tag))

# Cycles' CoC radius at 480 px across 36 mm: f^2/(N S1) |Z - S1| / Z * 480 / 0.036 / 2.
depth = np.array([[1.5, 3.0], [np.inf, 0.0]], dtype=np.float32)  # inf and 0 are ignored
k = 0.085 ** 2 / (1.4 * 3.0) * 480 / 0.036 / 2
check("max CoC radius", node_rules.max_coc_radius_px(CAM, depth, 480), k * 1.5 / 1.5, 1e-6)
depth = np.array([[30.0, 3.0]], dtype=np.float32)
check("max CoC radius (far)", node_rules.max_coc_radius_px(CAM, depth, 480), k * 27 / 30, 1e-6)
check("no depth", node_rules.max_coc_radius_px(CAM, np.zeros((2, 2), np.float32), 480), 0.0)

if failures:
    print("\n".join(failures))
    sys.exit(1)
print("node_rules: all checks passed (f-stop rules, names, CoC radius)")
