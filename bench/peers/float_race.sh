#!/usr/bin/env bash
# The race against Cycles in float images (docs/PEERS.md, "Cycles in floats"). run.sh compares
# 8-bit PNGs, whose steps of 1/255 are a relative error of ~0.02 by themselves on a caustic as dim
# as the glass sphere's (a mean of 0.07 over its region): below that its figures measure the
# quantisation. Here every image is linear floats (caustica's PFM, Cycles' EXR), clamped to
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
#   OUT when present. Their difference over sqrt 2 is one half's noise, half of it the average's.
# - Cycles': run.sh's (OUT/SCENE-cycles-mnee-ref-512px-*s.exr, made by run.sh --cycles-references
#   with the same OUT); Cycles is left out when it is missing.
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
size=512 resolution=--midres
case ${1:-} in
  "") ;;
  --quick) size=256 resolution=--lores times=${TIMES:-1} ref_passes=${REF_PASSES:-16} cycles=0 ;;
  *) echo "usage: OUT=DIR bench/peers/float_race.sh [--quick]" >&2; exit 2 ;;
esac
command -v "$blender" >/dev/null || cycles=0
for tool in caustica image_diff image_mean; do
  [[ -x $build/$tool ]] || { echo "float_race.sh: $build/$tool is missing (scripts/build.sh)" >&2; exit 2; }
done
mkdir -p "$out"

# relative TEST REFERENCE SCENE: the relative RMSE over the scene's region (common.sh).
relative() {
  local args=(--rect $(scaled "${region[$3]}"))
  [[ ${shadow_only[$3]} == 1 ]] && args+=(--mask-dark "$out/$3-no-caustics-$size.png")
  "$build/image_diff" "$1" "$2" "${args[@]}" | sed 's/.*relative=\([^ ]*\).*/\1/'
}
# ours SCENE SEED OUT.pfm [OPTIONS...]: one progressive render; OUT.pfm.log.
ours() {
  local scene=$1 seed=$2 pfm=$3
  shift 3
  "$build/caustica" render -S --integrator progressive --threads "$threads" "$resolution" \
    --caustic-num-photons "${scene_pp_photons[$scene]}" --caustic-num-neighbours 8 --seed "$seed" "$@" \
    "$here/$scene.lua" -o "$pfm" >"$pfm.log" 2>&1
}
passes_of() { sed -n 's/^ *progressive passes *\([0-9]*\).*/\1/p' "$1.log" | head -1; }
samples_of() { grep -o 'Sample [0-9]*/' "$1.log" | tr -dc '0-9\n' | sort -n | tail -n 1; }

tsv=$out/float-race.tsv
printf 'scene\trenderer\tseconds\tseed\twork\trelative_own\n' >"$tsv"
echo "float race: start $(date -u '+%Y-%m-%d %H:%M') UTC, load $(cut -d' ' -f1-3 /proc/loadavg)"
for scene in $scenes; do
  "$build/caustica" render -s --integrator progressive --threads "$threads" --disable-aa "$resolution" \
    --no-caustic-map "$here/$scene.lua" -o "$out/$scene-no-caustics-$size.png"
  ref=$out/$scene-float-ref-$size-$ref_passes.pfm
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
    cycles_ref=$(ls "$out/$scene"-cycles-mnee-ref-${size}px-*s.exr 2>/dev/null | head -1 || true)
    [[ -n $cycles_ref ]] || echo "   no Cycles reference in $out (run.sh --cycles-references): Cycles left out"
  fi
  for t in $times; do
    for seed in 1 2; do
      pfm=$out/$scene-float-$t-s$seed.pfm
      ours "$scene" "$seed" "$pfm" --passes 0 --time "$t" --accumulation-radius "$radius" --photons-per-pixel "$per_pixel"
      printf '%s\tcaustica\t%s\t%s\t%s\t%s\n' "$scene" "$t" "$seed" "$(passes_of "$pfm")" "$(relative "$pfm" "$ref" "$scene")" >>"$tsv"
      if [[ -n $cycles_ref ]]; then
        prefix=$out/$scene-float-cycles-$t-s$seed
        "$blender" -b --factory-startup --python-exit-code 2 -P "$here/${scene}_cycles.py" -- --out "$prefix" \
          --size "$size" --time "$t" --mode mnee --seed "$seed" --threads "$threads" --lamp-radius "$lamp_radius" \
          >"$prefix.log" 2>&1
        printf '%s\tcycles-mnee\t%s\t%s\t%s\t%s\n' "$scene" "$t" "$seed" "$(samples_of "$prefix")" \
          "$(relative "$prefix.exr" "$cycles_ref" "$scene")" >>"$tsv"
      fi
    done
    line="   $t s: caustica $(awk -F'\t' -v s="$scene" -v t="$t" '$1 == s && $2 == "caustica" && $3 == t { printf "%s ", $6 }' "$tsv")"
    line+="(noise $(awk -v d="$(relative "$out/$scene-float-$t-s1.pfm" "$out/$scene-float-$t-s2.pfm" "$scene")" 'BEGIN { printf "%.4f", d / sqrt(2) }'))"
    if [[ -n $cycles_ref ]]; then
      line+="; Cycles MNEE $(awk -F'\t' -v s="$scene" -v t="$t" '$1 == s && $2 == "cycles-mnee" && $3 == t { printf "%s ", $6 }' "$tsv")"
      line+="(noise $(awk -v d="$(relative "$out/$scene-float-cycles-$t-s1.exr" "$out/$scene-float-cycles-$t-s2.exr" "$scene")" 'BEGIN { printf "%.4f", d / sqrt(2) }'))"
    fi
    echo "$line"
  done
done
echo "float race: end $(date -u '+%H:%M') UTC, load $(cut -d' ' -f1-3 /proc/loadavg); $tsv"
