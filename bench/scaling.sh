#!/usr/bin/env bash
# Scaling measurements for `caustica render` under mpirun (docs/SCALING.md).
#
#   bench/scaling.sh [--quick] [--runs N] [--build DIR] [--keep]
#
# For each case (classic and progressive, default scene and caustic_box at --midres) it times
#   (a) one process, -j1      (b) mpirun -n 2, -j1 each (one core per rank)      (c) one process, -j2
# and prints medians of N runs (N = 5; --quick: 1) of the wall time (mpirun's start included) and
# of the time the renderer reports (from the scene's start to the image), the speed-ups (a)/(b) and
# (c)/(b), and checks that the three images are identical (cmp of the .pfm files, --reproducible).
# Then the pieces the scaling model needs: classic photon shooting and k-d tree time against the
# photon count, the photon bytes every rank receives in the all-gather (36 B a stored photon), the
# rays/s of one core, the time of a progressive pass per megapixel, the size of the final reduction
# (112 B a pixel: 14 int64) and mpirun's start-up time.
# Every timed run holds /tmp/caustica-bench.lock (and the build lock, see timed below); the load is
# printed before each case.
# Needs a built build/caustica (ninja -C build caustica) and Open MPI's mpirun.
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build="$root/build"
runs=5
quick=0
keep=0
while [[ $# -gt 0 ]]; do
    case "$1" in
        --quick) quick=1; runs=1 ;;
        --runs) runs="$2"; shift ;;
        --build) build="$2"; shift ;;
        --keep) keep=1 ;;
        -h|--help) sed -n '2,16p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
        *) echo "scaling.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
    esac
    shift
done
[[ "$runs" =~ ^[1-9][0-9]*$ ]] || { echo "scaling.sh: --runs needs a positive integer, not '$runs'" >&2; exit 2; }
caustica="$build/caustica"
[[ -x "$caustica" ]] || { echo "scaling.sh: $caustica is missing: build it first (ninja -C build caustica)" >&2; exit 2; }
command -v mpirun >/dev/null || { echo "scaling.sh: mpirun is not on PATH (apt-get install openmpi-bin)" >&2; exit 2; }

lock=/tmp/caustica-bench.lock
mpi=(mpirun -n 2 --bind-to core)
[[ $(id -u) -eq 0 ]] && mpi+=(--allow-run-as-root)
work=$(mktemp -d /tmp/caustica-scaling.XXXXXX)
if [[ $keep -eq 0 ]]; then trap 'rm -rf "$work"' EXIT; fi
cd "$root"
# A copy of the binary (taken under the build lock): a rebuild during the runs cannot mix versions.
flock "/tmp/caustica-build.lock" cp "$caustica" "$work/caustica"
caustica="$work/caustica"

now() { date +%s.%N; }
load() { cut -d' ' -f1-3 /proc/loadavg; }
median() { sort -g | awk '{v[NR] = $1} END {if (NR == 0) print "nan"; else print v[int((NR + 1) / 2)]}'; }
# A stage time ("  photon shooting   0.348 s") or 0 when the log has none.
stage() { awk -v name="$2" 'index($0, "  " name " ") == 1 && $NF == "s" {v = $(NF - 1)} END {print v + 0}' "$1"; }
reported() { sed -n 's/^wrote .*, \([0-9.]*\) s)$/\1/p' "$1" | tail -1; }
map_photons() { awk '$1 == "caustic" && $2 == "map" {print $3}' "$1" | tail -1; }
rays_per_second() { sed -n 's/^ *total .*(\([0-9.]*\) M rays\/s)$/\1/p' "$1" | tail -1; }
lines() { if [[ -f "$1" ]]; then wc -l <"$1"; else echo 0; fi; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN {if (b > 0) printf "%.2f", a / b; else print "nan"}'; }

# Before each timed run: the bench lock (/tmp/caustica-bench.lock), then the build lock
# (/tmp/caustica-build.lock, waited for at most two minutes: no build starts during a run), then up
# to 30 s for an idle half second (under 10% of the CPU busy; other helpers' runs hold no lock),
# except with --quick, whose timings are not measurements.
# Runs that started on a busy machine are counted and reported. None of the waiting is timed.
build_lock=/tmp/caustica-build.lock
cpu_busy() {  # per cent of the CPU busy over half a second
    local a b
    a=$(awk '/^cpu / {print $2 + $3 + $4 + $7 + $8, $2 + $3 + $4 + $5 + $6 + $7 + $8}' /proc/stat)
    sleep 0.5
    b=$(awk '/^cpu / {print $2 + $3 + $4 + $7 + $8, $2 + $3 + $4 + $5 + $6 + $7 + $8}' /proc/stat)
    awk -v a="$a" -v b="$b" 'BEGIN {split(a, x, " "); split(b, y, " "); t = y[2] - x[2];
        printf "%d\n", (t > 0) ? 100 * (y[1] - x[1]) / t : 0}'
}
wait_idle() {
    local i
    ((quick)) && return 0  # a smoke run: its timings are not measurements
    for ((i = 0; i < 60; ++i)); do
        (($(cpu_busy) < 10)) && return 0
    done
    echo busy >>"$work/busy-starts"  # timed runs in a subshell: counted in a file
}

# timed LOG CMD...: runs CMD with the locks held, its output into LOG; prints the wall seconds.
exec 9>>"$lock" 8>>"$build_lock"
timed() {
    local log="$1"; shift
    local t0 t1 status=0 build_held=1
    flock 9
    flock -w 120 8 || { build_held=0; echo nolock >>"$work/no-build-lock"; }
    # A run interrupted from outside (exit 130 or 143: another user's signal) is run again, twice at most.
    for _ in 1 2 3; do
        wait_idle
        status=0
        t0=$(now)
        "$@" >"$log" 2>&1 8>&- 9>&- || status=$?
        t1=$(now)
        [[ $status -eq 130 || $status -eq 143 ]] || break
        echo "$log" >>"$work/interrupted"
    done
    ((build_held)) && flock -u 8
    flock -u 9
    if [[ $status -ne 0 ]]; then
        echo "scaling.sh: failed (exit $status): $* (log: $log)" >&2
        tail -5 "$log" >&2
        exit 1
    fi
    awk -v a="$t0" -v b="$t1" 'BEGIN {printf "%.3f\n", b - a}'
}

echo "caustica scaling: $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo '?'), $(nproc) cores, $(mpirun --version | head -1)"
echo "runs per measurement: $runs; logs in $work$([[ $keep -eq 0 ]] && echo ' (removed at the end; --keep keeps them)')"
echo "uptime: $(uptime)"
if ((quick)); then
    echo "(--quick: a smoke run; no timed run waits for an idle machine, so these timings are not measurements)"
else
    echo "(each timed run holds the bench and build locks and waits up to 30 s for a half second under 10% CPU busy)"
fi
echo

# ---- 1. one process vs two processes vs two threads -------------------------------------------
cases=(
    "default classic|scenes/default.lua --integrator classic"
    "caustic_box classic|tests/ui/scenes/caustic_box.lua --midres --integrator classic"
    "default progressive|scenes/default.lua --integrator progressive --passes 16"
    "caustic_box progressive|tests/ui/scenes/caustic_box.lua --midres --integrator progressive --passes 16"
)
declare -A first_log
printf '%-24s %-15s %9s %9s %9s %9s %9s %9s %6s %6s %s\n' case load wall_a wall_b wall_c rep_a rep_b rep_c 'a/b' 'c/b' images
idx=0
for entry in "${cases[@]}"; do
    name=${entry%%|*}
    read -r -a args <<<"${entry#*|}"
    idx=$((idx + 1))
    before=$(load)
    declare -A walls=() reps=()
    same=identical
    for ((i = 1; i <= runs; ++i)); do
        for mode in a b c; do
            out="$work/c$idx-$mode-$i.pfm" log="$work/c$idx-$mode-$i.log"
            case $mode in
                a) w=$(timed "$log" "$caustica" render "${args[@]}" --reproducible -j1 -t -S -o "$out") ;;
                b) w=$(timed "$log" "${mpi[@]}" "$caustica" render "${args[@]}" --reproducible -j1 -t -S -o "$out") ;;
                c) w=$(timed "$log" "$caustica" render "${args[@]}" --reproducible -j2 -t -S -o "$out") ;;
            esac
            walls[$mode]+="$w "
            reps[$mode]+="$(reported "$log") "
            if [[ $mode != a ]] && ! cmp -s "$work/c$idx-a-$i.pfm" "$out"; then same="DIFFER($mode,run$i)"; fi
        done
    done
    declare -A mwall=() mrep=()
    for mode in a b c; do
        mwall[$mode]=$(tr ' ' '\n' <<<"${walls[$mode]}" | grep . | median)
        mrep[$mode]=$(tr ' ' '\n' <<<"${reps[$mode]}" | grep . | median)
    done
    first_log[$idx]="$work/c$idx-a-1.log"
    printf '%-24s %-15s %9s %9s %9s %9s %9s %9s %6s %6s %s\n' "$name" "${before// /,}" \
        "${mwall[a]}" "${mwall[b]}" "${mwall[c]}" "${mrep[a]}" "${mrep[b]}" "${mrep[c]}" \
        "$(ratio "${mwall[a]}" "${mwall[b]}")" "$(ratio "${mwall[c]}" "${mwall[b]}")" "$same"
    # Per-stage times of the last run of each mode (rank 0's for b).
    for mode in a b c; do
        log="$work/c$idx-$mode-$runs.log"
        printf '    %s: shoot %s s, tree %s s, first samples %s s, anti-aliasing %s s, passes %s s, photon passes %s s, %s M rays/s\n' \
            "$mode" "$(stage "$log" 'photon shooting')" "$(stage "$log" 'photon k-d tree')" "$(stage "$log" 'first samples')" \
            "$(stage "$log" 'anti-aliasing')" "$(stage "$log" 'progressive passes')" "$(stage "$log" 'photon passes')" \
            "$(rays_per_second "$log")"
    done
done
echo "wall: seconds from the command's start to its end (mpirun's start included); rep: what caustica"
echo "reports (scene start to image written); a = 1 process -j1, b = mpirun -n 2 -j1, c = 1 process -j2"
echo

# ---- 2. the pieces of the model ----------------------------------------------------------------
echo "uptime: $(uptime)"
echo "classic photons, default scene --minres, -j1 (shooting and k-d tree against the photon count):"
printf '  %12s %6s %10s %10s %10s %12s %9s %9s %14s %14s\n' directions ranks traced stored shoot_s tree_s \
    'ns/dir' 'ns/tree' 'gather_MB' 'map_MiB'
counts=(1000000 10000000 100000000)
[[ $quick -eq 1 ]] && counts=(1000000 10000000)
for n in "${counts[@]}"; do
    for ranks in 1 2; do
        log="$work/photons-$n-$ranks.log"
        if [[ $ranks -eq 1 ]]; then
            timed "$log" "$caustica" render scenes/default.lua --minres --integrator classic --caustic-num-photons "$n" \
                --reproducible -j1 -t -S -o "$work/photons.pfm" >/dev/null
        else
            timed "$log" "${mpi[@]}" "$caustica" render scenes/default.lua --minres --integrator classic \
                --caustic-num-photons "$n" --reproducible -j1 -t -S -o "$work/photons.pfm" >/dev/null
        fi
        line=$(grep -m1 'caustic photons, light 1:' "$log")
        dirs=$(sed -n 's/.*: \([0-9]*\) directions.*/\1/p' <<<"$line")
        traced=$(sed -n 's/.* \([0-9]*\) traced.*/\1/p' <<<"$line")
        stored=$(map_photons "$log")
        shoot=$(stage "$log" 'photon shooting') tree=$(stage "$log" 'photon k-d tree')
        mib=$(awk '$1 == "caustic" && $2 == "map" {print $5}' "$log" | tail -1)
        awk -v d="$dirs" -v r="$ranks" -v t="$traced" -v s="$stored" -v sh="$shoot" -v tr="$tree" -v mib="$mib" 'BEGIN {
            printf "  %12d %6d %10d %10d %10.3f %12.3f %9.1f %9.1f %14.2f %14s\n", d, r, t, s, sh, tr,
                1e9 * sh / d, (s > 0 ? 1e9 * tr / s : 0), s * 36 / 1e6, mib }'
    done
done
echo "  shoot_s is rank 0's own shooting (its share of the emission blocks); ns/dir = shoot_s per direction;"
echo "  ns/tree = k-d tree build per stored photon (every rank builds the whole tree);"
echo "  gather_MB = 36 B x stored photons: what every rank receives in the all-gather."
echo

echo "per-core rates from case (a) (one core):"
for idx in 1 2; do
    log=${first_log[$idx]}
    awk -v name="${cases[$((idx - 1))]%%|*}" -v fs="$(stage "$log" 'first samples')" -v aa="$(stage "$log" 'anti-aliasing')" \
        -v rays="$(rays_per_second "$log")" -v px="$(sed -n 's/^wrote .*(\([0-9]*\) x \([0-9]*\),.*/\1 \2/p' "$log" | awk '{print $1 * $2}')" 'BEGIN {
        printf "  %-22s %.2f M rays/s overall; first samples %.3f s = %.3f s/Mpx, anti-aliasing %.3f s\n",
            name, rays, fs, fs / (px / 1e6), aa }'
done
for idx in 3 4; do
    log=${first_log[$idx]}
    passes=$(awk '$1 == "progressive" && $2 == "passes" && $NF != "s" {print $3}' "$log" | tail -1)
    awk -v name="${cases[$((idx - 1))]%%|*}" -v pp="$(stage "$log" 'progressive passes')" -v ph="$(stage "$log" 'photon passes')" \
        -v n="$passes" -v px="$(sed -n 's/^wrote .*(\([0-9]*\) x \([0-9]*\),.*/\1 \2/p' "$log" | awk '{print $1 * $2}')" 'BEGIN {
        printf "  %-22s %d passes: tracing %.3f s/pass = %.3f s/pass/Mpx; photons %.3f s/pass (passes 2..n)\n",
            name, n, pp / n, pp / n / (px / 1e6), (n > 1 ? ph / (n - 1) : 0) }'
    dirs=$(sed -n 's/^ *photons over passes *\([0-9]*\) directions/\1/p' "$log")
    echo "      photon directions over the passes: $dirs; final reduction: 112 B x pixels = $(awk -v px="$(sed -n 's/^wrote .*(\([0-9]*\) x \([0-9]*\),.*/\1 \2/p' "$log" | awk '{print $1 * $2}')" 'BEGIN {printf "%.1f MB", 112 * px / 1e6}')"
done
echo

echo "mpirun -n 2 start-up and shutdown (a program that does nothing):"
ts=()
for ((i = 1; i <= runs; ++i)); do ts+=("$(timed "$work/true.log" "${mpi[@]}" /bin/true)"); done
echo "  median $(printf '%s\n' "${ts[@]}" | median) s over $runs runs"
echo "runs started on a busy machine (no idle half second within 30 s): $(lines "$work/busy-starts")"
echo "runs interrupted from outside and run again: $(lines "$work/interrupted")"
echo "runs without the build lock (not free within 2 minutes): $(lines "$work/no-build-lock")"
echo "uptime: $(uptime)"
