# SPDX-License-Identifier: MIT
"""The job as an OpenCue outline (pyoutline): one layer of ddof chunks, optionally after a
Blender render layer it depends on frame by frame (a chunk starts when its frames are rendered).

launch_local runs the outline on this machine with pyoutline's local dispatcher (no Cuebot);
pyoutline reads its configuration when imported, so outline_config.py writes it first."""

import os
import subprocess
import tempfile

import outline
import outline.cuerun
import outline.depend
import outline.layer
from outline.modules.shell import Shell

from . import frames as frame_lists

HERE = os.path.dirname(os.path.abspath(__file__))


class DdofChunk(outline.layer.Layer):
    """Runs `ddof` once over the frames of one task (a chunk), from the job's directory."""

    def __init__(self, name, **args):
        super().__init__(name, **args)
        self.require_arg("ddof_command")
        self.require_arg("workdir")

    def _execute(self, frames):
        numbered = self.get_arg("chunks")
        # Local: the layer's "frames" are the chunks' numbers (build(local=True)).
        chunk = (numbered[frames[0] - 1] if numbered
                 else frame_lists.format_frames(sorted(frames)))
        argv = list(self.get_arg("ddof_command")) + ["--frames", chunk, "--skip-existing",
                                                      "--stats", self.get_arg("stats_prefix") +
                                                      frame_lists.chunk_name(chunk) + ".json"]
        result = subprocess.run(argv, cwd=self.get_arg("workdir"), check=False)
        if result.returncode != 0:
            raise RuntimeError("ddof exited with %d on frames %s (its last line names the "
                               "failed frames)" % (result.returncode, chunk))


def build(job, render_command=None, layers=("render", "ddof"), local=False):
    """The outline: `render` (a shell command per frame, %{FRAME} its frame) when given, then
    `ddof` in chunks of job.chunk_size, each frame waiting on that frame's render. `layers`
    keeps only some of the two. `local`: the ddof layer's frames are the chunks' numbers
    (1..n, one per task), since pyoutline's local dispatcher picks a chunk's first frame from
    an unordered set (frames 1001-1099x2 in chunks of 20 ran overlapping chunks and left frames
    1001 and 1003 out)."""
    os.makedirs(job.stats_dir, exist_ok=True)
    ol = outline.Outline(job.name, shot="ddof", show="ddof")
    spec = frame_lists.format_frames(job.frames)
    render = None
    if render_command and "render" in layers:
        # From the job's directory, as the ddof tasks run (pyoutline's is its own user_dir).
        in_workdir = ["/bin/sh", "-c", 'cd "$1" && shift && exec "$@"', "render", job.workdir]
        render = Shell("render", command=in_workdir + list(render_command), range=spec, chunk=1)
        ol.add_layer(render)
    if "ddof" in layers:
        tasks = (dict(chunks=job.chunks, range="1-%d" % len(job.chunks), chunk=1) if local
                 else dict(range=spec, chunk=job.chunk_size))
        dof = DdofChunk("ddof", ddof_command=[job.ddof] + job.ddof_args, workdir=job.workdir,
                        stats_prefix=os.path.join(job.stats_dir, "chunk_"), **tasks)
        if render is not None:
            dof.depend_on(render, outline.depend.DependType.FrameByFrame)
        ol.add_layer(dof)
    return ol


def launch_local(job, render_command=None):
    """Runs the outline here through pyoutline's local dispatcher, one task at a time. That
    dispatcher runs frames in order and ignores dependencies, so the renders (when given) run
    as an outline of their own first. Returns the tasks that failed ("FRAME-LAYER"): the
    dispatcher only logs them, so the package's frame wrapper (wrappers/local_wrap_frame)
    lists them in the file DDOF_FARM_FAILED_TASKS names."""
    # The tasks run in child processes (pycuerun) that load this module to run DdofChunk.
    package_root = os.path.dirname(HERE)
    path = os.environ.get("PYTHONPATH", "")
    if package_root not in path.split(os.pathsep):
        os.environ["PYTHONPATH"] = package_root + (os.pathsep + path if path else "")
    spec = frame_lists.format_frames(job.frames)
    outline_dir = os.path.join(job.stats_dir, "outline")
    os.makedirs(outline_dir, exist_ok=True)
    fd, failed_path = tempfile.mkstemp(prefix="failed_tasks_", dir=outline_dir)
    os.close(fd)
    os.environ["DDOF_FARM_FAILED_TASKS"] = failed_path
    try:
        if render_command:
            outline.cuerun.launch(build(job, render_command, ("render",)), backend="local",
                                  range=spec)
        outline.cuerun.launch(build(job, None, ("ddof",), local=True), backend="local",
                              range="1-%d" % len(job.chunks))
        with open(failed_path, encoding="utf-8") as f:
            return [line.strip() for line in f if line.strip()]
    finally:
        del os.environ["DDOF_FARM_FAILED_TASKS"]
        os.unlink(failed_path)


def submit(job, render_command=None):
    """Sends the outline to the Cuebot that opencue's configuration names."""
    if not (os.environ.get("CUEBOT_HOSTS") or os.environ.get("OPENCUE_CONFIG_FILE")):
        raise RuntimeError("no Cuebot configured: set CUEBOT_HOSTS (or OPENCUE_CONFIG_FILE) to "
                           "submit, or run here with --local")
    ol = build(job, render_command)
    return outline.cuerun.launch(ol, backend="cue", range=frame_lists.format_frames(job.frames))
