# SPDX-License-Identifier: MIT
"""check_smoke.py OUTDIR - checks what `bash study/run.sh --smoke OUTDIR` wrote, and that the
library's committed presets (libddof/src/api/presets_measured.inc) are those docs/accuracy.md
reports."""
import json
import os
import re
import sys

out = sys.argv[1]
failures = []


def check(ok, what):
    print("%s: %s" % ("ok" if ok else "FAILED", what))
    if not ok:
        failures.append(what)


results = os.path.join(out, "results", "results.jsonl")
check(os.path.isfile(results), "results file %s" % results)
records = []
if os.path.isfile(results):
    with open(results) as f:
        records = [json.loads(line) for line in f if line.strip()]
types = [r.get("type") for r in records]
check(types[:1] == ["machine"] and "scene" in types and types[-1:] == ["done"],
      "machine, scene and done records")
machine = records[0] if records else {}
check(bool(machine.get("cpu")) and machine.get("cores", 0) >= 1, "the machine is described")
res = {r["id"]: r for r in records if r.get("type") == "result"}
base, pinhole = res.get("cpu/thomas/f32/n4/k0.03125/auto"), res.get("pinhole")
check(base is not None and pinhole is not None, "the two configurations were measured")
if base and pinhole:
    check(base.get("available") and pinhole.get("available"), "both available")
    check(base.get("ms", 0) > 0, "the diffusion was timed (%s ms)" % base.get("ms"))
    check(isinstance(base.get("psnr"), (int, float)) and isinstance(pinhole.get("psnr"),
          (int, float)) and base["psnr"] > pinhole["psnr"] + 1.0,
          "the diffusion beats the pinhole against the truth (%s dB vs %s dB)"
          % (base.get("psnr"), pinhole.get("psnr")))
    check(isinstance(base.get("ref_psnr"), (int, float, str)) and
          (base["ref_psnr"] == "inf" or base["ref_psnr"] > 80),
          "Thomas agrees with the double-precision solve (%s dB)" % base.get("ref_psnr"))
    check(base.get("host_bytes", 0) > 0, "memory is reported")
    # The lens moves light, it does not make it: the diffusion's mean brightness is the
    # truth's within a few percent, inside the frame and in its border band.
    check(all(isinstance(base.get(k), (int, float)) and abs(base[k] - 1.0) < 0.05
              for k in ("brightness_inside", "brightness_border")),
          "the diffusion's mean brightness is the truth's (inside %s, border %s)"
          % (base.get("brightness_inside"), base.get("brightness_border")))

# The split by the scene's object matte (matte.exr, rendered for the smoke scene too): measured,
# an input rather than a setting (never a preset), and its id parses back.
far, matte = (res.get("cpu/thomas/f32/disc-2x2/auto+ff+sil" + s) for s in ("", "+matte"))
check(far is not None and matte is not None and matte.get("available") and
      matte.get("matte") is True and far.get("matte") is False,
      "the split with and without the scene's object matte were measured")
if far and matte and matte.get("available"):
    check(isinstance(matte.get("psnr"), (int, float)) and
          matte["psnr"] > pinhole["psnr"] + 1.0,
          "the matte's result beats the pinhole (%s dB)" % matte.get("psnr"))

md = os.path.join(out, "accuracy.md")
check(os.path.isfile(md), "report %s" % md)
if os.path.isfile(md):
    text = open(md).read()
    check("Smoke run" in text, "the report says it is a smoke run")
    check("## Presets" in text and "- CPU:" in text, "the report has the presets and the machine")
for name in ("accuracy_pareto.png", "accuracy_pareto_image.png", "accuracy_crops.png"):
    p = os.path.join(out, name)
    ok = os.path.isfile(p) and os.path.getsize(p) > 1000
    if ok:
        with open(p, "rb") as f:
            ok = f.read(8) == b"\x89PNG\r\n\x1a\n"
    check(ok, "plot %s" % name)

inc = os.path.join(out, "presets_measured.inc")
check(os.path.isfile(inc), "presets file %s" % inc)
if os.path.isfile(inc):
    entry = re.compile(r"^\{DDOF_METHOD_[A-Z0-9_]+, DDOF_SOLVER_[A-Z0-9_]+, \d+, [0-9.e+-]+f, "
                       r"DDOF_LAYER_(AUTO|ON|OFF), \d+, DDOF_LAYER_(AUTO|ON|OFF), "
                       r"DDOF_KERNEL_(HEAT|DISC_\dX\d), DDOF_LAYER_(AUTO|ON|OFF), "
                       r"DDOF_LAYER_(AUTO|ON|OFF), DDOF_LAYER_(AUTO|ON|OFF), "
                       r"DDOF_LAYER_(AUTO|ON|OFF)\}, "
                       r"/\* (preview|default|final) \*/$")
    lines = [line for line in open(inc).read().splitlines() if line.startswith("{")]
    check(len(lines) == 3 and all(entry.match(line) for line in lines),
          "three preset entries in the format of libddof/src/api/presets_measured.inc")

# The library's committed presets are the full study's choice, as docs/accuracy.md states it
# (not edited by hand, not a smoke run's).
root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
committed = open(os.path.join(root, "libddof", "src", "api", "presets_measured.inc")).read()
report = open(os.path.join(root, "docs", "accuracy.md")).read()
check("Written by study/report.py" in committed and "SMOKE" not in committed,
      "libddof/src/api/presets_measured.inc was written by a full study run")
for line in committed.splitlines():
    m = re.match(r"^\{(DDOF_METHOD_\w+), (DDOF_SOLVER_\w+), (\d+), ([0-9.e+-]+)f, .*"
                 r"(DDOF_KERNEL_\w+)\}, /\* (\w+) \*/$", line)
    if not m:
        continue
    method, solver, substeps, k, kernel, name = m.groups()
    row = re.search(r"^\| \*\*%s\*\* \| ([^|]+) \|" % name, report, re.M)
    if not row:
        check(False, "docs/accuracy.md has a row for the %s preset" % name)
        continue
    settings = row.group(1).strip()
    if method == "DDOF_METHOD_COD4_PREVIEW":
        ok = settings == "CoD4 preview"
    elif kernel != "DDOF_KERNEL_HEAT":
        want = kernel[len("DDOF_KERNEL_"):].lower().replace("_", "-")
        s = re.match(r"cpu (\w+), ([\w-]+), ", settings)
        ok = bool(s) and s.group(2) == want
    else:
        s = re.match(r"cpu (\w+), n=(\d+), k=1/(\d+), ", settings)
        ok = bool(s) and s.group(2) == substeps and abs(1.0 / int(s.group(3)) - float(k)) < 1e-6
    check(ok, "the %s preset (%s, %s, n=%s, k=%s, %s) is the one docs/accuracy.md reports (%s)"
          % (name, method, solver, substeps, k, kernel, settings))

if failures:
    print("%d check(s) failed" % len(failures))
    sys.exit(1)
print("all checks passed")
