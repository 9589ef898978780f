#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Draws docs/images/disc_kernel_chains.png: point spreads of fitted disc-kernel constructions
(saved by disc_study.py --save) against the uniform disc at one CoC: the 2-D kernel, its
non-radial part (the cross), and cross-sections along the axis and the diagonal on a symmetric
log scale (the rings and the tails).

    python3 study/lens/disc_study_figure.py --d 32 --out PNG LABEL=FIT.json ...
"""
import argparse
import json
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import disc_study as ds  # noqa: E402
import fit_disc_kernel as fdk  # noqa: E402


def load(fn):
    s = json.load(open(fn))
    m = ds.Model(s["C"], s["M"], s["asym"], s["heat"], s.get("zeros", 0))
    m.phase_max = s.get("phase_max", 1.0)
    return m, np.array(s["p"])


def nonradial(K):
    c = K.shape[0] // 2
    y, x = np.mgrid[-c:c + 1, -c:c + 1]
    _, inv, cnt = np.unique((x * x + y * y).ravel(), return_inverse=True, return_counts=True)
    P = (np.bincount(inv, K.ravel()) / cnt)[inv].reshape(K.shape)
    return K - P


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--d", type=float, default=32)
    ap.add_argument("--out", default="docs/images/disc_kernel_chains.png")
    ap.add_argument("fits", nargs="+", help="LABEL=FILE.json")
    a = ap.parse_args()
    d = a.d
    half = int(1.5 * d) + 4
    D = fdk.disc(d, half)
    top = D.max()
    panels = [("uniform disc, CoC %g px" % d, D)]
    for item in a.fits:
        label, fn = item.rsplit("=", 1)
        m, p = load(fn)
        K = ds.kernel_full(m, p, d, half)
        snr = -20 * np.log10(np.linalg.norm(K - D) / np.linalg.norm(D))
        panels.append(("%s\n%.1f dB, min %.1f%%" % (label, snr, 100 * K.min() / top), K))
    n = len(panels)
    fig = plt.figure(figsize=(max(2.6 * n, 11), 12), dpi=100)
    for i, (name, K) in enumerate(panels):
        ax = fig.add_subplot(5, n, i + 1)
        ax.imshow(K / top, cmap="RdBu_r", vmin=-1.3, vmax=1.3)
        ax.set_title(name, fontsize=8)
        ax.set_axis_off()
        ax = fig.add_subplot(5, n, n + i + 1)
        ax.imshow(nonradial(K) / top, cmap="RdBu_r", vmin=-0.05, vmax=0.05)
        ax.set_title("non-radial part (+-5%)" if i == 0 else "", fontsize=8)
        ax.set_axis_off()
    x = np.arange(-half, half + 1)
    for row, (title, take, scale, log) in enumerate([
            ("axis (row through the centre), linear", lambda K: K[half], 1.0, False),
            ("axis, symmetric log", lambda K: K[half], 1.0, True),
            ("diagonal, symmetric log", lambda K: np.diagonal(K), np.sqrt(2.0), True)]):
        ax = fig.add_subplot(5, 1, 3 + row)
        for i, (name, K) in enumerate(panels):
            ax.plot(x * scale / d, take(K) / top, lw=2.2 if i == 0 else 1.2,
                    label=name.replace("\n", ", "))
        if log:
            ax.set_yscale("symlog", linthresh=1e-3)
            ax.set_ylim(-0.3, 1.5)
        ax.axhline(0, color="grey", lw=0.6)
        ax.set_xlim(-1.3, 1.3)
        ax.set_xlabel("distance from the bright pixel / CoC: %s" % title, fontsize=8)
        ax.set_ylabel("value / disc height", fontsize=8)
        if row == 0:
            ax.legend(fontsize=7, ncol=min(n, 5), loc="upper left", bbox_to_anchor=(0, 1.35))
    fig.tight_layout()
    fig.savefig(a.out)
    print("wrote %s" % a.out)


if __name__ == "__main__":
    main()
