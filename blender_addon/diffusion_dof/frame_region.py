# SPDX-License-Identifier: GPL-3.0-or-later
"""The part of the frame a render covers (a render border, with or without crop), and moving
pixels in and out of it. No bpy: tested from a plain Python (tests/blender/test_frame_region.py).

With a border and no crop, Blender renders a full-size image that is black and transparent
outside the border: only the border's pixels are given to the library (nothing from outside
diffuses in) and the rest of the frame is left as rendered. With crop the image is the border
alone. Either way the camera is the full frame's (ddof_camera's frame_width, frame_height,
window_x, window_y), so every pixel gets the CoC it has in the uncropped frame.

Pixel rows run bottom-up in Blender images, as border_min_y counts from the bottom: the window's
row offset is counted from the bottom too, and the library sees the frame upside down, which
changes nothing it computes.
"""

import struct

import numpy as np


def _f32(value):
    """value rounded to a C float, as Blender stores the border and multiplies it."""
    return struct.unpack("f", struct.pack("f", value))[0]


def full_size(resolution_x, resolution_y, percentage):
    """The rendered frame's size in pixels, as Blender computes it (integer percent)."""
    return resolution_x * percentage // 100, resolution_y * percentage // 100


def border_rect(border, frame_width, frame_height):
    """(x, y, width, height) of the pixels a border (min_x, min_y, max_x, max_y, fractions of
    the frame, y from the bottom) renders: Blender's `border * size`, in float, truncated."""
    min_x, min_y, max_x, max_y = border
    x0 = int(_f32(_f32(min_x) * frame_width))
    x1 = int(_f32(_f32(max_x) * frame_width))
    y0 = int(_f32(_f32(min_y) * frame_height))
    y1 = int(_f32(_f32(max_y) * frame_height))
    return x0, y0, x1 - x0, y1 - y0


class Region:
    """The frame's window a render's image holds or that gets depth of field."""

    def __init__(self, frame_width, frame_height, x, y, width, height, cropped):
        self.frame_width, self.frame_height = frame_width, frame_height
        self.x, self.y, self.width, self.height = x, y, width, height
        self.cropped = cropped  # the image is the window alone (else the full frame)

    def camera_fields(self):
        """The ddof_camera fields that place the window in the full frame."""
        return {"frame_width": self.frame_width, "frame_height": self.frame_height,
                "window_x": self.x, "window_y": self.y}

    def describe(self):
        return "render border %dx%d at (%d, %d) of %dx%d%s" % (
            self.width, self.height, self.x, self.y, self.frame_width, self.frame_height,
            ", cropped" if self.cropped else "")


def region_of(use_border, use_crop, border, frame_size, image_size):
    """The Region of a render's image (None without a border, or a border that is the whole
    frame). Whether it is cropped is read from the image's size, the frame's or the border's,
    which is what the passes really are; use_crop, Blender's setting, is kept for the message.
    Raises ValueError when the image's size is neither the frame's nor the border's."""
    if not use_border:
        return None
    fw, fh = frame_size
    x, y, w, h = border_rect(border, fw, fh)
    if (x, y, w, h) == (0, 0, fw, fh):
        return None
    if tuple(image_size) == (fw, fh):
        cropped = False
    elif tuple(image_size) == (w, h):
        cropped = True
    else:
        raise ValueError("the render is %dx%d, but its border is %dx%d of a %dx%d frame (%s)"
                         % (image_size[0], image_size[1], w, h, fw, fh,
                            "cropped" if use_crop else "not cropped"))
    if w < 1 or h < 1:
        raise ValueError("the render border is empty (%dx%d)" % (w, h))
    return Region(fw, fh, x, y, w, h, cropped)


def _rows(buf, width, channels):
    """The interleaved float buffer as a (rows, width, channels) array over the same memory."""
    return np.frombuffer(buf, dtype=np.float32).reshape(-1, width, channels)


def crop(buf, width, channels, x, y, w, h):
    """The w x h window at (x, y) of an interleaved float buffer `width` pixels wide, as a new
    tightly packed float32 array."""
    return np.ascontiguousarray(_rows(buf, width, channels)[y:y + h, x:x + w]).ravel()


def paste(dst, width, channels, x, y, w, h, src):
    """Writes a w x h window `src` into dst at (x, y), in place."""
    _rows(dst, width, channels)[y:y + h, x:x + w] = _rows(src, w, channels)[:h]
