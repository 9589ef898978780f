# SPDX-License-Identifier: MIT
"""The chosen presets as libddof/src/api/presets_measured.inc."""

import os

from .rule import PRESET_ORDER, PRESET_TOLERANCE_DB

SOLVER_C = {"thomas": "DDOF_SOLVER_THOMAS", "cr": "DDOF_SOLVER_CYCLIC_REDUCTION",
            "pcr": "DDOF_SOLVER_PCR", "jacobi": "DDOF_SOLVER_JACOBI",
            "reference": "DDOF_SOLVER_REFERENCE_F64", "gruen": "DDOF_SOLVER_GRUEN"}
LAYER_C = {"on": "DDOF_LAYER_ON", "off": "DDOF_LAYER_OFF", "auto": "DDOF_LAYER_AUTO"}
# Sub-steps and k a disc preset carries for the heat kernel (which the disc ignores), so that
# `--kernel heat` on top of it is a sensible heat diffusion: n = 2, k = 1/24.
HEAT_FALLBACK = (2, 1.0 / 24)
KERNEL_C = {"heat": "DDOF_KERNEL_HEAT", "disc-2x2": "DDOF_KERNEL_DISC_2X2",
            "disc-2x3": "DDOF_KERNEL_DISC_2X3", "disc-3x3": "DDOF_KERNEL_DISC_3X3"}


def settings_c(c):
    """The preset's fields (presets_measured.inc's order) of configuration c."""
    f = c.first
    if c.kind == "cod4":
        return ("DDOF_METHOD_COD4_PREVIEW", "DDOF_SOLVER_THOMAS", 1, 1.0 / 32,
                "DDOF_LAYER_AUTO", 1, "DDOF_LAYER_AUTO", "DDOF_KERNEL_HEAT",
                "DDOF_LAYER_AUTO", "DDOF_LAYER_OFF", "DDOF_LAYER_OFF", "DDOF_LAYER_OFF")
    return ("DDOF_METHOD_DIFFUSION", SOLVER_C[c.solver], int(c.substeps),
            float(c.k), LAYER_C[f["background"]], int(f["background_levels"]),
            LAYER_C[f["near_spread"]], KERNEL_C[c.kernel],
            LAYER_C[f.get("near_layer", "off")], LAYER_C[f.get("far_field", "off")],
            LAYER_C[f.get("silhouettes", "off")], LAYER_C[f.get("blurred_edges", "off")])


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
        " * kernel, near_layer, far_field, silhouettes, blurred_edges */",
    ]
    for name in PRESET_ORDER:
        s = settings_c(chosen[name])
        if chosen[name].kind == "cod4":
            # The fields the CoD4 preview ignores keep the default preset's values, so that
            # `--preset preview --method diffusion` is the default diffusion.
            s = (s[0],) + settings_c(chosen["default"])[1:]
        if s[7] != "DDOF_KERNEL_HEAT":
            # A disc ignores sub-steps and k: keep HEAT_FALLBACK's, so that `--kernel heat` on
            # top of the preset is a sensible heat diffusion.
            s = s[:2] + HEAT_FALLBACK + s[4:]
        lines.append("{%s, %s, %d, %sf, %s, %d, %s, %s, %s, %s, %s, %s}, /* %s */"
                     % (s[0], s[1], s[2], float_c(s[3]), s[4], s[5], s[6], s[7], s[8], s[9],
                        s[10], s[11], name))
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(tmp, path)


def float_c(v):
    text = "%.7g" % v
    if "." not in text and "e" not in text:
        text += ".0"
    return text
