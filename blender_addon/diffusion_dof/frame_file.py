# SPDX-License-Identifier: GPL-3.0-or-later
"""Replacing the frame file Blender wrote with the result, in the scene's format (main
thread)."""

import os

import bpy

from . import compat
from .errors import SetupError

MOVIE_FORMATS = {"FFMPEG", "AVI_JPEG", "AVI_RAW"}


def written_path(scene, frame, since):
    """The file this render just wrote for the frame. Animations (and `blender -f`) write
    frame_path(frame); a still with write_still writes the output path without a frame number.
    The candidate written since the render started is the one."""
    candidates = [scene.render.frame_path(frame=frame)]
    still = bpy.path.abspath(scene.render.filepath)
    candidates.append(still)
    if scene.render.use_file_extension:
        ext = scene.render.file_extension
        candidates += [still + ext, os.path.splitext(still)[0] + ext]
    found = [(os.path.getmtime(p), p) for p in candidates
             if os.path.isfile(p) and os.path.getmtime(p) >= since - 1.0]
    if not found:
        raise SetupError("Could not find the file this render wrote for frame %d (looked for "
                         "%s)." % (frame, ", ".join(sorted(set(candidates)))))
    return max(found)[1]


def write_frame(scene, image, frame, since):
    """Writes the result over the frame's output file, in the scene's format, atomically.
    Multilayer OpenEXR output is kept (it has the passes the user asked for) and the result is
    written beside it as <name>_dof.exr, a single-layer OpenEXR of the same depth and codec.
    Returns the path written."""
    settings = scene.render.image_settings
    fmt = settings.file_format
    if fmt in MOVIE_FORMATS:
        raise SetupError("the output is a movie (%s), which cannot be replaced frame by frame: "
                         "render to an image sequence (PNG, OpenEXR, ...) and encode it "
                         "afterwards" % fmt)
    path = written_path(scene, frame, since)
    if fmt == "OPEN_EXR_MULTILAYER":
        stem, ext = os.path.splitext(path)
        path = stem + "_dof" + (ext or ".exr")
    partial = path + ".ddof-partial"
    try:
        if fmt == "OPEN_EXR_MULTILAYER":
            compat.set_file_format(settings, "OPEN_EXR")
        image.save_render(partial, scene=scene)
        os.replace(partial, path)
    except RuntimeError as err:
        raise SetupError("Could not write %s: %s" % (path, str(err).strip())) from None
    finally:
        compat.set_file_format(settings, fmt)
        if os.path.exists(partial):
            os.remove(partial)
    return path

