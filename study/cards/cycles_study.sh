#!/bin/sh
# SPDX-License-Identifier: MIT
# The cards study (issue 25, docs/cards.md "Against Cycles"): renders the cards scene with
# Cycles (study/cards/make_cards_scene.py: the pinhole input and the lens truth, cached), runs
# `ddof --cards` on its scene.json, `ddof` one-image default on pinhole.exr and Blender's Defocus
# node on pinhole.exr, and prints the PSNR table (study/cards/report.py) with the montage.
#
#   sh study/cards/cycles_study.sh [OUTDIR] [--noise] [--single] [--png docs/images/cards_study.png]
#
# OUTDIR defaults to build/cards-study. --noise also renders a truth with seed 2 and reports the
# noise floor. --single also renders the wall, the checker and the ring each alone
# (OUTDIR/single/<card>) and prints the cards path against Cycles on them, over the pixels either
# image covers. Environment: DDOF (default build/dev/plugin/apps/ddof), BLENDER (blender),
# SAMPLES_TRUTH (1024), SAMPLES_PINHOLE (256), SIZE (480x270).
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
out=$root/build/cards-study
noise=0
single=0
png=
while [ $# -gt 0 ]; do
    case $1 in
        --noise) noise=1 ;;
        --single) single=1 ;;
        --png) png=$2; shift ;;
        *) out=$1 ;;
    esac
    shift
done
ddof=${DDOF:-$root/build/dev/plugin/apps/ddof}
blender=${BLENDER:-blender}
st=${SAMPLES_TRUTH:-1024}
sp=${SAMPLES_PINHOLE:-256}
size=${SIZE:-480x270}
mkdir -p "$out"
B="$blender -b --factory-startup --python-exit-code 1 --python"
$B "$root/study/cards/make_cards_scene.py" -- --out "$out" --size "$size" \
    --samples-pinhole "$sp" --samples-truth "$st"
if [ $noise = 1 ]; then
    $B "$root/study/cards/make_cards_scene.py" -- --out "$out" --size "$size" --only truth \
        --samples-truth "$st" --seed 2 --truth-name truth_seed2.exr
fi
"$ddof" --cards "$out/scene.json" -o "$out/cards.exr" --pixel-type float
"$ddof" "$out/pinhole.exr" -o "$out/one.exr" --camera "$out/camera.json" --pixel-type float
$B "$root/study/scenes/defocus_node.py" -- --scene-dir "$out" --repeats 1
set -- "$out"
[ $noise = 1 ] && set -- "$@" --noise truth_seed2.exr
[ -n "$png" ] && set -- "$@" --png "$png"
/usr/bin/python3 "$root/study/cards/report.py" "$@"
if [ $single = 1 ]; then
    for card in wall checker ring; do
        $B "$root/study/cards/make_cards_scene.py" -- --out "$out/single/$card" --size "$size" \
            --only truth --samples-truth "$st" --cards $card
        "$ddof" --cards "$out/single/$card/scene.json" -o "$out/single/$card/cards.exr" \
            --pixel-type float
        /usr/bin/python3 - "$root/study/scenes" "$out/single/$card" $card <<'EOF'
import sys
sys.path.insert(0, sys.argv[1])
import exr_io as e
t = e.rgb_of(e.read_exr(sys.argv[2] + "/truth.exr"))
c = e.rgb_of(e.read_exr(sys.argv[2] + "/cards.exr"))
m = (t.max(-1) > 1e-3) | (c.max(-1) > 1e-3)
print("%s alone: ddof --cards against Cycles %.2f dB over %d px"
      % (sys.argv[3], e.psnr_srgb(c, t, m), m.sum()))
EOF
    done
fi
