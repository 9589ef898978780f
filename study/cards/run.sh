#!/bin/sh
# SPDX-License-Identifier: MIT
# The cards' picture (docs/cards.png), timings and the mip-vs-SAT table: builds cards_demo and
# mip_vs_sat against the static library of build/test (cmake --build build/test first), then
# runs them.
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
out=${1:-$root/build/test/cards}
mkdir -p "$out"
cc -std=c11 -O2 -D_POSIX_C_SOURCE=200809L -I"$root/libddof/include" \
   "$root/study/cards/cards_demo.c" "$root/build/test/libddof/libddof.a" -lm -lpthread -ldl \
   -o "$out/cards_demo"
"$out/cards_demo" picture "$out/cards.rgba"
/usr/bin/env python3 "$root/study/cards/to_png.py" "$out/cards.rgba" 640 360 "$out/cards.png"
"$out/cards_demo" time 10
"$out/cards_demo" time 100
# The summed-area table against a mip pyramid, both against the brute force (docs/cards.md).
cc -std=c11 -O2 -D_POSIX_C_SOURCE=200809L -I"$root/libddof/include" -I"$root/tests" \
   "$root/study/cards/mip_vs_sat.c" "$root/build/test/libddof/libddof.a" -lm -lpthread -ldl \
   -o "$out/mip_vs_sat"
"$out/mip_vs_sat"
