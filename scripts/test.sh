#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test: the unit and integration suite (ctest:
# core, command line, preview model, headless and Xvfb snapshots), the preview's session tests
# under ThreadSanitizer, and short runs of the benchmarks so that they never rot (their timings
# are not asserted).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
ctest --test-dir build --output-on-failure -j2

echo "== session tests under ThreadSanitizer"
cmake -S . -B build-tsan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCAUSTICA_SANITIZE=thread \
      -DCAUSTICA_BUILD_BENCH=OFF >/dev/null
cmake --build build-tsan -j2 --target session_tests
TSAN_OPTIONS=halt_on_error=1 build-tsan/tests/ui/session_tests

echo "== benchmark smoke runs"
build/bench_render --benchmark_min_time=0.01 --benchmark_filter='nonhier' >/dev/null
build/bench_preview --changes 3 --frames 30 >/dev/null
build/trade --quick --out "$(mktemp -d)" | tail -1   # speed against accuracy (docs/ACCURACY.md)
echo "benchmarks ran"
