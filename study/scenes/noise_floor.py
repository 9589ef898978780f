# SPDX-License-Identifier: MIT
"""The noise floor of the ground truths: two truth renders of each scene with different seeds,
(and of the pinhole inputs, where both folders have pinhole.exr)
compared with the metric of `ddof --compare` (RGB, sRGB-encoded values clamped to [0, 1],
PSNR peak 1). System python3 + numpy.

    blender -b --factory-startup --python-exit-code 1 --python study/scenes/make_scenes.py -- \
        --out /tmp/seed2 --seed 2 --only truth,pinhole
    python3 study/scenes/noise_floor.py build/study-cache/scenes /tmp/seed2 [--json OUT.json]

Prints per scene: the PSNR between the two renders, the RMSE of one render's own noise (the
difference's RMSE over sqrt 2: what a method's error against one truth render includes), and the
worst 16x16 tile (where the noise concentrates).
"""

import json
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from exr_io import psnr_srgb, read_exr, rgb_of, srgb_encode  # noqa: E402


def compare(a_path, b_path, tile=16):
    a, b = rgb_of(read_exr(a_path)), rgb_of(read_exr(b_path))
    d = srgb_encode(a) - srgb_encode(b)
    rmse = float(np.sqrt(np.mean(d * d)))
    h, w = d.shape[:2]
    th, tw = h // tile, w // tile
    tiles = (d[:th * tile, :tw * tile] ** 2).reshape(th, tile, tw, tile, 3).mean(axis=(1, 3, 4))
    worst = float(np.sqrt(tiles.max()))
    return {
        "psnr_db": round(psnr_srgb(a, b), 2),
        "rmse_diff": round(rmse, 5),
        "rmse_one_render": round(rmse / math.sqrt(2.0), 5),
        "worst_tile_psnr_db": round(-20.0 * math.log10(worst), 2) if worst > 0 else None,
        "size": [w, h],
    }


def main(argv):
    if len(argv) < 3:
        print(__doc__)
        return 2
    out_json = argv[argv.index("--json") + 1] if "--json" in argv else None
    a_dir, b_dir = argv[1], argv[2]
    results = {}
    for name in sorted(os.listdir(a_dir)):
        for fname in ("truth.exr", "pinhole.exr"):
            a = os.path.join(a_dir, name, fname)
            b = os.path.join(b_dir, name, fname)
            if not (os.path.exists(a) and os.path.exists(b)):
                continue
            r = compare(a, b)
            for d, key in ((a_dir, "a"), (b_dir, "b")):
                try:
                    with open(os.path.join(d, name, "render.json")) as f:
                        info = json.load(f)["files"][fname]
                    r["samples_" + key], r["seed_" + key] = info["samples"], info["seed"]
                except (OSError, KeyError, ValueError):
                    pass
            results.setdefault(name, {})[fname] = r
            print("%-15s %-12s %5s samples  PSNR %6.2f dB  one render's noise RMSE %.5f  "
                  "worst 16x16 tile %6.2f dB"
                  % (name, fname, r.get("samples_a", "?"), r["psnr_db"], r["rmse_one_render"],
                     r["worst_tile_psnr_db"]))
    if out_json:
        with open(out_json, "w") as f:
            json.dump(results, f, indent=2)
            f.write("\n")
    return 0 if results else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
