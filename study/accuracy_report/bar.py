# SPDX-License-Identifier: MIT
"""The bar: the best Defocus node per scene, and the final preset's time budget from the
nodes' times."""

import math

from .names import BASELINES_TO_BEAT, NODE_IDS
from .results import num
from .rule import FINAL_TIME_FRACTION


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
    """[(scene, "image", "band" or "blurred edges", c's PSNR, the bar + margin)] where c falls
    short of the best node + margin: image PSNR on every scene with blur, band PSNR on those with
    a band, the blurred-edge band's on those with one. A scene no node ran on has no bar."""
    misses = []
    for s in study.blurred:
        for key, what, value in (("psnr", "image", c.psnr.get(s, math.nan)),
                                 ("psnr_band", "band", c.band.get(s, math.nan)),
                                 ("psnr_blurred_edges", "blurred edges",
                                  c.blurred_edges.get(s, math.nan))):
            if what == "band" and s not in study.with_band:
                continue
            if what == "blurred edges" and s not in study.with_blurred_edges:
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
