# SPDX-License-Identifier: MIT
"""The report's plots: the fronts, the solvers' error and the calibration of k."""

import math
import os

import matplotlib.pyplot as plt

from .formatting import k_text
from .names import BASELINE_NAMES, BASELINE_STYLE
from .rule import PRESET_ORDER

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


def draw_plots(study, chosen, front, images):
    """The report's plots into the folder images: [(path, alt text)] of those drawn."""
    plots = []
    p = os.path.join(images, "accuracy_pareto.png")
    pareto_plot(study, chosen, front, p, "accuracy", "accuracy, dB (image and band PSNR)",
                "Accuracy against time: every configuration, the front and the presets")
    plots.append((p, "Accuracy against time per frame, the Pareto front and the presets"))
    p = os.path.join(images, "accuracy_pareto_band.png")
    if study.with_band:
        pareto_plot(study, chosen, front, p, "band_mean", "PSNR in the band, dB",
                    "PSNR in the band around depth edges against time")
        plots.append((p, "Band PSNR against time"))
    p = os.path.join(images, "accuracy_pareto_image.png")
    pareto_plot(study, chosen, front, p, "image_mean", "PSNR over the image, dB",
                "PSNR over the image against time")
    plots.append((p, "Image PSNR against time"))
    p = os.path.join(images, "accuracy_solver_error.png")
    solver_plot(study, p)
    plots.append((p, "Solver error against the double-precision solve"))
    p = os.path.join(images, "accuracy_k.png")
    if k_plot(study, p):
        plots.append((p, "Accuracy against k for each number of sub-steps"))
    return plots
