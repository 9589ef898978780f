# SPDX-License-Identifier: MIT
"""The accuracy study's report (study/report.py is its command): results.jsonl read into
configurations (results.py), the presets chosen by the rule (rule.py, bar.py, presets.py) and
written for libddof (presets_file.py), the plots and the crop grid (plots.py, crops.py) and
docs/accuracy.md (markdown.py with tables.py, findings.py and formatting.py)."""

import matplotlib

# The plots are files: no display.
matplotlib.use("Agg")
