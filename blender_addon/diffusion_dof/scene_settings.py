# SPDX-License-Identifier: GPL-3.0-or-later
"""Where a scene keeps the add-on's settings (settings.py registers the property; the modules
that only read the settings find them here, below settings.py's update callbacks)."""

PROPERTY = "diffusion_dof"


def get(scene):
    """The settings of a scene, or None when the add-on is not registered."""
    return getattr(scene, PROPERTY, None)
