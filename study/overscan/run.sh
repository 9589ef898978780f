#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# study/overscan/run.sh - the frame's border (issue 29's two layers) on the study's thin_strands
# scene: the lens sees past the frame's edge, a render does not, so near the border ddof (and
# any post-process) continues the frame from its edge. The scene is rendered again with the
# Blender add-on's Auto overscan margin (blender_addon/diffusion_dof/overscan.py: half the CoC
# at infinity plus a pixel, each side; the sensor grows, the pixel pitch stays), as the pinhole,
# the pinhole with its object matte, the strands alone (fg) and the rest; ddof runs on each input
# with and without the margin, the margin is cropped off, and each result is compared with the
# Cycles truth (the study's, made without a margin): the whole frame, its 8 px border and the
# inside. Prints a table and writes a montage of the top-left corner (truth | without margin |
# with margin, for one image and for two layers) as OUT/overscan.png.
#
#   bash study/overscan/run.sh [OUT]        default OUT: build/overscan (renders cached there)
#
# Needs the study's scene cache (build/study-cache/scenes/thin_strands: `bash study/run.sh`, or
# make_scenes.py, renders it), a built ddof (DDOF: default build/dev/plugin/apps/ddof) and
# /usr/bin/python3 with numpy. About 30 s for the four renders, seconds after that.
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-build/overscan}
ddof=${DDOF:-build/dev/plugin/apps/ddof}
blender=${BLENDER:-blender}
cache=build/study-cache/scenes/thin_strands
[ -x "$ddof" ] || { echo "study/overscan/run.sh: no ddof at $ddof (build it first)" >&2; exit 2; }
for f in pinhole.exr matte.exr fg.exr rest.exr truth.exr camera.json; do
    [ -f "$cache/$f" ] || { echo "study/overscan/run.sh: no $cache/$f (bash study/run.sh" \
        "renders the scenes)" >&2; exit 2; }
done
margin=$(/usr/bin/python3 study/overscan/report.py --margin "$cache/camera.json")
"$blender" -b --factory-startup --python-exit-code 1 --python study/scenes/make_scenes.py \
    -- --out "$out" --scenes thin_strands --only pinhole,rest,fg,matte --no-1080 \
    --overscan "$margin" | grep -e '^\[' -e 'make_scenes' || true

# The same calls on the frame as rendered and on the grown one.
run_all() { # DIR TAG
    local dir=$1 tag=$2
    "$ddof" "$dir/pinhole.exr" --camera "$dir/camera.json" -o "$out/one_$tag.exr" -q
    "$ddof" "$dir/matte.exr" --matte auto --camera "$dir/camera.json" \
        -o "$out/matte_$tag.exr" -q
    "$ddof" "$dir/rest.exr" --foreground "$dir/fg.exr" --camera "$dir/camera.json" \
        -o "$out/layers_$tag.exr" -q
}
run_all "$cache" frame
run_all "$out/thin_strands" margin
/usr/bin/python3 study/overscan/report.py "$out" "$cache/truth.exr" "$margin"
