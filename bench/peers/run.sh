#!/usr/bin/env bash
# Against POV-Ray 3.7 (issue 6): renders the three peer scenes with caustica and POV-Ray at the
# same resolution and thread count and matched numbers of STORED caustic photons, several
# quality levels each, times every run with the wall clock and measures the caustic error of each
# render against its own renderer's reference (a render with many more photons). Writes the
# PNGs, logs and a Markdown report (results.md) into the output folder; bench/peers/README.md
# explains the scenes, the parameter mapping and how to read the report.
#
#   bench/peers/run.sh [--quick | --report]
#   bench/peers/run.sh --progressive [--quick]
#
# Environment: BUILD (build folder, default build/), OUT (default out/peers), THREADS (2),
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
# --progressive (issue 11): error against time instead of equal photons. POV-Ray at the LEVELS
# above (and its reference), caustica's progressive integrator as one curve of accumulated passes
# (PASSES: --passes of each render, PP_PHOTONS directions a pass (default 3e6, 2e7 for the glass
# of liquid), PP_NEIGHBOURS (8) for the first radius, jittered samples: no --disable-aa) and its
# own pixel-averaged reference (PP_REF_PASSES passes of PP_REF_PHOTONS). Each renderer's error is against its own reference (as above) and
# both against caustica's progressive reference (the "common" column: POV-Ray's bias shows there).
# Writes progressive.tsv and progressive.md (the two targets: POV-Ray's best error in a third of
# its time, and half its error at its time).
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${BUILD:-$root/build}
out=${OUT:-$root/out/peers}
threads=${THREADS:-2}
size=${SIZE:-512}
repeats=${REPEATS:-3}
levels=${LEVELS:-"10000 30000 100000 300000"}
reference=${REFERENCE:-1000000}
max_directions=${MAX_DIRECTIONS:-150000000}
neighbours=${NEIGHBOURS:-100}
pov_radius=${POV_RADIUS:-0.15}
scenes=${SCENES:-"glass_sphere ring glass_of_liquid"}
passes=${PASSES:-"1 2 4 8 16 32 64 128"}
pp_photons=${PP_PHOTONS:-}
pp_neighbours=${PP_NEIGHBOURS:-8}
pp_ref_passes=${PP_REF_PASSES:-256}
pp_ref_photons=${PP_REF_PHOTONS:-30000000}
mode=${1:-measure}
if [[ $mode == --progressive ]]; then
  [[ ${2:-} == --quick ]] && { size=256 repeats=1 levels="10000 100000" reference=300000 passes="1 4 16" pp_ref_passes=32; }
  [[ ${2:-} == --quick || -z ${2:-} ]] || { echo "usage: bench/peers/run.sh --progressive [--quick]" >&2; exit 2; }
fi
case $mode in
  measure | --report | --progressive) ;;
  --quick) size=256 repeats=1 levels="10000 100000" reference=300000 ;;
  *) echo "usage: bench/peers/run.sh [--quick | --report | --progressive [--quick]]" >&2; exit 2 ;;
esac

command -v povray >/dev/null || { echo "run.sh: povray is not installed (scripts/install-deps.sh)" >&2; exit 2; }
# Builds the three programs if they are missing (an existing build is used as it is).
if [[ ! -x "$build/caustica" || ! -x "$build/image_diff" || ! -x "$build/side_by_side" ]]; then
  [[ -f "$build/build.ninja" ]] || cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$build" -j2 --target caustica image_diff side_by_side
fi
declare -A resolution_flag=([256]=--lores [512]=--midres [1024]=--hires)
[[ -n "${resolution_flag[$size]:-}" ]] || { echo "run.sh: SIZE must be 256, 512 or 1024" >&2; exit 2; }
mkdir -p "$out"

# The caustic region of each scene, in pixels of a 512 x 512 render (scaled for other sizes):
# X0 Y0 X1 Y1, and whether only the pixels that are black without caustics count (the shadow
# of a transparent object, lit by the caustic alone; without ambient light the rest is lit
# directly, identically at every photon count, and would only dilute the error).
declare -A region=([glass_sphere]="150 292 470 420" [ring]="200 125 395 375" [glass_of_liquid]="344 205 512 340")
declare -A shadow_only=([glass_sphere]=1 [ring]=0 [glass_of_liquid]=1)
# A crop around the caustic for the detail row of the side-by-side images (512-pixel units).
declare -A detail=([glass_sphere]="176 272 432 400" [ring]="192 112 448 368" [glass_of_liquid]="256 200 512 328")

scaled() { local v out_=(); for v in $1; do out_+=($((v * size / 512))); done; echo "${out_[*]}"; }

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
# Photon directions a progressive pass shoots when PP_PHOTONS is not set: the glass of liquid's
# cup covers ~0.45% of the lamp's sphere (the glass sphere and the ring ~1%), so it gets more.
declare -A scene_pp_photons=([glass_sphere]=3000000 [ring]=3000000 [glass_of_liquid]=20000000)
# caustica_passes SCENE PASSES DIRECTIONS PNG: one progressive accumulation; PNG.log and PNG.time.
# (--time 1e6, never reached, makes --passes 1 an accumulation's first pass rather than the single
# k-nearest pass.)
caustica_passes() {
  wall "$4.time" "$4.log" "$build/caustica" render -S --integrator progressive --threads "$threads" "${resolution_flag[$size]}" \
    --passes "$2" --time 1e6 --caustic-num-photons "$3" --caustic-num-neighbours "$pp_neighbours" "$here/$1.lua" -o "$4"
}
# Seconds of an accumulation's photon stages and passes (caustica -S), without the scene build.
caustica_pass_stages() {
  awk '/time: (projection maps|photon shooting|photon k-d tree|photon passes|progressive passes)/ { s += $(NF-1) }
       END { printf "%.3f", s }' "$1.log"
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

# --progressive: POV-Ray's levels and caustica's accumulated passes, error against time.
progressive_tsv=$out/progressive.tsv
measure_progressive() {
  printf 'scene\trenderer\tlevel\tphotons\twall_s\tstages_s\trelative_own\trelative_common\n' >"$progressive_tsv"
  local scene level
  for scene in $scenes; do
    echo "== $scene (progressive)"
    prepare_scene "$scene"
    local ours_ref=$out/$scene-progressive-ref.png pov_ref=$out/$scene-povray-pref.png
    local photons=${pp_photons:-${scene_pp_photons[$scene]}}
    caustica_passes "$scene" "$pp_ref_passes" "$pp_ref_photons" "$ours_ref"
    povray_run "$scene" "$(awk -v t="$reference" -v r="$pov_ratio" 'BEGIN { printf "%d", t / r }')" "$pov_ref"
    echo "   references: caustica $pp_ref_passes passes in $(cat "$ours_ref.time") s, POV-Ray $(povray_stored "$pov_ref") stored in $(cat "$pov_ref.time") s"
    for level in $levels; do
      local png=$out/$scene-povray-p$level.png times=()
      for ((r = 0; r < repeats; ++r)); do
        povray_run "$scene" "$(awk -v t="$level" -v r="$pov_ratio" 'BEGIN { printf "%d", t / r }')" "$png"
        times+=("$(cat "$png.time")")
      done
      read -r _ own _ < <(caustic_error "$scene" "$png" "$pov_ref")
      read -r _ common _ < <(caustic_error "$scene" "$png" "$ours_ref")
      printf '%s\tpovray\t%s\t%s\t%s\t%s\t%s\t%s\n' "$scene" "$level" "$(povray_stored "$png")" \
        "$(echo "${times[*]}" | median)" "$(povray_stages "$png" | awk '{ printf "%.3f", $1 + $2 }')" "$own" "$common" \
        >>"$progressive_tsv"
      echo "   POV-Ray $(povray_stored "$png") stored: ${times[*]} s, relative $own (own reference), $common (common)"
    done
    for level in $passes; do
      local png=$out/$scene-progressive-$level.png times=()
      for ((r = 0; r < repeats; ++r)); do
        caustica_passes "$scene" "$level" "$photons" "$png"
        times+=("$(cat "$png.time")")
      done
      read -r _ own _ < <(caustic_error "$scene" "$png" "$ours_ref")
      printf '%s\tcaustica\t%s\t%s\t%s\t%s\t%s\t%s\n' "$scene" "$level" "$((level * photons))" \
        "$(echo "${times[*]}" | median)" "$(caustica_pass_stages "$png")" "$own" "$own" >>"$progressive_tsv"
      echo "   caustica $level passes: ${times[*]} s, relative $own"
    done
  done
  echo "$(date -u +%Y-%m-%d), $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg) at the end; ${size}x${size}," \
       "$threads threads; POV-Ray: $neighbours photons per estimate within $pov_radius, levels of stored photons $levels," \
       "reference $reference stored; caustica: --passes $passes of ${pp_photons:-3e6 (2e7 for glass_of_liquid)} directions, N $pp_neighbours," \
       "reference $pp_ref_passes passes of $pp_ref_photons; median of $repeats runs." >"$out/progressive-setup.txt"
}

# The progressive report: both curves, and the two targets per scene on wall time and on stage
# times, with errors against each renderer's own reference and against the common one.
report_progressive() {
  echo "# caustica's progressive integrator against POV-Ray 3.7: error against time"
  echo
  cat "$out/progressive-setup.txt"
  echo
  echo "| scene | renderer | level | photons | wall s | stages s | relative (own reference) | relative (common reference) |"
  echo "|---|---|---:|---:|---:|---:|---:|---:|"
  tail -n +2 "$progressive_tsv" | awk -F'\t' '{ printf "| %s | %s | %s%s | %.0f | %.2f | %.3f | %.3f | %.3f |\n", $1, $2, $3,
                                               $2 == "caustica" ? " passes" : " stored", $4, $5, $6, $7, $8 }'
  echo
  echo "Targets: T = POV-Ray's time at its best (lowest) error E; caustica's time to reach E (log-log"
  echo "interpolated between its passes; \">\" when no pass reaches it) against T / 3, and its error at"
  echo "time T (interpolated; its last pass's error when T is past it) against E / 2."
  echo
  echo "| scene | error | time | POV-Ray best E | at T s | caustica time to E | T / 3 | met | caustica error at T | E / 2 | met |"
  echo "|---|---|---|---:|---:|---:|---:|---|---:|---:|---|"
  tail -n +2 "$progressive_tsv" | awk -F'\t' '
    { k = ++n[$1, $2]; t[$1, $2, k, 5] = $5; t[$1, $2, k, 6] = $6; e[$1, $2, k, 7] = $7; e[$1, $2, k, 8] = $8
      if (!($1 in seen)) { seen[$1] = 1; order[++scenes] = $1 } }
    function lerp(x, x0, x1, y0, y1) { return x1 == x0 ? y1 : exp(log(y0) + (log(x) - log(x0)) / (log(x1) - log(x0)) * (log(y1) - log(y0))) }
    function target(s, ec, tc,   i, best, bt, reach, err, reached, fast, half) {
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
      half = (err <= best / 2) ? "yes" : "no"
      printf("| %s | %s | %s | %.3f | %.2f | %s | %.2f | %s | %.3f | %.3f | %s |\n", s, ec == 7 ? "own" : "common",
             tc == 5 ? "wall" : "stages", best, bt, reached, bt / 3, fast, err, best / 2, half)
    }
    END { for (k = 1; k <= scenes; ++k) for (ec = 7; ec <= 8; ++ec) for (tc = 5; tc <= 6; ++tc) target(order[k], ec, tc) }'
}

if [[ $mode == --progressive ]]; then
  measure_progressive
  report_progressive >"$out/progressive.md"
  cat "$out/progressive.md"
  echo "PNGs, logs and progressive.md are in $out"
  exit 0
fi
[[ $mode == --report ]] || measure
report >"$out/results.md"
cat "$out/results.md"
echo "PNGs, logs and results.md are in $out"
