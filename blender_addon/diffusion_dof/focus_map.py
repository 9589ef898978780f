# SPDX-License-Identifier: GPL-3.0-or-later
"""The focal-plane view and the focus picker's arithmetic. No bpy: tested from a plain Python
(tests/blender/test_focus_tools.py).

The view is the frame in false colour by its signed CoC, the same mapping as `ddof --focus-map`
(plugin/apps/cli/focus_map.h): green where the blur is under SHARP_PX (the in-focus band), orange in
front of the focus (near blur), blue behind it (far blur), each brighter with more blur (up to
the frame's largest CoC), all shaded by the picture's luminance.
"""

import array
import math

SHARP_PX = 1.0
SHARP = (0.15, 1.0, 0.2)
NEAR = (1.0, 0.45, 0.1)
FAR = (0.2, 0.45, 1.0)


def _byte(v):
    return int(min(max(v, 0.0), 1.0) * 255.0 + 0.5)


def focus_map_bytes(coc, rgb, channels, width, height):
    """The map as 8-bit RGB (a list of width * height * 3 ints), byte for byte the command's:
    coc signed (width * height), rgb `channels` >= 3 interleaved linear floats."""
    count = width * height
    largest = max((abs(c) for c in coc if math.isfinite(c)), default=0.0)
    span = largest - SHARP_PX
    out = [0] * (count * 3)
    for i in range(count):
        k = i * channels
        y = min(max(0.2126 * rgb[k] + 0.7152 * rgb[k + 1] + 0.0722 * rgb[k + 2], 0.0), 1.0)
        shade = 0.35 + 0.65 * math.sqrt(y)
        c = coc[i]
        a = abs(c)
        if a < SHARP_PX:
            hue, v = SHARP, 1.0
        else:
            t = min((a - SHARP_PX) / span, 1.0) if span > 0.0 else 1.0
            hue, v = (NEAR if c < 0.0 else FAR), 0.35 + 0.65 * t
        out[3 * i] = _byte(hue[0] * v * shade)
        out[3 * i + 1] = _byte(hue[1] * v * shade)
        out[3 * i + 2] = _byte(hue[2] * v * shade)
    return out


def _in_aperture(camera, x, y):
    """Whether the legend's point (x, y) (y down, the shape's unit radius at height 1) lies in
    the camera's aperture, as a light behind the focus draws it."""
    ax, ay = x * camera.get("aperture_ratio", 1.0), -y
    blades = camera.get("aperture_blades", 0)
    if blades < 3:
        return ax * ax + ay * ay <= 1.0
    rotation = camera.get("aperture_rotation_deg", 0.0) * (math.pi / 180.0)
    far = max(ax * math.cos(rotation + 2.0 * math.pi * k / blades) +
              ay * math.sin(rotation + 2.0 * math.pi * k / blades) for k in range(blades))
    return far <= math.cos(math.pi / blades)


def aperture_legend(camera, width, height):
    """The camera's aperture as the map's legend, as `ddof --focus-map` draws it
    (plugin/apps/cli/focus_map.c): {pixel index: 0 or 255} over a square of min(64, the smaller
    side / 4) pixels 2 from the top and right edges, white inside the shape; {} for a round
    aperture (blades < 3, ratio 1) or a map under 48 pixels a side."""
    ratio = camera.get("aperture_ratio", 1.0)
    if camera.get("aperture_blades", 0) < 3 and ratio == 1.0:
        return {}
    s = min(64, min(width, height) // 4)
    if s < 12:
        return {}
    x0, y0, half = width - s - 2, 2, 0.5 * s
    scale = half - 1.0
    extent = 1.0 / ratio if ratio < 1.0 else 1.0
    legend = {}
    for y in range(y0, y0 + s):
        for x in range(x0, x0 + s):
            u = (x + 0.5 - (x0 + half)) / scale * extent
            v = (y + 0.5 - (y0 + half)) / scale * extent
            legend[y * width + x] = 255 if _in_aperture(camera, u, v) else 0
    return legend


def focus_map_rgba(coc, rgb, channels, width, height, camera=None):
    """The map as RGBA floats (bytes / 255, alpha 1), for a Blender image; with the camera's
    aperture as its legend when a camera is given."""
    b = focus_map_bytes(coc, rgb, channels, width, height)
    for i, value in (aperture_legend(camera, width, height) if camera else {}).items():
        b[3 * i:3 * i + 3] = [value, value, value]
    out = array.array("f", [1.0]) * (width * height * 4)
    for i in range(width * height):
        out[4 * i:4 * i + 3] = array.array("f", (b[3 * i] / 255.0, b[3 * i + 1] / 255.0,
                                                  b[3 * i + 2] / 255.0))
    return out


def band_counts(coc):
    """(in focus, near, far) pixel counts, for the report."""
    sharp = sum(1 for c in coc if abs(c) < SHARP_PX)
    near = sum(1 for c in coc if c <= -SHARP_PX)
    return sharp, near, len(coc) - sharp - near


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
