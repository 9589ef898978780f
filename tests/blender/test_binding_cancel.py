# SPDX-License-Identifier: GPL-3.0-or-later
"""The add-on's binding, from a plain python3 with the built library: the cancel function is
the library's progress callback (through ctypes): called with growing fractions, a True answer
stops the call with Cancelled (DDOF_ERROR_CANCELLED), as does a callback that raises; a
function that never cancels changes nothing in the result.

    python3 test_binding_cancel.py LIBRARY
"""

import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "blender_addon", "diffusion_dof"))
import binding  # noqa: E402
import ddof_abi  # noqa: E402

failures = []


def check(ok, message):
    if not ok:
        failures.append(message)
        print("FAIL:", message)


lib = binding.Library(sys.argv[1])
w, h = 96, 64
color = binding.new_buffer(w * h * 4)
depth = binding.new_buffer(w * h)
for i in range(w * h):
    color[4 * i:4 * i + 4] = binding.array.array("f", [(i % 7) / 7.0, (i % 5) / 5.0, 0.5, 1.0])
    depth[i] = 2.0 + 20.0 * ((i // w) / h)
camera = {"focal_length_mm": 85.0, "fstop": 1.4, "focus_distance_m": 2.0}

plain, stats = lib.depth_of_field(w, h, color, 4, depth, 1, camera)
check(stats["max_coc_px"] > 5, "no blur: %r" % stats["max_coc_px"])
seen = []
watched, _ = lib.depth_of_field(w, h, color, 4, depth, 1, camera,
                                cancel=lambda f: seen.append(f) and False)
check(len(seen) >= 2 and seen == sorted(seen) and 0.0 <= seen[0] and seen[-1] <= 1.0,
      "progress fractions %r" % seen[:10])
check(watched == plain, "a cancel function that never cancels changed the result")
print("progress: %d calls, %.3f .. %.3f" % (len(seen), seen[0] if seen else -1,
                                            seen[-1] if seen else -1))
for name, fn in (("at once", lambda f: True), ("half way", lambda f: f >= 0.5),
                 ("raising", lambda f: 1 / 0)):
    try:
        lib.depth_of_field(w, h, color, 4, depth, 1, camera, cancel=fn)
        check(False, "cancel %s: the call finished" % name)
    except binding.Cancelled as err:
        check(err.status == ddof_abi.DDOF_ERROR_CANCELLED and "cancelled" in str(err),
              "cancel %s: %s" % (name, err))
# The foreground path (two library calls) is cancelled too.
fg = {"color": binding.new_buffer(w * h * 4), "depth": binding.new_buffer(w * h)}
for i in range(w * h):
    fg["depth"][i] = 1.0
try:
    lib.depth_of_field(w, h, color, 4, depth, 1, camera, foreground=fg, cancel=lambda f: True)
    check(False, "foreground call not cancelled")
except binding.Cancelled:
    pass
print("test_binding_cancel: %d failures" % len(failures))
sys.exit(1 if failures else 0)
