# SPDX-License-Identifier: MIT
"""The aperture study's table and montage (study/aperture/run.sh): for the hexagon and the
anamorphic renders of the highlights scene, each candidate against the Cycles truth: image PSNR
and bokeh PSNR (sRGB, clamped, as `ddof --compare`; bokeh: the pixels where the truth or any
candidate is brighter than 0.05 in a channel, the lights' blur), and a montage of truth | ddof |
ddof round | the 3.4 node per aperture (OUT/aperture.png).

    python3 study/aperture/report.py OUT
"""

import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes"))
from exr_io import montage, psnr_srgb, read_exr, rgb_of, write_png  # noqa: E402

CANDIDATES = [("ddof.exr", "ddof default, the camera's aperture"),
              ("ddof_round.exr", "ddof default, round aperture"),
              ("defocus.exr", "Defocus node, Blender 3.4"),
              ("defocus-4.2.exr", "Defocus node, Blender 4.2"),
              ("defocus-5.3.exr", "Defocus node, Blender 5.3")]


def main(out):
    tiles = []
    print("| aperture | candidate | image dB | bokeh dB |")
    print("|---|---|---:|---:|")
    for name in ("hexagon", "anamorphic"):
        d = os.path.join(out, name, "highlights")
        truth = rgb_of(read_exr(os.path.join(d, "truth.exr")))
        found = [(f, label, rgb_of(read_exr(os.path.join(d, f))))
                 for f, label in CANDIDATES if os.path.exists(os.path.join(d, f))]
        bokeh = truth.max(axis=-1) > 0.05
        for _, _, img in found:
            bokeh |= img.max(axis=-1) > 0.05
        for f, label, img in found:
            print("| %s | %s | %.2f | %.2f |" % (name, label, psnr_srgb(img, truth),
                                                 psnr_srgb(img, truth, bokeh)))
        images = {f: img for f, _, img in found}
        tiles += [truth] + [images.get(f, np.zeros_like(truth))
                            for f in ("ddof.exr", "ddof_round.exr", "defocus.exr")]
        print("| %s | bokeh pixels | %.1f%% | |" % (name, 100.0 * bokeh.mean()))
    write_png(os.path.join(out, "aperture.png"), montage(tiles, 4))
    print("montage (truth | ddof | ddof round | node 3.4; hexagon, then anamorphic): %s"
          % os.path.join(out, "aperture.png"))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        raise SystemExit("usage: report.py OUT")
    main(sys.argv[1])
