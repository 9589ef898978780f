#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# smoke_test.sh STUDY_EXE OUTDIR - ctest `study_smoke`: the study's smoke run, then its checks.
# Exit 77 (skipped) when Blender or python3 with numpy + matplotlib is missing.
set -euo pipefail
exe=$1
out=$2
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)

blender=${BLENDER:-blender}
if ! command -v "$blender" >/dev/null; then
    echo "skipped: blender is not installed (bash scripts/test.sh installs it)"
    exit 77
fi
python=
for candidate in /usr/bin/python3 python3; do
    if "$candidate" -c "import numpy, matplotlib" 2>/dev/null; then
        python=$candidate
        break
    fi
done
if [ -z "$python" ]; then
    echo "skipped: no python3 with numpy and matplotlib (Debian: python3-numpy python3-matplotlib)"
    exit 77
fi

rm -rf "$out"
mkdir -p "$out"
start=$(date +%s)
DDOF_STUDY_EXE=$exe DDOF_STUDY_NO_INSTALL=1 BLENDER=$blender bash "$root/study/run.sh" --smoke "$out"
echo "smoke run: $(($(date +%s) - start)) s"
"$python" "$here/check_smoke.py" "$out"
