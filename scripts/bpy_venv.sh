#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Installs Blender as a Python module from PyPI (bpy), one venv per version, for the add-on's
# `bpy` tests (tests/bpy). Cached: a venv that installed once is kept and reused.
#
#   bash scripts/bpy_venv.sh [VERSION...]      (default: the versions tests/bpy runs)
#
# Each venv is $DDOF_BPY_CACHE/venv-VERSION (default ~/.cache/ddof-bpy), made with the machine's
# python3 (a bpy wheel is built for one Python: 4.2 to 5.0 for CPython 3.11, manylinux x86_64).
# Where one cannot be had (no wheel for this Python or platform, no network) the reason goes
# to venv-VERSION.reason, which the tests print as their skip reason. Never fails itself.
set -uo pipefail
cache=${DDOF_BPY_CACHE:-$HOME/.cache/ddof-bpy}
python=${DDOF_BPY_PYTHON:-/usr/bin/python3}
versions=("$@")
[ ${#versions[@]} -eq 0 ] && versions=(5.0.1 4.2.23)
mkdir -p "$cache"
for v in "${versions[@]}"; do
    venv=$cache/venv-$v
    if [ -f "$venv/ok" ]; then
        echo "bpy $v: cached in $venv"
        continue
    fi
    rm -rf "$venv" "$venv.reason"
    log=$cache/pip-$v.log
    echo "bpy $v: installing into $venv (about 300 MB to download)"
    if ! "$python" -m venv "$venv" >"$log" 2>&1; then
        echo "$python -m venv failed: $(tail -1 "$log") (Debian: apt-get install python3-venv)" \
            >"$venv.reason"
    elif ! "$venv/bin/pip" install --disable-pip-version-check -q "bpy==$v" >>"$log" 2>&1; then
        echo "pip install bpy==$v with $("$python" --version 2>&1) failed: $(grep -m1 -E \
            'ERROR|No matching|Could not' "$log" || tail -1 "$log")" >"$venv.reason"
    elif ! "$venv/bin/python" -c "import bpy" >>"$log" 2>&1; then
        echo "bpy $v installed but does not import: $(tail -1 "$log")" >"$venv.reason"
    else
        touch "$venv/ok"
        echo "bpy $v: installed"
        continue
    fi
    echo "bpy $v: not available: $(cat "$venv.reason")" >&2
    rm -rf "$venv"
done
exit 0
