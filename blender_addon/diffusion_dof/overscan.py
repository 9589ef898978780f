# SPDX-License-Identifier: GPL-3.0-or-later
"""Overscan: a margin rendered around the frame, so that the light a lens spreads into the frame
from just outside it is there to be spread, and the light it spreads out of the frame has
somewhere to go. No bpy: tested from a plain Python (tests/blender/test_overscan_plain.py).

Blender has no overscan, so it is made from the camera: the resolution grows by the margin on
each side and the sensor grows with it (same lens, same pixel pitch), and the shift, which
Blender counts in sensor sizes, shrinks so that the frame stays where it was. The library then
runs on the whole image with the original frame as its window (ddof_camera's frame and window
fields: the window reaches outside the frame), and the frame is cropped out.

The margin (Auto) is the radius of the largest CoC a pixel at the frame's edge can have from a
point at least half the focus distance away: with a planar focus the CoC at half the focus
distance equals the CoC at infinity, f^2 / (N (s - f)). Anything nearer (whose CoC grows
without bound) is capped there, and the margin never exceeds MAX_FRACTION of the frame's larger
side, so a very near object or a macro focus cannot blow the render up.
"""

import math

MAX_FRACTION = 0.125  # the margin's cap: an eighth of the frame's larger side, per side
TAIL_PX = 1           # the diffusion's kernel reaches a little past the CoC's radius


def effective_fit(fit, width, height, aspect_x=1.0, aspect_y=1.0):
    """'HORIZONTAL' or 'VERTICAL': the image axis the sensor size spans, as Blender decides
    (AUTO: the larger one, pixel aspect included)."""
    if fit != "AUTO":
        return fit
    return "HORIZONTAL" if width * aspect_x >= height * aspect_y else "VERTICAL"


def coc_infinity_mm(focal_mm, fstop, focus_m, thin_lens=False):
    """The CoC diameter on the sensor, in mm, of a point at infinity (and, with a planar focus,
    of one at half the focus distance)."""
    focus_mm = focus_m * 1000.0
    if not (fstop > 0 and focus_mm > focal_mm > 0):
        return 0.0
    coc = focal_mm * focal_mm / (fstop * (focus_mm - focal_mm))
    if thin_lens:  # the textbook thin lens's CoC is larger by S1 / (S1 - f)
        coc *= focus_mm / (focus_mm - focal_mm)
    return coc


def pixel_pitch_mm(fit, sensor_mm, width, height, aspect_x=1.0, aspect_y=1.0):
    """(pitch along x, pitch along y) in mm on the sensor. Blender spans the fitted axis with the
    sensor size, and a pixel is aspect_x wide for aspect_y tall."""
    fit = effective_fit(fit, width, height, aspect_x, aspect_y)
    if fit == "HORIZONTAL":
        pitch_x = sensor_mm / width
        return pitch_x, pitch_x * aspect_y / aspect_x
    pitch_y = sensor_mm / height
    return pitch_y * aspect_x / aspect_y, pitch_y


def auto_margin(coc_mm, pitch, width, height):
    """(margin_x, margin_y) in pixels for a largest CoC of coc_mm on the sensor."""
    cap = int(MAX_FRACTION * max(width, height))
    if coc_mm <= 0.0:
        return 0, 0
    return tuple(min(cap, int(math.ceil(0.5 * coc_mm / p)) + TAIL_PX) for p in pitch)


def manual_margin(pixels, pitch):
    """(margin_x, margin_y) for a margin of `pixels` along x; y gets the same distance on the
    sensor (the same pixels with square pixels)."""
    pixels = max(0, int(pixels))
    return pixels, int(round(pixels * pitch[0] / pitch[1]))


class Plan:
    """The grown render: what to set on the scene and the camera, and where the frame lies."""

    def __init__(self, width, height, margin_x, margin_y, fit, sensor_mm):
        self.width, self.height = width, height          # the frame, in rendered pixels
        self.margin_x, self.margin_y = margin_x, margin_y
        self.fit = fit                                   # HORIZONTAL or VERTICAL, explicit
        fitted, grown = (width, self.full_width) if fit == "HORIZONTAL" else \
            (height, self.full_height)
        self.scale = grown / fitted                      # sensor and shift change by this
        self.sensor_mm = sensor_mm * self.scale          # along the fitted axis

    @property
    def full_width(self):
        return self.width + 2 * self.margin_x

    @property
    def full_height(self):
        return self.height + 2 * self.margin_y

    def shift(self, shift):
        """A camera shift (in sensor sizes) that keeps the frame in place on the grown sensor."""
        return shift / self.scale

    def camera_fields(self):
        """ddof_camera's frame and window: the frame is the original one, the image reaches
        margin pixels outside it on every side."""
        return {"frame_width": self.width, "frame_height": self.height,
                "window_x": -self.margin_x, "window_y": -self.margin_y}

    def extra_pixels(self):
        """The fraction of pixels the margin adds (0.19 for 19% more)."""
        return self.full_width * self.full_height / float(self.width * self.height) - 1.0

    def describe(self):
        return "%d x %d px margin: renders %dx%d for %dx%d (+%.0f%% pixels)" % (
            self.margin_x, self.margin_y, self.full_width, self.full_height, self.width,
            self.height, 100.0 * self.extra_pixels())


def plan(width, height, fit, sensor_mm, focal_mm, fstop, focus_m, aspect_x=1.0, aspect_y=1.0,
         manual=None, thin_lens=False):
    """The Plan of a width x height frame (rendered pixels) for a camera whose sensor size
    sensor_mm spans the axis `fit` says (AUTO/HORIZONTAL/VERTICAL, as Blender). manual: a
    margin in pixels instead of Auto. None when the margin is 0."""
    eff = effective_fit(fit, width, height, aspect_x, aspect_y)
    pitch = pixel_pitch_mm(eff, sensor_mm, width, height, aspect_x, aspect_y)
    if manual is not None:
        margin = manual_margin(manual, pitch)
    else:
        margin = auto_margin(coc_infinity_mm(focal_mm, fstop, focus_m, thin_lens), pitch,
                             width, height)
    if margin == (0, 0):
        return None
    return Plan(width, height, margin[0], margin[1], eff, sensor_mm)
