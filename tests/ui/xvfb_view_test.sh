#!/usr/bin/env bash
# The real window under Xvfb: `caustica view` must open a GLFW window (not fall back to headless),
# render the scene with the overlay on and orbited, and write a snapshot that snapshot_check accepts.
# With xdotool, a key tap (press and release sent back to back, so both reach GLFW within one frame,
# where ImGui 1.86's own key state never shows the key down) must turn the occupied cells on (Alt+C):
# ui/key_events.h.
# usage: xvfb_view_test.sh CAUSTICA SNAPSHOT_CHECK SCENE.lua [LIBRARY_KEPT_LOADED]
# LIBRARY_KEPT_LOADED (AddressSanitizer builds, see CMakeLists.txt) is preloaded into caustica only.
set -euo pipefail
caustica=$1 check=$2 scene=$3 keep_loaded=${4:-}
out=$(mktemp -d)
trap '[ -n "${KEEP_SNAPSHOT:-}" ] && cp "$out/window.png" "$KEEP_SNAPSHOT"; rm -rf "$out"' EXIT
run=("$caustica")
if [ -n "$keep_loaded" ]; then
  run=(env "LD_PRELOAD=$keep_loaded" "ASAN_OPTIONS=${ASAN_OPTIONS:-}:verify_asan_link_order=0" "$caustica")
fi
tap=0 cells=() frames=(--frames 30)
if command -v xdotool >/dev/null; then
  # --after-key: the run counts its frames (and so takes its snapshot) only from the frame that
  # saw the key, however late the tap comes.
  tap=1 cells=(--cells) frames=(--frames 3 --after-key)
else
  echo "note: xdotool is not installed: the key tap is not checked"
fi
if ! XDG_CONFIG_HOME="$out" xvfb-run -a -s "-screen 0 1280x720x24" bash -c '
       out=$1 scene=$2 tap=$3 frames=$4
       shift 4
       timeout 240 "$@" view "$scene" $frames --snapshot "$out/window.png" --overlay --orbit 20,5 >"$out/log" 2>&1 &
       pid=$!
       if [ "$tap" = 1 ]; then
         # The window, once mapped; the key goes to it (focused, and under the pointer, which stays
         # beside the image: no hover readout over the overlay).
         if id=$(timeout 120 xdotool search --sync --onlyvisible --name "^caustica view"); then
           xdotool mousemove --sync --window "$id" 20 700
           xdotool windowfocus --sync "$id" key alt+c || echo "xdotool could not send the key" >>"$out/log"
         else
           echo "xdotool did not find the window" >>"$out/log"
         fi
       fi
       wait "$pid"' _ "$out" "$scene" "$tap" "${frames[*]}" "${run[@]}"; then
  cat "$out/log"
  exit 1
fi
if grep -q "runs headless" "$out/log"; then
  echo "caustica view fell back to headless under Xvfb"
  exit 1
fi
"$check" "$out/window.png" glfw "${cells[@]}"
