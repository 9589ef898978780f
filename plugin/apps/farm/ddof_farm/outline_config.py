# SPDX-License-Identifier: MIT
"""pyoutline's configuration for its local backend. pyoutline reads its configuration file
(OUTLINE_CONFIG_FILE) when first imported, so this module must not import it: the command
writes the file and sets the variable, then imports the engine."""

import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def write_local_config(directory):
    """A pyoutline configuration for its local backend, in `directory`; returns its path."""
    os.makedirs(directory, exist_ok=True)
    path = os.path.join(directory, "outline.cfg")
    with open(path, "w", encoding="utf-8") as f:
        f.write("[outline]\n"
                "home = %s\n"
                "session_dir = %s\n"
                "wrapper_dir = %s\n"
                "user_dir = %s\n"
                "bin_dir = %s\n"
                "backend = local\n"
                "spec_version = 1.15\n"
                "facility = local\n"
                "domain = localdomain\n"
                "maxretries = 0\n"
                "default_show = ddof\n"
                "default_shot = ddof\n"
                % (directory, os.path.join(directory, "sessions"), os.path.join(HERE, "wrappers"),
                   directory, os.path.dirname(sys.executable)))
    return path


def use_local_backend(directory):
    """Points pyoutline at a local configuration in `directory` (unless one is set already)."""
    os.environ.setdefault("OUTLINE_CONFIG_FILE", write_local_config(directory))
