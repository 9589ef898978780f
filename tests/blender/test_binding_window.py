# SPDX-License-Identifier: GPL-3.0-or-later
"""The add-on's binding, from a plain python3 with the built library: a window of full-size
buffers (a render border without crop) goes to the library through its row stride, and the
result is bit for bit the one of the window's pixels copied out, run tightly packed and copied
back, with and without a foreground element, and with an object matte (its pixels read through
the same window: a NaN coverage inside the window is refused, one outside it is not read);
outside the window the frame is left as it was. A window outside its frame is refused.

    python3 test_binding_window.py LIBRARY
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plain_checks  # noqa: E402

plain_checks.import_from_addon()
import binding  # noqa: E402

checks = plain_checks.Checks("test_binding_window")
check = checks.check


def crop(buf, width, channels, x, y, w, h):
    out = binding.array.array("f")
    for row in range(y, y + h):
        start = (row * width + x) * channels
        out.extend(buf[start:start + w * channels])
    return out


def paste(dst, width, channels, x, y, w, h, src):
    for row in range(h):
        start = ((y + row) * width + x) * channels
        dst[start:start + w * channels] = src[row * w * channels:(row + 1) * w * channels]


W, H = 80, 48
X, Y, WW, WH = 13, 9, 41, 27  # the window
lib = binding.Library(sys.argv[1])
color = binding.new_buffer(W * H * 4)
depth = binding.new_buffer(W * H)
fg_color = binding.new_buffer(W * H * 4)
fg_depth = binding.new_buffer(W * H)
for i in range(W * H):
    x, y = i % W, i // W
    color[4 * i:4 * i + 4] = binding.array.array(
        "f", [((x * 7 + y * 3) % 11) / 5.0, (x % 5) / 5.0, 0.5, 1.0])
    depth[i] = 1.5 + ((x // 8 + y // 6) % 4) * 3.0
    covered = 30 <= x < 40 and 15 <= y < 25
    fg_color[4 * i:4 * i + 4] = binding.array.array("f", [0.9, 0.8, 0.2, 1.0] if covered
                                                    else [0.0] * 4)
    fg_depth[i] = 0.6 if covered else 1e10
camera = {"focal_length_mm": 85.0, "fstop": 1.4, "focus_distance_m": 3.0, "frame_width": W,
          "frame_height": H, "window_x": X, "window_y": Y}
foreground = {"color": fg_color, "depth": fg_depth, "depth_channels": 1}
# An object matte of 2 ranks: each depth block an object (its id's bits from its number),
# fully covering its pixels; in-focus blocks beside far ones make the silhouettes' split run.
matte = binding.new_buffer(W * H * 4)
for i in range(W * H):
    block = (i % W) // 8 + 16 * ((i // W) // 6)
    matte[4 * i:4 * i + 4] = binding.array.array("f", [1.0 + block / 64.0, 1.0, 0.0, 0.0])

with lib.session(threads=2) as session:
    for name, fg, mt in (("plain", None, None), ("foreground", foreground, None),
                         ("matte", None, matte)):
        part_matte = None if mt is None else (crop(mt, W, 4, X, Y, WW, WH), 4)
        part_fg = None if fg is None else {
            "color": crop(fg["color"], W, 4, X, Y, WW, WH),
            "depth": crop(fg["depth"], W, 1, X, Y, WW, WH), "depth_channels": 1}
        packed, stats = session.depth_of_field(
            WW, WH, crop(color, W, 4, X, Y, WW, WH), 4, crop(depth, W, 1, X, Y, WW, WH), 1,
            camera, {"substeps": 2}, foreground=part_fg, matte=part_matte)
        want = binding.array.array("f", color)
        paste(want, W, 4, X, Y, WW, WH, packed)
        got, got_stats = session.depth_of_field(WW, WH, color, 4, depth, 1, camera,
                                                {"substeps": 2}, foreground=fg,
                                                window=(X, Y, W, H),
                                                matte=None if mt is None else (mt, 4))
        differ = sum(1 for a, b in zip(got, want) if a != b)
        check(len(got) == len(want) and differ == 0, "%s: %d of %d values differ from the "
              "window copied out and back" % (name, differ, len(want)))
        check(got_stats["max_coc_px"] == stats["max_coc_px"] and packed != crop(
            color, W, 4, X, Y, WW, WH), "%s: the window was not blurred as the copy" % name)
        outside = [i for i in range(W * H)
                   if not (X <= i % W < X + WW and Y <= i // W < Y + WH)]
        check(all(got[4 * i:4 * i + 4] == color[4 * i:4 * i + 4] for i in outside),
              "%s: pixels outside the window changed" % name)
        if mt is not None:
            check(stats["matte_ranks"] == 2 and got_stats["matte_ranks"] == 2,
                  "matte: the library was not given the matte's 2 ranks")
    for name, (x, y), refused in (("inside", (X + 3, Y + 2), True),
                                  ("outside", (X - 1, Y), False)):
        bad = binding.array.array("f", matte)
        bad[4 * (y * W + x) + 1] = float("nan")
        try:
            session.depth_of_field(WW, WH, color, 4, depth, 1, camera, window=(X, Y, W, H),
                                   matte=(bad, 4))
            check(not refused, "a NaN coverage %s the window was accepted" % name)
        except binding.DdofError as err:
            check(refused, "a NaN coverage %s the window was read: %s" % (name, err))
    try:
        session.depth_of_field(WW, WH, color, 4, depth, 1, camera, window=(X + WW, Y, W, H))
        check(False, "a window outside its frame was accepted")
    except ValueError as err:
        check("outside" in str(err), "window message: %s" % err)
checks.finish()
