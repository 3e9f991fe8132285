#!/usr/bin/env bash
# The real window under Xvfb: `caustica view` must open a GLFW window (not fall back to headless),
# render the scene with the overlay on and orbited, and write a snapshot that snapshot_check accepts.
# usage: xvfb_view_test.sh CAUSTICA SNAPSHOT_CHECK SCENE.lua [LIBRARY_KEPT_LOADED]
# LIBRARY_KEPT_LOADED (AddressSanitizer builds, see CMakeLists.txt) is preloaded into caustica only.
set -euo pipefail
caustica=$1 check=$2 scene=$3 keep_loaded=${4:-}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
run=("$caustica")
if [ -n "$keep_loaded" ]; then
  run=(env "LD_PRELOAD=$keep_loaded" "ASAN_OPTIONS=${ASAN_OPTIONS:-}:verify_asan_link_order=0" "$caustica")
fi
if ! XDG_CONFIG_HOME="$out" xvfb-run -a -s "-screen 0 1280x720x24" \
     "${run[@]}" view "$scene" --frames 30 --snapshot "$out/window.png" --overlay --orbit 20,5 >"$out/log" 2>&1; then
  cat "$out/log"
  exit 1
fi
if grep -q "runs headless" "$out/log"; then
  echo "caustica view fell back to headless under Xvfb"
  exit 1
fi
"$check" "$out/window.png" glfw
