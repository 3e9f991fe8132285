#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test (unit, integration, command line) and a
# short smoke run of each benchmark so that they never rot (their timings are not asserted).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
ctest --test-dir build --output-on-failure -j2
echo "benchmark smoke run:"
build/bench_render --benchmark_min_time=0.01 --benchmark_filter='nonhier' >/dev/null
echo "benchmarks ran"
