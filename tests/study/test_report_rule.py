# SPDX-License-Identifier: MIT
"""ctest `study_report_rule`: study/report.py's preset rule (choose_presets, issue 30) on
made-up results: the bar is the best Defocus node per scene (image and band separately), the
default meets it, the final is the most accurate configuration within a tenth of the best node's
1080p time (the 4.2 / 5.x node's scaled by the 3.4 node's ratio) and beats the bar by 1 dB,
the default beats it by 1 dB too, or else meets it, the report says so in words when no candidate meets a rule, and results of a study before the
smooth far field (no psnr_smooth, a defocus-5.0 node) still report. System python3 + numpy +
matplotlib (exit 77 without them)."""

import json
import os
import sys
import tempfile

try:
    import matplotlib  # noqa: F401
    import numpy  # noqa: F401
except ImportError:
    print("skipped: no numpy/matplotlib for %s" % sys.executable)
    sys.exit(77)

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
sys.path.insert(0, os.path.join(ROOT, "study"))
import report  # noqa: E402

failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


def scene(name, band=True, smooth=True):
    return {"type": "scene", "scene": name, "dir": "/nonexistent/" + name, "width": 480,
            "height": 270, "large_width": 1920, "large_height": 1080, "max_abs_coc_px": 20.0,
            "blurred": True, "band_pixels": 100 if band else 0, "band_fraction": 0.1,
            "smooth_pixels": 100 if smooth else 0}


def diffusion(cid, kernel="heat"):
    return {"kind": "diffusion", "backend": "cpu", "solver": "thomas", "precision": "float",
            "substeps": 2, "beta_scale": 1.0 / 24, "layers": "auto", "kernel": kernel,
            "background": "auto", "background_levels": 1, "near_spread": "auto",
            "near_layer": "auto", "sweeps": "kernel"}


def result(cid, sc, psnr, band, ms_large, ms=10.0, smooth=None, base=None, **extra):
    r = {"type": "result", "id": cid, "scene": sc, "available": True, "ms": ms,
         "ms_large": ms_large, "psnr": psnr, "psnr_band": band}
    if smooth is not None:
        r["psnr_smooth"] = smooth
    r.update(base or {"kind": "baseline"})
    r.update(extra)
    return r


def run(lines, node5="defocus-5.3"):
    """The report on these lines: (chosen, study, markdown text)."""
    report.NODE_IDS[:] = list(report.STUDY_NODE_IDS)
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "results.jsonl")
        with open(path, "w") as f:
            f.write(json.dumps({"type": "machine", "date_utc": "2026-12-04T00:00:00Z"}) + "\n")
            for line in lines:
                f.write(json.dumps(line) + "\n")
        sys.argv = ["report.py", path, "--md", os.path.join(tmp, "a.md"), "--images",
                    os.path.join(tmp, "img"), "--presets", os.path.join(tmp, "p.inc"),
                    "--smoke"]
        report.main()
        study = report.Study([path])
        chosen, _, _ = report.choose_presets(study)
        with open(os.path.join(tmp, "a.md")) as f:
            text = f.read()
    return chosen, study, text


# Two scenes; nodes: 3.4 timed at 1080p (100 s), 4.2 at the scene's size only; 4.2 is the best
# on scene a (image 30, band 28), 3.4 on b (image 32, band 27.5).
SC = ["a", "b"]
nodes = []
for sc, (p34, b34, p42, b42) in zip(SC, [(29.0, 27.0, 30.0, 28.0), (32.0, 27.5, 31.0, 27.0)]):
    nodes.append(result("defocus", sc, p34, b34, 100000.0, ms=400.0, smooth=45.0))
    nodes.append(result("defocus-4.2", sc, p42, b42, None, ms=800.0, smooth=50.0))
    nodes.append(result("pinhole", sc, 15.0, 14.0, 1.0, smooth=20.0))
# Budget: a: 0.1 x (4.2's 800 ms x 100000 / 400) = 20000 ms; b: 0.1 x 100000 = 10000 ms.
configs = {
    # id: (per scene (psnr, band), 1080p ms)
    "cpu/thomas/f32/n1/k0.0625/auto": ([(29.5, 27.5), (31.0, 26.0)], 300.0),   # misses the bar
    "cpu/thomas/f32/disc-2x2/auto": ([(31.2, 29.0), (33.0, 28.4)], 600.0),     # meets it
    "cpu/thomas/f32/disc-3x3/auto": ([(31.5, 29.5), (33.5, 28.6)], 1100.0),    # +1 dB
    "cpu/thomas/f32/disc-2x3/auto": ([(31.6, 29.6), (33.6, 28.7)], 15000.0),   # over b's budget
}
# Accuracy (mean of the image mean and the band mean): n1 28.5, disc-2x2 30.4, disc-3x3 30.775,
# disc-2x3 30.875 (the most accurate): the default is the fastest within 0.5 dB of it that
# beats the bar by 1 dB (disc-2x2 only meets it: its band on b is 0.9 dB above the node's).
lines = [scene(sc) for sc in SC] + nodes
for cid, (per, ms) in configs.items():
    kernel = cid.split("/")[3] if cid.split("/")[3].startswith("disc") else "heat"
    for sc, (p, b) in zip(SC, per):
        lines.append(result(cid, sc, p, b, ms, smooth=p + 10, base=diffusion(cid, kernel)))

chosen, study, text = run(lines)
check(report.final_budget(study, "a")[0] == 20000.0, "budget a %r" % (report.final_budget(
    study, "a"),))
check(report.final_budget(study, "b")[0] == 10000.0, "budget b %r" % (report.final_budget(
    study, "b"),))
check(chosen["default"].id == "cpu/thomas/f32/disc-3x3/auto",
      "default %s, want disc-3x3 (the fastest within 0.5 dB that beats the bar by 1 dB)"
      % chosen["default"].id)
check(chosen["final"].id == "cpu/thomas/f32/disc-3x3/auto",
      "final %s, want disc-3x3 (disc-2x3 is over b's budget)" % chosen["final"].id)
check("| a | 30.00 (4.2) | 28.00 (4.2) |" in text, "bar row of scene a")
check("/ 45.00" not in text or "/ 50.00" in text, "smooth column shows the best node's")
check("No candidate" not in text, "no 'no candidate' note when the rules are met")

# Leave one scene out: on scene a alone every disc is within a's budget and beats its bar by
# 1 dB, so the final chosen without b is disc-2x3 (the most accurate; over b's budget), judged on
# b: image 33.60 / band 28.70 against the bar 32.00 / 27.50, a margin of 1.20 dB; the default
# chosen without b is disc-2x2 (on a it beats the bar by 1 dB), which misses it on b by 0.1.
held = text[text.index("### The presets held out"):]
row_b = [line for line in held.splitlines() if line.startswith("| b |")]
check(len(row_b) == 1 and "33.60 / 28.70 | 1.20 | cpu thomas, disc-2x3" in row_b[0]
      and "| 31.20 / 28.40 | " not in row_b[0],
      "held-out row of b: %r" % row_b)
check(len(row_b) == 1 and "| 33.00 / 28.40 | 0.90 | = | 33.00 / 28.40 | 0.90 | cpu thomas, "
      "disc-2x2" in row_b[0], "the default held out on b (after the preview): %r" % row_b)

# A sweep appended later (ddof-study run --append: a machine record, then its results) replaces
# what it measured again, and the report dates each part.
again = lines + [{"type": "machine", "date_utc": "2026-12-05T00:00:00Z"}] + [
    result("cpu/thomas/f32/disc-2x2/auto", sc, p + 0.5, b + 0.5, 600.0, smooth=p + 10,
           base=diffusion("x", "disc-2x2"))
    for sc, (p, b) in zip(SC, configs["cpu/thomas/f32/disc-2x2/auto"][0])]
chosen, study, text = run(again)
check("Measured 2026-12-04 00:00:00 UTC: 6 configurations; 2026-12-05 00:00:00 UTC: 1 "
      "configuration (`ddof-study run --append`)." in text, "the appended sweep dated")
check(abs(study.by_id["cpu/thomas/f32/disc-2x2/auto"].psnr["a"] - 31.7) < 1e-9,
      "the appended result replaces the first")

# No candidate beats the bar by 1 dB on b's band (disc-3x3 and disc-2x3 0.6 and 0.7 dB above
# it): the default is chosen among those that meet it, disc-2x2, and the report says so.
short_of_margin = []
for line in lines:
    line = dict(line)
    if line.get("type") == "result" and line["scene"] == "b" and line["id"] in (
            "cpu/thomas/f32/disc-3x3/auto", "cpu/thomas/f32/disc-2x3/auto"):
        line["psnr_band"] -= 0.5
    short_of_margin.append(line)
chosen, study, text = run(short_of_margin)
check(chosen["default"].id == "cpu/thomas/f32/disc-2x2/auto",
      "default %s, want disc-2x2 (no candidate beats the bar by 1 dB; it meets it)"
      % chosen["default"].id)
check("No candidate beats the best Defocus node by 1 dB" in text,
      "the default's margin failure said in words")

# The blurred-edge band is part of the bar where a scene has one: disc-2x2 beats the node's
# image and band on a but not where its blurred surfaces meet, so the default is disc-3x3.
edges = []
for line in lines:
    line = dict(line)
    if line.get("type") == "scene" and line["scene"] == "a":
        line["blurred_edge_pixels"] = 100
    if line.get("type") == "result" and line["scene"] == "a":
        line["psnr_blurred_edges"] = {"defocus": 34.0, "defocus-4.2": 35.0, "pinhole": 20.0,
                                      "cpu/thomas/f32/disc-2x2/auto": 34.0}.get(line["id"],
                                                                                  36.0)
    edges.append(line)
chosen, study, text = run(edges)
check(chosen["default"].id == "cpu/thomas/f32/disc-3x3/auto",
      "default %s, want disc-3x3 (disc-2x2 misses the blurred-edge bar)" % chosen["default"].id)
check("The blurred-edge band" in text and "| a | 0.1% |" in text,
      "the blurred-edge band table")

# The default's settings with the scenes' object matte, faster and more accurate than all: an
# input, never a preset; the per-scene tables show it as the default's column.
with_matte = lines + [result("cpu/thomas/f32/disc-2x2/auto+matte", sc, p + 3.0, b + 3.0, 500.0,
                             smooth=p + 10, base=dict(diffusion("m", "disc-2x2"), matte=True))
                      for sc, (p, b) in zip(SC, configs["cpu/thomas/f32/disc-2x2/auto"][0])]
chosen, study, text = run(with_matte)
check(all(not c.id.endswith("+matte") for c in chosen.values()),
      "a configuration with the object matte is never a preset (%s)"
      % [c.id for c in chosen.values()])
check("default + object matte" in text and "| a | 15.00 / 14.00 / 20.00 |" in text,
      "the per-scene table has the default's object-matte column")
check("34.20 / 32.00" in text, "the matte column holds its result on scene a")

# Nothing meets the bar or the margin: the report must say so.
for line in lines:
    if line.get("type") == "result" and line["id"].startswith("cpu/") and line["scene"] == "b":
        line["psnr"] -= 3.0
chosen, study, text = run(lines)
check("No candidate matches or beats the best Defocus node" in text,
      "the default's failure said in words")
check("No candidate within the budget beats the best node by 1 dB" in text,
      "the final's margin failure said in words")
check("Where the final preset falls short" in text, "the final's shortfall listed")

# An older study: no psnr_smooth, no smooth_pixels, the 5.0 node.
old = []
for line in lines:
    line = dict(line)
    line.pop("psnr_smooth", None)
    line.pop("smooth_pixels", None)
    if line.get("id") == "defocus-4.2":
        line["id"] = "defocus-5.0"
    old.append(line)
chosen, study, text = run(old)
check("node 5.0" in text, "the 5.0 node of old results is reported")
check("here: none in these results" in text, "no smooth column on old results")

if failures:
    print("FAILED:\n  " + "\n  ".join(failures))
    sys.exit(1)
print("report rule: ok")
