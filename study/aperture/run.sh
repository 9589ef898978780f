#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# study/aperture/run.sh - the camera's aperture (issue 23) on the study's highlights scene: the
# scene rendered twice more with Cycles, once with a 6-blade aperture turned by 15 degrees and
# once with an anamorphic ratio of 2 (pinhole and lens truth each, make_scenes.py --aperture),
# then against each truth: ddof's default with the camera's aperture, ddof with a round one
# (--aperture-blades 0 --aperture-ratio 1), and Blender's Defocus node given
# the camera's blades as a user would (Blender 3.4, and 4.2 / 5.3 through PyPI's bpy where
# scripts/bpy_venv.sh made their venvs). Prints a table (image PSNR, sRGB, as `ddof --compare`)
# and writes a montage (truth | ddof | ddof round | node 3.4, per aperture) as PNG.
#
#   bash study/aperture/run.sh [OUT]        default OUT: build/aperture (renders cached there)
#
# About 6 minutes on 2 cores for the two truths (8192 samples each), seconds after that. Needs
# a built ddof (DDOF: default build/dev/plugin/apps/ddof) and /usr/bin/python3 with numpy.
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-build/aperture}
ddof=${DDOF:-build/dev/plugin/apps/ddof}
blender=${BLENDER:-blender}
bpy_cache=${DDOF_BPY_CACHE:-$HOME/.cache/ddof-bpy}
[ -x "$ddof" ] || { echo "study/aperture/run.sh: no ddof at $ddof (build it first)" >&2; exit 2; }
mkdir -p "$out"

declare -A aperture=([hexagon]="6,15,1" [anamorphic]="0,0,2")
for name in hexagon anamorphic; do
    "$blender" -b --factory-startup --python-exit-code 1 --python study/scenes/make_scenes.py \
        -- --out "$out/$name" --scenes highlights --only pinhole,truth --no-1080 \
        --aperture "${aperture[$name]}" | grep -e '^\[' -e 'make_scenes' || true
    dir=$out/$name/highlights
    # Blender's Defocus node: 3.4, then the bpy versions that have a venv.
    [ -f "$dir/defocus.exr" ] ||
        "$blender" -b --factory-startup --python-exit-code 1 --python \
            study/scenes/defocus_node.py -- --scene-dir "$dir" | grep '^defocus_node' || true
    for v in 4.2.23 5.3.0; do
        if [ -f "$bpy_cache/venv-$v/ok" ] && [ ! -f "$dir/defocus-${v%.*}.exr" ]; then
            "$bpy_cache/venv-$v/bin/python" study/scenes/defocus_node.py -- --scene-dir "$dir" |
                grep '^defocus_node' || true
        fi
    done
    "$ddof" "$dir/pinhole.exr" --camera "$dir/camera.json" -o "$dir/ddof.exr" -q
    "$ddof" "$dir/pinhole.exr" --camera "$dir/camera.json" --aperture-blades 0 \
        --aperture-ratio 1 -o "$dir/ddof_round.exr" -q
done
/usr/bin/python3 study/aperture/report.py "$out"
