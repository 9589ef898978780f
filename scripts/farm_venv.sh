#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Installs the render-farm tools the `farm` tests run (tests/farm): OpenCue's pyoutline and the
# Open Job Description CLI from PyPI, in one cached venv ($DDOF_FARM_CACHE, default
# ~/.cache/ddof-farm/venv: about 90 MB on disk, 17 s to install). Where it cannot be made (no
# python3-venv, no network) the reason goes to venv.reason, which the tests print as their skip
# reason. Never fails itself.
set -uo pipefail
cache=${DDOF_FARM_CACHE:-$HOME/.cache/ddof-farm}
venv=$cache/venv
packages=(opencue-pyoutline==1.37.0 openjd-cli==0.8.0)
mkdir -p "$cache"
if "$venv/bin/python" -c "import outline, openjd" 2>/dev/null && [ -x "$venv/bin/openjd" ]; then
    exit 0
fi
rm -rf "$venv" "$cache/venv.reason"
if ! log=$(python3 -m venv "$venv" 2>&1); then
    echo "python3 -m venv failed: $log" > "$cache/venv.reason"
    echo "warning: the farm tests will be skipped: $(cat "$cache/venv.reason")" >&2
    exit 0
fi
if ! log=$("$venv/bin/pip" install --quiet "${packages[@]}" 2>&1); then
    echo "pip install ${packages[*]} failed: ${log: -400}" > "$cache/venv.reason"
    echo "warning: the farm tests will be skipped: $(cat "$cache/venv.reason")" >&2
    rm -rf "$venv"
fi
exit 0
