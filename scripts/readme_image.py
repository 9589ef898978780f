#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Redraws docs/images/before_after.png, the README's picture: the bundled sample's pinhole
input, ddof's result and Cycles' lens depth of field side by side (sRGB, 4 px white gaps).

    bash scripts/demo.sh && python3 scripts/readme_image.py

Reads samples/pinhole.exr, ddof-demo-out/dof.exr (what demo.sh writes) and samples/truth.exr
with study/scenes/exr_io.py; needs numpy and matplotlib (Debian: python3-numpy
python3-matplotlib)."""

import os
import sys

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(root, "study", "scenes"))
from exr_io import read_exr, rgb_of  # noqa: E402


def srgb(rgb):
    x = np.clip(rgb, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def main():
    paths = [os.path.join(root, p) for p in
             ("samples/pinhole.exr", "ddof-demo-out/dof.exr", "samples/truth.exr")]
    missing = [p for p in paths if not os.path.exists(p)]
    if missing:
        sys.exit("readme_image.py: missing %s (run bash scripts/demo.sh first)"
                 % ", ".join(missing))
    panels = [srgb(rgb_of(read_exr(p))) for p in paths]
    h = panels[0].shape[0]
    gap = np.ones((h, 4, 3))
    picture = np.concatenate([panels[0], gap, panels[1], gap, panels[2]], axis=1)
    out = os.path.join(root, "docs", "images", "before_after.png")
    plt.imsave(out, picture)
    print("readme_image.py: %s (%dx%d)" % (out, picture.shape[1], picture.shape[0]))


if __name__ == "__main__":
    main()
