#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The command's throughput per 1080p frame with each output compression (docs/benchmarks.md,
"EXR throughput"): read, depth of field and write from `ddof --stats`, for one frame and for a
12-frame sequence, and `oiiotool` writing the same image, all in one run so that the ratios
hold on a machine shared with other work.

    python3 tests/bench/exr_throughput.py DDOF IN.exr CAMERA.json SCRATCH [--reps N]
        [--old OLD_DDOF] [--compressions none,zip,piz,dwaa] [--seq-compressions zip]
        [--pixel-type float]

IN.exr is a 1920x1080 render (study/scenes/make_scenes.py's pinhole_1080.exr). --old runs
another build of the command beside it (the same cases, alternating), for before/after
figures. Prints one table of medians, in seconds, and the ratios the issue asks for.
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import time


def run_ddof(ddof, inp, out, camera, scratch, extra):
    stats = os.path.join(scratch, "stats.json")
    cmd = [ddof, inp, "-o", out, "--camera", camera, "--stats", stats, "-q"] + extra
    t0 = time.monotonic()
    proc = subprocess.Popen(cmd)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.monotonic() - t0
    if status != 0:
        raise SystemExit("%s failed (%d)" % (" ".join(cmd), status))
    frames = json.load(open(stats))["frames"]
    secs = [f["seconds"] for f in frames]
    # CPU seconds of the whole process: on a machine shared with other work the wall times
    # stretch, the CPU time much less.
    secs[0]["cpu"] = usage.ru_utime + usage.ru_stime
    return wall, secs


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("ddof")
    ap.add_argument("input")
    ap.add_argument("camera")
    ap.add_argument("scratch")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--old")
    ap.add_argument("--compressions", default="none,zip,piz,dwaa")
    ap.add_argument("--pixel-type", default="float")
    ap.add_argument("--frames", type=int, default=12)
    ap.add_argument("--seq-compressions", default="zip",
                    help="the compressions whose 12-frame sequences are timed too")
    a = ap.parse_args()
    os.makedirs(a.scratch, exist_ok=True)
    builds = [("new", a.ddof)] + ([("old", a.old)] if a.old else [])
    comps = a.compressions.split(",")
    seq_in = os.path.join(a.scratch, "in_####.exr")
    for i in range(1, a.frames + 1):
        link = seq_in.replace("####", "%04d" % i)
        if not os.path.exists(link):
            os.symlink(os.path.abspath(a.input), link)
    rows = {}
    for rep in range(a.reps):
        for comp in comps:
            for name, ddof in builds:
                if name == "old" and (comp.startswith("dwa") or ":" in comp):
                    continue
                extra = ["--compression", comp, "--pixel-type", a.pixel_type, "--threads", "2"]
                out = os.path.join(a.scratch, "one_%s_%s.exr" % (name, comp))
                wall, secs = run_ddof(ddof, a.input, out, a.camera, a.scratch, extra)
                r = rows.setdefault((name, comp), {"one": [], "read": [], "lib": [], "write": [],
                                                   "seq": [], "seq_lib": [], "seqj": [],
                                                   "cpu": []})
                r["one"].append(wall)
                r["cpu"].append(secs[0]["cpu"])
                r["read"].append(secs[0]["read"])
                r["lib"].append(secs[0]["library_total"])
                r["write"].append(secs[0]["write"])
                if comp not in a.seq_compressions.split(","):
                    continue
                # The sequence as the command plans it (1080p: one frame at a time on every
                # core), then frames in parallel (--jobs 2, one thread each).
                outs = os.path.join(a.scratch, "seq_%s_%s_####.exr" % (name, comp))
                frames = ["--frames", "1-%d" % a.frames]
                wall, secs = run_ddof(ddof, seq_in, outs, a.camera, a.scratch,
                                      ["--compression", comp, "--pixel-type", a.pixel_type] +
                                      frames)
                r["seq"].append(wall / a.frames)
                r["seq_lib"].append(sum(s["library_total"] for s in secs) / a.frames)
                wall, secs = run_ddof(ddof, seq_in, outs, a.camera, a.scratch,
                                      ["--compression", comp, "--pixel-type", a.pixel_type,
                                       "--jobs", "2"] + frames)
                r["seqj"].append(wall / a.frames)
        # oiiotool writing the frame ddof wrote (read from an uncompressed copy), 2 threads.
        if shutil.which("oiiotool"):
            src = os.path.join(a.scratch, "one_new_none.exr")
            if os.path.exists(src):
                for comp in comps:
                    out = os.path.join(a.scratch, "oiio_%s.exr" % comp)
                    t0 = time.monotonic()
                    subprocess.run(["oiiotool", "--threads", "2", src, "-d", a.pixel_type,
                                    "--compression", comp, "-o", out], check=True)
                    rows.setdefault(("oiiotool", comp), {"one": []})["one"].append(
                        time.monotonic() - t0)
    med = lambda v: statistics.median(v) if v else float("nan")
    print("build comp | frame read library write cpu | seq/frame (auto) seq/frame (--jobs 2) "
          "seq library/frame | write/library seq/one-library | size")
    one_lib = {}
    for (name, comp), r in sorted(rows.items()):
        if name == "oiiotool":
            continue
        one_lib[(name, comp)] = med(r["lib"])
    for (name, comp), r in sorted(rows.items()):
        if name == "oiiotool":
            size = os.path.getsize(os.path.join(a.scratch, "oiio_%s.exr" % comp))
            print("oiiotool %-5s | %.3f (read uncompressed + write) | | | %d" %
                  (comp, med(r["one"]), size))
            continue
        size = os.path.getsize(os.path.join(a.scratch, "one_%s_%s.exr" % (name, comp)))
        lib = one_lib[(name, comp)]
        print("%s %-5s | %.3f %.3f %.3f %.3f %.3f | %.3f %.3f %.3f | %.2f %.2f %.2f | %d" %
              (name, comp, med(r["one"]), med(r["read"]), lib, med(r["write"]), med(r["cpu"]),
               med(r["seq"]),
               med(r["seqj"]), med(r["seq_lib"]), med(r["write"]) / lib, med(r["seq"]) / lib,
               med(r["seqj"]) / lib, size))


if __name__ == "__main__":
    main()
