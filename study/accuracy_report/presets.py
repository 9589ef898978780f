# SPDX-License-Identifier: MIT
"""The accuracy-vs-time front and the choice of the three presets by the rule (rule.py)."""

import math

from .bar import bar_misses, beats_baseline, within_budget
from .formatting import fmt
from .names import BASELINES_TO_BEAT
from .rule import (BAR_MARGIN_DB, FINAL_TIME_FRACTION, FRONT_MIN_GAIN_DB, PRESET_METHODS,
                   PRESET_ORDER, PRESET_TOLERANCE_DB, PRESETS_BEATING_BASELINE)


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
        margin = 0.0
        if name in PRESETS_BEATING_BASELINE and any_node:
            beating = [c for c in pool if beats_baseline(c, study, BAR_MARGIN_DB)]
            margin = BAR_MARGIN_DB
            if not beating:
                study.preset_notes[name].append(
                    "No candidate beats the best Defocus node by %g dB on every scene with blur "
                    "(image and band): the %s preset is chosen among those that match or beat "
                    "it." % (BAR_MARGIN_DB, name))
                beating = [c for c in pool if beats_baseline(c, study)]
                margin = 0.0
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
        misses = bar_misses(chosen[name], study, margin) \
            if name in PRESETS_BEATING_BASELINE else []
        if misses:
            study.preset_notes[name].append("Where it falls short of the bar%s: %s dB." % (
                " + %g dB" % margin if margin else "", misses_text(misses)))

    # final: the most accurate within the time budget, beating the bar by the margin.
    pool = [c for c in cands if c.kind in PRESET_METHODS["final"]] or cands
    notes = study.preset_notes["final"]
    timed = [c for c in pool if within_budget(c, study)] if any_node else pool
    if any_node and not timed:
        notes.append("No candidate's time is within %g of the best node's on every scene with "
                     "blur: the final preset is the most accurate candidate, over the budget."
                     % FINAL_TIME_FRACTION)
        timed = pool
    tiers = [(BAR_MARGIN_DB, "beats the best node by %g dB or more on every scene with blur"
              % BAR_MARGIN_DB), (0.0, "matches or beats the best node on every scene with "
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
        misses = bar_misses(chosen["final"], study, BAR_MARGIN_DB)
        if misses:
            notes.append("Where the final preset falls short of the best node + %g dB: %s dB."
                         % (BAR_MARGIN_DB, misses_text(misses)))
    if chosen["final"].id == chosen["default"].id:
        notes.append("The final preset is the default's configuration: no candidate within "
                     "the budget is more accurate.")
    return chosen, front, cands


def held_out_presets(study):
    """[(scene, {preset: Config})] for every scene with blur: the presets the rule chooses on
    the other scenes, to be judged on the one left out (a preset chosen on a set of scenes and
    judged on the same set is fit to them)."""
    out = []
    for scene in study.blurred:
        chosen, _, _ = choose_presets(study.without(scene))
        if chosen:
            out.append((scene, chosen))
    return out
