# SPDX-License-Identifier: MIT
"""ddof-farm on the engines it can run here (ctest label `farm`), with the farm venv's Python:

    python tests/farm/test_farm.py DDOF SAMPLES_DIR SCRATCH_DIR

A 24-frame sequence of the bundled sample, in chunks of 5: through pyoutline's local backend
(OpenCue without a Cuebot) and through `openjd run` of the generated template, every output
bit-identical to one single-machine ddof run; a chunk killed part-way and run again completes
without recomputing the frames it had finished; a frame that fails makes its chunk fail with the
frame named; the merged report. Exit 77 (skipped) when the venv lacks pyoutline or openjd."""

import filecmp
import json
import os
import shutil
import signal
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
FARM = os.path.join(HERE, "..", "..", "plugin", "apps", "farm")
sys.path.insert(0, FARM)
FRAMES, CHUNK = 24, 5
failures = []


def check(ok, what):
    print(("ok: " if ok else "FAILED: ") + what)
    if not ok:
        failures.append(what)
    return ok


def farm(*args, cwd):
    return subprocess.run([sys.executable, os.path.join(FARM, "ddof-farm")] + list(args),
                          cwd=cwd, capture_output=True, text=True)


def same_outputs(a, b, what):
    names = ["d_%04d.exr" % f for f in range(1, FRAMES + 1)]
    missing = [n for n in names if not os.path.isfile(os.path.join(b, n))]
    _, mismatch, errors = filecmp.cmpfiles(a, b, names, shallow=False)
    check(not missing and not mismatch and not errors,
          "%s: %d frames bit-identical to the single run (missing %s, different %s)"
          % (what, FRAMES, missing, mismatch))


def main():
    ddof, samples, scratch = sys.argv[1:4]
    try:
        import outline  # noqa: F401
    except ImportError:
        print("skipped: this Python (%s) has no pyoutline: bash scripts/farm_venv.sh makes the "
              "venv" % sys.executable)
        return 77
    openjd = shutil.which("openjd", path=os.path.dirname(sys.executable))
    if not openjd:
        print("skipped: no openjd next to %s: bash scripts/farm_venv.sh makes the venv"
              % sys.executable)
        return 77
    shutil.rmtree(scratch, ignore_errors=True)
    os.makedirs(os.path.join(scratch, "in"))
    for f in range(1, FRAMES + 1):
        shutil.copyfile(os.path.join(samples, "pinhole.exr"),
                        os.path.join(scratch, "in", "r_%04d.exr" % f))
    shutil.copyfile(os.path.join(samples, "camera.json"), os.path.join(scratch, "camera.json"))
    dof_args = ["in/r_####.exr", "--camera", "camera.json", "-q"]

    # One machine.
    single = subprocess.run([ddof] + dof_args + ["-o", "single/d_####.exr", "--frames",
                                                 "1-%d" % FRAMES], cwd=scratch)
    check(single.returncode == 0, "single-machine ddof run")

    # OpenCue: pyoutline's local backend.
    t0 = time.monotonic()
    r = farm("opencue", "--local", "--frames", "1-%d" % FRAMES, "--chunk", str(CHUNK),
             "--stats-dir", "cue-stats", "--ddof", ddof, "--", *dof_args, "-o", "cue/d_####.exr",
             cwd=scratch)
    check(r.returncode == 0, "ddof-farm opencue --local (%.1f s): %s" % (time.monotonic() - t0,
                                                                          r.stderr[-500:]))
    same_outputs(os.path.join(scratch, "single"), os.path.join(scratch, "cue"), "OpenCue local")
    stats = sorted(os.listdir(os.path.join(scratch, "cue-stats")))
    check([s for s in stats if s.endswith(".json")] ==
          ["chunk_1-5.json", "chunk_11-15.json", "chunk_16-20.json", "chunk_21-24.json",
           "chunk_6-10.json"], "OpenCue: one --stats file per chunk of 5: %s" % stats)

    # OpenCue with a render layer first (here a copy of the sample per frame, %{FRAME} its
    # number), the ddof chunks after it.
    render = os.path.join(scratch, "render.py")
    with open(render, "w", encoding="utf-8") as f:
        f.write("import shutil, sys\nshutil.copyfile(%r, 'rendered/r_%%04d.exr' %% int(sys.argv[1]))\n"
                % os.path.join(samples, "pinhole.exr"))
    os.makedirs(os.path.join(scratch, "rendered"))
    r = farm("opencue", "--local", "--frames", "1-6", "--chunk", "3", "--stats-dir", "rcue-stats",
             "--ddof", ddof, "--render", "%s %s %%{FRAME}" % (sys.executable, render), "--",
             "rendered/r_####.exr", "--camera", "camera.json", "-q", "-o", "rcue/d_####.exr",
             cwd=scratch)
    names = ["d_%04d.exr" % f for f in range(1, 7)]
    _, mismatch, errors = filecmp.cmpfiles(os.path.join(scratch, "single"),
                                           os.path.join(scratch, "rcue"), names, shallow=False)
    check(r.returncode == 0 and not mismatch and not errors,
          "OpenCue local, a render layer then ddof: 6 frames identical (%s %s)"
          % (mismatch, errors))

    # Open Job Description: the template, checked and run.
    r = farm("openjd", "-o", "job.json", "--frames", "1-%d" % FRAMES, "--chunk", str(CHUNK),
             "--stats-dir", "jd-stats", "--ddof", ddof, "--", *dof_args, "-o", "jd/d_####.exr",
             cwd=scratch)
    check(r.returncode == 0, "ddof-farm openjd: %s" % (r.stdout + r.stderr).strip())
    r = subprocess.run([openjd, "check", "job.json"], cwd=scratch, capture_output=True, text=True)
    check(r.returncode == 0, "openjd check: %s" % (r.stdout + r.stderr).strip())
    t0 = time.monotonic()
    r = subprocess.run([openjd, "run", "job.json"], cwd=scratch, capture_output=True, text=True)
    check(r.returncode == 0 and "Chunks run: 5" in r.stdout,
          "openjd run (%.1f s): %s" % (time.monotonic() - t0, r.stdout.strip()[-300:]))
    same_outputs(os.path.join(scratch, "single"), os.path.join(scratch, "jd"), "OpenJD")

    # The merged report.
    r = farm("report", "jd-stats", "--json", "report.json", cwd=scratch)
    report = json.load(open(os.path.join(scratch, "report.json"), encoding="utf-8"))
    check(r.returncode == 0 and report["frames"] == FRAMES and report["computed"] == "1-24"
          and not report["failed"] and report["seconds_per_frame"]["mean"] > 0
          and report["plans"] and report["plans"][0]["frames"] == "1-24",
          "report: %s" % r.stdout.splitlines()[:2])

    # Kill and retry: one chunk's ddof killed once its first frame is written, then run again
    # as a farm retries a task.
    job = json.load(open(os.path.join(scratch, "job.json"), encoding="utf-8"))
    run = job["steps"][0]["script"]["actions"]["onRun"]
    argv = [run["command"]] + [a.replace("{{Task.Param.Frames}}", "6-10")
                              .replace("{{Task.Param.Chunk}}", "6-10") for a in run["args"]]
    argv = ["kill/d_####.exr" if a == "jd/d_####.exr" else a for a in argv]
    first = os.path.join(scratch, "kill", "d_0006.exr")
    proc = subprocess.Popen(argv + ["--jobs", "1"], cwd=scratch)
    while proc.poll() is None and not os.path.exists(first):
        time.sleep(0.001)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    done = {n: os.stat(os.path.join(scratch, "kill", n)).st_mtime_ns
            for n in os.listdir(os.path.join(scratch, "kill")) if n.endswith(".exr")}
    check("d_0006.exr" in done and len(done) < 5,
          "killed part-way: %d of 5 frames written (%s)" % (len(done), sorted(done)))
    time.sleep(0.05)
    r = subprocess.run(argv, cwd=scratch)
    kept = all(os.stat(os.path.join(scratch, "kill", n)).st_mtime_ns == t
               for n, t in done.items())
    names = ["d_%04d.exr" % f for f in range(6, 11)]
    _, mismatch, errors = filecmp.cmpfiles(os.path.join(scratch, "single"),
                                           os.path.join(scratch, "kill"), names, shallow=False)
    check(r.returncode == 0 and kept and not mismatch and not errors,
          "retry: the chunk complete and identical, the %d finished frames not recomputed"
          % len(done))
    stats = json.load(open(os.path.join(scratch, "jd-stats", "chunk_6-10.json"), encoding="utf-8"))
    skipped = sorted(f["frame"] for f in stats["frames"] if f["status"] == "skipped")
    check(len(skipped) >= len(done), "retry's stats: frames %s skipped" % skipped)

    # A frame that fails: its chunk fails and names it; the report lists it.
    with open(os.path.join(scratch, "in", "r_0013.exr"), "r+b") as f:
        f.truncate(100)
    r = farm("openjd", "-o", "bad.json", "--frames", "11-15", "--chunk", str(CHUNK),
             "--stats-dir", "bad-stats", "--ddof", ddof, "--", *dof_args, "-o", "bad/d_####.exr",
             cwd=scratch)
    r = subprocess.run([openjd, "run", "bad.json"], cwd=scratch, capture_output=True, text=True)
    check(r.returncode != 0 and "frame 13: FAILED" in r.stdout + r.stderr,
          "a truncated frame 13 fails its chunk, named: %s"
          % [line for line in (r.stdout + r.stderr).splitlines() if "13" in line][:2])
    r = farm("report", "bad-stats", cwd=scratch)
    check(r.returncode == 1 and "frame 13 failed" in r.stdout,
          "report of the failed chunk: %s" % r.stdout.strip().splitlines()[:2])

    # A job folder and file names a shell or OpenJD would read as code: $(...), quotes, spaces,
    # {{...}}. The tasks pass them on as written (the wrapper and the template never re-read
    # them), through OpenCue's local backend and openjd run.
    odd = os.path.join(scratch, "job $(touch INJECTED) 'q' {{Param.X}}")
    os.makedirs(odd)
    for f in (1, 2):
        shutil.copyfile(os.path.join(samples, "pinhole.exr"), os.path.join(odd, "in {{x}}_%d.exr" % f))
    shutil.copyfile(os.path.join(samples, "camera.json"), os.path.join(odd, "cam $(x).json"))
    odd_args = ["in {{x}}_#.exr", "--camera", "cam $(x).json", "-q"]
    r = farm("opencue", "--local", "--frames", "1-2", "--chunk", "1", "--stats-dir", "s {{y}}",
             "--ddof", ddof, "--", *odd_args, "-o", "cue $(y)_#.exr", cwd=odd)
    r2 = farm("openjd", "-o", "job {{x}}.json", "--frames", "1-2", "--chunk", "2",
              "--stats-dir", "s {{y}}", "--ddof", ddof, "--", *odd_args, "-o", "jd {{z}}_#.exr",
              cwd=odd)
    r3 = subprocess.run([openjd, "run", "job {{x}}.json"], cwd=odd, capture_output=True, text=True)
    written = sorted(n for n in os.listdir(odd) if n.startswith(("cue", "jd")))
    injected = [os.path.join(d, n) for d, _, ns in os.walk(scratch) for n in ns if n == "INJECTED"]
    check(r.returncode == 0 and r2.returncode == 0 and r3.returncode == 0 and not injected and
          written == ["cue $(y)_1.exr", "cue $(y)_2.exr", "jd {{z}}_1.exr", "jd {{z}}_2.exr"],
          "paths with $(...), quotes, spaces and {{...}} run as written: %s, injected %s, %s"
          % (written, injected, (r.stderr + r2.stderr + r3.stdout)[-300:]))

    # Frames on twos with 4-digit numbers in chunks of 20 through the local backend: every frame
    # once, in the job's chunks, each --stats name short (a chunk's list would pass 255 bytes
    # in chunks of 50).
    for f in range(1001, 1100, 2):
        os.symlink("r_0001.exr", os.path.join(scratch, "in", "t_%04d.exr" % f))
    r = farm("opencue", "--local", "--frames", "1001-1099x2", "--chunk", "20", "--stats-dir",
             "twos-stats", "--ddof", ddof, "--", "in/t_####.exr", "--camera", "camera.json", "-q",
             "-o", "twos/d_####.exr", cwd=scratch)
    written = sorted(os.listdir(os.path.join(scratch, "twos")))
    stats = sorted(n for n in os.listdir(os.path.join(scratch, "twos-stats")) if n.endswith(".json"))
    check(r.returncode == 0 and written == ["d_%04d.exr" % f for f in range(1001, 1100, 2)] and
          len(stats) == 3 and stats[0].startswith("chunk_1001-1039_"),
          "OpenCue local, 1001-1099x2 in chunks of 20: %d frames, stats %s" % (len(written), stats))

    # A chunk whose frame fails: ddof-farm opencue --local exits 1 naming the task.
    os.remove(os.path.join(odd, "in {{x}}_2.exr"))
    r = farm("opencue", "--local", "--frames", "1-2", "--chunk", "1", "--stats-dir", "f {{y}}",
             "--ddof", ddof, "--", *odd_args, "-o", "fail_#.exr", cwd=odd)
    check(r.returncode == 1 and "1 task failed: 2-ddof" in r.stderr,
          "OpenCue local, frame 2 missing: exit %d, %s" % (r.returncode, r.stderr[-200:]))

    print("%d failed" % len(failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
