#!/usr/bin/env bash
# Against POV-Ray 3.7 (docs/PEERS.md): renders the three peer scenes with caustica and POV-Ray at the
# same resolution and thread count and matched numbers of STORED caustic photons, several
# quality levels each, times every run with the wall clock and measures the caustic error of each
# render against its own renderer's reference (a render with many more photons). Writes the
# PNGs, logs and a Markdown report (results.md) into the output folder; bench/peers/README.md
# explains the scenes, the parameter mapping and how to read the report.
#
#   bench/peers/run.sh [--quick | --report]
#   bench/peers/run.sh --progressive [--quick | --report]
#   bench/peers/run.sh --cycles-references [--quick]
#
# Environment: BUILD (a CMake build folder, default build/, built if the programs are missing, or
# any folder holding caustica, image_diff and side_by_side), OUT (default out/peers), THREADS (2),
# SIZE (512), REPEATS (3: runs of each configuration, the median time is reported), LEVELS
# (stored photons per level), REFERENCE (stored photons of the references, at most what
# MAX_DIRECTIONS gives caustica), MAX_DIRECTIONS (1.5e8: caustica refuses photon counts whose
# worst-case map would not fit in 60% of memory, ignoring projection maps), NEIGHBOURS (100: the
# photons in each radiance estimate, both renderers), POV_RADIUS (0.15: POV-Ray's gather radius,
# caustica's default maximum distance; 0 = POV-Ray's own estimate), SCENES. SIZE is 256, 512 or 1024
# (caustica's --lores, --midres, --hires). --quick: 256 pixels, two levels, one repeat, small
# references (a smoke run, not a measurement). --report: only rewrite results.md from the
# measurements already in the output folder.
#
# --progressive: error against time instead of equal photons, a race between
# POV-Ray at the LEVELS above (and its reference), caustica's progressive integrator and Blender's
# Cycles (if installed), run in rounds: POV-Ray's level k, caustica's level k, Cycles' level k
# (each of CYCLES_MODES), each repeated REPEATS times in turn, then level k + 1, so that all see
# the same machine load (the report gives the load average at the start and the end).
# caustica's curve is time-limited by default (PP_CURVE=time: --passes 0 --time T for T in
# PP_TIMES, 1 2 5 15 60) or one of accumulated passes (PP_CURVE=passes: --passes N for N in
# PASSES, --time 1e6); PP_PHOTONS directions a pass (default 3e6, 2e7 for the glass of liquid),
# PP_NEIGHBOURS (8; no longer what sets the first radius), PP_RADIUS its first radius in pixel
# footprints (--accumulation-radius; empty: the default), PP_PER_PIXEL its --photons-per-pixel
# (empty: the directions as given), PP_AUTO_RADIUS its --auto-radius (on|off; empty: the default),
# jittered samples (no --disable-aa); its own pixel-averaged reference is PP_REF_PASSES (512) passes
# of PP_REF_PHOTONS from a first radius of PP_REF_RADIUS (1) pixel footprints, a third of the
# default's blur at sharp edges (its own estimated error is in the report: errors below it are not
# measurable; kept in OUT and made again when the binaries, the scene or these settings change).
# Cycles (<scene>_cycles.py, cycles_common.py): CPU, THREADS threads, path tracing with shadow
# caustics (MNEE, mode "mnee") and without ("path"), time-limited to each of CYCLES_TIMES (1 2 5 15
# 60) seconds; its references (one per mode, CYCLES_REF_TIME = 600 s of sampling) are made when
# missing or out of date (--cycles-references remakes them) and kept in OUT. CYCLES=0 leaves Cycles
# out; BLENDER names the program (blender); CYCLES_LAMP_RADIUS (0.02) is the radius given to the
# point lights.
# Each renderer's error is against its own reference (as above) and all against caustica's
# progressive reference (the "common" column: the others' biases show there), the median of the
# repeats. Writes progressive.tsv, progressive-refs.tsv and progressive.md (the targets: POV-Ray's
# best error in a third of its time, below it within 60 s, half its error at its time; a lower
# error than Cycles with shadow caustics at 5, 15 and 60 s) and, per scene, peers3_SCENE.png: the
# references side by side, caustica, POV-Ray, Cycles MNEE, Cycles path, and their caustics
# enlarged. --progressive --quick: 256 pixels, POV-Ray at two levels, caustica at 1 and 2 s,
# Cycles at 1 s against 1 s references, one repeat (a smoke run of well under two minutes).
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
source "$here/common.sh"
size=${SIZE:-512}
repeats=${REPEATS:-3}
levels=${LEVELS:-"10000 30000 100000 300000"}
reference=${REFERENCE:-1000000}
max_directions=${MAX_DIRECTIONS:-150000000}
neighbours=${NEIGHBOURS:-100}
pov_radius=${POV_RADIUS:-0.15}
scenes=${SCENES:-"glass_sphere ring glass_of_liquid"}
passes=${PASSES:-"1 2 4 8 16 32 64 128"}
pp_curve=${PP_CURVE:-time}
pp_times=${PP_TIMES:-"1 2 5 15 60"}
pp_photons=${PP_PHOTONS:-}
pp_neighbours=${PP_NEIGHBOURS:-8}
pp_ref_passes=${PP_REF_PASSES:-512}
pp_ref_photons=${PP_REF_PHOTONS:-30000000}
pp_ref_radius=${PP_REF_RADIUS:-1}
pp_radius=${PP_RADIUS:-}
pp_per_pixel=${PP_PER_PIXEL:-}
pp_auto_radius=${PP_AUTO_RADIUS:-}
cycles=${CYCLES:-1}
blender=${BLENDER:-blender}
cycles_modes=${CYCLES_MODES:-"mnee path"}
cycles_times=${CYCLES_TIMES:-"1 2 5 15 60"}
cycles_ref_time=${CYCLES_REF_TIME:-600}
cycles_lamp_radius=${CYCLES_LAMP_RADIUS:-0.02}
mode=${1:-measure} option=${2:-}
usage="usage: bench/peers/run.sh [--quick | --report] | --progressive [--quick | --report] | --cycles-references [--quick]"
case $mode in
  measure | --report) [[ -z $option ]] || { echo "$usage" >&2; exit 2; } ;;
  --quick) [[ -z $option ]] || { echo "$usage" >&2; exit 2; }
           size=256 repeats=1 levels="10000 100000" reference=300000 ;;
  --progressive | --cycles-references)
    case $option in
      "" | --report) ;;
      --quick) size=256 repeats=1 levels="10000 100000" reference=300000 passes="1 4 16" pp_ref_passes=32
               pp_times="1 2" cycles_times=${CYCLES_TIMES:-1} cycles_ref_time=${CYCLES_REF_TIME:-1} ;;
      *) echo "$usage" >&2; exit 2 ;;
    esac
    [[ $mode == --cycles-references && $option == --report ]] && { echo "$usage" >&2; exit 2; } ;;
  *) echo "$usage" >&2; exit 2 ;;
esac
[[ $pp_curve == time || $pp_curve == passes ]] || { echo "run.sh: PP_CURVE is time or passes" >&2; exit 2; }

command -v povray >/dev/null || { echo "run.sh: povray is not installed (scripts/install-deps.sh)" >&2; exit 2; }
# The three programs: BUILD may be a CMake build folder (built here if they are missing; an
# existing build is used as it is) or any folder that holds them (prebuilt binaries).
if [[ ! -x "$build/caustica" || ! -x "$build/image_diff" || ! -x "$build/side_by_side" ]]; then
  if [[ -n ${BUILD:-} && ! -f "$build/build.ninja" && ! -f "$build/CMakeCache.txt" ]]; then
    echo "run.sh: BUILD=$build has neither caustica, image_diff and side_by_side nor a CMake build" >&2
    exit 2
  fi
  [[ -f "$build/build.ninja" ]] || cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$build" -j2 --target caustica image_diff side_by_side
fi
# Cycles (--progressive, --cycles-references): Blender 3.4 as Debian packages it.
if [[ $mode == --progressive || $mode == --cycles-references ]] && [[ $cycles != 0 ]]; then
  if ! command -v "$blender" >/dev/null; then
    echo "run.sh: $blender is not installed: Cycles is left out of this run" \
         "(as root: apt-get install -y --no-install-recommends blender; bench/peers/README.md)" >&2
    cycles=0
    [[ $mode == --cycles-references ]] && exit 2
  fi
fi
[[ $cycles != 0 ]] || cycles_modes=""
declare -A resolution_flag=([256]=--lores [512]=--midres [1024]=--hires)
[[ -n "${resolution_flag[$size]:-}" ]] || { echo "run.sh: SIZE must be 256, 512 or 1024" >&2; exit 2; }
mkdir -p "$out"

# The caustic regions and shadow masks (region, shadow_only) are in common.sh.
# A crop around the caustic for the detail row of the side-by-side images (512-pixel units).
declare -A detail=([glass_sphere]="176 272 432 400" [ring]="192 112 448 368" [glass_of_liquid]="256 200 512 328")
# A patch of floor lit directly and by nothing else (no caustic, no reflection), to check that
# the renderers' direct light agrees (512-pixel units).
declare -A lit_patch=([glass_sphere]="20 400 120 500" [ring]="380 20 500 80" [glass_of_liquid]="40 400 160 480")

# wall SECONDS_FILE LOG COMMAND...: runs the command with its output in LOG, writes its wall time.
wall() {
  local seconds=$1 log=$2 TIMEFORMAT=%R
  shift 2
  { time "$@" >"$log" 2>&1; } 2>"$seconds"
}

# caustica_run SCENE DIRECTIONS PNG: one render; leaves PNG.log and PNG.time.
caustica_run() {
  wall "$3.time" "$3.log" "$build/caustica" render -S --integrator progressive --threads "$threads" --disable-aa "${resolution_flag[$size]}" \
    --caustic-num-photons "$2" --caustic-num-neighbours "$neighbours" "$here/$1.lua" -o "$3"
}
# povray_run SCENE COUNT PNG: one render; leaves PNG.log and PNG.time.
povray_run() {
  wall "$3.time" "$3.log" povray -D -V +WT"$threads" -A +W"$size" +H"$size" +FN File_Gamma=1.0 \
    Declare=Photons="$2" Declare=Gather="$neighbours" Declare=Radius="$pov_radius" +I"$here/$1.pov" +O"$3"
}
# caustica_passes SCENE PASSES DIRECTIONS PNG [RADIUS]: one progressive accumulation (RADIUS: its first
# radius in pixel footprints); PNG.log and PNG.time.
# (--time 1e6, never reached, makes --passes 1 an accumulation's first pass rather than the single
# k-nearest pass.)
caustica_passes() {
  wall "$4.time" "$4.log" "$build/caustica" render -S --integrator progressive --threads "$threads" "${resolution_flag[$size]}" \
    --passes "$2" --time 1e6 --caustic-num-photons "$3" --caustic-num-neighbours "$pp_neighbours" \
    ${5:+--accumulation-radius "$5"} "$here/$1.lua" -o "$4"
}
# The error caustica estimates for its own render (-S), from its log.
caustica_estimate() { sed -n 's/^ *estimated error *\([0-9.]*\).*/\1/p' "$1.log" | head -1; }
# Seconds of an accumulation's photon stages and passes (caustica -S), without the scene build.
caustica_pass_stages() {
  awk '/time: (projection maps|photon shooting|photon k-d tree|photon passes|progressive passes)/ { s += $(NF-1) }
       END { printf "%.3f", s }' "$1.log"
}
# caustica_timed SCENE SECONDS DIRECTIONS PNG: one progressive accumulation stopped by time
# (--passes 0: passes until --time); PNG.log and PNG.time.
caustica_timed() {
  wall "$4.time" "$4.log" "$build/caustica" render -S --integrator progressive --threads "$threads" "${resolution_flag[$size]}" \
    --passes 0 --time "$2" --caustic-num-photons "$3" --caustic-num-neighbours "$pp_neighbours" \
    ${pp_radius:+--accumulation-radius "$pp_radius"} ${pp_per_pixel:+--photons-per-pixel "$pp_per_pixel"} \
    ${pp_auto_radius:+--auto-radius "$pp_auto_radius"} "$here/$1.lua" -o "$4"
}
caustica_passes_done() { sed -n 's/^ *progressive passes *\([0-9]*\).*/\1/p' "$1.log" | head -1; }
# cycles_run SCENE MODE SECONDS SEED PREFIX: one Cycles render of SECONDS of sampling (its time
# limit) by <scene>_cycles.py; leaves PREFIX.png (8-bit clamped linear), PREFIX.exr (float),
# PREFIX.log and PREFIX.time (the wall time of the whole Blender process, start-up included, less
# the script's conversion of the EXR into the PNG).
cycles_run() {
  rm -f "$5.png" "$5.exr"
  if ! wall "$5.time" "$5.log" "$blender" -b --factory-startup --python-exit-code 2 -P "$here/$1_cycles.py" -- \
         --out "$5" --size "$size" --time "$3" --mode "$2" --seed "$4" --threads "$threads" \
         --lamp-radius "$cycles_lamp_radius" || [[ ! -s $5.png ]]; then
    echo "run.sh: Blender failed on $1 ($2, $3 s); the end of $5.log:" >&2
    tail -n 8 "$5.log" >&2
    exit 1
  fi
  # The wall time less the script's EXR-to-PNG conversion (a cost of this comparison, not Cycles').
  awk -v c="$(sed -n 's/^cycles: .* convert_s=\([0-9.]*\).*/\1/p' "$5.log")" '{ printf "%.3f\n", $1 - c }' \
    "$5.time" >"$5.time.tmp" && mv "$5.time.tmp" "$5.time"
}
# The samples per pixel Cycles finished, and its own render time: the Time of its "Finished"
# progress line (scene synchronisation included; Blender's start-up and the scene script not).
cycles_samples() { grep -o 'Sample [0-9]*/' "$1.log" | tr -dc '0-9\n' | sort -n | tail -n 1; }
cycles_seconds() {
  sed -n 's/.*| Time:\([0-9:.]*\) .*| Finished *$/\1/p' "$1.log" | tail -n 1 |
    awk -F: '{ s = 0; for (i = 1; i <= NF; ++i) s = s * 60 + $i; printf "%.3f", s }'
}
# Cycles' references: CYCLES_REF_TIME seconds of sampling with a seed no test render uses, named
# by size and time, remade when missing, when their key (settings, Blender's version, the scene
# scripts' checksum) changed, or when forced (--cycles-references).
cycles_ref() { echo "$out/$1-cycles-$2-ref-${size}px-${cycles_ref_time}s"; }
cycles_reference() {
  local prefix key
  prefix=$(cycles_ref "$1" "$2")
  key="lamp radius $cycles_lamp_radius, $threads threads, $blender_version, scripts $(cat "$here/$1_cycles.py" \
       "$here/cycles_common.py" | sha1sum | cut -c1-12)"
  if [[ ${3:-} != force && -s $prefix.png && -f $prefix.key && $(cat "$prefix.key") == "$key" ]]; then
    echo "   Cycles $2 reference kept: $(cycles_samples "$prefix") samples in $(cycles_seconds "$prefix") s"
    return
  fi
  echo "   Cycles $2 reference: $cycles_ref_time s of sampling..."
  cycles_run "$1" "$2" "$cycles_ref_time" 1000 "$prefix"
  echo "$key" >"$prefix.key"
  echo "   Cycles $2 reference: $(cycles_samples "$prefix") samples in $(cycles_seconds "$prefix") s ($(cat "$prefix.time") s wall)"
}
# caustica_reference SCENE PNG: caustica's progressive reference, made again only when the
# binaries, the scene or the reference's settings differ from those it was made with (PNG.key).
caustica_reference() {
  local key
  key="$pp_ref_passes passes of $pp_ref_photons from r1 $pp_ref_radius at $size, binaries and scene \
$(cat "$build/caustica" "$build/caustica-scene-loader" "$here/$1.lua" | sha1sum | cut -c1-12)"
  if [[ -s $2 && -f $2.key && -f $2.log && -f $2.time && $(cat "$2.key") == "$key" ]]; then
    echo "   caustica reference kept (made in $(cat "$2.time") s)"
    return
  fi
  rm -f "$2.key"
  caustica_passes "$1" "$pp_ref_passes" "$pp_ref_photons" "$2" "$pp_ref_radius"
  echo "$key" >"$2.key"
}
caustica_stored() { sed -n 's/.*caustic photons, light 1: .* \([0-9]*\) stored.*/\1/p' "$1.log"; }
caustica_traced() { sed -n 's/.*caustic photons, light 1: .* \([0-9]*\) traced.*/\1/p' "$1.log"; }
povray_stored() { sed -n 's/^Surface photons stored: *\([0-9]*\).*/\1/p' "$1.log"; }
povray_shot() { sed -n 's/^Number of photons shot: *\([0-9]*\).*/\1/p' "$1.log"; }
# Stage seconds: caustica's photon stages (projection maps, shooting, k-d tree) and image;
# POV-Ray's "Photon Time" and "Trace Time".
caustica_stages() {
  awk '/time: (projection maps|photon shooting|photon k-d tree)/ { p += $(NF-1) }
       /time: first samples/ { r += $(NF-1) } END { printf "%.3f %.3f", p, r }' "$1.log"
}
povray_stages() {
  awk -F'[(]' '/Photon Time:/ { split($2, a, " "); p = a[1] } /Trace Time:/ { split($2, a, " "); r = a[1] }
               END { printf "%.3f %.3f", p, r }' "$1.log"
}
median() { tr ' ' '\n' | sed '/^$/d' | sort -g | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }'; }
# The error of PNG against REFERENCE over SCENE's caustic region: "rmse relative mean clipped".
caustic_error() {
  local args=(--rect $(scaled "${region[$1]}"))
  [[ ${shadow_only[$1]} == 1 ]] && args+=(--mask-dark "$out/$1-no-caustics.png")
  "$build/image_diff" "$2" "$3" "${args[@]}" |
    sed 's/rmse=\([^ ]*\) relative=\([^ ]*\) mean_test=[^ ]* mean_ref=\([^ ]*\) pixels=[^ ]* clipped_ref=\(.*\)/\1 \2 \3 \4/'
}

# prepare_scene SCENE: the render without caustics (the shadow mask of caustic_error) and the
# stored photons per photon requested of each renderer (ours_ratio, pov_ratio), to match the two
# renderers' stored counts.
prepare_scene() {
  "$build/caustica" render -s --integrator progressive --threads "$threads" --disable-aa "${resolution_flag[$size]}" --no-caustic-map \
    "$here/$1.lua" -o "$out/$1-no-caustics.png"
  caustica_run "$1" 2000000 "$out/$1-calibrate-caustica.png"
  povray_run "$1" 30000 "$out/$1-calibrate-povray.png"
  ours_ratio=$(awk -v s="$(caustica_stored "$out/$1-calibrate-caustica.png")" 'BEGIN { print s / 2000000 }')
  pov_ratio=$(awk -v s="$(povray_stored "$out/$1-calibrate-povray.png")" 'BEGIN { print s / 30000 }')
}

results=$out/results.tsv references=$out/references.tsv
measure() {
  rm -f "$out"/runs.tsv.*
  printf 'scene\trenderer\tlevel\tstored\tshot\twall_s\tphoton_s\timage_s\trmse\trelative\n' >"$results"
  printf 'scene\tcaustica_mean\tpovray_mean\trmse\trelative\tcaustica_clipped\tpovray_clipped\n' >"$references"
  local startup
  startup=$(for i in 1 2 3; do
    printf '#version 3.7;\ncamera { location <0, 0, -1> look_at 0 }\n' >"$out/empty.pov"
    wall "$out/empty.time" "$out/empty.log" povray -D -V +WT"$threads" +W8 +H8 +I"$out/empty.pov" +O"$out/empty.png"
    cat "$out/empty.time"; done | median)

  local scene
  for scene in $scenes; do
    echo "== $scene"
    prepare_scene "$scene"

    # The references: as many stored photons as asked, or as caustica's direction cap allows.
    ref_target=$(awk -v t="$reference" -v c="$max_directions" -v r="$ours_ratio" \
                 'BEGIN { m = c * r; printf "%d", t < m ? t : m }')
    for level in $levels ref; do
      target=$level
      [[ $level == ref ]] && target=$ref_target
      pov_count=$(awk -v t="$target" -v r="$pov_ratio" 'BEGIN { printf "%d", t / r }')
      pov_png=$out/$scene-povray-$level.png ours_png=$out/$scene-caustica-$level.png
      pov_times=() ours_times=()
      runs=$repeats
      [[ $level == ref ]] && runs=1
      for ((r = 0; r < runs; ++r)); do
        # POV-Ray first: its stored count sets ours (directions = its stored count / our ratio).
        povray_run "$scene" "$pov_count" "$pov_png"
        pov_times+=("$(cat "$pov_png.time")")
        directions=$(awk -v s="$(povray_stored "$pov_png")" -v r="$ours_ratio" -v c="$max_directions" \
                     'BEGIN { d = s / r; printf "%d", d < c ? d : c }')
        caustica_run "$scene" "$directions" "$ours_png"
        ours_times+=("$(cat "$ours_png.time")")
      done
      printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$scene" povray "$level" "$(povray_stored "$pov_png")" \
        "$(povray_shot "$pov_png")" "$(echo "${pov_times[*]}" | median)" $(povray_stages "$pov_png") \
        >>"$out/runs.tsv.$scene"
      printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$scene" caustica "$level" "$(caustica_stored "$ours_png")" \
        "$(caustica_traced "$ours_png")" "$(echo "${ours_times[*]}" | median)" $(caustica_stages "$ours_png") \
        >>"$out/runs.tsv.$scene"
      echo "   $level: povray $(povray_stored "$pov_png") stored in ${pov_times[*]} s," \
           "caustica $(caustica_stored "$ours_png") stored in ${ours_times[*]} s"
    done

    while IFS=$'\t' read -r s renderer level rest; do
      rmse=- relative=-
      [[ $level != ref ]] &&
        read -r rmse relative _ _ < <(caustic_error "$scene" "$out/$scene-$renderer-$level.png" \
                                                    "$out/$scene-$renderer-ref.png")
      printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$s" "$renderer" "$level" "$rest" "$rmse" "$relative" >>"$results"
    done <"$out/runs.tsv.$scene"
    # Do the two converged references agree? (brightness and shape of the caustic)
    ours_ref=$out/$scene-caustica-ref.png pov_ref=$out/$scene-povray-ref.png
    read -r cross_rmse cross_relative pov_mean pov_clipped < <(caustic_error "$scene" "$ours_ref" "$pov_ref")
    read -r _ _ ours_mean ours_clipped < <(caustic_error "$scene" "$pov_ref" "$ours_ref")
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$scene" "$ours_mean" "$pov_mean" "$cross_rmse" "$cross_relative" \
      "$ours_clipped" "$pov_clipped" >>"$references"

    # Side by side: the references (caustica left, POV-Ray right), then the caustic region at the
    # level above the middle (100000 by default) enlarged twice.
    middle=$(echo $levels | awk '{ print $(int(NF / 2) + 1) }')
    "$build/side_by_side" "$out/$scene-refs.png" "$out/$scene-caustica-ref.png" "$out/$scene-povray-ref.png"
    "$build/side_by_side" "$out/$scene-detail.png" "$out/$scene-caustica-$middle.png" "$out/$scene-povray-$middle.png" \
      --crop $(scaled "${detail[$scene]}") --zoom 2
    "$build/side_by_side" "$out/peers_$scene.png" "$out/$scene-refs.png" "$out/$scene-detail.png" --vertical
  done
  rm -f "$out"/runs.tsv.*
  echo "$(date -u +%Y-%m-%d), $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg) at the end; ${size}x${size}," \
       "$threads threads, $neighbours photons per estimate (POV-Ray radius $pov_radius), median of $repeats runs;" \
       "POV-Ray's idle start-up (an empty scene) takes $startup s of wall time." >"$out/setup.txt"
}

# The report: every run, the references' agreement, and the time each renderer needs to reach the
# error the other reaches at each level.
report() {
  echo "# caustica against POV-Ray 3.7"
  echo
  cat "$out/setup.txt"
  echo
  echo "| scene | renderer | stored photons | shot/traced | wall s | photon s | image s | RMSE | relative RMSE |"
  echo "|---|---|---:|---:|---:|---:|---:|---:|---:|"
  tail -n +2 "$results" | awk -F'\t' '{ printf "| %s | %s%s | %d | %d | %.2f | %.3f | %.3f | %s | %s |\n", $1, $2,
                                        $3 == "ref" ? " (reference)" : "", $4, $5, $6, $7, $8,
                                        $3 == "ref" ? "-" : sprintf("%.4f", $9), $3 == "ref" ? "-" : sprintf("%.3f", $10) }'
  echo
  echo "References (the 'ref' rows' photons, one run): mean over the caustic region, RMSE between"
  echo "the two references, and the fraction of region pixels clipped at 255."
  echo
  echo "| scene | caustica mean | POV-Ray mean | RMSE between | relative | clipped caustica | clipped POV-Ray |"
  echo "|---|---:|---:|---:|---:|---:|---:|"
  tail -n +2 "$references" |
    awk -F'\t' '{ printf "| %s | %.4f | %.4f | %.4f | %.3f | %.4f | %.4f |\n", $1, $2, $3, $4, $5, $6, $7 }'
  echo
  echo "Equal quality: for each level of one renderer, the time the other needs for the same relative"
  echo "error: interpolated in log-log between its last level above that error and its first level at"
  echo "or below it; \"<=\" when its first level is already better, \"-\" when none of its levels"
  echo "reaches it. Wall time, and the renderers' own stage times (POV-Ray: photon + trace; caustica:"
  echo "photon stages + image), which leave out start-up."
  echo
  echo "| scene | relative error | POV-Ray wall s | caustica wall s | POV-Ray / caustica |" \
       "POV-Ray stages s | caustica stages s | POV-Ray / caustica |"
  echo "|---|---:|---:|---:|---:|---:|---:|---:|"
  tail -n +2 "$results" | awk -F'\t' '
    $3 == "ref" { next }
    {
      k = ++n[$1, $2]; t[$1, $2, k] = $6; u[$1, $2, k] = $7 + $8; e[$1, $2, k] = $10
      if (!($1 in seen)) { seen[$1] = 1; order[++scenes] = $1 }
    }
    # The time (column c: t wall, u stages) renderer r needs for error err; bound = 1 when its
    # first level is already better (the time is an upper bound), -1 when no level reaches it.
    function time_for(s, r, err, c,   i, x0, x1, y0, y1) {
      bound = 0
      for (i = 1; i <= n[s, r]; ++i) if (e[s, r, i] <= err) break
      if (i > n[s, r]) { bound = -1; return 0 }
      y1 = c == "t" ? t[s, r, i] : u[s, r, i]
      if (i == 1) { bound = (e[s, r, 1] < err); return y1 }
      y0 = c == "t" ? t[s, r, i - 1] : u[s, r, i - 1]
      x0 = log(e[s, r, i - 1]); x1 = log(e[s, r, i])
      if (x0 == x1) return y1
      return exp(log(y0) + (log(err) - x0) / (x1 - x0) * (log(y1) - log(y0)))
    }
    function cell(v, b) { return b < 0 ? "-" : sprintf("%s%.2f", b > 0 ? "<=" : "", v) }
    function ratio(p, bp, c, bc) {
      if (bp < 0 || bc < 0) return "-"
      if (bp > 0 && bc > 0) return "?"
      return sprintf("%s%.1f", bp > 0 ? "<=" : (bc > 0 ? ">=" : ""), p / c)
    }
    # One row: the error of level i of renderer r, and both renderers times for it.
    function row(s, r, i,   err, tp, bp, tc, bc, up, bup, uc, buc) {
      err = e[s, r, i]
      tp = time_for(s, "povray", err, "t"); bp = bound; up = time_for(s, "povray", err, "u"); bup = bound
      tc = time_for(s, "caustica", err, "t"); bc = bound; uc = time_for(s, "caustica", err, "u"); buc = bound
      printf "| %s | %.3f (%s level %d) | %s | %s | %s | %s | %s | %s |\n", s, err, r == "povray" ? "POV-Ray" : "caustica", i,
             cell(tp, bp), cell(tc, bc), ratio(tp, bp, tc, bc), cell(up, bup), cell(uc, buc), ratio(up, bup, uc, buc)
    }
    END {
      for (k = 1; k <= scenes; ++k) {
        for (i = 1; i <= n[order[k], "povray"]; ++i) row(order[k], "povray", i)
        for (i = 1; i <= n[order[k], "caustica"]; ++i) row(order[k], "caustica", i)
      }
    }'
}

# --progressive: POV-Ray's levels, caustica's progressive curve and Cycles' time-limited renders,
# error against time.
progressive_tsv=$out/progressive.tsv progressive_refs=$out/progressive-refs.tsv
declare -A samples_of=()  # "renderer quantity" -> the repeats' values, space-separated
# note RENDERER WALL OWN ERROR_OWN ERROR_COMMON: one repeat's measurements.
note() {
  samples_of[$1 wall]+="$2 " samples_of[$1 own]+="$3 " samples_of[$1 err]+="$4 " samples_of[$1 common]+="$5 "
}
# row SCENE RENDERER LEVEL UNIT WORK: a progressive.tsv row, the medians of the repeats noted.
row() {
  local q values=()
  for q in wall own err common; do values+=("$(echo "${samples_of[$2 $q]}" | median)"); done
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$1" "$2" "$3" "$4" "$5" "${values[@]}" >>"$progressive_tsv"
  echo "   $2 $3 $4: ${samples_of[$2 wall]}s wall, ${samples_of[$2 own]}s own, relative ${samples_of[$2 err]}(own reference)," \
       "${samples_of[$2 common]}(common)"
}
# ref_row SCENE RENDERER PNG DESCRIPTION: a progressive-refs.tsv row: the reference's mean over
# the caustic region, its relative RMSE against caustica's, and the means of the lit patch in it
# and in caustica's render without caustics (direct light only).
ref_row() {
  local ours_ref=$out/$1-progressive-ref.png mean relative patch
  read -r _ _ mean _ < <(caustic_error "$1" "$ours_ref" "$3")
  read -r _ relative _ < <(caustic_error "$1" "$3" "$ours_ref")
  patch=$("$build/image_diff" "$3" "$out/$1-no-caustics.png" --rect $(scaled "${lit_patch[$1]}") |
          sed 's/.*mean_test=\([^ ]*\) mean_ref=\([^ ]*\) .*/\1\t\2/')
  printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$1" "$2" "$4" "$mean" "$relative" "$patch" >>"$progressive_refs"
}

measure_progressive() {
  local started load_start scene
  started=$(date -u '+%Y-%m-%d %H:%M') load_start=$(cut -d' ' -f1-3 /proc/loadavg)
  printf 'scene\trenderer\tlevel\tunit\twork\twall_s\town_s\trelative_own\trelative_common\n' >"$progressive_tsv"
  printf 'scene\trenderer\treference\tregion_mean\trelative_to_caustica\tpatch_mean\tpatch_direct\n' >"$progressive_refs"
  for scene in $scenes; do
    echo "== $scene (progressive)"
    prepare_scene "$scene"
    local ours_ref=$out/$scene-progressive-ref.png pov_ref=$out/$scene-povray-pref.png m
    local photons=${pp_photons:-${scene_pp_photons[$scene]}}
    caustica_reference "$scene" "$ours_ref"
    povray_run "$scene" "$(awk -v t="$reference" -v r="$pov_ratio" 'BEGIN { printf "%d", t / r }')" "$pov_ref"
    echo "   references: caustica $pp_ref_passes passes in $(cat "$ours_ref.time") s, POV-Ray $(povray_stored "$pov_ref") stored in $(cat "$pov_ref.time") s"
    for m in $cycles_modes; do cycles_reference "$scene" "$m"; done
    ref_row "$scene" caustica "$ours_ref" \
      "$pp_ref_passes passes of $pp_ref_photons directions, r₁ $pp_ref_radius, own estimated error $(caustica_estimate "$ours_ref")"
    ref_row "$scene" povray "$pov_ref" "$(povray_stored "$pov_ref") stored photons"
    for m in $cycles_modes; do
      ref_row "$scene" "cycles-$m" "$(cycles_ref "$scene" "$m").png" \
        "$(cycles_samples "$(cycles_ref "$scene" "$m")") samples ($cycles_ref_time s)"
    done

    # The race: round k runs POV-Ray's level k, caustica's level k and Cycles' level k (each
    # mode), and again for each repeat, so that all see the same load.
    local pov_levels=($levels) ours_levels=($pp_times) cycles_levels=($cycles_times) k r n level png own common
    [[ $pp_curve == passes ]] && ours_levels=($passes)
    [[ -n $cycles_modes ]] || cycles_levels=()
    n=${#pov_levels[@]}
    ((${#ours_levels[@]} > n)) && n=${#ours_levels[@]}
    ((${#cycles_levels[@]} > n)) && n=${#cycles_levels[@]}
    for ((k = 0; k < n; ++k)); do
      samples_of=()
      for ((r = 0; r < repeats; ++r)); do
        if ((k < ${#pov_levels[@]})); then
          png=$out/$scene-povray-p${pov_levels[k]}.png
          povray_run "$scene" "$(awk -v t="${pov_levels[k]}" -v r="$pov_ratio" 'BEGIN { printf "%d", t / r }')" "$png"
          read -r _ own _ < <(caustic_error "$scene" "$png" "$pov_ref")
          read -r _ common _ < <(caustic_error "$scene" "$png" "$ours_ref")
          note povray "$(cat "$png.time")" "$(povray_stages "$png" | awk '{ printf "%.3f", $1 + $2 }')" "$own" "$common"
        fi
        if ((k < ${#ours_levels[@]})); then
          png=$out/$scene-progressive-${ours_levels[k]}.png
          if [[ $pp_curve == passes ]]; then
            caustica_passes "$scene" "${ours_levels[k]}" "$photons" "$png" "$pp_radius"
          else
            png=$out/$scene-progressive-${ours_levels[k]}s.png
            caustica_timed "$scene" "${ours_levels[k]}" "$photons" "$png"
          fi
          read -r _ own _ < <(caustic_error "$scene" "$png" "$ours_ref")
          note caustica "$(cat "$png.time")" "$(caustica_pass_stages "$png")" "$own" "$own"
        fi
        if ((k < ${#cycles_levels[@]})); then
          for m in $cycles_modes; do
            png=$out/$scene-cycles-$m-${cycles_levels[k]}s
            cycles_run "$scene" "$m" "${cycles_levels[k]}" "$((r + 1))" "$png"
            read -r _ own _ < <(caustic_error "$scene" "$png.png" "$(cycles_ref "$scene" "$m").png")
            read -r _ common _ < <(caustic_error "$scene" "$png.png" "$ours_ref")
            note "cycles-$m" "$(cat "$png.time")" "$(cycles_seconds "$png")" "$own" "$common"
          done
        fi
      done
      if ((k < ${#pov_levels[@]})); then
        row "$scene" povray "${pov_levels[k]}" stored "$(povray_stored "$out/$scene-povray-p${pov_levels[k]}.png")"
      fi
      if ((k < ${#ours_levels[@]})); then
        if [[ $pp_curve == passes ]]; then
          row "$scene" caustica "${ours_levels[k]}" passes "$((ours_levels[k] * photons))"
        else
          row "$scene" caustica "${ours_levels[k]}" s "$(caustica_passes_done "$out/$scene-progressive-${ours_levels[k]}s.png")"
        fi
      fi
      if ((k < ${#cycles_levels[@]})); then
        for m in $cycles_modes; do
          row "$scene" "cycles-$m" "${cycles_levels[k]}" s "$(cycles_samples "$out/$scene-cycles-$m-${cycles_levels[k]}s")"
        done
      fi
    done

    # Side by side: the references (caustica, POV-Ray, Cycles MNEE, Cycles path), then their
    # caustics enlarged twice.
    local panels=("$ours_ref" "$pov_ref")
    for m in $cycles_modes; do panels+=("$(cycles_ref "$scene" "$m").png"); done
    "$build/side_by_side" "$out/$scene-refs3.png" "${panels[@]}"
    "$build/side_by_side" "$out/$scene-refs3-detail.png" "${panels[@]}" --crop $(scaled "${detail[$scene]}") --zoom 2
    "$build/side_by_side" "$out/peers3_$scene.png" "$out/$scene-refs3.png" "$out/$scene-refs3-detail.png" --vertical
  done
  local caustica_curve="--passes 0 --time T for T in $pp_times"
  [[ $pp_curve == passes ]] && caustica_curve="--passes $passes (--time 1e6)"
  {
    echo "$started to $(date -u '+%H:%M') UTC, $(nproc) cores, load average $load_start at the start and" \
         "$(cut -d' ' -f1-3 /proc/loadavg) at the end; ${size}x${size}, $threads threads, median of $repeats runs," \
         "the renderers interleaved run by run."
    echo
    echo "- POV-Ray 3.7: $neighbours photons per estimate within $pov_radius, levels of stored photons $levels;" \
         "reference $reference stored."
    echo "- caustica: progressive integrator, $caustica_curve, ${pp_photons:-3e6 (2e7 for glass_of_liquid)}" \
         "directions a pass${pp_per_pixel:+ raised to $pp_per_pixel traced photons per pixel (time curve)}, N $pp_neighbours, first radius ${pp_radius:-3 (the default)} pixel footprints${pp_auto_radius:+, --auto-radius $pp_auto_radius}; reference $pp_ref_passes passes of $pp_ref_photons from a first radius" \
         "of $pp_ref_radius pixel footprints."
    if [[ -n $cycles_modes ]]; then
      echo "- Cycles ($blender_version): CPU, $threads threads, box filter of one pixel, no denoising, no" \
           "clamping, point light of radius $cycles_lamp_radius, time limits $cycles_times s;" \
           "modes: $cycles_modes (mnee: shadow caustics, manifold next-event estimation; path: plain path" \
           "tracing); references $cycles_ref_time s of sampling each. Own time: Cycles' render time" \
           "(scene synchronisation included, Blender's start-up and scene script not)."
    else
      echo "- Cycles: not in this run."
    fi
  } >"$out/progressive-setup.txt"
}

# The progressive report: every run, the references' agreement, each renderer's error at each
# time, and the targets.
report_progressive() {
  echo "# caustica's progressive integrator against POV-Ray 3.7 and Cycles: error against time"
  echo
  cat "$out/progressive-setup.txt"
  echo
  echo "## References"
  echo
  echo "Mean over the caustic region, relative RMSE against caustica's reference (region and shadow"
  echo "mask as for every error), and the mean of a directly lit floor patch against caustica's render"
  echo "without caustics (direct light only: does the lighting agree?)."
  echo
  echo "| scene | renderer | reference | region mean | relative RMSE to caustica's | lit patch | caustica direct | ratio |"
  echo "|---|---|---|---:|---:|---:|---:|---:|"
  tail -n +2 "$progressive_refs" | awk -F'\t' '{ printf "| %s | %s | %s | %.4f | %.3f | %.4f | %.4f | %.4f |\n",
                                                 $1, $2, $3, $4, $5, $6, $7, ($7 > 0 ? $6 / $7 : 0) }'
  echo
  echo "## Every run"
  echo
  echo "Level: POV-Ray's stored photons, caustica's seconds (--time) or passes, Cycles' time limit."
  echo "Work: photons stored, passes done, samples per pixel. Own time: POV-Ray's photon + trace"
  echo "time, caustica's photon and pass stages, Cycles' render time. Errors: relative RMSE over the"
  echo "caustic region against the renderer's own reference and against caustica's (\"common\")."
  echo
  echo "| scene | renderer | level | work | wall s | own s | relative (own reference) | relative (common reference) |"
  echo "|---|---|---:|---:|---:|---:|---:|---:|"
  tail -n +2 "$progressive_tsv" | awk -F'\t' '{
    work = $2 == "povray" ? " stored" : ($2 == "caustica" ? ($4 == "s" ? " passes" : " directions") : " samples")
    printf "| %s | %s | %s %s | %.0f%s | %.2f | %.2f | %.3f | %.3f |\n", $1, $2, $3, $4, $5, work, $6, $7, $8, $9 }'
  tail -n +2 "$progressive_tsv" | awk -F'\t' -v cycles_times="$cycles_times" -v pp_times="$pp_times" '
    { k = ++n[$1, $2]; lv[$1, $2, k] = $3; un[$1, $2, k] = $4; t["wall", $1, $2, k] = $6; t["own", $1, $2, k] = $7
      t["budget", $1, $2, k] = $4 == "s" ? $3 : $7; e["own", $1, $2, k] = $8; e["common", $1, $2, k] = $9
      if (!($1 in seen)) { seen[$1] = 1; order[++scenes] = $1 }
      if (!($2 in rseen)) { rseen[$2] = 1; renderers[++nr] = $2 } }
    function lerp(x, x0, x1, y0, y1) { return x1 == x0 ? y1 : exp(log(y0) + (log(x) - log(x0)) / (log(x1) - log(x0)) * (log(y1) - log(y0))) }
    # The error of renderer r at time x on axis a (wall, own, budget), error ec (own, common):
    # log-log between the runs around x; past = 1 when x is past its last run (its last error),
    # -1 when x is before its first run (no image yet), -2 when it did not run.
    function at(s, r, x, a, ec,   i, j, m, idx, tmp) {
      m = n[s, r]; past = 0
      if (m == 0) { past = -2; return 0 }
      for (i = 1; i <= m; ++i) idx[i] = i
      for (i = 2; i <= m; ++i) for (j = i; j > 1 && t[a, s, r, idx[j]] < t[a, s, r, idx[j - 1]]; --j) {
        tmp = idx[j]; idx[j] = idx[j - 1]; idx[j - 1] = tmp }
      if (x < t[a, s, r, idx[1]]) { past = -1; return 0 }
      for (i = 1; i <= m; ++i) if (t[a, s, r, idx[i]] >= x) break
      # A time-limited run that stopped early (caustica starts no pass it cannot finish in
      # time) stands for its whole time limit.
      if (i > m) { past = (un[s, r, idx[m]] == "s" && lv[s, r, idx[m]] >= x) ? 0 : 1; return e[ec, s, r, idx[m]] }
      if (i == 1) return e[ec, s, r, idx[1]]
      return lerp(x, t[a, s, r, idx[i - 1]], t[a, s, r, idx[i]], e[ec, s, r, idx[i - 1]], e[ec, s, r, idx[i]])
    }
    function cell(v) { return past == -2 ? "" : past < 0 ? "–" : sprintf("%.3f%s", v, past > 0 ? "*" : "") }
    function name(r) { return r == "povray" ? "POV-Ray" : r == "cycles-mnee" ? "Cycles MNEE" : r == "cycles-path" ? "Cycles path" : r }
    END {
      split(cycles_times " " pp_times " 1 2 5 15 60", raw, " ")
      for (i in raw) if (raw[i] != "" && !(raw[i] in tseen)) { tseen[raw[i]] = 1; times[++nt] = raw[i] + 0 }
      for (i = 2; i <= nt; ++i) for (j = i; j > 1 && times[j] < times[j - 1]; --j) { tmp = times[j]; times[j] = times[j - 1]; times[j - 1] = tmp }
      for (a = 1; a <= 2; ++a) {
        axis = a == 1 ? "wall" : "own"
        print ""
        print "## Error at each time (" (a == 1 ? "wall time of the process" : "the renderers'"'"' own time") ")"
        print ""
        print "Relative RMSE against each renderer'"'"'s own reference at T seconds, log-log between its runs;"
        print "– : no image yet (its first run took longer); * : past its last run (that run'"'"'s error)."
        print ""
        hdr = "| scene | T s |"; sep = "|---|---:|"
        for (q = 1; q <= nr; ++q) { hdr = hdr " " name(renderers[q]) " |"; sep = sep "---:|" }
        print hdr; print sep
        for (k = 1; k <= scenes; ++k) for (i = 1; i <= nt; ++i) {
          line = "| " order[k] " | " times[i] " |"
          for (q = 1; q <= nr; ++q) { v = at(order[k], renderers[q], times[i], axis, "own"); line = line " " cell(v) " |" }
          print line
        }
      }
      if (!("cycles-mnee" in rseen)) exit
      print ""
      print "## Target: a lower caustic error than Cycles with shadow caustics at 5, 15 and 60 s"
      print ""
      print "On the glass sphere and the glass of liquid (the ring is shown, not a target: MNEE follows"
      print "refraction only, and Cycles culls the paths off a caustic caster that would draw the"
      print "cardioid). Budget: both given T seconds (caustica'"'"'s --time, which counts everything;"
      print "Cycles'"'"' time limit, which leaves out Blender'"'"'s start-up and the scene'"'"'s synchronisation);"
      print "wall: the whole process, interpolated at T. Errors against each one'"'"'s own reference, and"
      print "both against caustica'"'"'s (common)."
      print ""
      print "| scene | error | T s | caustica (budget) | Cycles MNEE (budget) | lower | caustica (wall) | Cycles MNEE (wall) | lower |"
      print "|---|---|---:|---:|---:|---|---:|---:|---|"
      for (k = 1; k <= scenes; ++k) for (c = 1; c <= 2; ++c) for (i = 1; i <= 3; ++i) {
        s = order[k]; ec = c == 1 ? "own" : "common"; T = i == 1 ? 5 : (i == 2 ? 15 : 60)
        line = "| " s (s == "ring" ? " (not a target)" : "") " | " ec " | " T " |"
        for (a = 1; a <= 2; ++a) {
          axis = a == 1 ? "budget" : "wall"
          ours = at(s, "caustica", T, axis, ec); po = past; theirs = at(s, "cycles-mnee", T, axis, ec); pt = past
          past = po; c1 = cell(ours); past = pt; c2 = cell(theirs)
          # Not judged when either is past its last run (T outside what was measured).
          verdict = (po != 0 || pt == -2 || pt == 1) ? "–" : (pt == -1 ? "**yes** (no Cycles image yet)" : (ours < theirs ? "**yes**" : "**no**"))
          line = line " " c1 " | " c2 " | " verdict " |"
        }
        print line
      }
    }'
  echo
  echo "## Targets against POV-Ray"
  echo
  echo "T = POV-Ray's time at its best (lowest) error E; caustica's time to reach E (log-log"
  echo "interpolation between its runs; \">\" when none reaches it) against T / 3 and against 60 s, and"
  echo "its error at time T (interpolated; its first or last run's error outside its range) against E / 2."
  echo "\"?\": none of caustica's runs reaches E and they end before 60 s."
  echo
  echo "| scene | error | time | POV-Ray best E | at T s | caustica time to E | T / 3 | met | within 60 s | caustica error at T | E / 2 | met |"
  echo "|---|---|---|---:|---:|---:|---:|---|---|---:|---:|---|"
  tail -n +2 "$progressive_tsv" | awk -F'\t' '
    $2 != "povray" && $2 != "caustica" { next }
    { k = ++n[$1, $2]; t[$1, $2, k, 6] = $6; t[$1, $2, k, 7] = $7; e[$1, $2, k, 8] = $8; e[$1, $2, k, 9] = $9
      limit[$1, $2, k] = $4 == "s" ? $3 : 0
      if (!($1 in seen)) { seen[$1] = 1; order[++scenes] = $1 } }
    function lerp(x, x0, x1, y0, y1) { return x1 == x0 ? y1 : exp(log(y0) + (log(x) - log(x0)) / (log(x1) - log(x0)) * (log(y1) - log(y0))) }
    function target(s, ec, tc,   i, best, bt, reach, err, reached, fast, half, minute) {
      if (!n[s, "povray"] || !n[s, "caustica"]) return
      best = 1e30
      for (i = 1; i <= n[s, "povray"]; ++i) if (e[s, "povray", i, ec] < best) { best = e[s, "povray", i, ec]; bt = t[s, "povray", i, tc] }
      reach = -1
      for (i = 1; i <= n[s, "caustica"]; ++i) if (e[s, "caustica", i, ec] <= best) {
        reach = i == 1 ? t[s, "caustica", 1, tc] : lerp(best, e[s, "caustica", i - 1, ec], e[s, "caustica", i, ec],
                                                       t[s, "caustica", i - 1, tc], t[s, "caustica", i, tc])
        break
      }
      err = e[s, "caustica", n[s, "caustica"], ec]
      for (i = 1; i <= n[s, "caustica"]; ++i) if (t[s, "caustica", i, tc] >= bt) {
        err = i == 1 ? e[s, "caustica", 1, ec] : lerp(bt, t[s, "caustica", i - 1, tc], t[s, "caustica", i, tc],
                                                     e[s, "caustica", i - 1, ec], e[s, "caustica", i, ec])
        break
      }
      reached = reach < 0 ? "> " sprintf("%.2f", t[s, "caustica", n[s, "caustica"], tc]) : sprintf("%.2f", reach)
      fast = (reach >= 0 && reach <= bt / 3) ? "yes" : "no"
      i = n[s, "caustica"]
      minute = reach >= 0 ? (reach <= 60 ? "yes" : "no") : (t[s, "caustica", i, tc] >= 60 || limit[s, "caustica", i] >= 60 ? "no" : "?")
      half = (err <= best / 2) ? "yes" : "no"
      printf("| %s | %s | %s | %.3f | %.2f | %s | %.2f | %s | %s | %.3f | %.3f | %s |\n", s, ec == 8 ? "own" : "common",
             tc == 6 ? "wall" : "own", best, bt, reached, bt / 3, fast, minute, err, best / 2, half)
    }
    END { for (k = 1; k <= scenes; ++k) for (ec = 8; ec <= 9; ++ec) for (tc = 6; tc <= 7; ++tc) target(order[k], ec, tc) }'
}

blender_version=
if [[ -n $cycles_modes && $option != --report ]]; then
  blender_version=$("$blender" --version 2>/dev/null | head -n 1)
  [[ $blender_version == "Blender 3.4"* ]] ||
    echo "run.sh: the Cycles scripts are written for Blender 3.4; this is $blender_version" >&2
fi
if [[ $mode == --cycles-references ]]; then
  for scene in $scenes; do
    echo "== $scene (Cycles references)"
    for m in $cycles_modes; do cycles_reference "$scene" "$m" force; done
  done
  exit 0
fi
if [[ $mode == --progressive ]]; then
  [[ $option == --report ]] || measure_progressive
  report_progressive >"$out/progressive.md"
  cat "$out/progressive.md"
  echo "PNGs, logs and progressive.md are in $out"
  exit 0
fi
[[ $mode == --report ]] || measure
report >"$out/results.md"
cat "$out/results.md"
echo "PNGs, logs and results.md are in $out"
