#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Builds the installable Blender add-on (the library and its GL backend inside) in build/addon,
# installing the build packages first if missing (scripts/deps.sh):
#
#   bash scripts/addon.sh  ->  build/addon/diffusion_dof-VERSION.zip            Blender 3.x and
#                                  later: Preferences > Add-ons > Install
#                              build/addon/diffusion_dof-VERSION-linux_x64.zip  Blender 4.2 and
#                                  later: Preferences > Get Extensions > Install from Disk
#
# Only the library and the add-on's target are built (not the tests): a minute or two.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/deps.sh
ensure_packages "${BUILD_PACKAGES[@]}" python3
cmake -S . -B build/addon -G Ninja -DCMAKE_BUILD_TYPE=Release -DDDOF_BUILD_TESTS=OFF \
    -DDDOF_BUILD_BENCH=OFF >/dev/null
cmake --build build/addon --target ddof-blender-addon
echo "The add-on (Blender 3.x: Preferences > Add-ons > Install; 4.2+: Get Extensions >" \
    "Install from Disk):"
ls -1 "$PWD"/build/addon/diffusion_dof-*.zip
