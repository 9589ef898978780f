# SPDX-License-Identifier: MIT
"""The chunks' `ddof --stats` files merged into one sequence report: per frame its last status
(a retried chunk's file replaces the killed attempt's), the failures with their errors, the time
per frame of the frames computed, and the planner's decisions grouped by the frames they hold
for."""

import glob
import json
import os
import statistics

from . import frames as frame_lists


def load(paths):
    """Every frame record of the given --stats files (or directories of them), oldest file
    first, so that a later attempt's record of a frame wins."""
    files = []
    for path in paths:
        if os.path.isdir(path):
            found = glob.glob(os.path.join(path, "*.json"))
            if not found:
                raise ValueError("no --stats file (*.json) in %s" % path)
            files += found
        elif os.path.isfile(path):
            files.append(path)
        else:
            raise ValueError("%s: no such --stats file or folder" % path)
    files.sort(key=lambda f: (os.path.getmtime(f), f))
    frames = {}
    for path in files:
        with open(path, encoding="utf-8") as f:
            try:
                stats = json.load(f)
            except (json.JSONDecodeError, UnicodeDecodeError) as err:
                raise ValueError("%s is not a ddof --stats file: %s" % (path, err)) from None
        problem = _shape_problem(stats)
        if problem:
            raise ValueError("%s is not a ddof --stats file: %s" % (path, problem))
        for record in stats.get("frames", []):
            previous = frames.get(record["frame"])
            # A frame another attempt computed stays computed when this one only skipped it.
            if previous and record.get("status") == "skipped" and previous.get("status") == "ok":
                continue
            frames[record["frame"]] = dict(record, stats_file=path)
    return frames


def _is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _shape_problem(stats):
    """What in a parsed --stats file the merge cannot read, or None: {"frames": [record, ...]},
    each record an object with an integer "frame" and, where present, a string "status" and
    "error", "seconds" an object whose "frame" is a number, "simulated" an object whose "plan"
    is a list of strings."""
    if not isinstance(stats, dict):
        return "not a JSON object"
    records = stats.get("frames", [])
    if not isinstance(records, list):
        return '"frames" is not a list'
    for i, record in enumerate(records):
        where = "frame record %d" % i
        if not isinstance(record, dict):
            return "%s is not an object" % where
        frame = record.get("frame")
        if not isinstance(frame, int) or isinstance(frame, bool) or frame < 0:
            return '%s has no "frame" number' % where
        for key in ("status", "error"):
            if key in record and not isinstance(record[key], str):
                return '%s: "%s" is not a string' % (where, key)
        seconds = record.get("seconds", {})
        if not isinstance(seconds, dict) or ("frame" in seconds and
                                             not _is_number(seconds["frame"])):
            return '%s: "seconds" is not an object of numbers' % where
        simulated = record.get("simulated", {})
        plan = simulated.get("plan", []) if isinstance(simulated, dict) else None
        if not isinstance(plan, list) or not all(isinstance(line, str) for line in plan):
            return '%s: "simulated" is not an object with a "plan" of strings' % where
    return None


def summary(frames):
    """The merged report as a dict."""
    numbers = sorted(frames)
    by_status = {}
    for n in numbers:
        by_status.setdefault(frames[n].get("status", "?"), []).append(n)
    times = [frames[n]["seconds"]["frame"] for n in by_status.get("ok", [])
             if "frame" in frames[n].get("seconds", {})]
    plans = {}
    for n in by_status.get("ok", []):
        plan = tuple(frames[n].get("simulated", {}).get("plan", []))
        plans.setdefault(plan, []).append(n)
    return {
        "frames": len(numbers),
        "computed": frame_lists.format_frames(by_status.get("ok", [])),
        "skipped": frame_lists.format_frames(by_status.get("skipped", [])),
        "failed": [{"frame": n, "error": frames[n].get("error", "")}
                   for n in by_status.get("failed", [])],
        "seconds_per_frame": {
            "mean": statistics.mean(times) if times else None,
            "median": statistics.median(times) if times else None,
            "max": max(times) if times else None,
        },
        "plans": [{"frames": frame_lists.format_frames(ns), "plan": list(plan)}
                  for plan, ns in sorted(plans.items(), key=lambda item: item[1][0])],
    }


def text(report):
    """The report for a person."""
    lines = ["%d frames: computed %s; skipped (already complete) %s; failed %d"
             % (report["frames"], report["computed"] or "none", report["skipped"] or "none",
                len(report["failed"]))]
    for failure in report["failed"]:
        lines.append("  frame %d failed: %s" % (failure["frame"], failure["error"]))
    t = report["seconds_per_frame"]
    if t["mean"] is not None:
        lines.append("time per computed frame: mean %.3f s, median %.3f s, max %.3f s"
                     % (t["mean"], t["median"], t["max"]))
    for group in report["plans"]:
        lines.append("frames %s:" % group["frames"])
        lines += ["  " + line for line in group["plan"]]
    return "\n".join(lines)
