#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The cards study's table and montage (issue 25): every method against the Cycles truth.

    python3 study/cards/report.py DIR [--png docs/images/cards_study.png] [--noise truth_seed2.exr]

DIR holds what study/cards/cycles_study.sh made: truth.exr, pinhole.exr (the input), one.exr
(`ddof` one-image default on pinhole.exr), defocus.exr (Blender's Defocus node on pinhole.exr),
cards.exr (`ddof --cards scene.json`). Prints a Markdown table of sRGB PSNR (as `ddof
--compare`: RGB clamped to [0, 1], sRGB-encoded, peak 1) over the whole frame and over the
near ring's blurred footprint (the pixels within 20 px of where the ring covers the pinhole
frame, found from pinhole.exr's depth < 0.6 m), and with --noise the truth's noise floor (PSNR
of two truths rendered with different seeds). --png writes the montage: input | one image |
Defocus node | cards | truth, the whole frames above, a 2x crop of the near ring below.
"""

import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes"))
import exr_io  # noqa: E402

METHODS = [("pinhole input (no blur)", "pinhole.exr"),
           ("ddof one image, default", "one.exr"),
           ("Blender Defocus node (3.4)", "defocus.exr"),
           ("ddof --cards", "cards.exr")]


BANDS = [("ring, 0.50-0.56 m", 0.0, 0.6), ("leaf, 1.1-1.5 m", 1.0, 1.6),
         ("checker, 2 m (in focus)", 1.9, 2.1), ("text, 5-11 m", 4.9, 11.1),
         ("wall, 20 m", 19.0, 21.0)]


def dilate(mask, r):
    out = mask.copy()
    h, w = mask.shape
    ys, xs = np.nonzero(mask)
    if len(ys) == 0:
        return out
    for dy in range(-r, r + 1):
        for dx in range(-r, r + 1):
            if dx * dx + dy * dy <= r * r:
                y, x = np.clip(ys + dy, 0, h - 1), np.clip(xs + dx, 0, w - 1)
                out[y, x] = True
    return out


def main(argv):
    d = argv[1]
    png = argv[argv.index("--png") + 1] if "--png" in argv else None
    noise = argv[argv.index("--noise") + 1] if "--noise" in argv else None
    truth = exr_io.rgb_of(exr_io.read_exr(os.path.join(d, "truth.exr")))
    pin = exr_io.read_exr(os.path.join(d, "pinhole.exr"))
    near = dilate(exr_io.depth_of(pin) < 0.6, 20)
    print("| method | image PSNR (dB) | near ring region PSNR (dB) |")
    print("|---|---|---|")
    images = {}
    for label, fname in METHODS:
        img = exr_io.rgb_of(exr_io.read_exr(os.path.join(d, fname)))
        images[fname] = img
        print("| %s | %.2f | %.2f |" % (label, exr_io.psnr_srgb(img, truth),
                                          exr_io.psnr_srgb(img, truth, near)))
    if noise:
        other = exr_io.rgb_of(exr_io.read_exr(os.path.join(d, noise)))
        print("| noise floor: truth, seed 1 vs seed 2 | %.2f | %.2f |"
              % (exr_io.psnr_srgb(other, truth), exr_io.psnr_srgb(other, truth, near)))
    print("\nnear ring region: %d of %d pixels" % (near.sum(), near.size))
    # Per card: the pixels where the pinhole frame sees it (its depth range), undilated.
    z = exr_io.depth_of(pin)
    other = exr_io.rgb_of(exr_io.read_exr(os.path.join(d, noise))) if noise else None
    print("\n| pixels the pinhole sees on | one image | Defocus node | cards | noise floor |")
    print("|---|---|---|---|---|")
    for label, lo, hi in BANDS:
        m = (z >= lo) & (z < hi)
        row = [exr_io.psnr_srgb(images[f], truth, m) for f in ("one.exr", "defocus.exr",
                                                                 "cards.exr")]
        cells = ["%.2f" % v for v in row]
        cells.append("%.2f" % exr_io.psnr_srgb(other, truth, m) if noise else "-")
        print("| %s (%d px) | %s |" % (label, m.sum(), " | ".join(cells)))
    if png:
        frames = [images[f] for _l, f in METHODS] + [truth]
        ys, xs = np.nonzero(exr_io.depth_of(pin) < 0.6)
        h, w = truth.shape[:2]
        ch, cw = h // 2, w // 2
        cy = int(np.clip((ys.min() + ys.max()) // 2 - ch // 2, 0, h - ch))
        cx = int(np.clip((xs.min() + xs.max()) // 2 - cw // 2, 0, w - cw))
        crops = [np.repeat(np.repeat(f[cy:cy + ch, cx:cx + cw], 2, 0), 2, 1) for f in frames]
        exr_io.write_png(png, exr_io.montage(frames + crops, len(frames)))
        print("montage: %s (input | one image | Defocus node | cards | truth; below: the 2x "
              "crop x %d..%d, y %d..%d)" % (png, cx, cx + cw, cy, cy + ch))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
