# SPDX-License-Identifier: MIT
"""docs/accuracy.md from the study, its plots and the chosen presets."""

import math
import os

from .bar import best_node, nodes_ran
from .findings import findings
from .formatting import config_name, fmt, fmt_ms, k_text, scene_size
from .names import LAYERS_TEXT, NODE_IDS, NODE_NAMES
from .presets_file import HEAT_FALLBACK
from .results import mean, num
from .rule import (ACCURACY_TEXT, BAR_MARGIN_DB, FINAL_TIME_FRACTION, FRONT_MIN_GAIN_DB,
                   PRESET_LAYERS, PRESET_ORDER, PRESET_SOLVERS, PRESET_TOLERANCE_DB)
from .presets import held_out_presets
from .tables import (bar_table, blurred_edge_table, brightness_table, describe_machine,
                     held_out_table, per_scene_rows, silhouette_table, spread, sweep_table,
                     table_rows, time_against_node)


def write_markdown(study, chosen, front, cands, args, plots, crops):
    """docs/accuracy.md (args.md): its sections in order, written in one step."""
    md_dir = os.path.dirname(os.path.abspath(args.md))

    def rel(p):
        return os.path.relpath(os.path.abspath(p), md_dir)

    marks = front_marks(study, chosen, front)
    L = header_lines(study, args)
    L += scenes_lines(study)
    L += measures_lines(study)
    L += presets_lines(study, chosen, front, cands)
    if chosen:
        L += against_baselines_lines(study, chosen, args, rel)
    L += findings(study)
    L += front_lines(study, front, plots, marks, rel)
    L += crops_lines(study, crops, rel)
    L += knobs_lines(study, marks)
    L += all_configurations_lines(study, marks)
    tmp = args.md + ".tmp"
    with open(tmp, "w") as f:
        f.write("\n".join(L))
    os.replace(tmp, args.md)


def front_marks(study, chosen, front):
    """{id: the mark after its name in the tables}: ◆ on the front, the presets' names."""
    marks = {}
    front_ids = {c.id for c in front}
    for c in study.configs:
        if c.id in front_ids:
            marks[c.id] = " ◆"
    if chosen:
        for n in PRESET_ORDER:
            marks[chosen[n].id] = marks.get(chosen[n].id, "") + " **%s**" % n
    return marks


def header_lines(study, args):
    """The title, what the page is, when and where it was measured."""
    m = study.machine
    blender = sorted({study.scenes[s].get("blender", "") for s in study.scene_order} - {""})
    L = ["# Accuracy versus cost", ""]
    if args.smoke:
        L.append("> **Smoke run** (`bash study/run.sh --smoke`): one tiny scene and two "
                 "configurations, to keep the study's code from rotting. The numbers mean "
                 "nothing; the real report is `docs/accuracy.md` from `bash study/run.sh`.")
        L.append("")
    L.append("What each knob of ddof costs in time and buys in accuracy, measured against "
             "physically based ground truth (Cycles renders with lens depth of field) on "
             "procedural scenes, with the baselines users already have. This page is generated: "
             "`%s` renders the scenes (cached), runs the sweep and rewrites this file, its "
             "plots and `libddof/src/api/presets_measured.inc`; nothing here is edited by hand. "
             "`study/README.md` says how it works." % args.command)
    L.append("")
    def when(date):
        return date.replace("T", " ").replace("Z", " UTC")
    # A sweep appended later (ddof-study run --append) replaces the results it measured again.
    sweeps = [s for s in getattr(study, "sweeps", []) if s["ids"]]
    if len(sweeps) > 1:
        L.append("Measured %s (`ddof-study run --append`)." % "; ".join(
            "%s: %d configuration%s" % (when(s["date_utc"]), len(s["ids"]),
                                        "s" if len(s["ids"]) > 1 else "") for s in sweeps))
    else:
        L.append("Measured %s." % when(m.get("date_utc", "?")))
    L.append("")
    L += describe_machine(m, study, ", ".join(blender))
    L.append("")
    return L


def scenes_lines(study):
    """The scenes: their sizes, blur, bands, the pinhole's error and the nodes' times."""
    small = scene_size(study)
    L = ["## Scenes", ""]
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
    return L


def measures_lines(study):
    """What is measured: the metrics, the accuracy, the time and the memory."""
    opts = study.machine.get("options", {})
    small = scene_size(study)
    L = ["## What is measured", ""]
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
    L.append("- **Mean brightness**: the mean of linear R, G, B over the truth's, inside the "
             "frame (pixels 14 px or more from every side) and in the border band within 14 px "
             "of a side, where light whose disc reaches past the frame's edge must leave the "
             "frame rather than fold back (`study_brightness`).")
    L.append("")
    return L


def presets_lines(study, chosen, front, cands):
    """The rule in words, the bar per scene and the chosen presets."""
    small = scene_size(study)
    pin = study.by_id.get("pinhole")
    L = ["## Presets", ""]
    if chosen:
        L.append("The rule (`choose_presets` in `study/accuracy_report/presets.py`): candidates "
                 "are the configurations a preset can hold and the CPU (the default backend) "
                 "can run: "
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
                 "CoD4 post-process does not keep) beating the bar by %g dB on every scene "
                 "with blur, image and band (band on the scenes that have one; a mean can hide "
                 "a scene where a preset loses, and a default that only matches the node gives "
                 "no reason to choose it there); among those the fastest point within %g dB "
                 "of the most accurate point (or, when none is within it, the most accurate); "
                 "when no candidate beats the bar by the margin, the same among those matching "
                 "or beating it; when none meets the bar, the tolerance alone picks; the report "
                 "says below which held. "
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
                    PRESET_TOLERANCE_DB["preview"], BAR_MARGIN_DB, PRESET_TOLERANCE_DB["default"],
                    FINAL_TIME_FRACTION, BAR_MARGIN_DB))
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
        L.append("Written to `libddof/src/api/presets_measured.inc`, which "
                 "`ddof_params_init_preset` (and through it the `ddof` command's `--preset` and the Blender add-on) uses.")
    else:
        L.append("No configuration qualified as a preset candidate in this run.")
    L.append("")
    return L


def against_baselines_lines(study, chosen, args, rel):
    """The presets against the baselines per scene, the silhouette band, the time against the nodes
    and the near layer's picture."""
    L = []
    cols = [("pinhole", "pinhole")]
    cols += [(chosen[n].id, n) for n in PRESET_ORDER]
    d = chosen["default"]
    parts = d.id.split("/")
    fg_id = "/".join(parts[:-1] + ["fg"])  # the layers are the id's last part
    spread_id = "/".join(parts[:-1] + ["autospread"])
    if d.kind == "diffusion" and parts[-1] == "auto" and spread_id in study.by_id:
        cols.append((spread_id, "default, near layer off"))
    if fg_id in study.by_id and any(study.scenes[x].get("fg_element")
                                    for x in study.scene_order):
        cols.append((fg_id, "default + fg element"))
    if d.id + "+matte" in study.by_id:
        cols.append((d.id + "+matte", "default + object matte"))
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
             "default preset's settings with the near layer off (the near spread instead); "
             "*default + fg element*: the default "
             "preset's settings with the scene's separately rendered foreground element over "
             "the rest of the scene (scenes that have one; the others: near spread on); "
             "*default + object matte*: the default preset's settings with the scene's "
             "Cryptomatte (matte.exr: Blender's CryptoObject pass, 6 ranks) for the "
             "silhouettes' split, `ddof --matte` (scenes that have one)."
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
    L += blurred_edge_table(study, chosen)
    L += brightness_table(study, chosen)
    L += held_out_table(study, held_out_presets(study), chosen)
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
    return L


def front_lines(study, front, plots, marks, rel):
    """The plots and the front's table."""
    L = ["## The front", ""]
    for p, alt in plots:
        L.append("![%s](%s)" % (alt, rel(p)))
        L.append("")
    L.append("Front (◆ in the tables), fastest first:")
    L.append("")
    L += table_rows(study, front, marks)
    L.append("")
    return L


def crops_lines(study, crops, rel):
    """The crop grid at hard edges, when it was drawn."""
    L = []
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
    return L


def knobs_lines(study, marks):
    """Each knob in words and its one-at-a-time sweep's table."""
    L = ["## The knobs", "",
         "Each knob is swept one at a time around the base configuration (CPU, Thomas, "
         "n = 4, k = 1/32, layers AUTO); sub-steps x k x layers, which interact, are swept "
         "as a cross product on the CPU Thomas solver.", ""]
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
    return L


def all_configurations_lines(study, marks):
    """Every configuration by accuracy, and per scene."""
    L = ["## All configurations", ""]
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
    return L
