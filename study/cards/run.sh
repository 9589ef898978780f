#!/bin/sh
# SPDX-License-Identifier: MIT
# The cards' picture (docs/cards.png) and timings: builds cards_demo against the static library
# of build/test (cmake --build build/test first), then runs it.
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
