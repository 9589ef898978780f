#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The accuracy-vs-cost report of the study (issue 7): results.jsonl -> docs/accuracy.md, its
plots (docs/images/accuracy_*.png) and libddof/src/presets_measured.inc.

    python3 study/report.py RESULTS.jsonl [--md docs/accuracy.md] [--images docs/images]
        [--presets libddof/src/presets_measured.inc] [--study-exe build/study/study/ddof-study]
        [--work DIR] [--smoke] [--command "bash study/run.sh"]

RESULTS.jsonl is what `ddof-study run` writes (study/main.c): a machine line, a line per scene,
a line per (scene, configuration). With --study-exe the crops of the chosen presets and the
baselines are rendered by `ddof-study images` into --work and drawn as a grid.

Needs python3, numpy and matplotlib (Debian: python3-numpy python3-matplotlib).

Everything the report says about the presets comes from PRESET_RULE below, applied to the
measurements: the presets are chosen from the measured front, not by hand.
"""

import argparse
import json
import math
import os
import subprocess
import sys

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# ---------------------------------------------------------------------------------------------
# The rule that chooses the presets (stated in the report from these constants).

# Accuracy of a configuration: the mean, over the scenes with blur, of its PSNR against the
# Cycles truth over the image and over the band around depth edges (ACCURACY_TEXT).
# Cost: its median time per frame on the CPU at 1920x1080 (at the scenes' size when no 1080p
# frame was measured), mean over the same scenes.
# The preview and the default are the fastest configuration on the front whose accuracy is
# within their tolerance of the most accurate one (the default among those that meet the bar,
# below); the final preset is the most accurate configuration within its time budget (below).
PRESET_TOLERANCE_DB = {"final": 0.1, "default": 0.5, "preview": 2.0}
PRESET_ORDER = ["preview", "default", "final"]  # ddof_preset order
# default and final must be the diffusion: ddof.h promises, for ddof_params_init's settings,
# that in-focus pixels stay untouched and nothing diffuses across them, which the CoD4
# post-process does not keep. The preview may be the CoD4 method.
PRESET_METHODS = {"preview": {"diffusion", "cod4"}, "default": {"diffusion"},
                  "final": {"diffusion"}}
# The bar (issue 30): Blender's Defocus node as users have it, the node of every Blender measured
# (3.4, 4.2 LTS, 5.3: their CoC and quality differ); on each scene the best of them, separately
# for the image PSNR and the band PSNR, is the one to beat.
# default: must match or beat the bar on every scene with blur, image and band (band on the
# scenes that have one): a mean can hide a scene where the preset loses (the 2026-12-02 study's
# fastest point within 0.5 dB, heat n = 4, lost to the node on two of five). Among those the
# tolerance picks; when none does, the report says so and the tolerance alone picks.
# final: the most accurate candidate whose 1080p time is at most FINAL_TIME_FRACTION of the
# best node's on every scene with blur (the node with the best image PSNR there), and that
# beats the bar by FINAL_MARGIN_DB on every such scene, image and band; where none beats it
# by the margin, the most accurate within the budget that meets the bar, then the most accurate
# within the budget; where none is within the budget, the most accurate candidate. The report
# says which of these held.
PRESETS_BEATING_BASELINE = {"default", "final"}
FINAL_TIME_FRACTION = 0.1
FINAL_MARGIN_DB = 1.0
# The nodes ddof-study knows (study_node_names, study/configs.c). Results of an older study
# may name another 5.x node (defocus-5.0): register_nodes adds it, so old results still report.
STUDY_NODE_IDS = ["defocus", "defocus-4.2", "defocus-5.3"]
NODE_IDS = list(STUDY_NODE_IDS)
NODE_NAMES = {"defocus": "Defocus node 3.4", "defocus-4.2": "Defocus node 4.2",
              "defocus-5.3": "Defocus node 5.3"}
BASELINES_TO_BEAT = NODE_IDS
# Only settings a preset can hold and the CPU can run: ddof_params_init_preset sets method,
# solver, substeps, beta_scale, background, background_levels, near_spread, near_layer,
# far_field and silhouettes (Jacobi keeps its default 50 sweeps); no foreground element (that is
# an input, not a setting).
PRESET_SOLVERS = {"thomas", "cr", "pcr", "reference"}
PRESET_LAYERS = {"single", "bg", "bg2", "bgnear", "auto", "auto2", "autospread"}

ACCURACY_TEXT = ("the mean of two means over the scenes with blur: the PSNR over the whole image, "
                 "and the PSNR over the band around depth edges (scenes without such edges count "
                 "in the first mean only)")

SOLVER_C = {"thomas": "DDOF_SOLVER_THOMAS", "cr": "DDOF_SOLVER_CYCLIC_REDUCTION",
            "pcr": "DDOF_SOLVER_PCR", "jacobi": "DDOF_SOLVER_JACOBI",
            "reference": "DDOF_SOLVER_REFERENCE_F64", "gruen": "DDOF_SOLVER_GRUEN"}
LAYER_C = {"on": "DDOF_LAYER_ON", "off": "DDOF_LAYER_OFF", "auto": "DDOF_LAYER_AUTO"}
# Sub-steps and k a disc preset carries for the heat kernel (which the disc ignores): the heat
# default the study chose before the disc kernel existed (n = 2, k = 1/24).
HEAT_FALLBACK = (2, 1.0 / 24)
KERNEL_C = {"heat": "DDOF_KERNEL_HEAT", "disc-2x2": "DDOF_KERNEL_DISC_2X2",
            "disc-2x3": "DDOF_KERNEL_DISC_2X3", "disc-3x3": "DDOF_KERNEL_DISC_3X3"}

LAYERS_TEXT = {
    "single": "single layer (background off, near spread off)",
    "bg": "+ background layer (on, 1 level)",
    "bg2": "+ background layer (on, 2 levels)",
    "bgnear": "+ background + near spread (both on)",
    "auto": "background, near layer and near spread as the planner decides (AUTO; the near "
            "layer takes the near field where it runs)",
    "auto2": "AUTO, 2 background levels",
    "autospread": "AUTO without the near layer (libddof 0.5's AUTO: a blurred near object "
                  "stays opaque, its silhouette spread)",
    "fg": "+ background + the scene's separately rendered foreground element (fg.exr: the near "
          "objects alone) composited over rest.exr (the scene without them), the paper's layers, "
          "where it has one; else near spread on",
    "fgpin": "the same element composited over pinhole.exr (the near objects then lie in the "
             "main image too, as in `ddof pinhole.exr --foreground fg.exr`)",
}

BASELINE_NAMES = {"pinhole": "pinhole input", "cod4": "CoD4 preview", "gather": "gather blur",
                  "defocus": "Blender Defocus node 3.4",
                  "defocus-4.2": "Blender Defocus node 4.2",
                  "defocus-5.3": "Blender Defocus node 5.3"}


def register_nodes(ids):
    """Adds the Defocus nodes of ids (results' ids) that NODE_IDS lacks ("defocus-5.0" from an
    older study) to NODE_IDS and the name tables, ordered by version."""
    for cid in ids:
        if cid.startswith("defocus-") and cid not in NODE_IDS:
            version = cid[len("defocus-"):]
            NODE_IDS.append(cid)
            NODE_NAMES[cid] = "Defocus node %s" % version
            BASELINE_NAMES[cid] = "Blender Defocus node %s" % version
            BASE_NAMES_CAP[cid] = "Blender %s's Defocus node" % version
            BASELINE_STYLE.setdefault(cid, ("olive", "v"))

    def key(cid):
        if cid == "defocus":
            return (3, 4)
        return tuple(int(x) for x in cid[len("defocus-"):].split(".") if x.isdigit())
    NODE_IDS.sort(key=key)


def num(v):
    """JSON value -> float (None and missing -> nan; "inf" -> inf)."""
    if v is None:
        return math.nan
    if isinstance(v, str):
        return math.inf if v == "inf" else math.nan
    return float(v)


def mean(values):
    vals = [v for v in values if not math.isnan(v)]
    return sum(vals) / len(vals) if vals else math.nan


# ---------------------------------------------------------------------------------------------
# Reading


class Study:
    def __init__(self, paths):
        self.machine = {}
        self.scenes = {}        # name -> scene record
        self.scene_order = []
        self.results = {}       # id -> {scene: record}
        self.order = []         # ids in first-seen order
        self.seconds = 0.0
        self.peak_rss = 0.0
        for path in paths:
            with open(path) as f:
                for line in f:
                    line = line.strip()
                    if not line:
                        continue
                    rec = json.loads(line)
                    t = rec.get("type")
                    if t == "machine":
                        if not self.machine:
                            self.machine = rec
                    elif t == "scene":
                        if rec["scene"] not in self.scenes:
                            self.scene_order.append(rec["scene"])
                        self.scenes[rec["scene"]] = rec
                    elif t == "result":
                        cid = rec["id"]
                        if cid not in self.results:
                            self.results[cid] = {}
                            self.order.append(cid)
                        self.results[cid][rec["scene"]] = rec
                    elif t == "done":
                        self.seconds += float(rec.get("seconds", 0.0))
                        self.peak_rss = max(self.peak_rss, float(rec.get("peak_rss_bytes", 0)))
        register_nodes(self.order)
        self.blurred = [s for s in self.scene_order if self.scenes[s].get("blurred")]
        self.with_band = [s for s in self.blurred if self.scenes[s].get("band_pixels", 0) > 0]
        # The smooth far field (study_smooth, study/metrics.c); results before it lack it.
        self.with_smooth = [s for s in self.scene_order
                            if self.scenes[s].get("smooth_pixels", 0) > 0]
        # The silhouette band (study_silhouettes); results before it lack it.
        self.with_silhouette = [s for s in self.blurred
                                if self.scenes[s].get("silhouette_pixels", 0) > 0]
        self.has_large = any(self.scenes[s].get("large_width") for s in self.scene_order)
        self.configs = [Config(cid, self.results[cid], self) for cid in self.order]
        self.by_id = {c.id: c for c in self.configs}


class Config:
    def __init__(self, cid, per_scene, study):
        self.id = cid
        self.per = per_scene
        first = next(iter(per_scene.values()))
        self.first = first
        self.kind = first["kind"]
        self.label = first.get("label", cid)
        self.sweeps = first.get("sweeps", "")
        self.backend = first.get("backend", "cpu")
        self.solver = first.get("solver", "")
        self.jacobi = int(first.get("jacobi_iterations", 50) or 50)
        self.precision = first.get("precision", "")
        self.substeps = first.get("substeps")
        self.k = first.get("beta_scale")
        self.layers = first.get("layers", "")
        self.kernel = first.get("kernel", "heat")
        blurred = study.blurred
        self.available = all(per_scene.get(s, {}).get("available") for s in study.scene_order
                             if s in per_scene) and all(s in per_scene for s in blurred)
        notes = [r.get("note", "") for r in per_scene.values() if r.get("note")]
        self.note = notes[0] if notes else ""

        def col(key, scenes):
            return [num(per_scene.get(s, {}).get(key)) for s in scenes]

        self.ms = mean(col("ms", blurred))
        self.ms_large = math.nan
        self.estimated = False  # 1080p time predicted from the scenes' size (too slow to run)
        if study.has_large:
            large = col("ms_large", blurred)
            if any(math.isnan(v) for v in large):
                est = col("ms_large_estimate", blurred)
                large = [e if math.isnan(v) else v for v, e in zip(large, est)]
                self.estimated = not all(math.isnan(v) for v in large)
            if not any(math.isnan(v) for v in large):
                self.ms_large = mean(large)
        self.psnr = {s: num(per_scene.get(s, {}).get("psnr")) for s in study.scene_order}
        self.band = {s: num(per_scene.get(s, {}).get("psnr_band")) for s in study.scene_order}
        self.smooth = {s: num(per_scene.get(s, {}).get("psnr_smooth"))
                       for s in study.scene_order}
        self.silhouette = {s: num(per_scene.get(s, {}).get("psnr_silhouette"))
                           for s in study.scene_order}
        self.image_mean = mean([self.psnr[s] for s in blurred])
        self.band_mean = mean([self.band[s] for s in study.with_band])
        if any(math.isnan(self.psnr[s]) for s in blurred):
            self.image_mean = math.nan
        if any(math.isnan(self.band[s]) for s in study.with_band):
            self.band_mean = math.nan
        parts = [self.image_mean] + ([self.band_mean] if study.with_band else [])
        self.accuracy = math.nan if any(math.isnan(p) for p in parts) else sum(parts) / len(parts)
        ref = col("ref_psnr", study.scene_order)
        self.ref_psnr = min(ref) if ref and not any(math.isnan(v) for v in ref) else math.nan
        refmax = col("ref_max_abs", study.scene_order)
        self.ref_max = max(refmax) if refmax and not any(math.isnan(v) for v in refmax) \
            else math.nan
        mem = []
        for r in per_scene.values():
            if "host_bytes_large" in r:
                mem.append(num(r.get("host_bytes_large")) + num(r.get("device_bytes_large", 0)))
            elif "host_bytes" in r:
                mem.append(num(r.get("host_bytes")) + num(r.get("device_bytes", 0)))
        self.mem = max(mem) if mem else math.nan
        self.renderer = first.get("renderer", "")
        # the cost used for the front: 1080p when measured, else the scenes' size
        self.cost = self.ms_large if study.has_large else self.ms

    def eligible(self):
        """Whether a preset can hold this configuration (and the CPU run it)."""
        if not self.available or math.isnan(self.accuracy) or math.isnan(self.cost) or \
                self.estimated:
            return False
        if self.kind == "cod4":
            return True
        if self.kind != "diffusion" or self.backend != "cpu":
            return False
        if self.layers not in PRESET_LAYERS or self.precision not in ("float", "double"):
            return False
        return self.solver in PRESET_SOLVERS or (self.solver == "jacobi" and self.jacobi == 50)

    def settings_c(self):
        f = self.first
        if self.kind == "cod4":
            return ("DDOF_METHOD_COD4_PREVIEW", "DDOF_SOLVER_THOMAS", 1, 1.0 / 32,
                    "DDOF_LAYER_AUTO", 1, "DDOF_LAYER_AUTO", "DDOF_KERNEL_HEAT",
                    "DDOF_LAYER_AUTO", "DDOF_LAYER_OFF", "DDOF_LAYER_OFF")
        return ("DDOF_METHOD_DIFFUSION", SOLVER_C[self.solver], int(self.substeps),
                float(self.k), LAYER_C[f["background"]], int(f["background_levels"]),
                LAYER_C[f["near_spread"]], KERNEL_C[self.kernel],
                LAYER_C[f.get("near_layer", "off")], LAYER_C[f.get("far_field", "off")],
                LAYER_C[f.get("silhouettes", "off")])


def k_text(k):
    if k is None:
        return ""
    inv = 1.0 / k
    if abs(inv - round(inv)) < 1e-3 * inv:
        return "1/%d" % round(inv)
    return "%.4g" % k


# ---------------------------------------------------------------------------------------------
# The front and the presets


# A point joins the front only if it is more accurate than every faster point by more than
# this (differences below it are not resolved by the measurement).
FRONT_MIN_GAIN_DB = 0.01


def pareto(points):
    """Configurations not dominated (another at most as slow and more accurate, or faster and
    at least as accurate), fastest first."""
    pts = sorted(points, key=lambda c: (c.cost, -c.accuracy))
    front, best = [], -math.inf
    for c in pts:
        if c.accuracy > best + FRONT_MIN_GAIN_DB:
            front.append(c)
            best = c.accuracy
    return front


def node_value(study, cid, scene, key):
    """A Defocus node's value (psnr, psnr_band, ms, ms_large) on a scene; nan when absent."""
    node = study.by_id.get(cid)
    if node is None or not node.available:
        return math.nan
    r = node.per.get(scene, {})
    return num(r.get(key)) if r.get("available") else math.nan


def best_node(study, scene, key="psnr"):
    """(value, id) of the best Defocus node on the scene by key ("psnr" or "psnr_band");
    (nan, None) when none ran."""
    best = (math.nan, None)
    for cid in BASELINES_TO_BEAT:
        v = node_value(study, cid, scene, key)
        if not math.isnan(v) and (math.isnan(best[0]) or v > best[0]):
            best = (v, cid)
    return best


def best_node_psnr(study, scene):
    """(image PSNR, id) of the best Defocus node on the scene; (nan, None) when none ran."""
    return best_node(study, scene, "psnr")


def bar_misses(c, study, margin=0.0):
    """[(scene, "image" or "band", c's PSNR, the bar + margin)] where c falls short of the best
    node + margin: image PSNR on every scene with blur, band PSNR on those with a band. A scene no
    node ran on has no bar."""
    misses = []
    for s in study.blurred:
        for key, what, value in (("psnr", "image", c.psnr.get(s, math.nan)),
                                 ("psnr_band", "band", c.band.get(s, math.nan))):
            if what == "band" and s not in study.with_band:
                continue
            bar, _ = best_node(study, s, key)
            if math.isnan(bar):
                continue
            if not value >= bar + margin:
                misses.append((s, what, value, bar + margin))
    return misses


def beats_baseline(c, study, margin=0.0):
    """Image and band PSNR at least the best Defocus node's (+ margin) on every scene with
    blur (band: on those with a band)."""
    return not bar_misses(c, study, margin)


def node_time_large(study, cid, scene):
    """(ms at 1920x1080, how) of a Defocus node on a scene: measured; or, where only the scene's
    size was timed (the 4.2 and 5.x nodes unless --bpy-nodes-1080), its scene-size time times
    the 3.4 node's 1080p / scene-size ratio on that scene (all of them gather over the CoC disc,
    a cost of pixels x radius^2); or, without that either, times (pixel ratio)^2 (16x the
    pixels, 4x the radius: 256 at 480x270). (nan, "") when the node did not run."""
    ms_large = node_value(study, cid, scene, "ms_large")
    if not math.isnan(ms_large):
        return ms_large, "measured"
    ms = node_value(study, cid, scene, "ms")
    if math.isnan(ms):
        return math.nan, ""
    a, b = node_value(study, "defocus", scene, "ms"), node_value(study, "defocus", scene,
                                                                 "ms_large")
    if not math.isnan(a) and not math.isnan(b) and a > 0:
        return ms * b / a, "scaled by the 3.4 node's ratio"
    r = study.scenes[scene]
    ratio = 1920.0 * 1080.0 / (float(r["width"]) * float(r["height"]))
    return ms * ratio * ratio, "scaled by (pixel ratio)^2"


def final_budget(study, scene):
    """(budget in ms, the best node's id, its time, how it was timed) of the final preset on a
    scene: FINAL_TIME_FRACTION of the time of the node with the best image PSNR there, at
    1920x1080 (at the scene's size when the study timed no 1080p frame)."""
    _, cid = best_node(study, scene, "psnr")
    if cid is None:
        return math.nan, None, math.nan, ""
    if study.has_large:
        t, how = node_time_large(study, cid, scene)
    else:
        t, how = node_value(study, cid, scene, "ms"), "measured at the scene's size"
    return FINAL_TIME_FRACTION * t, cid, t, how


def within_budget(c, study):
    """Whether c's time is within the final preset's budget on every scene with blur that has
    one (1080p time, or the scene's size without 1080p frames)."""
    for s in study.blurred:
        budget = final_budget(study, s)[0]
        if math.isnan(budget):
            continue
        t = num(c.per.get(s, {}).get("ms_large" if study.has_large else "ms"))
        if not t <= budget:
            return False
    return True


def nodes_ran(study):
    """[(id, Blender versions)] of the Defocus nodes with results, in NODE_IDS order."""
    out = []
    for cid in NODE_IDS:
        node = study.by_id.get(cid)
        if node is None or not node.available:
            continue
        versions = sorted({r.get("blender_version") or "?" for r in node.per.values()
                           if r.get("available")})
        out.append((cid, versions))
    return out


def time_against_node(study, d):
    """The default preset's time per scene as a fraction of each Defocus node's (1080p)."""
    lines = []
    for cid in NODE_IDS:
        node = study.by_id.get(cid)
        if node is None:
            continue
        cells = []
        for sc in study.blurred:
            a, b = d.per.get(sc, {}).get("ms_large"), node.per.get(sc, {}).get("ms_large")
            if a and b and not math.isnan(num(a)) and not math.isnan(num(b)):
                cells.append("%s 1/%.0f (%.0f ms against %.0f ms)"
                             % (sc, num(b) / num(a), num(a), num(b)))
        if cells:
            lines += ["The default preset's time at 1920x1080 as a fraction of the %s's, per "
                      "scene with blur, in this run: %s." % (NODE_NAMES[cid], "; ".join(cells)),
                      ""]
    return lines


def misses_text(misses):
    return "; ".join("%s %s %s < %s" % (sc, what, fmt(v), fmt(bar))
                     for sc, what, v, bar in misses)


def choose_presets(study):
    """(chosen {preset: Config}, the front, the candidates); study.preset_notes gets, per
    preset, the sentences that say how the rule went (which conditions no candidate met)."""
    study.preset_notes = {n: [] for n in PRESET_ORDER}
    cands = [c for c in study.configs if c.eligible()]
    if not cands:
        return None, [], []
    front = pareto(cands)
    best = max(c.accuracy for c in front)
    any_node = any(study.by_id.get(cid) is not None and study.by_id[cid].available
                   for cid in BASELINES_TO_BEAT)
    chosen = {}
    for name in ("preview", "default"):
        tol = PRESET_TOLERANCE_DB[name]
        pool = [c for c in cands if c.kind in PRESET_METHODS[name]] or cands
        if name in PRESETS_BEATING_BASELINE and any_node:
            beating = [c for c in pool if beats_baseline(c, study)]
            if not beating:
                study.preset_notes[name].append(
                    "No candidate matches or beats the best Defocus node on every scene with "
                    "blur (image and band): the %s preset is chosen by the tolerance alone and "
                    "does not meet the bar." % name)
            pool = beating or pool
        ok = [c for c in front if c in pool and c.accuracy >= best - tol]
        if not ok:  # the front's points within tolerance are all of another method
            sub = pareto(pool)
            ok = [c for c in sub if c.accuracy >= best - tol] or \
                [max(sub, key=lambda c: c.accuracy)]
        chosen[name] = min(ok, key=lambda c: (c.cost, -c.accuracy))
        misses = bar_misses(chosen[name], study) if name in PRESETS_BEATING_BASELINE else []
        if misses:
            study.preset_notes[name].append("Where it falls short of the bar: %s dB."
                                            % misses_text(misses))

    # final: the most accurate within the time budget, beating the bar by the margin.
    pool = [c for c in cands if c.kind in PRESET_METHODS["final"]] or cands
    notes = study.preset_notes["final"]
    timed = [c for c in pool if within_budget(c, study)] if any_node else pool
    if any_node and not timed:
        notes.append("No candidate's time is within %g of the best node's on every scene with "
                     "blur: the final preset is the most accurate candidate, over the budget."
                     % FINAL_TIME_FRACTION)
        timed = pool
    tiers = [(FINAL_MARGIN_DB, "beats the best node by %g dB or more on every scene with blur"
              % FINAL_MARGIN_DB), (0.0, "matches or beats the best node on every scene with "
                                        "blur"), (None, "")]
    for margin, text in tiers:
        group = timed if margin is None or not any_node else \
            [c for c in timed if beats_baseline(c, study, margin)]
        if group:
            chosen["final"] = max(group, key=lambda c: (c.accuracy, -c.cost))
            break
        if any_node:
            notes.append("No candidate within the budget %s (image and band)." % text)
    if any_node:
        misses = bar_misses(chosen["final"], study, FINAL_MARGIN_DB)
        if misses:
            notes.append("Where the final preset falls short of the best node + %g dB: %s dB."
                         % (FINAL_MARGIN_DB, misses_text(misses)))
    if chosen["final"].id == chosen["default"].id:
        notes.append("The final preset is the default's configuration: no candidate within "
                     "the budget is more accurate.")
    return chosen, front, cands


def write_presets(path, chosen, study, smoke):
    m = study.machine
    lines = [
        "/* presets_measured.inc - the settings of the three presets, in ddof_preset order.",
        " * Written by study/report.py from the accuracy study (docs/accuracy.md): each preset is "
        "the",
        " * fastest CPU configuration of the measured accuracy-vs-time front within %s dB"
        % "/".join("%g" % PRESET_TOLERANCE_DB[n] for n in PRESET_ORDER),
        " * (preview/default/final) of the most accurate one. Measured %s on %s, %s cores."
        % (m.get("date_utc", "?")[:10], m.get("cpu", "?"), m.get("cores", "?")),
        " * Regenerate with: bash study/run.sh%s" % ("  (THIS IS A SMOKE RUN)" if smoke else ""),
        " * Fields: method, solver, substeps, beta_scale, background, background_levels, "
        "near_spread,",
        " * kernel, near_layer, far_field, silhouettes */",
    ]
    for name in PRESET_ORDER:
        s = chosen[name].settings_c()
        if chosen[name].kind == "cod4":
            # The fields the CoD4 preview ignores keep the default preset's values, so that
            # `--preset preview --method diffusion` is the default diffusion.
            s = (s[0],) + chosen["default"].settings_c()[1:]
        if s[7] != "DDOF_KERNEL_HEAT":
            # A disc ignores sub-steps and k: keep HEAT_FALLBACK's, so that `--kernel heat` on
            # top of the preset is a sensible heat diffusion.
            s = s[:2] + HEAT_FALLBACK + s[4:]
        lines.append("{%s, %s, %d, %sf, %s, %d, %s, %s, %s, %s, %s}, /* %s */"
                     % (s[0], s[1], s[2], float_c(s[3]), s[4], s[5], s[6], s[7], s[8], s[9],
                        s[10], name))
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(tmp, path)


def float_c(v):
    text = "%.7g" % v
    if "." not in text and "e" not in text:
        text += ".0"
    return text


# ---------------------------------------------------------------------------------------------
# Plots

FAMILY_STYLE = [  # (test, label, colour, marker)
    (lambda c: c.backend not in ("cpu", "blender") and c.kind == "diffusion", "GL backends",
     "tab:purple", "D"),
    (lambda c: c.solver == "jacobi", "Jacobi (approximate)", "tab:red", "v"),
    (lambda c: c.solver in ("cr", "pcr", "reference"), "CR / PCR / double reference",
     "tab:brown", "s"),
    (lambda c: c.kernel != "heat", "CPU Thomas, disc kernel", "tab:cyan", "h"),
    (lambda c: c.layers in ("fg", "fgpin"), "+ foreground element (separate render)",
     "tab:olive", "P"),
    (lambda c: c.kind == "diffusion", "CPU Thomas: sub-steps x k x layers", "tab:blue", "o"),
]
BASELINE_STYLE = {"pinhole": ("black", "x"), "cod4": ("tab:orange", "*"),
                  "gather": ("tab:pink", "X"), "defocus": ("tab:green", "^"),
                  "defocus-4.2": ("darkgreen", "<"), "defocus-5.3": ("lime", ">")}


def family(c):
    for test, label, colour, marker in FAMILY_STYLE:
        if test(c):
            return label, colour, marker
    return "other", "grey", "."


def pareto_plot(study, chosen, front, path, metric, ylabel, title):
    fig, ax = plt.subplots(figsize=(9, 5.6), dpi=110)
    seen = set()
    for c in study.configs:
        y = getattr(c, metric)
        if not c.available or math.isnan(y) or math.isnan(c.cost) or c.kind != "diffusion":
            continue
        label, colour, marker = family(c)
        if c.estimated:
            ax.scatter([c.cost], [y], s=22, facecolors="none", edgecolors=colour, marker=marker,
                       label=None if "est" in seen else "time estimated (not run at 1080p)",
                       zorder=2)
            seen.add("est")
            continue
        ax.scatter([c.cost], [y], s=18, c=colour, marker=marker, alpha=0.6,
                   label=None if label in seen else label, zorder=2)
        seen.add(label)
    for cid, (colour, marker) in BASELINE_STYLE.items():
        c = study.by_id.get(cid)
        if not c or not c.available:
            continue
        y = getattr(c, metric)
        if math.isnan(y):
            continue
        x = c.cost
        name = BASELINE_NAMES[cid]
        if math.isnan(x) or x <= 0:
            ax.axhline(y, color=colour, lw=0.8, ls=":", zorder=1)
            ax.annotate(name + " (no time)", (0.01, y), xycoords=("axes fraction", "data"),
                        fontsize=8, va="bottom")
            continue
        edge = {} if marker in ("x", "+") else {"edgecolors": "black", "linewidths": 0.5}
        ax.scatter([x], [y], s=90, c=colour, marker=marker, label=name, zorder=4, **edge)
    if front and metric == "accuracy":
        ax.plot([c.cost for c in front], [c.accuracy for c in front], "-", color="tab:blue",
                lw=1.2, alpha=0.8, zorder=3, label="front (preset candidates)")
    if chosen:
        names = {}
        for name in PRESET_ORDER:
            names.setdefault(chosen[name].id, []).append(name)
        for cid, preset_names in names.items():
            c = study.by_id[cid]
            y = getattr(c, metric)
            if math.isnan(y):
                continue
            ax.scatter([c.cost], [y], s=160, facecolors="none", edgecolors="red", linewidths=1.6,
                       zorder=5)
            ax.annotate(", ".join(preset_names), (c.cost, y), textcoords="offset points",
                        xytext=(7, -12), fontsize=9, color="red", weight="bold")
    ax.set_xscale("log")
    size = "1920x1080" if study.has_large else "the scenes' size"
    ax.set_xlabel("time per frame at %s, ms (log scale; mean over the scenes with blur)" % size)
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7.5, loc="lower right", framealpha=0.85)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def solver_plot(study, path):
    """The largest difference from the double-precision solve against time, per solver,
    precision and backend at the base settings."""
    fig, ax = plt.subplots(figsize=(8, 4.6), dpi=110)
    floor = 1e-9
    for c in study.configs:
        if c.kind != "diffusion" or not c.available or math.isnan(c.cost):
            continue
        if (c.substeps, k_text(c.k), c.layers, c.kernel) != (4, "1/32", "auto", "heat"):
            continue
        if c.solver == "reference" or math.isnan(c.ref_max):
            continue
        y = max(c.ref_max, floor)
        label, colour, marker = family(c)
        if c.estimated:
            ax.scatter([c.cost], [y], facecolors="none", edgecolors=colour, marker=marker, s=40,
                       zorder=3)
        else:
            ax.scatter([c.cost], [y], c=colour, marker=marker, s=40, zorder=3)
        name = c.solver + ("%d" % c.jacobi if c.solver == "jacobi" else "")
        if c.backend != "cpu":
            name = c.backend + " " + name + (" half" if c.precision == "packed half" else "")
        ax.annotate(name, (c.cost, y), textcoords="offset points", xytext=(5, 3), fontsize=7.5)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("time per frame at %s, ms (log; hollow: estimated)"
                  % ("1920x1080" if study.has_large else "the scenes' size"))
    ax.set_ylabel("largest |difference| from the double-\nprecision solve (linear RGBA; log)")
    ax.set_title("Solver and precision error at the base settings (n = 4, k = 1/32, AUTO)",
                 fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def k_plot(study, path):
    """Accuracy against k for each sub-step count (layers AUTO, CPU Thomas)."""
    fig, ax = plt.subplots(figsize=(8, 4.6), dpi=110)
    any_line = False
    for n, colour in zip((1, 2, 4, 8), ("tab:red", "tab:orange", "tab:blue", "tab:green")):
        pts = sorted((c.k, c.accuracy) for c in study.configs
                     if c.kind == "diffusion" and c.backend == "cpu" and c.solver == "thomas"
                     and c.layers == "auto" and c.substeps == n and c.kernel == "heat"
                     and not math.isnan(c.accuracy))
        if len(pts) < 2:
            continue
        any_line = True
        ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", color=colour, label="n = %d" % n)
    if not any_line:
        plt.close(fig)
        return False
    ax.set_xscale("log", base=2)
    ax.axvline(1.0 / 32, color="grey", ls=":", lw=0.8)
    ax.annotate("1/32 (moments)", (1.0 / 32, ax.get_ylim()[0]), fontsize=8,
                textcoords="offset points", xytext=(3, 5))
    ax.set_xlabel("k in beta = k d^2 (log scale)")
    ax.set_ylabel("accuracy, dB")
    ax.set_title("Calibration of k: accuracy against k per sub-step count (CPU Thomas, AUTO)",
                 fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return True


# ---------------------------------------------------------------------------------------------
# The crop grid


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


# ---------------------------------------------------------------------------------------------
# Markdown


def fmt(v, digits=2, unit=""):
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "–"
    if isinstance(v, float) and math.isinf(v):
        return "exact"
    return ("%." + str(digits) + "f%s") % (v, unit)


def fmt_ms(v, estimated=False):
    if math.isnan(v):
        return "–"
    text = "%.0f" % v if v >= 100 else "%.1f" % v if v >= 1 else "%.2f" % v
    return "~" + text if estimated else text


def fmt_mem(b):
    if math.isnan(b):
        return "–"
    return "%.0f" % (b / 2 ** 20) if b >= 10 * 2 ** 20 else "%.1f" % (b / 2 ** 20)


def fmt_ref(c):
    if c.kind != "diffusion":
        return "–"
    if c.solver == "reference":
        return "(reference)"
    if math.isnan(c.ref_psnr):
        return "–"
    db = "exact" if math.isinf(c.ref_psnr) else "%.0f dB" % c.ref_psnr
    return "%s / %.1e" % (db, c.ref_max)


def silhouette_table(study, chosen):
    """The silhouette band per scene: the presets, the default without the far field and the
    silhouettes' split (libddof 0.7), and the nodes."""
    if not study.with_silhouette:
        return []
    default = chosen["default"]
    before = default.id.replace("+ff", "").replace("+sil", "")
    cols = [("pinhole", "pinhole")] + [(chosen[n].id, n) for n in PRESET_ORDER]
    if before != default.id:
        cols.append((before, "default without far field and split"))
    cols += [(cid, NODE_NAMES[cid].replace("Defocus node", "node")) for cid in NODE_IDS]
    cols = [(cid, name) for cid, name in cols if cid in study.by_id]
    L = ["The silhouette band (issue 29: the pixels within %g px of an in-focus pixel that "
         "borders one with |CoC| >= %g px, `study_silhouettes` in `study/metrics.c`: where the "
         "mixed pixels of thin sharp structure are), PSNR in dB:" % (2, 2), "",
         "| scene | share | " + " | ".join(name for _, name in cols) + " |",
         "|---|---:|" + "---:|" * len(cols)]
    for sc in study.with_silhouette:
        share = 100.0 * study.scenes[sc]["silhouette_pixels"] / (
            study.scenes[sc]["width"] * study.scenes[sc]["height"])
        L.append("| %s | %.1f%% | %s |" % (sc, share, " | ".join(
            fmt(study.by_id[cid].silhouette[sc]) for cid, _ in cols)))
    L.append("")
    return L


def config_name(c):
    if c.kind != "diffusion":
        return BASELINE_NAMES.get(c.id, c.id)
    solver = c.solver + ("%d" % c.jacobi if c.solver == "jacobi" else "")
    prec = {"packed half": " half", "double": " (double)"}.get(c.precision, "")
    layers = c.layers + (" + far field" if c.first.get("far_field", "off") != "off" else "") + \
        (" + silhouettes" if c.first.get("silhouettes", "off") != "off" else "")
    if c.kernel != "heat":
        return "%s %s%s, %s, %s" % (c.backend, solver, prec, c.kernel, layers)
    return "%s %s%s, n=%s, k=%s, %s" % (c.backend, solver, prec, c.substeps, k_text(c.k),
                                         layers)


def table_rows(study, configs, marks):
    head = ("| configuration | ms %s | ms 1080p | MiB | vs double (PSNR / max abs) | "
            "image dB | band dB | accuracy dB |" % scene_size(study))
    out = [head, "|---|---:|---:|---:|---|---:|---:|---:|"]
    for c in configs:
        if not c.available:
            why = short(c.note) if c.note else ""
            if not why.startswith("not available"):
                why = "not available" + (": " + why if why else "")
            out.append("| %s | %s | | | | | | |" % (config_name(c), why))
            continue
        out.append("| %s%s | %s | %s | %s | %s | %s | %s | %s |" % (
            config_name(c), marks.get(c.id, ""), fmt_ms(c.ms), fmt_ms(c.ms_large, c.estimated),
            fmt_mem(c.mem), fmt_ref(c), fmt(c.image_mean), fmt(c.band_mean), fmt(c.accuracy)))
    return out


def short(text, n=110):
    text = " ".join(text.split())
    return text if len(text) <= n else text[:n - 1] + "…"


def scene_size(study):
    """The scenes' own frame sizes (where the errors are measured), e.g. "480x270" or
    "480x270 / 320x180" when they differ."""
    sizes = []
    for name in study.scene_order:
        text = "%dx%d" % (study.scenes[name]["width"], study.scenes[name]["height"])
        if text not in sizes:
            sizes.append(text)
    return " / ".join(sizes)


def per_scene_rows(study, configs, marks):
    names = study.scene_order
    head = "| configuration | " + " | ".join(
        "%s img / band%s" % (n, " / smooth" if n in study.with_smooth else "")
        for n in names) + " |"
    out = [head, "|---|" + "---:|" * len(names)]
    for c in configs:
        if not c.available:
            continue
        cells = []
        for s in names:
            cells.append("%s / %s" % (fmt(c.psnr[s]), fmt(c.band[s])) +
                         (" / %s" % fmt(c.smooth[s]) if s in study.with_smooth else ""))
        out.append("| %s%s | %s |" % (config_name(c), marks.get(c.id, ""), " | ".join(cells)))
    return out


def sweep_table(study, sweep, key, label, marks):
    """The configurations of one one-at-a-time sweep (and the base configuration)."""
    cs = [c for c in study.configs if sweep in c.sweeps.split(",") or
          (sweep in ("solver", "backend") and "base" in c.sweeps.split(","))]
    if not cs:
        return []
    cs = sorted(cs, key=key)
    out = ["", "**%s**" % label, ""]
    out += table_rows(study, cs, marks)
    return out


def spread(study, key):
    """Median over the (scene, configuration) measurements with 3 or more timed calls of
    (max - min) / median, as a percentage."""
    values = []
    for c in study.configs:
        for r in c.per.values():
            runs = r.get(key) or []
            if len(runs) >= 3:
                med = float(np.median(runs))
                if med > 0:
                    values.append((max(runs) - min(runs)) / med)
    return "%.0f%%" % (100 * float(np.median(values))) if values else "–"


def describe_machine(m, study, blender_version):
    mem = m.get("memory_bytes")
    gl = m.get("gl", {})
    lines = [
        "- CPU: %s, %s cores online (%s threads used by the CPU contexts)%s"
        % (m.get("cpu", "?"), m.get("cores", "?"), m.get("threads", "?"),
           "; AVX-512" if m.get("avx512") else ""),
        "- memory: %s GiB; OS: %s (%s)" % ("%.0f" % (mem / 2 ** 30) if mem else "?",
                                            m.get("os", "?"), m.get("kernel", "?")),
        "- compiler: %s, build type %s; ddof %s" % (m.get("compiler", "?"),
                                                    m.get("build_type", "?"),
                                                    m.get("ddof_version", "?")),
        "- Blender (scenes, truth and the 3.4 Defocus node): %s" % (blender_version or
                                                                     "unknown"),
        "- Defocus nodes that ran: %s" % ("; ".join(
            "%s (Blender %s)" % (cid, ", ".join(v)) for cid, v in nodes_ran(study)) or "none"),
    ]
    for name in ("osmesa", "egl"):
        g = gl.get(name, {})
        if g.get("available"):
            lines.append("- GL %s: %s%s" % (name, g.get("renderer", "?"),
                                            " (hardware)" if g.get("hardware") else ""))
        else:
            lines.append("- GL %s: not available (%s)" % (name, short(g.get("why", "?"), 160)))
    lines.append("- sweep: %.0f s of measuring%s; peak memory of the process %.0f MiB"
                 % (study.seconds, "", study.peak_rss / 2 ** 20))
    return lines


BASE_ID = "cpu/thomas/f32/n4/k0.03125/auto"


def cfg_id(n=4, k="0.03125", layers="auto", solver="thomas", backend="cpu", prec="f32"):
    return "%s/%s/%s/n%d/k%s/%s" % (backend, solver, prec, n, k, layers)


def near_layer_findings(study, fg_scenes):
    """The near layer against the near spread it replaces and the separately rendered element,
    with the disc-2x2 kernel (the default's), per scene with a near element."""
    by = study.by_id
    ids = {name: "cpu/thomas/f32/disc-2x2/%s" % name for name in ("autospread", "auto", "fg")}
    if not fg_scenes or not all(x in by and by[x].available for x in ids.values()):
        return []
    parts = []
    for sc in fg_scenes:
        img = [by[ids[n]].psnr.get(sc, math.nan) for n in ("autospread", "auto", "fg")]
        band = [by[ids[n]].band.get(sc, math.nan) for n in ("autospread", "auto", "fg")]
        parts.append("%s: near layer off %s / %s dB, on %s / %s dB, separate element %s / %s dB"
                     % (sc, fmt(img[0]), fmt(band[0]), fmt(img[1]), fmt(band[1]), fmt(img[2]),
                        fmt(band[2])))
    cost = [by[ids[n]].cost for n in ("autospread", "auto")]
    return ["**The near layer** (disc-2x2, image / band PSNR): " + "; ".join(parts) +
            ". Time per frame at 1920x1080, mean over the scenes with blur: %s ms off, %s ms on "
            "(the near layer runs only on frames with a blurred near silhouette)."
            % (fmt_ms(cost[0]), fmt_ms(cost[1]))]


def findings(study):
    """Sentences that read the measurements: each states numbers, none a judgement made by
    hand."""
    out = []
    by = study.by_id

    def acc(cid):
        c = by.get(cid)
        return c.accuracy if c and c.available else math.nan

    def cost(cid):
        c = by.get(cid)
        return c.cost if c and c.available else math.nan

    items = []
    # sub-steps
    pts = [(n, acc(cfg_id(n=n)), cost(cfg_id(n=n))) for n in (1, 2, 4, 8)]
    pts = [p for p in pts if not math.isnan(p[1])]
    if len(pts) > 1:
        items.append("**Sub-steps** (k = 1/32, AUTO): " + ", ".join(
            "n = %d: %.2f dB in %s ms" % (n, a, fmt_ms(t)) for n, a, t in pts) + ".")
    # k
    best_k = []
    for n in (1, 2, 4, 8):
        cs = [c for c in study.configs if c.kind == "diffusion" and c.backend == "cpu" and
              c.solver == "thomas" and c.layers == "auto" and c.substeps == n and
              c.kernel == "heat" and c.available and not math.isnan(c.accuracy)]
        if len(cs) > 2:
            b = max(cs, key=lambda c: c.accuracy)
            m = next((c for c in cs if k_text(c.k) == "1/32"), None)
            best_k.append("n = %d: k = %s, %.2f dB%s" % (
                n, k_text(b.k), b.accuracy,
                " (1/32: %.2f dB)" % m.accuracy if m and m is not b else ""))
    if best_k:
        items.append("**k** giving the best accuracy (layers AUTO): " + "; ".join(best_k) +
                     ". (k = 1/32 is the match of second moments with a uniform disk.)")
    # layers
    lay = [(lname, acc(cfg_id(layers=lname)), cost(cfg_id(layers=lname)))
           for lname in ("single", "bg", "bg2", "bgnear", "auto", "auto2")]
    lay = [x for x in lay if not math.isnan(x[1])]
    if len(lay) > 1:
        items.append("**Layers** (n = 4, k = 1/32): " + ", ".join(
            "%s %.2f dB in %s ms" % (lname, a, fmt_ms(t)) for lname, a, t in lay) + ".")
    # the foreground element
    fg_scenes = [sc for sc in study.blurred if study.scenes[sc].get("fg_element")]
    if fg_scenes and all(x in by for x in (cfg_id(), cfg_id(layers="fg"))):
        parts = []
        for sc in fg_scenes:
            vals = [by[x].psnr.get(sc, math.nan) if x in by else math.nan
                    for x in (cfg_id(), cfg_id(layers="fg"), cfg_id(layers="fgpin"))]
            parts.append("%s: AUTO %s dB, element over the rest %s dB, element over the pinhole "
                         "%s dB" % (sc, fmt(vals[0]), fmt(vals[1]), fmt(vals[2])))
        items.append("**The foreground element** (image PSNR, n = 4, k = 1/32): " +
                     "; ".join(parts) + ".")
    # the near layer, on the default kernel
    items += near_layer_findings(study, fg_scenes)
    # solvers
    exact = [by[x] for x in (cfg_id(), cfg_id(solver="cr"), cfg_id(solver="pcr"))
             if x in by and by[x].available]
    if exact:
        items.append("**Exact solvers** (Thomas, CR, PCR) differ from the double-precision "
                     "solve by at most %.1e (linear RGBA); their accuracy against the truth "
                     "differs by at most %.3f dB." % (
                         max(c.ref_max for c in exact),
                         max(c.accuracy for c in exact) - min(c.accuracy for c in exact)))
    jac = [(it, by[cfg_id(solver="jacobi%d" % it)]) for it in (10, 50, 200, 1000)
           if cfg_id(solver="jacobi%d" % it) in by and by[cfg_id(solver="jacobi%d" % it)].available]
    if jac and BASE_ID in by:
        items.append("**Jacobi**: " + "; ".join(
            "%d sweeps %.1e from the exact solve, %+.2f dB against the truth, %s ms" % (
                it, c.ref_max, c.accuracy - by[BASE_ID].accuracy,
                fmt_ms(c.cost, c.estimated)) for it, c in jac) +
            " (differences in accuracy relative to Thomas).")
    # baselines
    base = by.get(BASE_ID)
    if base:
        for cid in NODE_IDS + ["gather", "cod4"]:
            c = by.get(cid)
            if not c or not c.available:
                continue
            better = [sc for sc in study.blurred
                      if c.psnr.get(sc, math.nan) > base.psnr.get(sc, math.nan)]
            items.append("**%s** against the base configuration: accuracy %s vs %s dB; better "
                         "image PSNR on %s." % (BASE_NAMES_CAP.get(cid, cid), fmt(c.accuracy),
                                                fmt(base.accuracy),
                                                ", ".join(better) if better else "no scene"))
    if items:
        out += ["### What the numbers say", ""] + ["- " + x for x in items] + [""]
    return out


def bar_table(study, chosen):
    """The bar per scene with blur: the best node's image and band PSNR, the final preset's
    time budget, and how the default and final presets stand against it."""
    if not any(study.by_id.get(cid) is not None and study.by_id[cid].available
               for cid in BASELINES_TO_BEAT):
        return ["No Defocus node ran: there is no bar.", ""]
    size = "1080p" if study.has_large else scene_size(study)
    out = ["| scene | bar: image dB (node) | bar: band dB (node) | final's budget: %g x the "
           "best node's ms %s | default image / band | final image / band |"
           % (FINAL_TIME_FRACTION, size), "|---|---:|---:|---:|---:|---:|"]
    for s in study.blurred:
        img, img_id = best_node(study, s, "psnr")
        band, band_id = best_node(study, s, "psnr_band")
        budget, cid, t, how = final_budget(study, s)

        def node_short(cid):
            return NODE_NAMES.get(cid, cid).replace("Defocus node ", "") if cid else "–"

        budget_text = "–" if math.isnan(budget) else "%s (%s: %s ms, %s)" % (
            fmt_ms(budget), node_short(cid), fmt_ms(t), how)
        cells = []
        for n in ("default", "final"):
            c = chosen[n]
            cells.append("%s / %s" % (fmt(c.psnr[s]), fmt(c.band[s]) if s in study.with_band
                                      else "–"))
        out.append("| %s | %s (%s) | %s | %s | %s |" % (
            s, fmt(img), node_short(img_id),
            "%s (%s)" % (fmt(band), node_short(band_id)) if s in study.with_band else "–",
            budget_text, " | ".join(cells)))
    out.append("")
    return out


BASE_NAMES_CAP = {"defocus": "Blender 3.4's Defocus node",
                  "defocus-4.2": "Blender 4.2's Defocus node",
                  "defocus-5.3": "Blender 5.3's Defocus node", "gather": "The gather blur",
                  "cod4": "The CoD4 preview"}


def write_markdown(study, chosen, front, cands, args, plots, crops):
    m = study.machine
    opts = m.get("options", {})
    md_dir = os.path.dirname(os.path.abspath(args.md))

    def rel(p):
        return os.path.relpath(os.path.abspath(p), md_dir)

    blender = sorted({study.scenes[s].get("blender", "") for s in study.scene_order} - {""})
    small = scene_size(study)
    marks = {}
    front_ids = {c.id for c in front}
    for c in study.configs:
        if c.id in front_ids:
            marks[c.id] = " ◆"
    if chosen:
        for n in PRESET_ORDER:
            marks[chosen[n].id] = marks.get(chosen[n].id, "") + " **%s**" % n
    L = []
    L.append("# Accuracy versus cost")
    L.append("")
    if args.smoke:
        L.append("> **Smoke run** (`bash study/run.sh --smoke`): one tiny scene and two "
                 "configurations, to keep the study's code from rotting. The numbers mean "
                 "nothing; the real report is `docs/accuracy.md` from `bash study/run.sh`.")
        L.append("")
    L.append("What each knob of ddof costs in time and buys in accuracy, measured against "
             "physically based ground truth (Cycles renders with lens depth of field) on "
             "procedural scenes, with the baselines users already have. This page is generated: "
             "`%s` renders the scenes (cached), runs the sweep and rewrites this file, its "
             "plots and `libddof/src/presets_measured.inc`; nothing here is edited by hand. "
             "`study/README.md` says how it works." % args.command)
    L.append("")
    L.append("Measured %s." % m.get("date_utc", "?").replace("T", " ").replace("Z", " UTC"))
    L.append("")
    L += describe_machine(m, study, ", ".join(blender))
    L.append("")

    # --- scenes
    L.append("## Scenes")
    L.append("")
    L.append("Rendered by `study/scenes/make_scenes.py` (Blender, Cycles): the pinhole colour + "
             "depth that ddof gets, and the same camera with lens depth of field as the truth "
             "(`study/scenes/README.md` describes each scene; `bundled_sample` is the "
             "bundled sample, `samples/`, rendered by `samples/make_sample.py`: a lit scene "
             "where the others are emission-only). Errors are measured at %s; "
             "times at that size and at 1920x1080 (a 1080p pinhole render of the same scene)."
             % small)
    L.append("")
    ran_nodes = [cid for cid in NODE_IDS if study.by_id.get(cid) is not None]
    L.append("| scene | size | largest CoC (px) | band | smooth far field | foreground element "
             "| pinhole dB (image / band) | Defocus node times (%s) |"
             % "; ".join(NODE_NAMES[cid].replace("Defocus node ", "") for cid in ran_nodes))
    L.append("|---|---|---:|---:|---:|---|---:|---:|")
    pin = study.by_id.get("pinhole")

    def node_time(cid, s):
        dfc = study.by_id.get(cid)
        if not (dfc and s in dfc.per and dfc.per[s].get("available")):
            return "–"
        a, b = num(dfc.per[s].get("ms")), num(dfc.per[s].get("ms_large"))
        return "%s ms%s" % (fmt_ms(a), (" (1080p %s ms)" % fmt_ms(b)) if not math.isnan(b)
                            else "")

    for s in study.scene_order:
        r = study.scenes[s]
        dtime = "; ".join(node_time(cid, s) for cid in ran_nodes) or "–"
        L.append("| %s | %dx%d%s | %.1f | %.1f%% | %s | %s | %s | %s |" % (
            s, r["width"], r["height"],
            " + %dx%d" % (r["large_width"], r["large_height"]) if r.get("large_width") else "",
            r["max_abs_coc_px"], 100 * r["band_fraction"],
            "%.1f%%" % (100 * r["smooth_fraction"]) if "smooth_fraction" in r else "–",
            "yes" + (" (upscaled for 1080p timing)" if r.get("fg_resampled_large") else "")
            if r.get("fg_element") else "no",
            "%s / %s" % (fmt(pin.psnr[s]), fmt(pin.band[s])) if pin else "–", dtime))
    L.append("")
    L.append("Scenes with blur (largest CoC >= 1 px), over which means are taken: %s. "
             "Scenes with a band: %s." % (", ".join(study.blurred) or "none",
                                          ", ".join(study.with_band) or "none"))
    L.append("")

    # --- metrics
    L.append("## What is measured")
    L.append("")
    L.append("- **Error against the truth**: PSNR over R, G, B of sRGB-encoded values clamped to "
             "[0, 1], peak 1: exactly what `ddof --compare` and `bash scripts/demo.sh` print "
             "(`plugin/apps/cli/compare.c`; the study links that code). *image*: every pixel; "
             "*band*: the pixels around depth edges.")
    L.append("- **The band**: a depth edge is a pair of 4-neighbours whose signed CoC differs "
             "by at least 2 px (a depth discontinuity that changes the blur); every pixel within "
             "max(4 px, half the larger |CoC| of the pair) of either pixel (Euclidean distance) "
             "is in the band: the reach of the blur that crosses the edge, where bleeding and "
             "missing partial occlusion show. A smooth depth ramp (the receding plane) has no "
             "band.")
    L.append("- **The smooth far field** (*smooth*): the pixels with |CoC| > 8 px, no pixel of "
             "a depth edge (as above) within 12 px (or within half the pair's larger |CoC| "
             "where that is more), and no highlight reaching them (an input or truth pixel "
             "brighter than 1 excludes the pixels within its own |CoC| / 2 + 2 px): plain "
             "blurred texture, where the blur kernel's shape alone makes the error "
             "(`study_smooth`, `study/metrics.c`). Shown per scene; not part of the accuracy.")
    L.append("- **Accuracy** (the y axis of the front): %s." % ACCURACY_TEXT)
    L.append("- **Error against the double-precision solve** (*vs double*): the same settings "
             "with `DDOF_SOLVER_REFERENCE_F64` (double throughout, one thread) on the CPU; PSNR "
             "as above (worst scene) and the largest absolute difference of linear RGBA values "
             "(largest over the scenes). This isolates solver and precision error from "
             "modelling error.")
    L.append("- **Time**: the whole `ddof_diffuse_layers` call (planner, layers, solves; the "
             "signed CoC is computed once beforehand from the camera with "
             "`ddof_coc_from_camera`, %.2f ms at 1080p), median of up to %d (%s) or %d "
             "(1080p) calls after one warm-up call, each size in a fresh context; a call over "
             "1 s is measured once; a call that the %s time predicts (x the pixel ratio) to "
             "take "
             "over %g s is not run at 1080p: its time is shown as ~estimate and it is no preset "
             "candidate. Mean over the scenes with blur. Spread of the timed calls (max - min "
             "over the median, median over the configurations): %s at %s, %s at 1080p. The "
             "Defocus node's time is the compositing step only (`seconds_median` of "
             "`defocus.json`: the median of its timed composites after a warm-up; a warm-up "
             "over 20 s is itself the measurement); the pinhole's is one copy of the frame."
             % (mean([num(study.scenes[s].get("coc_ms_large")) for s in study.scene_order]),
                opts.get("reps", 5), small, opts.get("large_reps", 3), small,
                opts.get("large_limit_s", 5), spread(study, "ms_runs"), small,
                spread(study, "ms_large_runs")))
    L.append("- **Memory** (MiB): `ddof_stats.host_bytes + device_bytes` of the 1080p call "
             "(the working memory the context holds, besides the caller's images), largest over "
             "the scenes.")
    L.append("")

    # --- presets
    L.append("## Presets")
    L.append("")
    if chosen:
        L.append("The rule (`choose_presets` in `study/report.py`): candidates are the "
                 "configurations a preset can hold and the CPU (the default backend) can run: "
                 "the diffusion with solver %s (Jacobi only with its default 50 sweeps, which a "
                 "preset cannot change) and layers %s, without a foreground element (an input, "
                 "not a setting), and the CoD4 preview. Their accuracy-vs-time front (%d of %d "
                 "candidates; a point joins it only when it is more accurate than every faster "
                 "point by more than %g dB) is taken. The time is the CPU time per frame at %s. "
                 "**The bar** is Blender's Defocus node as users have it: on each scene the best "
                 "of the nodes that ran (3.4, 4.2 LTS, 5.3), for the image PSNR and for the "
                 "band PSNR separately. "
                 "**preview**: the fastest point of the front within %g dB of the most accurate "
                 "point (it may be the CoD4 preview, and then its ignored fields keep the "
                 "default preset's values). "
                 "**default**: the diffusion (ddof.h promises for the default settings that "
                 "in-focus pixels stay untouched and nothing diffuses across them, which the "
                 "CoD4 post-process does not keep) matching or beating the bar on every scene "
                 "with blur, image and band (band on the scenes that have one; a mean can hide "
                 "a scene where a preset loses); among those the fastest point within %g dB "
                 "of the most accurate point (or, when none is within it, the most accurate); "
                 "when no candidate meets the bar, the tolerance alone picks and the report "
                 "says so below. "
                 "**final**: the most accurate diffusion candidate whose time is at most %g of "
                 "the best node's (on each scene with blur, the node with the best image PSNR "
                 "there) and which beats the bar by %g dB on every scene with blur, image and "
                 "band; when none beats it by that margin, the most accurate within the time "
                 "budget that meets the bar, then the most accurate within the budget; when "
                 "none is within the budget, the most accurate candidate; the lines below say "
                 "which held. The 4.2 and 5.x nodes are timed at the scenes' size only unless "
                 "`--bpy-nodes-1080`: their 1080p time is their scene-size time times the 3.4 "
                 "node's 1080p / scene-size ratio on the same scene (every version gathers "
                 "over the CoC disc, a cost of pixels x radius^2), or times the pixel ratio "
                 "squared where the 3.4 node has no 1080p time. "
                 "The default beta calibration k (`ddof_params_init`) is the default preset's."
                 % (", ".join(sorted(PRESET_SOLVERS | {"jacobi"})),
                    ", ".join(sorted(PRESET_LAYERS)), len(front), len(cands),
                    FRONT_MIN_GAIN_DB, "1920x1080" if study.has_large else "the scenes' size",
                    PRESET_TOLERANCE_DB["preview"], PRESET_TOLERANCE_DB["default"],
                    FINAL_TIME_FRACTION, FINAL_MARGIN_DB))
        L.append("")
        L += bar_table(study, chosen)
        for n in PRESET_ORDER:
            for note in getattr(study, "preset_notes", {}).get(n, []):
                L.append("- **%s**: %s" % (n, note))
        if any(getattr(study, "preset_notes", {}).get(n) for n in PRESET_ORDER):
            L.append("")
        L.append("| preset | settings | ms %s | ms 1080p | image dB | band dB | accuracy dB |"
                 % small)
        L.append("|---|---|---:|---:|---:|---:|---:|")
        best = max(c.accuracy for c in front)
        for n in PRESET_ORDER:
            c = chosen[n]
            L.append("| **%s** | %s | %s | %s | %s | %s | %s (best %s) |" % (
                n, config_name(c), fmt_ms(c.ms), fmt_ms(c.ms_large), fmt(c.image_mean),
                fmt(c.band_mean), fmt(c.accuracy), fmt(best)))
        if pin:
            L.append("| *pinhole* | the input | | | %s | %s | %s |"
                     % (fmt(pin.image_mean), fmt(pin.band_mean), fmt(pin.accuracy)))
        L.append("")
        d = chosen["default"]
        if d.kind == "diffusion" and d.kernel != "heat":
            L.append("The default preset draws discs (kernel %s), which have no sub-steps or k; "
                     "it carries n = %d, k = %s for the heat kernel (`--kernel heat`)."
                     % (d.kernel, HEAT_FALLBACK[0], k_text(HEAT_FALLBACK[1])))
        elif d.kind == "diffusion":
            L.append("Default k: **%s** (%.6g), the default preset's." % (k_text(d.k), d.k))
        L.append("")
        L.append("Written to `libddof/src/presets_measured.inc`, which `ddof_params_init_preset` "
                 "(and through it the `ddof` command's `--preset` and the Blender add-on) uses.")
    else:
        L.append("No configuration qualified as a preset candidate in this run.")
    L.append("")

    # --- presets against the baselines, per scene
    if chosen:
        cols = [("pinhole", "pinhole")]
        cols += [(chosen[n].id, n) for n in PRESET_ORDER]
        d = chosen["default"]
        parts = d.id.split("/")
        fg_id = "/".join(parts[:-1] + ["fg"])  # the layers are the id's last part if d.kind == "diffusion" else None
        spread_id = "/".join(parts[:-1] + ["autospread"])
        if d.kind == "diffusion" and parts[-1] == "auto" and spread_id in study.by_id:
            cols.append((spread_id, "default, near layer off"))
        if fg_id in study.by_id and any(study.scenes[x].get("fg_element")
                                        for x in study.scene_order):
            cols.append((fg_id, "default + fg element"))
        cols += [("cod4", "CoD4"), ("gather", "gather")] + [
            (cid, NODE_NAMES[cid].replace("Defocus node", "node")) for cid in NODE_IDS]
        cols = [(cid, name) for cid, name in cols if cid in study.by_id]
        L.append("### The presets against the baselines, per scene")
        L.append("")
        L.append("PSNR against the truth, image / band (dB), and / smooth on the scenes with "
                 "a smooth far field (here: %s; the pixels with |CoC| > 8 px, no depth edge "
                 "within 12 px and no highlight brighter than 1 reaching them: `study_smooth` in "
                 "`study/metrics.c`, `study/README.md`); – where a scene has no band or a "
                 "result no smooth PSNR (a study before it). *bar*: the best Defocus node's "
                 "value on the scene, each metric separately. *default, near layer off*: the "
                 "default preset's settings with the near layer off (libddof 0.5's AUTO: the near "
                 "spread instead); *default + fg element*: the default "
                 "preset's settings with the scene's separately rendered foreground element over "
                 "the rest of the scene (scenes that have one; the others: near spread on)."
                 % (", ".join(study.with_smooth) or "none in these results"))
        L.append("")
        L.append("| scene | " + " | ".join(name for _, name in cols) + " | bar |")
        L.append("|---|" + "---:|" * (len(cols) + 1))

        def cell(values, smooth):
            return " / ".join(fmt(v) for v in (values if smooth else values[:2]))

        for sc in study.scene_order:
            smooth = sc in study.with_smooth
            cells = []
            for cid, _ in cols:
                c = study.by_id[cid]
                r = c.per.get(sc, {})
                if not r.get("available"):
                    cells.append("–")
                else:
                    cells.append(cell([c.psnr[sc], c.band[sc], c.smooth[sc]], smooth))
            cells.append(cell([best_node(study, sc, k)[0]
                               for k in ("psnr", "psnr_band", "psnr_smooth")], smooth))
            L.append("| %s | %s |" % (sc, " | ".join(cells)))
        L.append("")
        L += silhouette_table(study, chosen)
        L += time_against_node(study, chosen["default"])
        picture = os.path.join(args.images, "near_layer.png")
        if not args.smoke and os.path.exists(picture):
            L.append("![The scenes with a blurred near object: the input, ddof without and with "
                     "the near layer, the separately rendered element, the truth](%s)"
                     % rel(picture))
            L.append("")
            L.append("The scenes with a blurred near object (`scripts/near_layer_image.py`, run "
                     "by `study/run.sh`): the pinhole input, the default without the near layer "
                     "(the object opaque, its silhouette spread), the default (the near layer: "
                     "the object turns see-through over a fill of what it hid), the separately "
                     "rendered element over the rest (what the layers give when the hidden part "
                     "is known), Cycles' lens depth of field.")
            L.append("")
    L += findings(study)

    # --- plots
    L.append("## The front")
    L.append("")
    for p, alt in plots:
        L.append("![%s](%s)" % (alt, rel(p)))
        L.append("")
    L.append("Front (◆ in the tables), fastest first:")
    L.append("")
    L += table_rows(study, front, marks)
    L.append("")

    if crops:
        L.append("## Hard edges")
        L.append("")
        L.append("![Crops at hard edges](%s)" % rel(crops[0]))
        L.append("")
        L.append("Each row is the %s window of a scene where the pinhole differs most from the "
                 "truth inside the band (around depth edges), enlarged without interpolation, as "
                 "sRGB clamped to [0, 1] (what the PSNR measures). Columns: the input, the truth, "
                 "the three presets%s, the baselines." % (
                     "square", ", the default preset's settings with the scene's separately "
                     "rendered foreground element composited over the rest of the scene (scenes "
                     "that have one)" if any(study.scenes[s].get("fg_element")
                                             for s in study.blurred) else ""))
        L.append("")

    # --- knobs
    L.append("## The knobs")
    L.append("")
    L.append("Each knob is swept one at a time around the base configuration (CPU, Thomas, "
             "n = 4, k = 1/32, layers AUTO); sub-steps x k x layers, which interact, are swept "
             "as a cross product on the CPU Thomas solver.")
    L.append("")
    L.append("- **solver**: Thomas (LU, the CPU default), CR (cyclic reduction), PCR (parallel "
             "cyclic reduction) solve the same systems exactly: their differences are rounding. "
             "Jacobi with a fixed number of sweeps (10 to 1000) is approximate: it shows what "
             "an iterative solver costs in "
             "accuracy. Gruen's solver exists on the GL backends only.")
    L.append("- **sub-steps n**: n ADI steps of beta/n each; the kernel goes from a diamond-"
             "shaped exponential (n = 1) towards a Gaussian, at linear cost.")
    L.append("- **precision**: float (all CPU solvers; Thomas keeps its running value in "
             "double where beta exceeds 65,536 gamma), double (the reference solver, one "
             "thread), packed half (GL Gruen: a, b, c and x in one RGBA32UI texel).")
    L.append("- **k** in beta = k d^2: the calibration of the blur size; k = 1/32 matches the "
             "second moments of a uniform disk of diameter d.")
    L.append("- **layers**: " + "; ".join("*%s*: %s" % (k, v) for k, v in LAYERS_TEXT.items())
             + ".")
    L.append("- **backend**: the CPU, or the GL plugin through OSMesa (software) or EGL (a GPU "
             "when one is found, else Mesa's software renderer); configurations of a backend "
             "that cannot be opened on this machine are listed as not available.")
    L.append("- **baselines**: the pinhole input (no blur), the CoD4 post-process DOF (GPU Gems "
             "3 ch. 28, `DDOF_METHOD_COD4_PREVIEW`), a naive gather blur by CoC "
             "(`study/baselines/`, it bleeds sharp objects into their blurred background), and "
             "Blender's compositor Defocus node on the same pinhole input "
             "(`study/scenes/defocus_node.py`), as Blender 3.4 (Debian's: `defocus`), 4.2 LTS "
             "(`defocus-4.2`) and 5.3 (`defocus-5.3`; PyPI's bpy) have it. Up to 4.1 the "
             "node's f-stop is a blur amount (f-stop N x 1000 / sensor mm matches Cycles); "
             "from 4.2 the node computes a thin-lens CoC and gets N x S1 / (S1 - f) (S1 the "
             "focus distance, f the focal length). Ran here: %s."
             % ("; ".join("%s (Blender %s)" % (cid, ", ".join(v)) for cid, v in nodes_ran(study))
                or "none"))
    L.append("")

    def k_key(c):
        return (c.k or 0)

    L += sweep_table(study, "solver", lambda c: (c.solver, c.jacobi), "Solvers and precision",
                     marks)
    L += sweep_table(study, "substeps", lambda c: c.substeps or 0, "Sub-steps", marks)
    L += sweep_table(study, "k", k_key, "k", marks)
    L += sweep_table(study, "layers", lambda c: list(LAYERS_TEXT).index(c.layers)
                     if c.layers in LAYERS_TEXT else 99, "Layers", marks)
    L += sweep_table(study, "backend", lambda c: (c.backend, c.solver, c.precision),
                     "Backends", marks)
    base = [c for c in study.configs if c.kind != "diffusion"]
    if base:
        L += ["", "**Baselines**", ""] + table_rows(study, base, marks)
    L.append("")

    # --- everything
    L.append("## All configurations")
    L.append("")
    L.append("Sorted by accuracy; ◆ marks the front of the preset candidates. *ms*: median time "
             "per frame; *vs double*: error against the double-precision solve of the same "
             "settings; *image*, *band*, *accuracy*: PSNR against the truth (means over the "
             "scenes with blur).")
    L.append("")
    ordered = sorted(study.configs, key=lambda c: (not c.available,
                                                   -(c.accuracy if not math.isnan(c.accuracy)
                                                     else -1e9)))
    L.append("<details><summary>%d configurations</summary>" % len(ordered))
    L.append("")
    L += table_rows(study, ordered, marks)
    L.append("")
    L.append("</details>")
    L.append("")
    L.append("### Per scene (PSNR against the truth, image / band, and smooth where measured)")
    L.append("")
    L.append("<details><summary>per scene</summary>")
    L.append("")
    L += per_scene_rows(study, ordered, marks)
    L.append("")
    L.append("</details>")
    L.append("")
    tmp = args.md + ".tmp"
    with open(tmp, "w") as f:
        f.write("\n".join(L))
    os.replace(tmp, args.md)


# ---------------------------------------------------------------------------------------------


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("results", nargs="+")
    ap.add_argument("--md", default="docs/accuracy.md")
    ap.add_argument("--images", default="docs/images")
    ap.add_argument("--presets", default="libddof/src/presets_measured.inc")
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
    plots = []
    p = os.path.join(args.images, "accuracy_pareto.png")
    pareto_plot(study, chosen, front, p, "accuracy", "accuracy, dB (image and band PSNR)",
                "Accuracy against time: every configuration, the front and the presets")
    plots.append((p, "Accuracy against time per frame, the Pareto front and the presets"))
    p = os.path.join(args.images, "accuracy_pareto_band.png")
    if study.with_band:
        pareto_plot(study, chosen, front, p, "band_mean", "PSNR in the band, dB",
                    "PSNR in the band around depth edges against time")
        plots.append((p, "Band PSNR against time"))
    p = os.path.join(args.images, "accuracy_pareto_image.png")
    pareto_plot(study, chosen, front, p, "image_mean", "PSNR over the image, dB",
                "PSNR over the image against time")
    plots.append((p, "Image PSNR against time"))
    p = os.path.join(args.images, "accuracy_solver_error.png")
    solver_plot(study, p)
    plots.append((p, "Solver error against the double-precision solve"))
    p = os.path.join(args.images, "accuracy_k.png")
    if k_plot(study, p):
        plots.append((p, "Accuracy against k for each number of sub-steps"))

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
