# SPDX-License-Identifier: MIT
"""The report's tables: configurations, scenes, the bar, the silhouette band, the blurred-edge
band, the mean brightness, the presets held out, the machine."""

import math

import numpy as np

from .bar import best_node, final_budget, nodes_ran
from .formatting import config_name, fmt, fmt_mem, fmt_ms, fmt_ref, scene_size, short
from .names import BASELINES_TO_BEAT, NODE_IDS, NODE_NAMES
from .results import num
from .rule import FINAL_TIME_FRACTION, PRESET_ORDER


def silhouette_table(study, chosen):
    """The silhouette band per scene: the presets, the default without the far field and the
    silhouettes' split, and the nodes."""
    if not study.with_silhouette:
        return []
    default = chosen["default"]
    before = default.id.replace("+ff", "").replace("+sil", "")
    cols = [("pinhole", "pinhole")] + [(chosen[n].id, n) for n in PRESET_ORDER]
    if before != default.id:
        cols.append((before, "default without far field and split"))
    if default.id + "+matte" in study.by_id:
        cols.append((default.id + "+matte", "default + object matte"))
    cols += [(cid, NODE_NAMES[cid].replace("Defocus node", "node")) for cid in NODE_IDS]
    cols = [(cid, name) for cid, name in cols if cid in study.by_id]
    L = ["The silhouette band (issue 29: the pixels within %g px of an in-focus pixel that "
         "borders one with |CoC| >= %g px, `study_silhouettes` in `study/metrics.c`: where the "
         "mixed pixels of thin sharp structure are), PSNR in dB; *default + object matte*: "
         "the default with the scene's Cryptomatte for the split (`ddof --matte`), – on a "
         "scene without one:" % (2, 2), "",
         "| scene | share | " + " | ".join(name for _, name in cols) + " |",
         "|---|---:|" + "---:|" * len(cols)]
    for sc in study.with_silhouette:
        share = 100.0 * study.scenes[sc]["silhouette_pixels"] / (
            study.scenes[sc]["width"] * study.scenes[sc]["height"])
        L.append("| %s | %.1f%% | %s |" % (sc, share, " | ".join(
            fmt(study.by_id[cid].silhouette[sc]) if study.by_id[cid].per.get(sc, {}).get(
                "available") else "–" for cid, _ in cols)))
    L.append("")
    return L


def blurred_edge_table(study, chosen):
    """The blurred-edge band per scene: the presets, the default without the depth slices, and
    the nodes."""
    if not study.with_blurred_edges:
        return []
    default = chosen["default"]
    before = default.id.replace("+be", "")
    cols = [("pinhole", "pinhole")] + [(chosen[n].id, n) for n in PRESET_ORDER]
    if before != default.id:
        cols.append((before, "default without blurred edges"))
    cols += [(cid, NODE_NAMES[cid].replace("Defocus node", "node")) for cid in NODE_IDS]
    cols = [(cid, name) for cid, name in cols if cid in study.by_id]
    L = ["The blurred-edge band (issue 39: the pixels within 12 px of a depth edge whose two "
         "sides both have |CoC| >= 2 px, less those within 12 px of an edge at a sharper pixel, "
         "`study_blurred_edges` in `study/metrics.c`: where two blurred surfaces meet, a tree's "
         "crown before the sky), PSNR in dB:", "",
         "| scene | share | " + " | ".join(name for _, name in cols) + " |",
         "|---|---:|" + "---:|" * len(cols)]
    for sc in study.with_blurred_edges:
        share = 100.0 * study.scenes[sc]["blurred_edge_pixels"] / (
            study.scenes[sc]["width"] * study.scenes[sc]["height"])
        L.append("| %s | %.1f%% | %s |" % (sc, share, " | ".join(
            fmt(study.by_id[cid].blurred_edges[sc]) if study.by_id[cid].per.get(sc, {}).get(
                "available") else "–" for cid, _ in cols)))
    L.append("")
    return L


BRIGHTNESS_TOLERANCE = 0.01  # issue 39: the frame's mean brightness within 1% of the truth's


def brightness_table(study, chosen):
    """The mean brightness over the truth's per scene, inside the frame and in its border band:
    the presets, the pinhole and the nodes; the presets' ratios outside 1 +- 1% in bold."""
    cols = [("pinhole", "pinhole")] + [(chosen[n].id, n) for n in PRESET_ORDER]
    cols += [(cid, NODE_NAMES[cid].replace("Defocus node", "node")) for cid in NODE_IDS]
    cols = [(cid, name) for cid, name in cols if cid in study.by_id]
    scenes = [sc for sc in study.scene_order
              if not math.isnan(study.by_id[cols[0][0]].brightness[sc][0])]
    if not scenes:
        return []
    presets = {chosen[n].id for n in PRESET_ORDER}

    def ratio(cid, v):
        if math.isnan(v):
            return "–"
        text = "%.3f" % v
        return "**%s**" % text if cid in presets and abs(v - 1.0) > BRIGHTNESS_TOLERANCE else text

    L = ["The mean brightness (linear RGB) over the truth's, inside the frame / in the border "
         "band within 14 px of its sides (`study_brightness` in `study/metrics.c`: light whose "
         "disc reaches past the frame's edge leaves it, so a border folded back reads too "
         "bright); bold: a preset more than %g%% off:" % (100 * BRIGHTNESS_TOLERANCE), "",
         "| scene | " + " | ".join(name for _, name in cols) + " |",
         "|---|" + "---:|" * len(cols)]
    for sc in scenes:
        cells = []
        for cid, _ in cols:
            c = study.by_id[cid]
            if not c.per.get(sc, {}).get("available"):
                cells.append("–")
            else:
                cells.append(" / ".join(ratio(cid, v) for v in c.brightness[sc]))
        L.append("| %s | %s |" % (sc, " | ".join(cells)))
    L.append("")
    return L


def held_out_table(study, held_out, chosen_all):
    """Each preset chosen on every scene but one and judged on the one left out, against the
    best node there: image / band / blurred-edge band, and the smallest margin."""
    if not held_out:
        return []
    L = ["### The presets held out", "",
         "Leave one scene out: for every scene with blur, the rule above chooses the presets on "
         "the other scenes alone, and the table judges them on the scene left out. PSNR image / "
         "band / blurred-edge band in dB (– where the scene has no such band); *margin*: the "
         "smallest of the three differences to the best Defocus node's (the bar, each metric "
         "separately); *config*: the configuration chosen without the scene (= where it is the "
         "preset chosen on all scenes).", "",
         "| scene | " + " | ".join("%s | %s margin | %s config" % (n, n, n)
                                   for n in PRESET_ORDER) + " | bar |",
         "|---|" + "---:|---:|---|" * len(PRESET_ORDER) + "---:|"]
    keys = (("psnr", "psnr"), ("band", "psnr_band"), ("blurred_edges", "psnr_blurred_edges"))

    def values(c, sc):
        out = []
        for attr, key in keys:
            if key == "psnr_band" and sc not in study.with_band:
                out.append(math.nan)
            elif key == "psnr_blurred_edges" and sc not in study.with_blurred_edges:
                out.append(math.nan)
            else:
                out.append(getattr(c, "psnr" if attr == "psnr" else attr)[sc])
        return out

    for sc, chosen in held_out:
        bar = [best_node(study, sc, key)[0] for _, key in keys]
        cells = []
        for name in PRESET_ORDER:
            c = study.by_id[chosen[name].id]  # measured on every scene, the left-out one too
            v = values(c, sc)
            margins = [a - b for a, b in zip(v, bar) if not math.isnan(a) and not math.isnan(b)]
            cells.append("%s | %s | %s" % (" / ".join(fmt(x) for x in v if not math.isnan(x)),
                                           fmt(min(margins)) if margins else "–",
                                           "=" if c.id == chosen_all[name].id
                                           else short(config_name(c))))
        L.append("| %s | %s | %s |" % (sc, " | ".join(cells),
                                       " / ".join(fmt(x) for x in bar if not math.isnan(x))))
    L.append("")
    return L


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
