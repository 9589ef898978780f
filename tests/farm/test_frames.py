# SPDX-License-Identifier: MIT
"""ddof-farm's frame lists and chunks (plugin/apps/farm/ddof_farm/frames.py) and the merged
report of --stats files, with plain python3 (no farm tool needed)."""
import json
import os
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "plugin", "apps", "farm"))
from ddof_farm import frames, report  # noqa: E402
from ddof_farm.job import JobError, SequenceJob  # noqa: E402

failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAILED: " + what)


check(frames.parse("1-5") == [1, 2, 3, 4, 5], "1-5")
check(frames.parse("1-10x3") == [1, 4, 7, 10], "1-10x3")
check(frames.parse("1,4,10-12,4") == [1, 4, 10, 11, 12], "a list, 4 once")
for bad in ("", "5-1", "a-3", "1-3x0", "-2", "1,,2"):
    try:
        frames.parse(bad)
        check(False, "%r accepted" % bad)
    except frames.FrameError:
        pass
check(frames.format_frames([1, 2, 3, 7, 9, 10]) == "1-3,7,9-10", "format")
check(frames.chunks(frames.parse("1-24"), 5) == ["1-5", "6-10", "11-15", "16-20", "21-24"],
      "chunks of 5")
check(frames.chunks(frames.parse("1-9x2"), 2) == ["1,3", "5,7", "9"], "chunks of a stepped list")
for args in ([], ["in.exr", "--frames", "1-3"], ["in.exr", "--stats", "s.json"]):
    try:
        SequenceJob(args, "1-3", 2, "s")
        check(False, "job %r accepted" % args)
    except JobError:
        pass
job = SequenceJob(["r_####.exr", "-o", "d_####.exr"], "1-7", 3, "st", ddof="/x/ddof",
                  workdir="/w")
check(job.command("4-6") == ["/x/ddof", "r_####.exr", "-o", "d_####.exr", "--frames", "4-6",
                             "--skip-existing", "--stats", "/w/st/chunk_4-6.json"], "command")

# The report: a retried chunk's record wins, a skip does not hide the earlier computation.
with tempfile.TemporaryDirectory() as d:
    def write(name, records, mtime):
        path = os.path.join(d, name)
        json.dump({"frames": records}, open(path, "w"))
        os.utime(path, (mtime, mtime))
    ok = lambda f, t: {"frame": f, "status": "ok", "seconds": {"frame": t},  # noqa: E731
                       "simulated": {"plan": ["midground: on"]}}
    write("a.json", [ok(1, 0.1), {"frame": 2, "status": "failed", "error": "killed"}], 100)
    write("b.json", [{"frame": 1, "status": "skipped"}, ok(2, 0.3), ok(3, 0.2)], 200)
    merged = report.summary(report.load([d]))
    check(merged["frames"] == 3 and merged["computed"] == "1-3" and not merged["failed"],
          "merged: %r" % merged)
    check(abs(merged["seconds_per_frame"]["mean"] - 0.2) < 1e-9, "mean time")
    check(merged["plans"] == [{"frames": "1-3", "plan": ["midground: on"]}], "plans")
print("%d failed" % len(failures))
sys.exit(1 if failures else 0)
