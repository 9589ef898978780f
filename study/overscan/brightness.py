# SPDX-License-Identifier: MIT
"""study/overscan/brightness.py OUT SCENE... - the table of study/overscan/brightness.sh: per
scene the mean of linear R, G, B over the truth's, inside the frame (14 px or more from every
side) and in the border band, for the pinhole, ddof on the frame as rendered and ddof on the
frame rendered with the margin (cropped), and the sides where the margin's border is off by
more than the study's tolerance."""

import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "scenes"))
sys.path.insert(0, os.path.join(HERE, ".."))
from exr_io import read_exr, rgb_of  # noqa: E402
from accuracy_report.tables import BRIGHTNESS_TOLERANCE  # noqa: E402

BAND_PX = 14  # the study's border band (STUDY_BORDER_PX of study_brightness, study/metrics.c)
SCENES = os.path.join(HERE, "..", "..", "build", "study-cache", "scenes")


def regions(h, w):
    inside = np.zeros((h, w), bool)
    inside[BAND_PX:h - BAND_PX, BAND_PX:w - BAND_PX] = True
    sides = {"top": (slice(0, BAND_PX), slice(None)),
             "bottom": (slice(h - BAND_PX, h), slice(None)),
             "left": (slice(BAND_PX, h - BAND_PX), slice(0, BAND_PX)),
             "right": (slice(BAND_PX, h - BAND_PX), slice(w - BAND_PX, w))}
    return inside, sides


def main(out, scenes):
    print("Mean linear RGB over the truth's, inside / in the %d px border band; ddof's default "
          "preset" % BAND_PX)
    print("")
    print("| scene | margin px | pinhole | ddof, the frame as rendered | ddof, with the margin |")
    print("|---|---:|---|---|---|")
    notes = []
    for s in scenes:
        truth = rgb_of(read_exr(os.path.join(SCENES, s, "truth.exr")))
        h, w = truth.shape[:2]
        with open(os.path.join(out, s + ".margin")) as f:
            m = int(f.read())
        images = [rgb_of(read_exr(os.path.join(SCENES, s, "pinhole.exr"))),
                  rgb_of(read_exr(os.path.join(out, s + "_frame.exr"))),
                  rgb_of(read_exr(os.path.join(out, s + "_margin.exr")))[m:m + h, m:m + w]]
        inside, sides = regions(h, w)
        cells = []
        for img in images:
            cells.append("%.4f / %.4f" % (img[inside].mean() / truth[inside].mean(),
                                          img[~inside].mean() / truth[~inside].mean()))
        print("| %s | %d | %s |" % (s, m, " | ".join(cells)))
        off = ["%s %.4f" % (n, images[2][r].mean() / truth[r].mean())
               for n, r in sides.items()
               if abs(images[2][r].mean() / truth[r].mean() - 1) > BRIGHTNESS_TOLERANCE]
        if off:
            notes.append("%s with the margin, the sides off by more than %g%%: %s"
                         % (s, 100 * BRIGHTNESS_TOLERANCE, ", ".join(off)))
    if notes:
        print("")
        for n in notes:
            print("- " + n)


if __name__ == "__main__":
    if len(sys.argv) < 3:
        raise SystemExit(__doc__)
    main(sys.argv[1], sys.argv[2:])
