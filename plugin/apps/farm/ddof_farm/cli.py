# SPDX-License-Identifier: MIT
"""ddof-farm: one ddof frame sequence as a render-farm job, and the merged report.

    ddof-farm openjd   -o job.json  [job options] -- DDOF_ARGS...
    ddof-farm opencue  [--local|--submit] [--render CMD] [job options] -- DDOF_ARGS...
                       (neither: print the tasks' commands)
    ddof-farm flamenco SCRIPTS_DIR
    ddof-farm report   STATS_DIR_OR_FILE... [--json FILE]

job options: --frames LIST (as ddof --frames), --chunk N (frames per task, default 10),
--stats-dir DIR (default farm-stats), --ddof PATH, --name NAME. DDOF_ARGS are ddof's own
(input pattern, -o, --camera, ...), relative to the current directory, where each task runs."""

import argparse
import json
import shlex
import sys

from . import __version__
from .frames import FrameError
from .job import JobError, SequenceJob


def _job_options(parser):
    parser.add_argument("--frames", required=True, help="frames, as ddof --frames reads them")
    parser.add_argument("--chunk", type=int, default=10, help="frames per task (default 10)")
    parser.add_argument("--stats-dir", default="farm-stats",
                        help="where each task writes its --stats file (default farm-stats)")
    parser.add_argument("--ddof", help="the ddof command the tasks run (default: ddof on PATH)")
    parser.add_argument("--name", default="ddof", help="the job's name (default ddof)")
    parser.add_argument("ddof_args", nargs=argparse.REMAINDER,
                        help="-- then ddof's arguments: input pattern, -o, --camera, ...")


def _job(args):
    ddof_args = args.ddof_args[1:] if args.ddof_args[:1] == ["--"] else args.ddof_args
    return SequenceJob(ddof_args, args.frames, args.chunk, args.stats_dir, ddof=args.ddof,
                       name=args.name)


def _openjd(args):
    from . import openjd
    job = _job(args)
    openjd.write(job, args.output)
    print("ddof-farm: %s: %d tasks of up to %d frames (run it: openjd run %s)"
          % (args.output, len(job.chunks), job.chunk_size, args.output))


def _opencue(args):
    job = _job(args)
    if not (args.local or args.submit):
        for chunk in job.chunks:
            print(shlex.join(job.command(chunk)))
        return
    if args.local:
        import os
        from .outline_config import use_local_backend
        use_local_backend(os.path.join(job.stats_dir, "outline"))
    try:
        from . import opencue
    except ImportError as err:
        raise JobError("OpenCue needs pyoutline (pip install opencue-pyoutline): %s" % err)
    render = shlex.split(args.render) if args.render else None
    if args.local:
        failed = opencue.launch_local(job, render)
        if failed:
            print("ddof-farm: %d task%s failed: %s (its log above names the failed frames)"
                  % (len(failed), "" if len(failed) == 1 else "s", ", ".join(failed)),
                  file=sys.stderr)
            return 1
    else:
        opencue.submit(job, render)


def _flamenco(args):
    from . import flamenco
    print("ddof-farm: wrote %s (restart the Flamenco Manager to load it)"
          % flamenco.install(args.scripts_dir))


def _report(args):
    from . import report
    merged = report.summary(report.load(args.stats))
    print(report.text(merged))
    if args.json:
        with open(args.json, "w", encoding="utf-8") as f:
            json.dump(merged, f, indent=2)
            f.write("\n")
    return 1 if merged["failed"] else 0


def main(argv=None):
    parser = argparse.ArgumentParser(prog="ddof-farm", description=__doc__.split("\n")[0])
    parser.add_argument("--version", action="version", version="ddof-farm " + __version__)
    sub = parser.add_subparsers(dest="engine", required=True)
    p = sub.add_parser("openjd", help="an Open Job Description template")
    p.add_argument("-o", "--output", required=True, help="the template file to write (JSON)")
    _job_options(p)
    p.set_defaults(run=_openjd)
    p = sub.add_parser("opencue", help="an OpenCue outline (pyoutline)")
    how = p.add_mutually_exclusive_group()
    how.add_argument("--local", action="store_true", help="run it here (pyoutline's local backend)")
    how.add_argument("--submit", action="store_true", help="send it to the configured Cuebot")
    p.add_argument("--render", help="a render command per frame (%%{FRAME} the frame, %%{ZFRAME} "
                                    "zero-padded to 4 digits: pyoutline's tokens) that each "
                                    "ddof frame waits for")
    _job_options(p)
    p.set_defaults(run=_opencue)
    p = sub.add_parser("flamenco", help="install the Flamenco 3 job type")
    p.add_argument("scripts_dir", help="the Manager's scripts/ folder")
    p.set_defaults(run=_flamenco)
    p = sub.add_parser("report", help="merge the tasks' --stats files")
    p.add_argument("stats", nargs="+", help="--stats files or folders of them")
    p.add_argument("--json", help="also write the merged report as JSON")
    p.set_defaults(run=_report)
    args = parser.parse_args(argv)
    try:
        return args.run(args) or 0
    except (JobError, FrameError, ValueError, RuntimeError, OSError) as err:
        print("ddof-farm: %s" % err, file=sys.stderr)
        return 2
