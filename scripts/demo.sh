#!/usr/bin/env bash
# The main job on the embedded default scene: builds ddof (installing what is missing), renders
# the synthetic pinhole scene with depth, applies depth of field and writes PNGs to look at.
#
#   bash scripts/demo.sh [ddof-demo options]     e.g. --fstop 2.8 --focus 10 -o /tmp/out
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/deps.sh
ensure_packages "${BUILD_PACKAGES[@]}"
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release -DDDOF_BUILD_TESTS=OFF >/dev/null
cmake --build build/release -j "$(nproc 2>/dev/null || echo 2)" --target ddof-demo
build/release/plugin/ddof-demo "$@"
