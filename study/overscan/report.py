# SPDX-License-Identifier: MIT
"""The overscan study's margin, table and montage (study/overscan/run.sh).

    python3 study/overscan/report.py --margin CAMERA.json   the add-on's Auto margin, pixels
    python3 study/overscan/report.py OUT TRUTH.exr MARGIN    the table and OUT/overscan.png
"""

import json
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "scenes"))
sys.path.insert(0, os.path.join(HERE, "..", "..", "blender_addon", "diffusion_dof"))
from exr_io import montage, psnr_srgb, read_exr, rgb_of, srgb_encode, write_png  # noqa: E402
import overscan  # noqa: E402  (the add-on's bpy-free margin)

BORDER_PX = 8
INPUTS = [("one", "one image (pinhole.exr)"),
          ("matte", "one image + object matte (matte.exr --matte auto)"),
          ("layers", "two layers (rest.exr --foreground fg.exr)")]
ERROR_GAIN = 8.0  # the montage's |result - truth| (sRGB) scale


def error_image(img, truth):
    """|img - truth| of the sRGB values (clamped, as the PSNR), times ERROR_GAIN, as linear
    values for write_png (which encodes sRGB): grey levels that show the difference."""
    diff = np.abs(srgb_encode(img) - srgb_encode(truth)).mean(axis=-1) * ERROR_GAIN
    grey = np.clip(diff, 0.0, 1.0)
    linear = np.where(grey <= 0.04045, grey / 12.92, ((grey + 0.055) / 1.055) ** 2.4)
    return np.repeat(linear[..., None], 3, axis=-1)


def auto_margin(camera_path):
    """The add-on's Auto margin along x for this camera (overscan.py): square pixels."""
    with open(camera_path) as f:
        cam = json.load(f)
    width, height = cam["resolution"]
    coc = overscan.coc_infinity_mm(cam["focal_length_mm"], cam["fstop"], cam["focus_distance_m"])
    pitch = overscan.pixel_pitch_mm(cam["sensor_fit"], cam["sensor_width_mm"], width, height)
    return overscan.auto_margin(coc, pitch, width, height)[0]


def main(out, truth_path, margin):
    truth = rgb_of(read_exr(truth_path))
    h, w = truth.shape[:2]
    inside = np.zeros((h, w), bool)
    inside[BORDER_PX:h - BORDER_PX, BORDER_PX:w - BORDER_PX] = True
    print("thin_strands, ddof's default against the Cycles truth (sRGB PSNR, dB); margin %d px "
          "each side (the add-on's Auto), cropped off; border: the outer %d px (%.1f%% of the "
          "frame)" % (margin, BORDER_PX, 100.0 * (~inside).mean()))
    print("")
    print("| input | margin | image | border | inside |")
    print("|---|---:|---:|---:|---:|")
    errors = {}
    for key, label in INPUTS:
        for tag, m in (("frame", 0), ("margin", margin)):
            img = rgb_of(read_exr(os.path.join(out, "%s_%s.exr" % (key, tag))))
            img = img[m:m + h, m:m + w]
            print("| %s | %d px | %.2f | %.2f | %.2f |" % (
                label, m, psnr_srgb(img, truth), psnr_srgb(img, truth, ~inside),
                psnr_srgb(img, truth, inside)))
            errors[key, tag] = error_image(img, truth)
    path = os.path.join(out, "overscan.png")
    write_png(path, montage([errors[k, t] for k in ("matte", "layers")
                             for t in ("frame", "margin")], 2))
    print("")
    print("montage: |result - truth| in sRGB x %g, without | with the margin; one image with "
          "its matte, then two layers: %s" % (ERROR_GAIN, path))


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "--margin":
        print(auto_margin(sys.argv[2]))
    elif len(sys.argv) == 4:
        main(sys.argv[1], sys.argv[2], int(sys.argv[3]))
    else:
        raise SystemExit(__doc__)
