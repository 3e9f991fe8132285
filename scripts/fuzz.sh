#!/usr/bin/env bash
# Fuzzes the scene loader, the OBJ reader and the PNG reader with libFuzzer (docs/RELIABILITY.md,
# "Fuzzing"): builds build-fuzz with clang, makes the seed corpus (fuzz/make_corpus.sh), then runs
# each target for SECONDS (default 60) on its corpus and its regressions, one after the other.
#   scripts/fuzz.sh [SECONDS] [TARGET...]        TARGET: scene_loader, obj_reader, png_reader
# Inputs found that grow coverage stay in build-fuzz/corpus/TARGET (the next run starts from
# them); a crash is written to build-fuzz/findings/DATE/TARGET/ and makes the script exit 1 at the end.
# Extra libFuzzer flags, e.g. two processes per target: FUZZ_FLAGS=-fork=2 scripts/fuzz.sh 600.
# On a shared machine set CAUSTICA_BUILD_LOCK to a file: the build then runs under flock on it.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
shift || true
targets=("$@")
((${#targets[@]})) || targets=(scene_loader obj_reader png_reader)

cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang \
      -DCMAKE_CXX_COMPILER=clang++ -DCAUSTICA_FUZZ=ON -DCAUSTICA_BUILD_TESTS=OFF \
      -DCAUSTICA_BUILD_BENCH=OFF >/dev/null
build=(cmake --build build-fuzz -j2 --target "${targets[@]/#/fuzz_}")
if [ -n "${CAUSTICA_BUILD_LOCK:-}" ]; then flock "$CAUSTICA_BUILD_LOCK" "${build[@]}"; else "${build[@]}"; fi

fuzz/make_corpus.sh build-fuzz/seeds >/dev/null
# A smaller quarantine than ASan's 256 MiB: freed blocks wait there before reuse, and with the
# loader's many small allocations the process grows about 12 times the quarantine (3 GB for a
# 100000-node scene that needs 75 MB), which would make every big seed an out-of-memory finding.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:quarantine_size_mb=64}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1}
stamp=$(date +%Y%m%d-%H%M%S)
failed=()
for target in "${targets[@]}"; do
    corpus=build-fuzz/corpus/$target
    findings=build-fuzz/findings/$stamp/$target
    log=build-fuzz/$target.log
    mkdir -p "$corpus" "$findings"
    # On the first run the seeds that add coverage are merged into the corpus (some seeds are
    # slow on purpose, so they are not read again each run). rm -rf build-fuzz/corpus to start
    # again from the seeds. A seed that crashes is left out by the merge and shown here.
    if [ -z "$(ls -A "$corpus")" ]; then
        echo "== $target: merging the seeds into $corpus"
        "build-fuzz/fuzz_$target" -merge=1 -timeout=30 -rss_limit_mb=2048 -malloc_limit_mb=1024 \
            -artifact_prefix="$findings/seed-" "$corpus" "build-fuzz/seeds/$target" >"build-fuzz/$target.merge.log" 2>&1 || true
        grep -E 'ERROR|MERGE-OUTER: (attempt|[0-9]+ new)' "build-fuzz/$target.merge.log" | sort | uniq -c || true
    fi
    inputs=("$corpus" "fuzz/regressions/$target")
    # -timeout: seconds one input may take. -rss_limit_mb / -malloc_limit_mb: a process over 2 GiB
    # or one allocation over 1 GiB is a finding (memory is bounded).
    flags=(-max_total_time="$seconds" -rss_limit_mb=2048 -malloc_limit_mb=1024 -dict="fuzz/$target.dict"
           -artifact_prefix="$findings/" -print_final_stats=1 -print_funcs=0)
    if [ "$target" = scene_loader ]; then
        # The loader runs in this process (its child process would hide crashes from libFuzzer),
        # where it cannot interrupt one long C call (a backtracking string pattern): such inputs
        # exceed -timeout. Fork mode keeps fuzzing past them; they are listed below, not failed.
        # A hung render is caught by the target itself (more than 15 s for 8 x 8 pixels aborts).
        flags+=(-timeout=30 -fork=1 -ignore_timeouts=1 -ignore_ooms=0 -ignore_crashes=0)
    else
        # (The ignore flags matter in fork mode only, e.g. FUZZ_FLAGS=-fork=2: nothing is ignored.)
        flags+=(-timeout=10 -ignore_timeouts=0 -ignore_ooms=0 -ignore_crashes=0)
    fi
    echo "== $target: ${seconds} s"
    set +e
    # shellcheck disable=SC2086
    "build-fuzz/fuzz_$target" "${flags[@]}" ${FUZZ_FLAGS:-} "${inputs[@]}" >"$log" 2>&1
    status=$?
    set -e
    grep -aE '^(stat::|#[0-9]+: )|ERROR|SUMMARY' "$log" | tail -8 || true
    for found in "$findings"/*; do
        [ -e "$found" ] || continue
        case "$target:$(basename "$found")" in
            scene_loader:timeout-*|scene_loader:seed-timeout-*) echo "slow in-process load (not a failure): $found: $(head -c 120 "$found" | tr '\n' ' ')" ;;
            *) echo "FINDING: $found"; status=1 ;;
        esac
    done
    if [ "$status" -ne 0 ]; then failed+=("$target"); fi
done
if ((${#failed[@]})); then
    echo "findings in: ${failed[*]} (build-fuzz/findings/$stamp/TARGET/; logs build-fuzz/TARGET.log)."
    echo "Each crashing input goes to fuzz/regressions/TARGET/ once understood (replayed by the suite)."
    exit 1
fi
echo "no findings"
