# SPDX-License-Identifier: MIT
"""The crop grid: each scene's hardest depth edge through the presets and the baselines."""

import os
import subprocess

import matplotlib.pyplot as plt
import numpy as np

from .names import NODE_NAMES, STUDY_NODE_IDS
from .rule import PRESET_ORDER


def srgb(img):
    x = np.clip(img[..., :3], 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def pick_crop(pinhole, truth, band, size):
    """The size x size window with the largest pinhole-vs-truth error inside the band (on the
    whole image when the scene has no band): where the depth edges matter most."""
    err = np.abs(srgb(pinhole) - srgb(truth)).mean(axis=2)
    if band is not None and band.sum() > 0:
        err = err * (band > 0)
    h, w = err.shape
    size = min(size, h, w)
    sat = np.zeros((h + 1, w + 1))
    sat[1:, 1:] = err.cumsum(0).cumsum(1)
    best, where = -1.0, (0, 0)
    for y in range(0, h - size + 1, 2):
        for x in range(0, w - size + 1, 2):
            s = sat[y + size, x + size] - sat[y, x + size] - sat[y + size, x] + sat[y, x]
            if s > best:
                best, where = s, (y, x)
    return where[0], where[1], size


def crop_grid(study, chosen, exe, work, path):
    """Rows: a hard-edge crop of each scene with blur; columns: pinhole, truth, the presets and
    the baselines. Returns the list of rows drawn, or None."""
    d = chosen["default"]
    fg_id = None
    if d.kind == "diffusion" and any(study.scenes[s].get("fg_element") for s in study.blurred):
        # the default preset's settings with the scene's foreground element (over rest.exr)
        parts = d.id.split("/")
        fg_id = "/".join(parts[:-1] + ["fg"])  # the layers are the id's last part
    ids = ["pinhole"] + STUDY_NODE_IDS + ["cod4", "gather"] + [chosen[n].id
                                                              for n in PRESET_ORDER]
    ids = list(dict.fromkeys(ids + ([fg_id] if fg_id else [])))
    dirs = [study.scenes[s]["dir"] for s in study.blurred]
    if not dirs:
        return None
    cmd = [exe, "images", "--out", work, "--configs", ",".join(ids), "-q"] + dirs
    subprocess.run(cmd, check=True)
    columns = [("pinhole", "pinhole (input)"), ("truth", "Cycles truth")]
    columns += [(chosen[n].id, "%s preset" % n) for n in PRESET_ORDER]
    if fg_id:
        columns += [(fg_id, "default + fg element")]
    columns += [("cod4", "CoD4 preview"), ("gather", "gather blur")]
    columns += [(cid, NODE_NAMES[cid]) for cid in STUDY_NODE_IDS
                if cid in study.by_id and study.by_id[cid].available]
    rows = []
    for scene in study.blurred:
        d = os.path.join(work, scene)

        def load(name):
            p = os.path.join(d, name.replace("/", "_") + ".npy")
            return np.load(p) if os.path.exists(p) else None

        pinhole, truth, band = load("input_pinhole"), load("input_truth"), load("input_band")
        if pinhole is None or truth is None:
            continue
        h, w = pinhole.shape[:2]
        size = max(16, min(96, h // 2))
        y, x, size = pick_crop(pinhole, truth, band, size)
        imgs = []
        for cid, _ in columns:
            img = pinhole if cid == "pinhole" else truth if cid == "truth" else load(cid)
            if cid == fg_id and not study.scenes[scene].get("fg_element"):
                img = None  # that scene has no element: the column is about the element
            imgs.append(None if img is None else srgb(img[y:y + size, x:x + size]))
        rows.append((scene, (x, y, size), imgs))
    if not rows:
        return None
    ncol = len(columns)
    fig, axes = plt.subplots(len(rows), ncol, figsize=(1.45 * ncol, 1.5 * len(rows) + 0.4),
                             dpi=120, squeeze=False)
    for r, (scene, (x, y, size), imgs) in enumerate(rows):
        for cidx, img in enumerate(imgs):
            ax = axes[r][cidx]
            ax.set_xticks([])
            ax.set_yticks([])
            if img is None:
                ax.imshow(np.full((size, size, 3), 0.87), vmin=0, vmax=1)
                ax.text(size / 2, size / 2, "n/a", ha="center", va="center", fontsize=8)
            else:
                ax.imshow(img, interpolation="nearest")
            if r == 0:
                ax.set_title(columns[cidx][1], fontsize=7.5)
            if cidx == 0:
                ax.set_ylabel("%s\n(%d,%d) %dpx" % (scene, x, y, size), fontsize=7)
    fig.tight_layout(pad=0.3)
    fig.savefig(path)
    plt.close(fig)
    return [(scene, box) for scene, box, _ in rows]
