# SPDX-License-Identifier: MIT
"""ddof-farm's frame lists and chunks (plugin/apps/farm/ddof_farm/frames.py) and the merged
report of --stats files, with plain python3 (no farm tool needed)."""
import json
import os
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "plugin", "apps", "farm"))
from ddof_farm import frames, openjd, report  # noqa: E402
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
# ddof's bounds (plugin/apps/cli/frames.h), checked before any list is made: a huge range is
# refused at once, not after filling the memory.
check(frames.parse("99999999") == [99999999], "the largest frame")
for bad in ("100000000", "1-100000000", "1-10x100000000", "0-1000000", "0-999999,5-6", "+5",
            "1_000", " 5-"):
    try:
        frames.parse(bad)
        check(False, "%r accepted" % bad)
    except frames.FrameError as err:
        check("99999999" in str(err) or "1000000" in str(err) or "not a frame" in str(err)
              or "empty" in str(err), "%r: %s" % (bad, err))
check(len(frames.parse("0-999999")) == 1000000, "a million frames")
check(frames.format_frames([1, 2, 3, 7, 9, 10]) == "1-3,7,9-10", "format")
# Chunk names: bounded and unique, the list itself for one run.
check(frames.chunk_name("4-6") == "4-6" and frames.chunk_name("7") == "7", "a run's name")
twos = frames.chunks(frames.parse("1001-1099x2"), 50)
check(len(twos) == 1 and len(twos[0]) > 240 and
      frames.chunk_name(twos[0]) == "1001-1099_%08x" % frames.fnv1a32(twos[0]),
      "a chunk on twos: %s" % frames.chunk_name(twos[0]))
check(frames.fnv1a32("") == 0x811C9DC5 and frames.fnv1a32("a") == 0xE40C292C, "FNV-1a")
names = {frames.chunk_name(c) for c in frames.chunks(frames.parse("1-3000x3,5000-5010"), 7)}
check(len(names) == len(frames.chunks(frames.parse("1-3000x3,5000-5010"), 7)) and
      max(len(n) for n in names) <= 26, "chunk names unique and short")
check(frames.chunks(frames.parse("1-24"), 5) == ["1-5", "6-10", "11-15", "16-20", "21-24"],
      "chunks of 5")
check(frames.chunks(frames.parse("1-9x2"), 2) == ["1,3", "5,7", "9"], "chunks of a stepped list")
for args in ([], ["in.exr", "--frames", "1-3"], ["in.exr", "--stats", "s.json"],
             ["in.exr", "--frames=1-3"], ["in.exr", "--stats=s.json"],
             ["in.exr", "--skip-existing"]):
    try:
        SequenceJob(args, "1-3", 2, "s")
        check(False, "job %r accepted" % args)
    except JobError:
        pass
job = SequenceJob(["r_####.exr", "-o", "d_####.exr"], "1-7", 3, "st", ddof="/x/ddof",
                  workdir="/w")
check(job.command("4-6") == ["/x/ddof", "r_####.exr", "-o", "d_####.exr", "--frames", "4-6",
                             "--skip-existing", "--stats", "/w/st/chunk_4-6.json"], "command")
check(SequenceJob(["r_####.exr"], "1001-1099x2", 50, "st", ddof="/x/ddof", workdir="/w")
      .command(twos[0])[-1] == "/w/st/chunk_%s.json" % frames.chunk_name(twos[0]),
      "a long chunk's --stats name")

# OpenJD: the user's strings holding "{{" reach the task as written (as job parameters, which
# OpenJD does not read again); the task's --stats name is the chunk's short name.
job = SequenceJob(["in {{Param.X}}_####.exr", "-o", "o_####.exr"], "1-5,7", 3, "st {{a}}",
                  ddof="/x/ddof", workdir="/w/{{Task.Param.Frames}}", name="n{{")
template = openjd.template(job)
params = {"{{Param.%s}}" % p["name"]: p["default"] for p in template["parameterDefinitions"]}
args = template["steps"][0]["script"]["actions"]["onRun"]["args"]
check(params.get(args[3]) == "/w/{{Task.Param.Frames}}" and args[4] == "/x/ddof" and
      params.get(args[5]) == "in {{Param.X}}_####.exr" and args[6:8] == ["-o", "o_####.exr"] and
      params.get(template["name"]) == "n{{", "OpenJD literals: %s %s" % (args, params))
check(args[-1] == "%s{{Task.Param.Chunk}}.json" % [k for k, v in params.items()
                                                  if v == "/w/{{Task.Param.Frames}}/st {{a}}/chunk_"][0],
      "OpenJD stats path: %s" % args[-1])
space = template["steps"][0]["parameterSpace"]
check(space["combination"] == "(Frames, Chunk)" and
      space["taskParameterDefinitions"][0]["range"] == ["1-3", "4-5,7"] and
      space["taskParameterDefinitions"][1]["range"] ==
      ["1-3", "4-7_%08x" % frames.fnv1a32("4-5,7")], "OpenJD task parameters: %s" % space)
try:
    openjd.template(SequenceJob(["in.exr"], "1-2000", 1, "st"))
    check(False, "2000 OpenJD tasks accepted")
except JobError:
    pass

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

# Files of another shape: a clear error (ValueError naming the file), never a crash.
for i, content in enumerate(['{"frames": [{"status": "ok"}]}', "[]", '{"frames": 5}',
                             '{"frames": [{"frame": "7", "status": "ok"}]}',
                             '{"frames": [{"frame": 1, "status": 3}]}',
                             '{"frames": [{"frame": 1, "seconds": 2}]}',
                             '{"frames": [{"frame": 1, "seconds": {"frame": "2"}}]}',
                             '{"frames": [{"frame": 1, "simulated": {"plan": [1]}}]}',
                             '{"frames": [7]}', '{"frames": [{"frame": true}]}']):
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "bad%d.json" % i)
        with open(path, "w", encoding="utf-8") as f:
            f.write(content)
        try:
            report.summary(report.load([path]))
            check(False, "report of %s accepted" % content)
        except ValueError as err:
            check("is not a ddof --stats file" in str(err) and path in str(err),
                  "report of %s: %s" % (content, err))
print("%d failed" % len(failures))
sys.exit(1 if failures else 0)
