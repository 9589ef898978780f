# SPDX-License-Identifier: GPL-3.0-or-later
"""Errors the add-on reports to the user as one clear sentence (never as a traceback)."""


class SetupError(Exception):
    """The scene cannot get depth of field as it is; the message says what to do."""
