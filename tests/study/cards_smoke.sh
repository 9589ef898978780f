#!/bin/sh
# SPDX-License-Identifier: MIT
# The cards study's smoke test (issue 25): study/cards/cycles_study.sh on a 96x54 cards scene
# with 4 pinhole and 16 truth samples (about 5 s: two Blender starts), then checks that its
# table has every method and that the cards path beats the unblurred input. It keeps the code
# of docs/cards.md's "Against Cycles" from rotting; the figures come from the full run.
#   cards_smoke.sh DDOF OUTDIR      (exit 77: no Blender, or no /usr/bin/python3 with numpy)
set -eu
ddof=$1
out=$2
root=$(cd "$(dirname "$0")/../.." && pwd)
command -v "${BLENDER:-blender}" >/dev/null 2>&1 || { echo "no blender: skipped"; exit 77; }
/usr/bin/python3 -c "import numpy" 2>/dev/null || { echo "no numpy: skipped"; exit 77; }
rm -rf "$out"
DDOF=$ddof SIZE=96x54 SAMPLES_PINHOLE=4 SAMPLES_TRUTH=16 \
    sh "$root/study/cards/cycles_study.sh" "$out" --png "$out/montage.png" > "$out.log" 2>&1 ||
    { cat "$out.log"; exit 1; }
cat "$out.log"
test -s "$out/montage.png"
/usr/bin/python3 - "$out.log" <<'PY'
import re, sys
rows = dict(re.findall(r"^\| (pinhole input|ddof one image|Blender Defocus node|ddof --cards)[^|]*\| ([0-9.]+) \|",
                       open(sys.argv[1]).read(), re.M))
assert len(rows) == 4, rows
assert float(rows["ddof --cards"]) > float(rows["pinhole input"]) + 3, rows
print("cards smoke: ok", rows)
PY
