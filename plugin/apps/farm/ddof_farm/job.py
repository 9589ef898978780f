# SPDX-License-Identifier: MIT
"""One ddof sequence as farm tasks: the command each chunk runs.

Every chunk runs `ddof` with the user's arguments, its frames, `--skip-existing` (a retried
chunk does not recompute the frames a killed attempt finished; ddof writes outputs by renaming
complete files, so a frame that is there is whole) and its own --stats file, from the
directory the job was made in (relative paths in the arguments stay valid on the farm when that
directory is shared)."""

import os
import shutil

from . import frames as frame_lists


# The options each task sets itself; ddof also reads them as --name=value.
FARM_OPTIONS = ("--frames", "--stats", "--skip-existing")


class JobError(ValueError):
    """A job that cannot be made as asked."""


class SequenceJob:
    def __init__(self, ddof_args, frames, chunk_size, stats_dir, ddof=None, workdir=None,
                 name="ddof"):
        if not ddof_args:
            raise JobError("no ddof arguments: give them after --, e.g. "
                           "-- render_####.exr -o dof/dof_####.exr --camera camera.json")
        for option in FARM_OPTIONS:
            if any(a == option or a.startswith(option + "=") for a in ddof_args):
                raise JobError("%s is the farm's to set per chunk; leave it out of the ddof "
                               "arguments" % option)
        self.ddof_args = list(ddof_args)
        self.frames = frame_lists.parse(frames)
        if not self.frames:
            raise JobError("the frame list %r holds no frame" % frames)
        self.chunk_size = int(chunk_size)
        self.chunks = frame_lists.chunks(self.frames, self.chunk_size)
        self.workdir = os.path.abspath(workdir or os.getcwd())
        self.stats_dir = os.path.join(self.workdir, stats_dir)
        self.ddof = ddof or shutil.which("ddof") or "ddof"
        self.ddof = os.path.abspath(self.ddof) if os.sep in self.ddof else self.ddof
        self.name = name

    def stats_path(self, chunk):
        return os.path.join(self.stats_dir, "chunk_%s.json" % frame_lists.chunk_name(chunk))

    def command(self, chunk):
        """The argv of one chunk (a --frames list), to run in self.workdir."""
        return [self.ddof] + self.ddof_args + ["--frames", chunk, "--skip-existing",
                                               "--stats", self.stats_path(chunk)]
