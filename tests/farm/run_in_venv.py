# SPDX-License-Identifier: MIT
"""Runs a test script with the farm venv's Python (scripts/farm_venv.sh), or skips (77) saying
why the venv is missing: run_in_venv.py CACHE_DIR SCRIPT ARGS..."""
import os
import subprocess
import sys

cache, script = sys.argv[1], sys.argv[2]
python = os.path.join(cache, "venv", "bin", "python")
if not os.path.isfile(python):
    reason_file = os.path.join(cache, "venv.reason")
    reason = (open(reason_file, encoding="utf-8").read().strip() if os.path.isfile(reason_file)
              else "no venv at %s: bash scripts/farm_venv.sh makes it" % os.path.dirname(python))
    print("skipped: " + reason)
    sys.exit(77)
sys.exit(subprocess.run([python, script] + sys.argv[3:]).returncode)
