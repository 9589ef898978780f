#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Installs Blender as a Python module from PyPI (bpy), one venv per version, for the add-on's
# `bpy` tests (tests/bpy). Cached: a venv that installed once is kept and reused.
#
#   bash scripts/bpy_venv.sh [VERSION...]      (default: the versions in tests/bpy/versions.txt)
#
# Each venv is $DDOF_BPY_CACHE/venv-VERSION (default ~/.cache/ddof-bpy): about 300 MB to
# download and 1 GB on disk per version. A bpy wheel is built for one Python (manylinux x86_64):
# 4.2 to 5.0 for CPython 3.11, 5.1 and later for CPython 3.13. The interpreter is
# $DDOF_BPY_PYTHON when set, else the first one of that Python found that runs: pythonX.Y in
# /usr/bin, /usr/local/bin, on PATH (a pyenv shim may not run), in pyenv's versions (PYENV_ROOT,
# `pyenv root`, ~/.pyenv), or /usr/bin/python3. Where a venv cannot be had (no such Python, no wheel for it, no network) the
# reason goes to venv-VERSION.reason, which the tests print as their skip reason. Never fails
# itself.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
cache=${DDOF_BPY_CACHE:-$HOME/.cache/ddof-bpy}
versions=("$@")
if [ ${#versions[@]} -eq 0 ]; then
    mapfile -t versions < <(grep -v '^#' "$here/../tests/bpy/versions.txt" | grep .)
fi

# The Python (X.Y) that bpy VERSION's wheels are built for.
wheel_python() {
    case $1 in
    4.* | 5.0.*) echo 3.11 ;;
    *) echo 3.13 ;;
    esac
}

# find_python X.Y: prints an interpreter of Python X.Y that runs; fails when there is none.
find_python() {
    local want=$1 root c
    local candidates=("/usr/bin/python$want" "/usr/local/bin/python$want"
        "$(command -v "python$want" 2>/dev/null)")
    root=${PYENV_ROOT:-}
    if [ -z "$root" ] && command -v pyenv >/dev/null 2>&1; then
        root=$(pyenv root 2>/dev/null)
    fi
    for root in "$root" "$HOME/.pyenv"; do
        [ -n "$root" ] || continue
        for c in "$root"/versions/"$want".*/bin/"python$want"; do
            candidates+=("$c")
        done
    done
    candidates+=(/usr/bin/python3)
    for c in "${candidates[@]}"; do
        [ -n "$c" ] && [ -x "$c" ] || continue
        if [ "$("$c" -c 'import sys; print("%d.%d" % sys.version_info[:2])' 2>/dev/null)" \
            = "$want" ]; then
            echo "$c"
            return 0
        fi
    done
    return 1
}

mkdir -p "$cache"
for v in "${versions[@]}"; do
    venv=$cache/venv-$v
    if [ -f "$venv/ok" ]; then
        echo "bpy $v: cached in $venv"
        continue
    fi
    rm -rf "$venv" "$venv.reason"
    log=$cache/pip-$v.log
    want=$(wheel_python "$v")
    python=${DDOF_BPY_PYTHON:-$(find_python "$want")}
    if [ -z "$python" ]; then
        echo "bpy $v is built for Python $want only, and this machine has no Python $want" \
            "(looked for python$want on PATH, in pyenv's versions and in /usr; set" \
            "DDOF_BPY_PYTHON to one, or install it: pyenv install $want)" >"$venv.reason"
        echo "bpy $v: not available: $(cat "$venv.reason")" >&2
        continue
    fi
    echo "bpy $v: installing into $venv with $python (about 300 MB to download, 1 GB on disk)"
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
