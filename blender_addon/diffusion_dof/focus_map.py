# SPDX-License-Identifier: GPL-3.0-or-later
"""The focal-plane view and the focus picker's arithmetic. No bpy: tested from a plain Python
(tests/blender/test_focus_tools.py).

The view is the frame in false colour by its signed CoC, the same mapping as `ddof --focus-map`
(plugin/apps/cli/focus_map.h): green where the blur is under SHARP_PX (the in-focus band), orange in
front of the focus (near blur), blue behind it (far blur), each brighter with more blur (up to
the frame's largest CoC), all shaded by the picture's luminance.
"""

import math

import numpy as np

SHARP_PX = 1.0
SHARP = (0.15, 1.0, 0.2)
NEAR = (1.0, 0.45, 0.1)
FAR = (0.2, 0.45, 1.0)


def _bytes(values):
    """Values in [0, 1] as bytes, rounded as the command rounds them (int(v * 255 + 0.5))."""
    return (np.clip(values, 0.0, 1.0) * 255.0 + 0.5).astype(np.int64)


def _map_bytes(coc, rgb, channels, width, height):
    """The map as a (width * height, 3) array of bytes (see focus_map_bytes)."""
    count = width * height
    coc = np.asarray(coc, dtype=np.float64)[:count]
    rgb = np.asarray(rgb, dtype=np.float64)[:count * channels].reshape(count, channels)
    a = np.abs(coc)
    finite = a[np.isfinite(a)]
    largest = float(finite.max()) if finite.size else 0.0
    span = largest - SHARP_PX
    y = np.clip(0.2126 * rgb[:, 0] + 0.7152 * rgb[:, 1] + 0.0722 * rgb[:, 2], 0.0, 1.0)
    shade = 0.35 + 0.65 * np.sqrt(y)
    t = np.minimum((a - SHARP_PX) / span, 1.0) if span > 0.0 else np.ones(count)
    sharp = a < SHARP_PX
    v = np.where(sharp, 1.0, 0.35 + 0.65 * t)
    hue = np.where((coc < 0.0)[:, None], NEAR, FAR)
    hue[sharp] = SHARP
    return _bytes(hue * v[:, None] * shade[:, None])


def focus_map_bytes(coc, rgb, channels, width, height):
    """The map as 8-bit RGB (a list of width * height * 3 ints), byte for byte the command's:
    coc signed (width * height), rgb `channels` >= 3 interleaved linear floats."""
    return _map_bytes(coc, rgb, channels, width, height).ravel().tolist()


def _legend_square(camera, width, height):
    """(x0, y0, s, inside): the legend's square of s pixels at (x0, y0) (y down) and whether
    each of its pixels lies in the camera's aperture, an s x s boolean array; None when there is
    no legend (see aperture_legend)."""
    ratio = camera.get("aperture_ratio", 1.0)
    blades = camera.get("aperture_blades", 0)
    if blades < 3 and ratio == 1.0:
        return None
    s = min(64, min(width, height) // 4)
    if s < 12:
        return None
    x0, y0, half = width - s - 2, 2, 0.5 * s
    scale = half - 1.0
    extent = 1.0 / ratio if ratio < 1.0 else 1.0
    steps = np.arange(s, dtype=np.float64)
    u = (x0 + steps + 0.5 - (x0 + half)) / scale * extent
    v = (y0 + steps + 0.5 - (y0 + half)) / scale * extent
    # As a light behind the focus draws it: the shape's unit radius at height 1, y up.
    ax, ay = u[None, :] * ratio, -v[:, None]
    if blades < 3:
        return x0, y0, s, ax * ax + ay * ay <= 1.0
    rotation = camera.get("aperture_rotation_deg", 0.0) * (math.pi / 180.0)
    far = np.max([ax * math.cos(rotation + 2.0 * math.pi * k / blades) +
                  ay * math.sin(rotation + 2.0 * math.pi * k / blades)
                  for k in range(blades)], axis=0)
    return x0, y0, s, far <= math.cos(math.pi / blades)


def aperture_legend(camera, width, height):
    """The camera's aperture as the map's legend, as `ddof --focus-map` draws it
    (plugin/apps/cli/focus_map.c): {pixel index: 0 or 255} over a square of min(64, the smaller
    side / 4) pixels 2 from the top and right edges, white inside the shape; {} for a round
    aperture (blades < 3, ratio 1) or a map under 48 pixels a side."""
    square = _legend_square(camera, width, height)
    if square is None:
        return {}
    x0, y0, s, inside = square
    rows, columns = np.mgrid[y0:y0 + s, x0:x0 + s]
    return dict(zip((rows * width + columns).ravel().tolist(),
                    np.where(inside, 255, 0).ravel().tolist()))


def draw_legend(rgba, camera, width, height):
    """Draws the camera's aperture legend (aperture_legend) into an RGBA float map in place: the
    square's pixels white (1) inside the shape, black outside, alpha 1."""
    square = _legend_square(camera, width, height)
    if square is None:
        return
    x0, y0, s, inside = square
    block = np.frombuffer(rgba, dtype=np.float32).reshape(-1, width, 4)[y0:y0 + s, x0:x0 + s]
    block[:, :, :3] = np.where(inside, 1.0, 0.0)[:, :, None]
    block[:, :, 3] = 1.0


def focus_map_rgba(coc, rgb, channels, width, height, camera=None):
    """The map as RGBA floats (bytes / 255, alpha 1; a float32 array), for a Blender image;
    with the camera's aperture as its legend when a camera is given."""
    out = np.ones((width * height, 4), dtype=np.float32)
    out[:, :3] = _map_bytes(coc, rgb, channels, width, height) / 255.0
    out = out.ravel()
    if camera:
        draw_legend(out, camera, width, height)
    return out


def band_counts(coc):
    """(in focus, near, far) pixel counts, for the report."""
    coc = np.asarray(coc, dtype=np.float64)
    sharp = int(np.count_nonzero(np.abs(coc) < SHARP_PX))
    near = int(np.count_nonzero(coc <= -SHARP_PX))
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
