# SPDX-License-Identifier: MIT
"""The rule that chooses the presets, as constants (the report states it from these)."""

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
# default: must beat the bar by BAR_MARGIN_DB on every scene with blur, image and band (band
# on the scenes that have one): a mean can hide a scene where the preset loses, and a default
# that only matches the node on a scene gives a user no reason to choose it there (issue 39).
# Among those the tolerance picks; where none beats it by the margin, among those that match or
# beat it; when none does, the report says so and the tolerance alone picks.
# final: the most accurate candidate whose 1080p time is at most FINAL_TIME_FRACTION of the
# best node's on every scene with blur (the node with the best image PSNR there), and that
# beats the bar by BAR_MARGIN_DB on every such scene, image and band; where none beats it
# by the margin, the most accurate within the budget that meets the bar, then the most accurate
# within the budget; where none is within the budget, the most accurate candidate. The report
# says which of these held.
PRESETS_BEATING_BASELINE = {"default", "final"}
FINAL_TIME_FRACTION = 0.1
BAR_MARGIN_DB = 1.0

# Only settings a preset can hold and the CPU can run: ddof_params_init_preset sets method,
# solver, substeps, beta_scale, background, background_levels, near_spread, near_layer,
# far_field and silhouettes (Jacobi keeps its default 50 sweeps); no foreground element and no
# object matte (those are inputs, not settings).
PRESET_SOLVERS = {"thomas", "cr", "pcr", "reference"}
PRESET_LAYERS = {"single", "bg", "bg2", "bgnear", "auto", "auto2", "autospread"}

ACCURACY_TEXT = ("the mean of two means over the scenes with blur: the PSNR over the whole image, "
                 "and the PSNR over the band around depth edges (scenes without such edges count "
                 "in the first mean only)")

# A point joins the front only if it is more accurate than every faster point by more than
# this (differences below it are not resolved by the measurement).
FRONT_MIN_GAIN_DB = 0.01
