#!/usr/bin/env bash
# The race against Cycles in float images (docs/PEERS.md, "Cycles in floats"). run.sh compares
# 8-bit PNGs: on a caustic as dim as the glass sphere's (a mean of 0.07 over its region) a PNG is
# 0.03 from its own float image and two PNGs differ by up to 0.02 from their steps of 1/255 alone,
# so below that its figures measure the quantisation. Here every image is linear floats (caustica's PFM, Cycles' EXR), clamped to
# [0, 1] as a PNG would show it, over run.sh's region and shadow mask.
#
#   OUT=DIR bench/peers/float_race.sh [--quick]
#
# For each scene (SCENES, default glass_sphere) and each time (TIMES, default "5 15 60"), caustica's
# progressive accumulation (PP_RADIUS 2.5 footprints, PP_PER_PIXEL 1 photon a pixel) and, if
# Blender is installed and CYCLES is not 0, Cycles with shadow caustics (MNEE), each with seeds 1
# and 2, interleaved run by run; each against its own reference:
# - caustica's: two independent halves (seeds 11 and 12) of REF_PASSES (400) passes at
#   REF_PER_PIXEL (12) photons a pixel from r1 REF_RADIUS (1.5), averaged (image_mean); kept in
#   OUT (named by those settings) and reused. Their difference over sqrt 2 is one half's noise;
#   half the difference is the average's.
# - Cycles': run.sh's (OUT/SCENE-cycles-mnee-ref-512px-Ts.exr with T = CYCLES_REF_TIME, 600 by
#   default, made by run.sh --cycles-references with the same OUT); Cycles is left out, with a
#   message, when it or Blender is missing.
# The two seeds' difference over sqrt 2 is a run's own noise. Writes OUT/float-race.tsv (scene,
# renderer, seconds, seed, passes or samples, relative error against its own reference) and
# prints the noise figures. --quick: 256², 1 s, a 16-pass reference, no Cycles (a smoke run).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/common.sh"
scenes=${SCENES:-glass_sphere}
times=${TIMES:-"5 15 60"}
radius=${PP_RADIUS:-2.5} per_pixel=${PP_PER_PIXEL:-1}
ref_passes=${REF_PASSES:-400} ref_per_pixel=${REF_PER_PIXEL:-12} ref_radius=${REF_RADIUS:-1.5}
cycles=${CYCLES:-1} blender=${BLENDER:-blender} lamp_radius=${CYCLES_LAMP_RADIUS:-0.02}
cycles_ref_time=${CYCLES_REF_TIME:-600}
size=512 resolution=--midres
case ${1:-} in
  "") ;;
  --quick) size=256 resolution=--lores times=${TIMES:-1} ref_passes=${REF_PASSES:-16} cycles=0 ;;
  *) echo "usage: OUT=DIR bench/peers/float_race.sh [--quick]" >&2; exit 2 ;;
esac
if [[ $cycles != 0 ]] && ! command -v "$blender" >/dev/null; then
  echo "float_race.sh: $blender is not installed: Cycles is left out"
  cycles=0
fi
for tool in caustica image_diff image_mean; do
  [[ -x $build/$tool ]] || { echo "float_race.sh: $build/$tool is missing (scripts/build.sh)" >&2; exit 2; }
done
mkdir -p "$out"

# relative TEST REFERENCE SCENE: the relative RMSE over the scene's region (common.sh); stops the
# script when image_diff fails.
relative() {
  local args=(--rect $(scaled "${region[$3]}")) line
  [[ ${shadow_only[$3]} == 1 ]] && args+=(--mask-dark "$out/$3-no-caustics-$size.png")
  if ! line=$("$build/image_diff" "$1" "$2" "${args[@]}"); then
    echo "float_race.sh: image_diff $1 $2 failed" >&2
    exit 1
  fi
  sed 's/.*relative=\([^ ]*\).*/\1/' <<<"$line"
}
# noise A B SCENE: the noise of one of two independent renders, their difference over sqrt 2.
noise() { local d; d=$(relative "$1" "$2" "$3"); awk -v d="$d" 'BEGIN { printf "%.4f", d / sqrt(2) }'; }
# ours SCENE SEED OUT.pfm [OPTIONS...]: one progressive render; OUT.pfm.log.
ours() {
  local scene=$1 seed=$2 pfm=$3
  shift 3
  if ! "$build/caustica" render -S --integrator progressive --threads "$threads" "$resolution" \
         --caustic-num-photons "${scene_pp_photons[$scene]}" --caustic-num-neighbours 8 --seed "$seed" "$@" \
         "$here/$scene.lua" -o "$pfm" >"$pfm.log" 2>&1; then
    echo "float_race.sh: caustica failed on $scene; the end of $pfm.log:" >&2
    tail -n 8 "$pfm.log" >&2
    exit 1
  fi
}
passes_of() { sed -n 's/^ *progressive passes *\([0-9]*\).*/\1/p' "$1.log" | head -1; }
samples_of() { grep -o 'Sample [0-9]*/' "$1.log" | tr -dc '0-9\n' | sort -n | tail -n 1; }

tsv=$out/float-race.tsv
printf 'scene\trenderer\tseconds\tseed\twork\trelative_own\n' >"$tsv"
echo "float race: start $(date -u '+%Y-%m-%d %H:%M') UTC, load $(cut -d' ' -f1-3 /proc/loadavg)"
for scene in $scenes; do
  "$build/caustica" render -s --integrator progressive --threads "$threads" --disable-aa "$resolution" \
    --no-caustic-map "$here/$scene.lua" -o "$out/$scene-no-caustics-$size.png"
  ref=$out/$scene-float-ref-$size-$ref_passes-pp$ref_per_pixel-r$ref_radius.pfm
  if [[ ! -s $ref ]]; then
    for seed in 11 12; do
      ours "$scene" "$seed" "$ref.half$seed.pfm" --passes "$ref_passes" --time 1e6 \
        --accumulation-radius "$ref_radius" --photons-per-pixel "$ref_per_pixel"
    done
    "$build/image_mean" "$ref" "$ref.half11.pfm" "$ref.half12.pfm"
  fi
  halves=$(relative "$ref.half11.pfm" "$ref.half12.pfm" "$scene")
  echo "== $scene: caustica's reference ($ref_passes passes x 2, $ref_per_pixel photons a pixel, r1 $ref_radius):" \
       "its own noise $(awk -v h="$halves" 'BEGIN { printf "%.4f", h / 2 }') (halves differ by $halves)"
  cycles_ref=
  if [[ $cycles != 0 ]]; then
    cycles_ref=$out/$scene-cycles-mnee-ref-${size}px-${cycles_ref_time}s.exr
    if [[ -s $cycles_ref ]]; then
      echo "   Cycles' reference: $cycles_ref"
    else
      echo "   no $cycles_ref (CYCLES_REF_TIME=$cycles_ref_time run.sh --cycles-references): Cycles left out"
      cycles_ref=
    fi
  fi
  for t in $times; do
    for seed in 1 2; do
      pfm=$out/$scene-float-$t-s$seed.pfm
      ours "$scene" "$seed" "$pfm" --passes 0 --time "$t" --accumulation-radius "$radius" --photons-per-pixel "$per_pixel"
      e=$(relative "$pfm" "$ref" "$scene")
      printf '%s\tcaustica\t%s\t%s\t%s\t%s\n' "$scene" "$t" "$seed" "$(passes_of "$pfm")" "$e" >>"$tsv"
      if [[ -n $cycles_ref ]]; then
        prefix=$out/$scene-float-cycles-$t-s$seed
        rm -f "$prefix.exr" "$prefix.png"
        if ! "$blender" -b --factory-startup --python-exit-code 2 -P "$here/${scene}_cycles.py" -- --out "$prefix" \
               --size "$size" --time "$t" --mode mnee --seed "$seed" --threads "$threads" \
               --lamp-radius "$lamp_radius" >"$prefix.log" 2>&1 || [[ ! -s $prefix.exr ]]; then
          echo "float_race.sh: Blender failed on $scene ($t s); the end of $prefix.log:" >&2
          tail -n 8 "$prefix.log" >&2
          exit 1
        fi
        e=$(relative "$prefix.exr" "$cycles_ref" "$scene")
        printf '%s\tcycles-mnee\t%s\t%s\t%s\t%s\n' "$scene" "$t" "$seed" "$(samples_of "$prefix")" "$e" >>"$tsv"
      fi
    done
    line="   $t s: caustica $(awk -F'\t' -v s="$scene" -v t="$t" '$1 == s && $2 == "caustica" && $3 == t { printf "%s ", $6 }' "$tsv")"
    n=$(noise "$out/$scene-float-$t-s1.pfm" "$out/$scene-float-$t-s2.pfm" "$scene")
    line+="(noise $n)"
    if [[ -n $cycles_ref ]]; then
      line+="; Cycles MNEE $(awk -F'\t' -v s="$scene" -v t="$t" '$1 == s && $2 == "cycles-mnee" && $3 == t { printf "%s ", $6 }' "$tsv")"
      n=$(noise "$out/$scene-float-cycles-$t-s1.exr" "$out/$scene-float-cycles-$t-s2.exr" "$scene")
      line+="(noise $n)"
    fi
    echo "$line"
  done
done
echo "float race: end $(date -u '+%H:%M') UTC, load $(cut -d' ' -f1-3 /proc/loadavg); $tsv"
