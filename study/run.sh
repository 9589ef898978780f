#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# study/run.sh - the accuracy-vs-cost study (issue 7) in one command: builds ddof-study, renders
# the ground-truth scenes (cached), runs Blender's Defocus node on them (cached; Blender 3.4, and
# 4.2 and 5.3 through PyPI's bpy where scripts/bpy_venv.sh can install it), runs the sweep and
# writes the report. Installs what is missing first (Debian packages, as scripts/test.sh).
#
#   bash study/run.sh                  the full study: docs/accuracy.md, docs/images/accuracy_*.png
#                                      and libddof/src/api/presets_measured.inc (about 10-15 minutes
#                                      on 2 cores after the scenes are rendered; see study/README.md)
#   bash study/run.sh --smoke OUTDIR   one tiny scene (96x54), two configurations, the report
#                                      written into OUTDIR only (docs/ and the presets untouched);
#                                      well under a minute once ddof-study is built
#   bash study/run.sh --report-only    rewrite the report from the last sweep's results
#
# Options: --configs LIST (ddof-study's list: full, smoke, ids), --scenes a,b (a subset of the
# scenes), --no-large (no 1920x1080 timings), --threads N (the CPU contexts' threads),
# --no-gl (never load the GL plugin), --bpy-nodes-1080 (time the 4.2 and 5.3 Defocus nodes at
# 1920x1080 too: off by default, as they are far slower than 3.4's; see study/scenes/README.md).
# Environment: DDOF_STUDY_EXE (a built ddof-study: skip the build), DDOF_STUDY_NO_INSTALL=1
# (never install packages; what ctest sets), BLENDER (the blender executable).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

mode=full
outdir=
configs=
scenes_arg=
sweep_args=()
bpy_nodes_1080=0
while [ $# -gt 0 ]; do
    case "$1" in
    --smoke)
        mode=smoke
        outdir=${2:?"--smoke needs an output directory"}
        shift 2
        ;;
    --report-only) mode=report; shift ;;
    --configs) configs=${2:?}; shift 2 ;;
    --scenes) scenes_arg=${2:?}; shift 2 ;;
    --no-large) sweep_args+=(--no-large); shift ;;
    --threads) sweep_args+=(--threads "${2:?}"); shift 2 ;;
    --no-gl) sweep_args+=(--no-gl); shift ;;
    --bpy-nodes-1080) bpy_nodes_1080=1; shift ;;
    -h | --help) awk 'NR > 1 && !/^#/ {exit} NR > 1 {print}' "$0"; exit 0 ;;
    *) echo "study/run.sh: unknown argument $1 (see --help)" >&2; exit 2 ;;
    esac
done

t_start=$(date +%s)
step() { echo "== study: $* ($(($(date +%s) - t_start)) s)"; }
# Blender's banner and blank lines out; the scripts' own lines (and any error) through.
blender_filter() { grep -v -e '^$' -e '^Blender quit' -e '^Blender [0-9]' -e '^Read prefs' || true; }

# --- what is needed -------------------------------------------------------------------------
if [ "${DDOF_STUDY_NO_INSTALL:-0}" != 1 ]; then
    source scripts/deps.sh
    ensure_packages "${BUILD_PACKAGES[@]}" python3 python3-numpy python3-matplotlib
    [ "$mode" = report ] || ensure_packages blender
fi
blender=${BLENDER:-blender}
# The Debian python3 has the Debian numpy and matplotlib; a python3 earlier on PATH (pyenv,
# a venv) may not.
python=python3
for candidate in /usr/bin/python3 python3; do
    if "$candidate" -c "import numpy, matplotlib" 2>/dev/null; then
        python=$candidate
        break
    fi
done

# --- ddof-study -----------------------------------------------------------------------------
if [ -n "${DDOF_STUDY_EXE:-}" ]; then
    exe=$DDOF_STUDY_EXE
else
    step "building ddof-study (build/study, Release)"
    cmake -S . -B build/study -G Ninja -DCMAKE_BUILD_TYPE=Release -DDDOF_BUILD_TESTS=OFF \
        -DDDOF_BUILD_BENCH=OFF >/dev/null
    cmake --build build/study -j "$(nproc 2>/dev/null || echo 2)" --target ddof-study
    # The GL backend plugin, when this tree has it: without it the GL configurations are
    # reported as not available, which is not an error.
    if ninja -C build/study -t targets all 2>/dev/null | grep -q '^ddof_gl:'; then
        cmake --build build/study -j "$(nproc 2>/dev/null || echo 2)" --target ddof_gl ||
            echo "study/run.sh: warning: the GL plugin did not build; GL configurations will" \
                "be reported as not available" >&2
    fi
    exe=$root/build/study/study/ddof-study
fi

if [ "$mode" = smoke ]; then
    mkdir -p "$outdir"
    outdir=$(cd "$outdir" && pwd)
    cache=$outdir/scenes
    results=$outdir/results
    md=$outdir/accuracy.md
    images=$outdir
    presets=$outdir/presets_measured.inc
    scene_flags=(--smoke)
    # No GL in the smoke run: its configurations are CPU ones, and loading Mesa would bring
    # Mesa's own allocations into a sanitizer build's leak report.
    sweep_args+=(--no-gl)
    [ -n "$configs" ] || configs=smoke
    report_flags=(--smoke --command "bash study/run.sh --smoke $outdir")
else
    cache=$root/build/study-cache/scenes
    results=$root/build/study-results
    md=$root/docs/accuracy.md
    images=$root/docs/images
    presets=$root/libddof/src/api/presets_measured.inc
    scene_flags=()
    [ -n "$configs" ] || configs=full
    report_flags=(--command "bash study/run.sh")
fi
[ -z "$scenes_arg" ] || scene_flags+=(--scenes "$scenes_arg")

# --- the scenes and the Defocus node (both cached) ------------------------------------------
if [ "$mode" != report ]; then
    step "rendering the scenes into $cache (cached renders are kept)"
    if ! "$blender" -b --factory-startup --python-exit-code 1 \
        --python study/scenes/make_scenes.py -- --out "$cache" "${scene_flags[@]}" 2>&1 |
        blender_filter; then
        echo "study/run.sh: make_scenes.py failed" >&2
        exit 1
    fi

    # The bundled sample (samples/: a lit scene, unlike the emission-only study scenes) is a
    # scene of the study too: copied into the cache (the Defocus node writes beside its
    # inputs), with a 1920x1080 pinhole for the timings rendered by its own script.
    if [ "$mode" = full ]; then
        sample=$cache/bundled_sample
        mkdir -p "$sample"
        for f in pinhole.exr truth.exr camera.json; do
            [ "$sample/$f" -nt "samples/$f" ] || cp "samples/$f" "$sample/$f"
        done
        if ! [ "$sample/pinhole_1080.exr" -nt samples/make_sample.py ]; then
            step "rendering the bundled sample's 1920x1080 pinhole (samples/make_sample.py)"
            tmp=$sample/.render_1080
            rm -rf "$tmp"
            if ! "$blender" -b --factory-startup --python-exit-code 1 \
                --python samples/make_sample.py -- --out "$tmp" --size 1920x1080 \
                --samples-pinhole 16 --only pinhole 2>&1 | blender_filter; then
                echo "study/run.sh: make_sample.py failed" >&2
                exit 1
            fi
            mv "$tmp/pinhole.exr" "$sample/pinhole_1080.exr"
            rm -rf "$tmp"
        fi
    fi

    scene_dirs=()
    for dir in "$cache"/*/; do
        dir=${dir%/}
        [ -f "$dir/pinhole.exr" ] && [ -f "$dir/truth.exr" ] || continue
        if [ -n "$scenes_arg" ] && [[ ",$scenes_arg," != *",$(basename "$dir"),"* ]]; then
            continue
        fi
        scene_dirs+=("$dir")
    done
    [ "$mode" != smoke ] || scene_dirs=("$cache/thin_bars")
    [ ${#scene_dirs[@]} -gt 0 ] || { echo "study/run.sh: no scenes in $cache" >&2; exit 1; }

    # One Blender's Defocus node on every scene (cached: a result newer than its input and
    # the script is kept). $1: the node's file name (defocus, defocus-4.2, ...); the rest: the
    # command that runs study/scenes/defocus_node.py (arguments follow it).
    # At 1920x1080 one composite takes up to minutes (its cost grows with the blur radius
    # squared): 3 timed runs after the warm-up there (and defocus_node.py takes a warm-up
    # over 20 s as the one measurement).
    # $node_tags: the frame sizes ("" the scene's own, 1080 the timing frame).
    run_node() {
        local name=$1 dir tag src json
        shift
        for dir in "${scene_dirs[@]}"; do
            for tag in "${node_tags[@]}"; do
                src=$dir/pinhole${tag:+_$tag}.exr
                json=$dir/$name${tag:+_$tag}.json
                [ -f "$src" ] || continue
                if [ -f "$json" ] && [ "$json" -nt "$src" ] &&
                    [ "$json" -nt study/scenes/defocus_node.py ]; then
                    continue
                fi
                if ! "$@" study/scenes/defocus_node.py -- --scene-dir "$dir" \
                    ${tag:+--size-tag "$tag" --repeats 3} 2>&1 | blender_filter; then
                    echo "study/run.sh: defocus_node.py ($name) failed on $dir" >&2
                    exit 1
                fi
            done
        done
    }
    node_tags=("" 1080)
    step "Blender's Defocus node (3.4, $blender) on ${#scene_dirs[@]} scene(s) (cached)"
    run_node defocus "$blender" -b --factory-startup --python-exit-code 1 --python

    # The node of Blender 4.2 LTS and 5.3 through PyPI's bpy (scripts/bpy_venv.sh makes the
    # venvs, cached; a version it cannot install is skipped with its reason). Not in the smoke
    # run (its configurations do not use them).
    if [ "$mode" = full ]; then
        bpy_cache=${DDOF_BPY_CACHE:-$HOME/.cache/ddof-bpy}
        if [ "$bpy_nodes_1080" = 1 ]; then
            node_tags=("" 1080)
        else
            node_tags=("")
            echo "study/run.sh: the 4.2 and 5.3 Defocus nodes run at the scenes' size only" \
                "(--bpy-nodes-1080 times them at 1920x1080 too)"
        fi
        [ "${DDOF_STUDY_NO_INSTALL:-0}" = 1 ] || bash scripts/bpy_venv.sh 4.2.23 5.3.0
        for v in 4.2.23 5.3.0; do
            venv=$bpy_cache/venv-$v
            if [ ! -f "$venv/ok" ]; then
                reason=$(cat "$venv.reason" 2>/dev/null ||
                    echo "no venv (bash scripts/bpy_venv.sh $v)")
                echo "study/run.sh: skipping Blender $v's Defocus node: $reason" >&2
                continue
            fi
            step "Blender's Defocus node ($v, bpy) on ${#scene_dirs[@]} scene(s) (cached)"
            run_node "defocus-${v%.*}" "$venv/bin/python"
        done
    fi

    count=$("$exe" list --configs "$configs" | wc -l)
    step "sweep: $count configurations x ${#scene_dirs[@]} scene(s) -> $results/results.jsonl"
    "$exe" run --out "$results" --configs "$configs" "${sweep_args[@]}" "${scene_dirs[@]}"
fi

# --- the near layer's picture (the scenes with a blurred near object, through `ddof`) --------
if [ "$mode" = full ] && [ -d build/study ]; then
    step "the near layer's picture -> docs/images/near_layer.png"
    if cmake --build build/study -j "$(nproc 2>/dev/null || echo 2)" --target ddof-cli >/dev/null; then
        "$python" scripts/near_layer_image.py --ddof build/study/plugin/apps/ddof ||
            echo "warning: scripts/near_layer_image.py failed; the report keeps the old picture" >&2
    fi
fi

# --- the report -----------------------------------------------------------------------------
[ -f "$results/results.jsonl" ] || { echo "study/run.sh: no $results/results.jsonl" >&2; exit 1; }
step "report -> $md"
"$python" study/report.py "$results/results.jsonl" --md "$md" --images "$images" \
    --presets "$presets" --study-exe "$exe" --work "$results/images" "${report_flags[@]}"
step "done"
if [ "$mode" != smoke ]; then
    echo "The presets in libddof/src/api/presets_measured.inc are compiled into libddof: rebuild" \
        "(cmake --build ...) for ddof_params_init, the ddof command and the add-on to use them."
fi
