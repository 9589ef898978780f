# SPDX-License-Identifier: MIT
""""What the numbers say": sentences that read the measurements of the one-at-a-time sweeps."""

import math

from .formatting import fmt, fmt_ms, k_text
from .names import BASE_NAMES_CAP, NODE_IDS

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
