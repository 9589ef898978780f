# SPDX-License-Identifier: MIT
"""Reading results.jsonl: the study's scenes and configurations with their measurements."""

import copy
import json
import math

from .names import register_nodes
from .rule import PRESET_LAYERS, PRESET_SOLVERS


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


class Study:
    def __init__(self, paths):
        self.machine = {}
        self.sweeps = []        # per sweep (a machine record): its date and the ids whose results
        #                         it holds (a later sweep's result replaces an earlier one's)
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
                        self.sweeps.append({"date_utc": rec.get("date_utc", "?"), "ids": set()})
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
                        for sweep in self.sweeps[:-1]:
                            sweep["ids"].discard(cid)
                        if self.sweeps:
                            self.sweeps[-1]["ids"].add(cid)
                    elif t == "done":
                        self.seconds += float(rec.get("seconds", 0.0))
                        self.peak_rss = max(self.peak_rss, float(rec.get("peak_rss_bytes", 0)))
        register_nodes(self.order)
        self._derive()

    def without(self, scene):
        """The same results with one scene left out: for choosing the presets on the other
        scenes and judging them on the one left out."""
        other = copy.copy(self)
        other.scene_order = [s for s in self.scene_order if s != scene]
        other._derive()
        return other

    def _derive(self):
        """The scene lists and the configurations' measures over self.scene_order."""
        self.blurred = [s for s in self.scene_order if self.scenes[s].get("blurred")]
        self.with_band = [s for s in self.blurred if self.scenes[s].get("band_pixels", 0) > 0]
        # The smooth far field (study_smooth, study/metrics.c); results before it lack it.
        self.with_smooth = [s for s in self.scene_order
                            if self.scenes[s].get("smooth_pixels", 0) > 0]
        # The silhouette band (study_silhouettes); results before it lack it.
        self.with_silhouette = [s for s in self.blurred
                                if self.scenes[s].get("silhouette_pixels", 0) > 0]
        # Where two blurred surfaces meet (study_blurred_edges); results before it lack it.
        self.with_blurred_edges = [s for s in self.blurred
                                   if self.scenes[s].get("blurred_edge_pixels", 0) > 0]
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
        self.matte = bool(first.get("matte"))  # the scene's object matte: an input
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
        self.blurred_edges = {s: num(per_scene.get(s, {}).get("psnr_blurred_edges"))
                              for s in study.scene_order}
        # The mean brightness over the truth's, inside the frame and in its border band
        # (study_brightness); results before it lack them.
        self.brightness = {s: (num(per_scene.get(s, {}).get("brightness_inside")),
                               num(per_scene.get(s, {}).get("brightness_border")))
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
        if self.layers not in PRESET_LAYERS or self.precision not in ("float", "double") or \
                self.matte:
            return False
        return self.solver in PRESET_SOLVERS or (self.solver == "jacobi" and self.jacobi == 50)
