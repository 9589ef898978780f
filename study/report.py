#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The accuracy-vs-cost report of the study (issue 7): results.jsonl -> docs/accuracy.md, its
plots (docs/images/accuracy_*.png) and libddof/src/api/presets_measured.inc.

    python3 study/report.py RESULTS.jsonl [--md docs/accuracy.md] [--images docs/images]
        [--presets libddof/src/api/presets_measured.inc] [--study-exe build/study/study/ddof-study]
        [--work DIR] [--smoke] [--command "bash study/run.sh"]

RESULTS.jsonl is what `ddof-study run` writes (study/cmd_run.c): a machine line, a line per scene,
a line per (scene, configuration). With --study-exe the crops of the chosen presets and the
baselines are rendered by `ddof-study images` into --work and drawn as a grid.

Needs python3, numpy and matplotlib (Debian: python3-numpy python3-matplotlib).

Everything the report says about the presets comes from the rule in accuracy_report/rule.py,
applied to the measurements: the presets are chosen from the measured front, not by hand. The
modules of accuracy_report/ each do one part (its __init__.py lists them); this file is the
command.
"""

import argparse
import os
import sys

from accuracy_report.bar import final_budget
from accuracy_report.crops import crop_grid
from accuracy_report.formatting import fmt, fmt_ms
from accuracy_report.markdown import write_markdown
from accuracy_report.names import NODE_IDS, STUDY_NODE_IDS
from accuracy_report.plots import draw_plots
from accuracy_report.presets import choose_presets
from accuracy_report.presets_file import write_presets
from accuracy_report.rule import PRESET_ORDER
from accuracy_report.results import Study

# The command, and what tests/study/test_report_rule.py reads from it.
__all__ = ["main", "Study", "choose_presets", "final_budget", "NODE_IDS", "STUDY_NODE_IDS"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("results", nargs="+")
    ap.add_argument("--md", default="docs/accuracy.md")
    ap.add_argument("--images", default="docs/images")
    ap.add_argument("--presets", default="libddof/src/api/presets_measured.inc")
    ap.add_argument("--study-exe", default=None)
    ap.add_argument("--work", default=None)
    ap.add_argument("--smoke", action="store_true")
    ap.add_argument("--command", default="bash study/run.sh")
    args = ap.parse_args()

    study = Study(args.results)
    if not study.scene_order or not study.configs:
        sys.exit("report.py: no results in %s" % ", ".join(args.results))
    os.makedirs(args.images, exist_ok=True)
    os.makedirs(os.path.dirname(os.path.abspath(args.md)), exist_ok=True)

    chosen, front, cands = choose_presets(study)
    plots = draw_plots(study, chosen, front, args.images)

    crops = None
    if chosen and args.study_exe:
        work = args.work or os.path.join(os.path.dirname(os.path.abspath(args.results[0])),
                                         "images")
        p = os.path.join(args.images, "accuracy_crops.png")
        rows = crop_grid(study, chosen, args.study_exe, work, p)
        if rows:
            crops = (p, rows)
    write_markdown(study, chosen, front, cands, args, plots, crops)
    if chosen:
        write_presets(args.presets, chosen, study, args.smoke)
    print("report.py: %s (%d configurations x %d scenes), plots in %s%s"
          % (args.md, len(study.configs), len(study.scene_order), args.images,
             ", presets -> %s" % args.presets if chosen else ""))
    if chosen:
        for n in PRESET_ORDER:
            c = chosen[n]
            print("  %-8s %s: %s ms, accuracy %s dB" % (n, c.id, fmt_ms(c.cost),
                                                        fmt(c.accuracy)))


if __name__ == "__main__":
    main()
