# SPDX-License-Identifier: MIT
"""The Flamenco 3 job type (flamenco/ddof.js), copied where a Manager reads job types."""

import os
import shutil

JOB_TYPE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "flamenco", "ddof.js")


def install(scripts_dir):
    """Copies the job type into a Manager's scripts/ folder; returns the file written."""
    os.makedirs(scripts_dir, exist_ok=True)
    target = os.path.join(scripts_dir, "ddof.js")
    shutil.copyfile(JOB_TYPE, target)
    return target
