#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The main job on the embedded default: builds ddof (installing what is missing) and runs the
# `ddof` command with its default preset on the bundled Blender sample (samples/pinhole.exr:
# a 320x180 pinhole render with depth, samples/camera.json: its camera), then prints the error
# of the result and of the pinhole input against the Cycles lens-blur render of the same
# camera (samples/truth.exr). Writes, into ddof-demo-out/:
#   dof.exr       the result (half RGBA, ZIP)
#   dof.png       its sRGB preview
#   pinhole.png   the input's preview, to compare before and after
#   stats.json    what was simulated and why, and the time of every stage
#
#   bash scripts/demo.sh [ddof options]     e.g. --preset final, --fstop 2.8, --solver pcr
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/deps.sh
ensure_packages "${BUILD_PACKAGES[@]}"
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release -DDDOF_BUILD_TESTS=OFF >/dev/null
cmake --build build/release -j "$(nproc 2>/dev/null || echo 2)" --target ddof-cli
out=ddof-demo-out
build/release/plugin/apps/ddof samples/pinhole.exr -o "$out/dof.exr" --camera samples/camera.json \
    --preview "$out/dof.png" --preview-input "$out/pinhole.png" --stats "$out/stats.json" \
    --compare samples/truth.exr "$@"
echo "look at: $out/pinhole.png (input) and $out/dof.png (result); EXR: $out/dof.exr"
