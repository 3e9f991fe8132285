#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test: the unit and integration suite (ctest:
# core, command line, preview model, headless and Xvfb snapshots, replay of fuzz/regressions),
# the same suite again under AddressSanitizer + UndefinedBehaviorSanitizer with leak detection,
# the preview's session tests under ThreadSanitizer, and short runs of the benchmarks so that they
# never rot (their timings are not asserted). Tests that need ../shared (the course scenes) skip
# when it is absent, and a stage runs them so; any skip tests/expected_skips does not explain
# fails its stage (scripts/check-skips.sh). See docs/RELIABILITY.md for the sanitizer settings
# and for fuzzing.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
log=$(mktemp)
trap 'rm -f "$log"' EXIT
# Without ../shared beside this clone the course-scene tests skip in every stage, as they should.
without_shared=""
[ -d ../shared/cs488 ] || without_shared=" no-shared"
ctest --test-dir build --output-on-failure -j2 | tee "$log"
scripts/check-skips.sh "release$without_shared" "$log"

echo "== the tests that read ../shared, as a clone without it runs them"
CAUSTICA_CS488_DIR=/nonexistent/cs488 ctest --test-dir build --output-on-failure -j2 \
    -R 'Cs488/|CourseScenes\.|SceneLoader\.(EveryCourseSceneLoads|HierarchyTransformsAndInstancing)|MeshObj\.TheCourseCowLoads|Wysiwyg\.|ReadmeRecipes' \
    | tee "$log"
grep -q 'Cs488/CourseScene.*(Skipped)' "$log"  # the course scenes were indeed missing
scripts/check-skips.sh no-shared "$log"

echo "== suite under AddressSanitizer + UndefinedBehaviorSanitizer"
# Exported, so that the programs the tests start (caustica, caustica-view...) run with the same
# settings. Undefined behaviour stops the program (-fno-sanitize-recover=undefined at compile
# time, halt_on_error here); every leak fails the test except those of the graphics libraries
# named in tests/lsan.supp. RelWithDebInfo: optimised enough for the renderer's tests, with line
# numbers in the reports. No benchmarks. A quarantine of 64 MiB instead of 256: the loader's
# many small allocations make a process grow about 12 times the quarantine, which the memory
# bounds of the reproducer tests would take for a leak of the budget. Line tables only (-g1): the
# reports keep their file:line frames, the build is a fifth faster; the test sources themselves
# are built at -O0 (tests/CMakeLists.txt), four times faster to compile. Built with clang: it
# builds this tree in half GCC's time under the sanitizers, and a second compiler's warnings and
# checks see what the first does not (the release build above is GCC's).
export ASAN_OPTIONS=detect_leaks=1:halt_on_error=1:strict_string_checks=1:check_initialization_order=1:quarantine_size_mb=64
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp:print_suppressions=0"
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
      -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DCAUSTICA_SANITIZE=address,undefined \
      -DCAUSTICA_BUILD_BENCH=OFF >/dev/null
cmake --build build-asan -j2
ctest --test-dir build-asan --output-on-failure -j2 | tee "$log"
scripts/check-skips.sh "asan$without_shared" "$log"
unset ASAN_OPTIONS UBSAN_OPTIONS LSAN_OPTIONS

echo "== session tests under ThreadSanitizer"
# Built with GCC, as the release build: clang's ThreadSanitizer reports a race inside oneTBB's
# partitioner header (its work-stealing check), which GCC's does not.
cmake -S . -B build-tsan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
      -DCAUSTICA_SANITIZE=thread \
      -DCAUSTICA_BUILD_BENCH=OFF >/dev/null
cmake --build build-tsan -j2 --target session_tests
TSAN_OPTIONS=halt_on_error=1 build-tsan/tests/ui/session_tests

echo "== every benchmark and tool, once (timings not asserted)"
# Each prints its last lines; a benchmark that skips says so, and fails the stage when what it
# needs is there (bench_render's course scenes).
out=$(mktemp -d)
smoke() {
    local name=$1 output
    shift
    if ! output=$("$@" 2>&1); then
        echo "$output" | tail -20
        echo "$name failed"
        return 1
    fi
    echo "$output" | tail -2
    if grep -qi "skipped:" <<<"$output"; then
        if [ "$name" = bench_render ] && [ ! -d ../shared/cs488 ]; then
            echo "$name: skipped as expected (no ../shared/cs488 beside this clone)"
        else
            echo "$name: UNEXPECTED SKIP"
            return 1
        fi
    fi
}
smoke bench_render build/bench_render --benchmark_min_time=0.01 --benchmark_filter='nonhier'
smoke bench_csg build/bench_csg --benchmark_min_time=0.001
smoke bench_loader build/bench_loader --benchmark_min_time=0.001
smoke bench_photons build/bench_photons --benchmark_min_time=0.001
smoke bench_photon_grid build/bench_photon_grid --benchmark_min_time=0.001
smoke bench_photon_knn build/bench_photon_knn --benchmark_min_time=0.001 --benchmark_filter='photons:1M'
smoke bench_preview build/bench_preview tests/ui/scenes/caustic_box.lua --changes 3 --frames 30 --size 320x180  # a small scene: the same paths
smoke caustic_error build/caustic_error --quick
smoke probe_model build/probe_model   # the blur probe on model caustics (docs/ACCURACY.md)
smoke trade build/trade --quick --out "$out/trade"   # speed against accuracy (docs/ACCURACY.md)
smoke image_diff build/image_diff "$out/trade/trade-default.png" "$out/trade/trade-default.png"
# image_diff reads float images: a PFM against itself differs by 0, against the same render's
# 8-bit PNG (values truncated to 1/255) by more than 0 and less than one step, against its
# half-float EXR by more than 0 and less than half-float rounding (2^-11 of values up to 1).
image_diff_floats() {
    local d="$out/diff" r
    mkdir -p "$d"
    for f in pfm png exr; do build/caustica render --reproducible --minres scenes/default.lua -o "$d/x.$f" >/dev/null; done
    rmse_between() {  # rmse_between A B LOW HIGH: image_diff A B, its rmse in (LOW, HIGH)
        r=$(build/image_diff "$1" "$2") && echo "$r" &&
            awk -v r="$r" -v lo="$3" -v hi="$4" 'BEGIN { split(r, f, "[= ]"); exit !(f[2] > lo && f[2] < hi) }'
    }
    r=$(build/image_diff "$d/x.pfm" "$d/x.pfm") && echo "$r" && [[ $r == rmse=0.000000\ * ]] &&
        rmse_between "$d/x.png" "$d/x.pfm" 0 "$(awk 'BEGIN { print 1 / 255 }')" &&
        rmse_between "$d/x.exr" "$d/x.pfm" 0 "$(awk 'BEGIN { print 2 ^ -11 }')"
}
smoke image_diff-floats image_diff_floats
smoke side_by_side build/side_by_side "$out/pair.png" "$out/trade/trade-default.png" "$out/trade/trade-glass_of_liquid.png"
smoke scaling bench/scaling.sh --quick   # mpirun against threads (docs/SCALING.md)
smoke peers env OUT="$out/peers" CYCLES=0 bench/peers/run.sh --quick   # against POV-Ray (docs/PEERS.md)
smoke peers-progressive env OUT="$out/peers-progressive" CYCLES=0 bench/peers/run.sh --progressive --quick
smoke float_race env OUT="$out/float-race" bench/peers/float_race.sh --quick   # in floats (docs/PEERS.md)
rm -rf "$out"
echo "benchmarks and tools ran"
