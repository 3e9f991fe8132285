#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test: the unit and integration suite (ctest:
# core, command line, preview model, headless and Xvfb snapshots, replay of fuzz/regressions),
# the same suite again under AddressSanitizer + UndefinedBehaviorSanitizer with leak detection,
# the preview's session tests under ThreadSanitizer, and short runs of the benchmarks so that they
# never rot (their timings are not asserted). Tests that need ../shared (the course scenes) skip
# when it is absent. See docs/RELIABILITY.md for the sanitizer settings and for fuzzing.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
ctest --test-dir build --output-on-failure -j2

echo "== suite under AddressSanitizer + UndefinedBehaviorSanitizer"
# Exported, so that the programs the tests start (caustica, caustica-view...) run with the same
# settings. Undefined behaviour stops the program (-fno-sanitize-recover=undefined at compile
# time, halt_on_error here); every leak fails the test except those of the graphics libraries
# named in tests/lsan.supp. RelWithDebInfo: optimised enough for the renderer's tests, with line
# numbers in the reports. No benchmarks. A quarantine of 64 MiB instead of 256: the loader's
# many small allocations make a process grow about 12 times the quarantine, which the memory
# bounds of the reproducer tests would take for a leak of the budget. Line tables only (-g1): the
# reports keep their file:line frames, the build is a fifth faster; the test sources themselves
# are built at -O0 (tests/CMakeLists.txt), four times faster to compile.
export ASAN_OPTIONS=detect_leaks=1:halt_on_error=1:strict_string_checks=1:check_initialization_order=1:quarantine_size_mb=64
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp:print_suppressions=0"
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
      -DCAUSTICA_SANITIZE=address,undefined \
      -DCAUSTICA_BUILD_BENCH=OFF >/dev/null
cmake --build build-asan -j2
ctest --test-dir build-asan --output-on-failure -j2
unset ASAN_OPTIONS UBSAN_OPTIONS LSAN_OPTIONS

echo "== session tests under ThreadSanitizer"
cmake -S . -B build-tsan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
      -DCAUSTICA_SANITIZE=thread \
      -DCAUSTICA_BUILD_BENCH=OFF >/dev/null
cmake --build build-tsan -j2 --target session_tests
TSAN_OPTIONS=halt_on_error=1 build-tsan/tests/ui/session_tests

echo "== benchmark smoke runs"
build/bench_render --benchmark_min_time=0.01 --benchmark_filter='nonhier' >/dev/null
build/bench_preview --changes 3 --frames 30 >/dev/null
build/trade --quick --out "$(mktemp -d)" | tail -1   # speed against accuracy (docs/ACCURACY.md)
echo "benchmarks ran"
