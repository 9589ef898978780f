#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# study/overscan/brightness.sh - the frame's mean brightness against the Cycles truth, inside
# and in the 14 px border band (the study's `study_brightness`), with and without the Blender
# add-on's Auto overscan margin: a render does not see past the frame's edge, the lens does, so
# near the border ddof (and any post-process) continues the frame from its edge. Each scene's
# pinhole is rendered again with the margin (half the CoC at infinity plus a pixel, each side:
# blender_addon/diffusion_dof/overscan.py), ddof's default runs on it and on the frame as
# rendered, the margin is cropped off and both are compared with the study's truth.
#
#   bash study/overscan/brightness.sh [OUT] [SCENE ...]
#        default OUT: build/overscan-brightness (renders cached there); default scenes: the
#        five whose brightness the accuracy study finds off by more than 1%
#
# Needs the study's scene cache (`bash study/run.sh`), a built ddof (DDOF: default
# build/dev/plugin/apps/ddof), Blender and /usr/bin/python3 with numpy. About 15 s a scene.
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-build/overscan-brightness}
shift || true
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(highlights near_occluder near_railing thin_bars thin_strands)
ddof=${DDOF:-build/dev/plugin/apps/ddof}
blender=${BLENDER:-blender}
[ -x "$ddof" ] || { echo "study/overscan/brightness.sh: no ddof at $ddof (build it first)" >&2
    exit 2; }
mkdir -p "$out"
for s in "${scenes[@]}"; do
    cache=build/study-cache/scenes/$s
    for f in pinhole.exr truth.exr camera.json; do
        [ -f "$cache/$f" ] || { echo "study/overscan/brightness.sh: no $cache/$f (bash" \
            "study/run.sh renders the scenes)" >&2; exit 2; }
    done
    margin=$(/usr/bin/python3 study/overscan/report.py --margin "$cache/camera.json")
    [ -f "$out/$s/pinhole.exr" ] ||
        "$blender" -b --factory-startup --python-exit-code 1 --python study/scenes/make_scenes.py \
            -- --out "$out" --scenes "$s" --only pinhole --no-1080 --overscan "$margin" |
            grep -e '^\[' -e 'make_scenes' || true
    "$ddof" "$cache/pinhole.exr" --camera "$cache/camera.json" -o "$out/${s}_frame.exr" -q
    "$ddof" "$out/$s/pinhole.exr" --camera "$out/$s/camera.json" -o "$out/${s}_margin.exr" -q
    echo "$margin" > "$out/$s.margin"
done
/usr/bin/python3 study/overscan/brightness.py "$out" "${scenes[@]}"
