#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Draws docs/images/near_layer.png: the study's scenes with a blurred near object, one row
each: the pinhole input, ddof without the near layer (the object stays opaque, its
silhouette spread), ddof's default with the near layer (one image: the object turns see-through), ddof
with the separately rendered foreground element (the exact layers) and Cycles' lens depth of
field, each panel with its PSNR against the truth.

    bash study/run.sh && python3 scripts/near_layer_image.py [--ddof build/study/plugin/apps/ddof]

Reads build/study-cache/scenes/<scene>/{pinhole,truth,fg,rest}.exr and camera.json (what
study/run.sh renders), runs the `ddof` command (default: the first of build/test, build/study,
build/release that has one), and needs numpy and matplotlib (Debian: python3-numpy
python3-matplotlib)."""

import os
import subprocess
import sys
import tempfile

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(root, "study", "scenes"))
from exr_io import psnr_srgb, read_exr, rgb_of  # noqa: E402

SCENES = ["near_occluder", "near_railing", "near_border"]
COLUMNS = ["pinhole input", "near layer off", "near layer (default)",
           "separate element", "Cycles lens DOF"]


def srgb(rgb):
    x = np.clip(rgb, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def find_ddof(argv):
    if "--ddof" in argv:
        return argv[argv.index("--ddof") + 1]
    for build in ("build/test", "build/study", "build/release"):
        path = os.path.join(root, build, "plugin", "apps", "ddof")
        if os.access(path, os.X_OK):
            return path
    sys.exit("near_layer_image.py: no built ddof (build it, or give --ddof PATH)")


def run(ddof, args):
    result = subprocess.run([ddof] + args + ["--quiet"], capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit("near_layer_image.py: ddof %s failed:\n%s" % (" ".join(args), result.stderr))


def main():
    ddof = find_ddof(sys.argv)
    cache = os.path.join(root, "build", "study-cache", "scenes")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for scene in SCENES:
            d = os.path.join(cache, scene)
            need = [os.path.join(d, f) for f in ("pinhole.exr", "truth.exr", "fg.exr",
                                                 "rest.exr", "camera.json")]
            if not all(os.path.exists(p) for p in need):
                print("near_layer_image.py: %s is not rendered, left out" % scene)
                continue
            cam = ["--camera", os.path.join(d, "camera.json")]
            outs = [os.path.join(tmp, "%s_%d.exr" % (scene, k)) for k in range(3)]
            run(ddof, [need[0], "-o", outs[0], "--near-layer", "off"] + cam)
            run(ddof, [need[0], "-o", outs[1]] + cam)
            run(ddof, [need[3], "-o", outs[2], "--foreground", need[2]] + cam)
            truth = rgb_of(read_exr(need[1]))
            images = [rgb_of(read_exr(need[0]))] + [rgb_of(read_exr(o)) for o in outs] + [truth]
            rows.append((scene, images, [psnr_srgb(truth, im) for im in images]))
    if not rows:
        sys.exit("near_layer_image.py: no scene rendered (run bash study/run.sh first)")
    h, w = rows[0][1][0].shape[:2]
    fig, axes = plt.subplots(len(rows), len(COLUMNS), squeeze=False,
                             figsize=(len(COLUMNS) * w / 100.0, len(rows) * (h + 36) / 100.0),
                             dpi=100)
    for r, (scene, images, psnrs) in enumerate(rows):
        for c, (image, psnr) in enumerate(zip(images, psnrs)):
            ax = axes[r][c]
            ax.imshow(srgb(image), interpolation="nearest")
            ax.set_xticks([])
            ax.set_yticks([])
            label = COLUMNS[c] if c == len(COLUMNS) - 1 else "%s: %.1f dB" % (COLUMNS[c], psnr)
            ax.set_title("%s\n%s" % (scene, label) if c == 0 else label, fontsize=8)
    fig.tight_layout(pad=0.3)
    out = os.path.join(root, "docs", "images", "near_layer.png")
    fig.savefig(out)
    print("near_layer_image.py: %s" % out)
    for scene, _, psnrs in rows:
        print("  %-14s " % scene + ", ".join("%s %.2f dB" % (n, p)
                                               for n, p in zip(COLUMNS[:-1], psnrs)))


if __name__ == "__main__":
    main()
