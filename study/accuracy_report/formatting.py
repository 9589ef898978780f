# SPDX-License-Identifier: MIT
"""Numbers and configurations as the report's text writes them."""

import math

from .names import BASELINE_NAMES


def k_text(k):
    if k is None:
        return ""
    inv = 1.0 / k
    if abs(inv - round(inv)) < 1e-3 * inv:
        return "1/%d" % round(inv)
    return "%.4g" % k


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


def config_name(c):
    if c.kind != "diffusion":
        return BASELINE_NAMES.get(c.id, c.id)
    solver = c.solver + ("%d" % c.jacobi if c.solver == "jacobi" else "")
    prec = {"packed half": " half", "double": " (double)"}.get(c.precision, "")
    layers = c.layers + (" + far field" if c.first.get("far_field", "off") != "off" else "") + \
        (" + blurred edges" if c.first.get("blurred_edges", "off") != "off" else "") + \
        (" + silhouettes" if c.first.get("silhouettes", "off") != "off" else "") + \
        (" + object matte" if c.first.get("matte") else "")
    if c.kernel != "heat":
        return "%s %s%s, %s, %s" % (c.backend, solver, prec, c.kernel, layers)
    return "%s %s%s, n=%s, k=%s, %s" % (c.backend, solver, prec, c.substeps, k_text(c.k),
                                         layers)


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
