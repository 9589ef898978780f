#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Draws docs/images/disc_kernel_psf.png: what each kernel makes of one bright pixel (the point
spread), against the disc a lens draws, and a row through the middle.

    python3 study/lens/psf_figure.py [--library build/rel/libddof/libddof.so] [--out PNG]

Runs libddof through the Blender add-on's ctypes binding (blender_addon/diffusion_dof/binding.py and ddof_abi.py,
which needs no Blender); numpy and matplotlib (Debian: python3-numpy python3-matplotlib)."""
import argparse
import ctypes
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "blender_addon", "diffusion_dof"))
import binding  # noqa: E402
import ddof_abi  # noqa: E402

D = 32.0          # CoC diameter, px
SIZE = 3 * 32 + 9  # as tests/point_spread.h


def spread(lib, kernel, substeps=None):
    """The output of one bright pixel of value 1 at uniform CoC D."""
    w = SIZE
    color = np.zeros((w, w), np.float32)
    color[w // 2, w // 2] = 1.0
    coc = np.full((w, w), D, np.float32)
    out = np.zeros((w, w), np.float32)
    p = lib.default_params()
    p.kernel = ddof_abi.KERNELS[kernel]
    if substeps:
        p.substeps = substeps
    p.background = p.near_spread = ddof_abi.LAYER_OFF
    fptr = ctypes.POINTER(ctypes.c_float)
    ci = ddof_abi.ImageIn(color.ctypes.data_as(fptr), w, w, 1, 0)
    zi = ddof_abi.ImageIn(coc.ctypes.data_as(fptr), w, w, 1, 0)
    oi = ddof_abi.Image(out.ctypes.data_as(fptr), w, w, 1, 0)
    ctx = lib._context(2)
    try:
        status = lib._dll.ddof_diffuse_layers(ctx, ctypes.byref(p), ctypes.byref(ci),
                                              ctypes.byref(zi), None, ctypes.byref(oi), None)
        if status != 0:
            raise SystemExit("ddof_diffuse_layers: %s" % lib.status_string(status))
    finally:
        lib._dll.ddof_context_free(ctx)
    return out


def disc(w, d):
    o = (np.arange(8) + 0.5) / 8 - 0.5 - w // 2
    x = (np.arange(w)[:, None] + o[None, :]).ravel()
    inside = (x[:, None] ** 2 + x[None, :] ** 2) <= (d / 2) ** 2
    cover = inside.reshape(w, 8, w, 8).mean(axis=(1, 3))
    return cover / cover.sum()


def snr(k, ref):
    return -20 * np.log10(np.linalg.norm(k - ref) / np.linalg.norm(ref))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--library", default=os.path.join(ROOT, "build", "rel", "libddof",
                                                      "libddof.so"))
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "images", "disc_kernel_psf.png"))
    args = ap.parse_args()
    lib = binding.Library(args.library)
    ref = disc(SIZE, D)
    panels = [("lens (uniform disc)", ref, None),
              ("heat, n=2 (0.3 default)", spread(lib, "heat", 2), None),
              ("heat, n=8", spread(lib, "heat", 8), None),
              ("disc-2x2 (default)", spread(lib, "disc-2x2"), None),
              ("disc-3x3 (final)", spread(lib, "disc-3x3"), None)]
    top = ref.max()
    fig = plt.figure(figsize=(13, 5.4), dpi=100)
    for i, (name, k, _) in enumerate(panels):
        ax = fig.add_subplot(2, len(panels), i + 1)
        ax.imshow(k / top, cmap="magma", vmin=-0.1, vmax=1.3)
        ax.set_title(name if i == 0 else "%s\n%.1f dB vs the disc" % (name, snr(k, ref)),
                     fontsize=9)
        ax.set_axis_off()
    ax = fig.add_subplot(2, 1, 2)
    x = np.arange(SIZE) - SIZE // 2
    for name, k, _ in panels:
        ax.plot(x, k[SIZE // 2] / top, label=name, lw=2.2 if name.startswith("lens") else 1.4)
    ax.axhline(0, color="grey", lw=0.6)
    ax.set_xlim(-1.2 * D, 1.2 * D)
    ax.set_xlabel("pixels from the bright pixel (CoC %g px)" % D)
    ax.set_ylabel("value / disc height")
    ax.legend(fontsize=8, ncol=5, loc="upper center")
    fig.tight_layout()
    fig.savefig(args.out)
    print("wrote %s" % args.out)


if __name__ == "__main__":
    main()
