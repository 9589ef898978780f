# SPDX-License-Identifier: GPL-3.0-or-later
"""The focal-plane view's pixels for a Blender image, and the focus picker's arithmetic. No bpy:
tested from a plain Python (tests/blender/test_focus_map_plain.py).

The view itself (the frame in false colour by its signed CoC, with the aperture's legend) is the
library's ddof_focus_map, the one `ddof --focus-map` draws too (binding.Library.focus_map); here
its bytes become the float RGBA a Blender image holds.
"""

import math

import numpy as np


def rgba_of(rgb, width, height):
    """The view's 8-bit RGB (width * height * 3 bytes) as RGBA floats (bytes / 255, alpha 1; a
    float32 array), for a Blender image."""
    out = np.ones((width * height, 4), dtype=np.float32)
    out[:, :3] = np.frombuffer(bytes(rgb), dtype=np.uint8).reshape(-1, 3)[:width * height] / 255.0
    return out.ravel()


def paste_rgb(frame, width, x, y, part, part_width, part_height):
    """Writes the RGB bytes of a part_width x part_height view at (x, y) of a frame's RGB bytes
    `width` pixels wide (a bytearray), in place: a render border's view in the whole frame."""
    rows = np.frombuffer(frame, dtype=np.uint8).reshape(-1, width, 3)
    rows[y:y + part_height, x:x + part_width] = \
        np.frombuffer(bytes(part), dtype=np.uint8).reshape(part_height, part_width, 3)


def pixel_of(u, v, width, height):
    """The pixel (x, y) under image coordinates (u, v) in 0..1 (Blender's image editor view:
    v from the bottom, as the image's rows), or None outside the image."""
    if not (0.0 <= u < 1.0 and 0.0 <= v < 1.0):
        return None
    return min(int(u * width), width - 1), min(int(v * height), height - 1)


def depth_at(depth, width, height, channels, x, y):
    """The depth value (first channel) at pixel (x, y); None outside or for no surface (the
    sky: +inf, or Blender's 1e10 for empty pixels)."""
    if not (0 <= x < width and 0 <= y < height):
        return None
    z = depth[(y * width + x) * channels]
    if not math.isfinite(z) or z <= 0.0 or z >= 1e9:
        return None
    return z
