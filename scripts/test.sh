#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Builds ddof with warnings as errors and runs every test. Installs what is missing first.
#
#   bash scripts/test.sh              Release build, all ctest tests (the README's test command),
#                                     the Blender add-on's included (installs Blender if missing,
#                                     and bpy 5.3, 5.2 LTS, 4.5 LTS and 4.2 LTS from PyPI:
#                                     scripts/bpy_venv.sh, about 300 MB to download and 1 GB on
#                                     disk each, once)
#   bash scripts/test.sh --sanitize   the same under AddressSanitizer + UndefinedBehaviorSanitizer
#   bash scripts/test.sh --valgrind   the unit and EXR tests under valgrind memcheck (reduced sizes)
#   bash scripts/test.sh --fuzz [S]   the libFuzzer targets (clang, fuzz/): each runs S seconds
#                                     (default 60) from its corpus; any finding (a crash, a
#                                     sanitizer report, an allocation over 1 GB) fails, and what
#                                     each target reported ends the output
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/deps.sh

mode=${1:-}
jobs=$(nproc 2>/dev/null || echo 2)
case "$mode" in
"")
    ensure_packages "${BUILD_PACKAGES[@]}"
    # The Blender add-on's background-mode tests (tests/blender, ctest label `blender`) run
    # when Debian's Blender is installed; without it they are reported as skipped.
    ensure_packages blender python3 ||
        echo "warning: could not install blender: the Blender add-on tests will be skipped" >&2
    ensure_packages "${TEST_TOOL_PACKAGES[@]}" ||
        echo "warning: could not install ${TEST_TOOL_PACKAGES[*]}: the exrheader check will be skipped" >&2
    ensure_packages xvfb xauth ||
        echo "warning: could not install xvfb: the add-on's UI test will be skipped" >&2
    ensure_packages python3-numpy python3-matplotlib || echo "warning: could not install numpy/matplotlib: the study smoke test (tests/study) will be skipped" >&2
    # Blender as a Python module from PyPI (tests/bpy/versions.txt: 4.2 LTS to the newest 5.x),
    # for the add-on's `bpy` tests (tests/bpy): cached venvs under ~/.cache/ddof-bpy; bpy 5.1+
    # needs a Python 3.13 (pyenv's is found); one that cannot be installed is a skipped test
    # that says why.
    ensure_packages python3-venv || echo "warning: could not install python3-venv: the bpy tests will be skipped" >&2
    bash scripts/bpy_venv.sh
    # OpenCue's pyoutline and the Open Job Description CLI (PyPI) for the `farm` tests
    # (tests/farm): one cached venv under ~/.cache/ddof-farm; nodejs checks the Flamenco job
    # type's syntax.
    ensure_packages nodejs || echo "warning: could not install nodejs: the Flamenco job type's check will be skipped" >&2
    bash scripts/farm_venv.sh
    cmake -S . -B build/test -G Ninja -DCMAKE_BUILD_TYPE=Release -DDDOF_WERROR=ON
    cmake --build build/test -j "$jobs"
    ctest --test-dir build/test --output-on-failure -j "$jobs"
    ;;
--sanitize)
    ensure_packages "${BUILD_PACKAGES[@]}"
    cmake -S . -B build/sanitize -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDDOF_WERROR=ON \
        -DDDOF_SANITIZE=ON -DDDOF_BUILD_BENCH=OFF
    cmake --build build/sanitize -j "$jobs"
    ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
        ctest --test-dir build/sanitize --output-on-failure -j "$jobs" -E consumer
    ;;
--valgrind)
    ensure_packages "${BUILD_PACKAGES[@]}" valgrind
    cmake -S . -B build/valgrind -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDDOF_WERROR=ON \
        -DDDOF_BUILD_BENCH=OFF
    cmake --build build/valgrind -j "$jobs"
    passed=0
    failed=0
    scratch=build/valgrind/valgrind-scratch
    rm -rf "$scratch"
    # memcheck NAME COMMAND...: one test program under valgrind, counted.
    memcheck() {
        local name=$1
        shift
        if DDOF_TEST_QUICK=1 valgrind --quiet --error-exitcode=99 --leak-check=full \
            --errors-for-leak-kinds=definite,indirect "$@" >/dev/null; then
            passed=$((passed + 1))
        else
            echo "valgrind: $name failed" >&2
            failed=$((failed + 1))
        fi
    }
    for exe in build/valgrind/tests/test_*; do
        [ -x "$exe" ] && memcheck "$exe" "$exe"
    done
    # The EXR library's tests (the command's tests run `ddof` as a child process, which this
    # does not reach).
    exr=build/valgrind/tests/exr
    memcheck exr_roundtrip "$exr/test_exr_roundtrip" "$scratch/roundtrip" tests/exr/data
    memcheck exr_bad_input "$exr/test_exr_bad_input" "$scratch/bad_input" fuzz/corpus/exr_read
    memcheck exr_threads "$exr/test_exr_threads" "$scratch/threads"
    memcheck exr_dwa_roundtrip "$exr/test_exr_dwa" roundtrip "$scratch/dwa_roundtrip"
    memcheck exr_blender_sample "$exr/test_exr_blender" sample samples "$scratch/sample"
    memcheck cli_option_table "$exr/test_option_table" "$scratch/option_table"
    # The fuzz targets' corpora (seeds and former crashes), replayed without libFuzzer.
    for exe in build/valgrind/fuzz/fuzz_replay_*; do
        [ -x "$exe" ] && memcheck "$exe" "$exe" "fuzz/corpus/${exe##*/fuzz_replay_}"
    done
    echo "valgrind: $passed passed, $failed failed"
    [ "$failed" -eq 0 ]
    ;;
--fuzz)
    seconds=${2:-60}
    ensure_packages "${BUILD_PACKAGES[@]}" clang libclang-rt-14-dev
    CC=clang CXX=clang++ cmake -S . -B build/fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDDOF_WERROR=ON \
        -DDDOF_FUZZ=ON -DDDOF_BUILD_TESTS=OFF -DDDOF_BUILD_BENCH=OFF -DDDOF_BUILD_GL=OFF
    cmake --build build/fuzz -j "$jobs" --target fuzz_exr_read fuzz_camera_json fuzz_options \
        fuzz_library fuzz_cards_scene fuzz_matte
    found=0
    failed=()
    for name in exr_read camera_json options library cards_scene matte; do
        # New inputs go to a scratch corpus in the build tree; the committed one is read only.
        work=build/fuzz/work/$name
        mkdir -p "$work" build/fuzz/findings build/fuzz/logs
        echo "fuzz_$name: $seconds s (log: build/fuzz/logs/$name.log)"
        # One allocation over 1 GB is a finding of its own, named with its stack: under the
        # RSS limit alone, inputs that each allocate 1.7 GB add up and the one running when the
        # process crosses 2 GB is written out instead of the one that allocated.
        if ! ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
            "build/fuzz/fuzz/fuzz_$name" -max_total_time="$seconds" -close_fd_mask=3 \
            -rss_limit_mb=2048 -malloc_limit_mb=1024 -timeout=25 -print_final_stats=1 \
            -artifact_prefix="build/fuzz/findings/$name-" "$work" "fuzz/corpus/$name" \
            >"build/fuzz/logs/$name.log" 2>&1; then
            echo "fuzz_$name: finding in build/fuzz/findings (copy it into fuzz/corpus/$name" \
                "once fixed: it then replays as a test)" >&2
            found=1
            failed+=("$name")
        fi
        grep -E '^(stat::|Done )' "build/fuzz/logs/$name.log" || true
    done
    # Last, where a log's tail shows it: which targets found something, and the inputs.
    if [ "$found" -ne 0 ]; then
        echo "fuzz: findings by ${failed[*]}" >&2
        for name in "${failed[@]}"; do
            echo "== fuzz_$name: what it reported" >&2
            grep -E -A 14 'ERROR|runtime error|SUMMARY' "build/fuzz/logs/$name.log" | head -n 60 >&2
        done
        for f in build/fuzz/findings/*; do
            [ -f "$f" ] || continue
            echo "== $f ($(wc -c <"$f") bytes), first 512 as hex:" >&2
            head -c 512 "$f" | od -A d -t x1 >&2
        done
    fi
    [ "$found" -eq 0 ]
    ;;
*)
    echo "usage: bash scripts/test.sh [--sanitize|--valgrind|--fuzz [SECONDS]]" >&2
    exit 2
    ;;
esac
