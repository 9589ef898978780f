# SPDX-License-Identifier: MIT
"""Checks the Defocus node's f-stop mapping (f-stop = N * 1000 / sensor_mm, docs/design.md section 1)
on a scene's isolated highlights and against its truth. System python3 + numpy.

    for s in 0.5 0.707 1 1.414 2; do
        blender -b --factory-startup --python-exit-code 1 --python study/scenes/defocus_node.py \
            -- --scene-dir SCENES/highlights --fstop-scale $s --out-dir /tmp/fstop \
               --out-name defocus_x$s --repeats 1
    done
    python3 study/scenes/fstop_check.py SCENES/highlights /tmp/fstop

For every bright light that stands alone in the pinhole (a blob brighter than --min, whose
window (half-width 0.8 CoC + 8 px) holds no other blob and one background surface), it measures the
light's blur diameter in the truth and in each defocus_x<scale>.exr as the disc-equivalent
diameter of the light's second moment (2 * sqrt(2) * RMS radius of the background-subtracted
luminance; a uniform disc of diameter D gives D), and prints those next to the Cycles CoC the
camera predicts at the light's depth (the light's own pinhole width added in quadrature), and
each image's PSNR against the truth. The scale whose diameters match the truth's checks the mapping.
"""

import json
import math
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from exr_io import depth_of, psnr_srgb, read_exr, rgb_of  # noqa: E402


def luminance(rgb):
    return rgb @ np.array([0.2126, 0.7152, 0.0722])


def blobs(mask):
    """Connected components (4-neighbour) of a boolean mask: lists of (y, x)."""
    seen = np.zeros_like(mask, dtype=bool)
    out = []
    for y, x in zip(*np.nonzero(mask)):
        if seen[y, x]:
            continue
        stack, pixels = [(y, x)], []
        seen[y, x] = True
        while stack:
            cy, cx = stack.pop()
            pixels.append((cy, cx))
            for ny, nx in ((cy + 1, cx), (cy - 1, cx), (cy, cx + 1), (cy, cx - 1)):
                if 0 <= ny < mask.shape[0] and 0 <= nx < mask.shape[1] and mask[ny, nx] \
                        and not seen[ny, nx]:
                    seen[ny, nx] = True
                    stack.append((ny, nx))
        out.append(pixels)
    return out


def coc_px(cam, z, width):
    f = cam["focal_length_mm"] / 1000.0
    s1 = cam["focus_distance_m"]
    return f * f / (cam["fstop"] * s1) * abs(z - s1) / z * width / (cam["sensor_width_mm"] / 1000.0)


def blur_diameter(lum, cy, cx, half):
    """Disc-equivalent diameter of the blob around (cy, cx): background = median of the
    window's border ring."""
    h, w = lum.shape
    y0, y1 = int(max(0, math.floor(cy - half))), int(min(h, math.ceil(cy + half) + 1))
    x0, x1 = int(max(0, math.floor(cx - half))), int(min(w, math.ceil(cx + half) + 1))
    win = lum[y0:y1, x0:x1]
    yy, xx = np.mgrid[y0:y1, x0:x1]
    r2 = (yy - cy) ** 2 + (xx - cx) ** 2
    ring = win[(r2 > (half - 2) ** 2) & (r2 <= half ** 2)]
    bg = float(np.median(ring)) if ring.size else 0.0
    inside = r2 <= half ** 2
    i = np.clip(win - bg, 0.0, None) * inside
    total = float(i.sum())
    if total <= 0:
        return float("nan")
    # Centre of mass, then the second moment about it.
    my, mx = float((i * yy).sum() / total), float((i * xx).sum() / total)
    var = float((i * ((yy - my) ** 2 + (xx - mx) ** 2)).sum() / total)
    return 2.0 * math.sqrt(2.0 * var)


def main(argv):
    if len(argv) < 3:
        print(__doc__)
        return 2
    scene_dir, defocus_dir = argv[1], argv[2]
    min_lum = float(argv[argv.index("--min") + 1]) if "--min" in argv else 2.0
    with open(os.path.join(scene_dir, "camera.json")) as f:
        cam = json.load(f)
    pin = read_exr(os.path.join(scene_dir, "pinhole.exr"))
    pin_rgb, depth = rgb_of(pin), depth_of(pin)
    truth = rgb_of(read_exr(os.path.join(scene_dir, "truth.exr")))
    h, w = depth.shape
    lum_pin = luminance(pin_rgb)
    found = []
    for px in blobs(lum_pin > min_lum):
        ys, xs = np.array([p[0] for p in px]), np.array([p[1] for p in px])
        wts = lum_pin[ys, xs]
        cy, cx = float((wts * ys).sum() / wts.sum()), float((wts * xs).sum() / wts.sum())
        z = float(depth[ys, xs].min())  # its halo may hold the background's depth
        width_px = 2.0 * math.sqrt(len(px) / math.pi)
        found.append({"y": cy, "x": cx, "z": z, "coc": coc_px(cam, z, w), "size": width_px,
                      "pixels": (ys, xs)})
    lights = []
    for a in found:
        half = 0.8 * a["coc"] + 8.0
        if a["x"] - half < 0 or a["y"] - half < 0 or a["x"] + half >= w or a["y"] + half >= h:
            continue
        if any(b is not a and math.hypot(a["x"] - b["x"], a["y"] - b["y"]) <
               half + 0.8 * b["coc"] + 8.0 for b in found):
            continue
        # Over a plain background only: the window's depth, the light's blob (grown by 2 px)
        # left out, must be one surface.
        y0, y1 = int(a["y"] - half), int(a["y"] + half) + 1
        x0, x1 = int(a["x"] - half), int(a["x"] + half) + 1
        keep = np.ones((y1 - y0, x1 - x0), dtype=bool)
        for dy in range(-2, 3):
            for dx in range(-2, 3):
                yy, xx = a["pixels"][0] + dy - y0, a["pixels"][1] + dx - x0
                ok = (yy >= 0) & (yy < keep.shape[0]) & (xx >= 0) & (xx < keep.shape[1])
                keep[yy[ok], xx[ok]] = False
        around = depth[y0:y1, x0:x1][keep]
        if around.max() > 1.5 * around.min():
            continue
        a["half"] = half
        lights.append(a)
    scales = []
    for name in sorted(os.listdir(defocus_dir)):
        m = re.match(r"defocus_x([0-9.]+)\.exr$", name)
        if m:
            scales.append((float(m.group(1)), os.path.join(defocus_dir, name)))
    scales.sort()
    images = [("truth", truth)] + [("x%g" % s, rgb_of(read_exr(p))) for s, p in scales]
    header = "%-18s %6s %8s" % ("light (x, y)", "Z m", "Cycles") + "".join(
        "%9s" % n for n, _ in images)
    print(header)
    ratios = {n: [] for n, _ in images}
    for a in lights:
        pred = math.hypot(a["coc"], a["size"])
        row = "%-18s %6.2f %8.1f" % ("(%.0f, %.0f)" % (a["x"], a["y"]), a["z"], pred)
        d_truth = None
        for n, img in images:
            d = blur_diameter(luminance(img), a["y"], a["x"], a["half"])
            if n == "truth":
                d_truth = d
            ratios[n].append(d / d_truth)
            row += "%9.1f" % d
        print(row)
    if lights:
        print("%-34s" % "median diameter / truth's" + "".join(
            "%9.3f" % float(np.median(ratios[n])) for n, _ in images))
    else:
        print("(no isolated highlight in this scene: PSNR only)")
    print("%-34s" % "PSNR against the truth (dB)" + "".join(
        "%9s" % ("-" if n == "truth" else "%.2f" % psnr_srgb(img, truth)) for n, img in images))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
