#!/usr/bin/env bash
# Installs what is missing, builds, and runs the main job on the default scene: the preview
# window when a display exists, otherwise a batch render to PNG whose path it prints.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
if [ -n "${DISPLAY:-}" ]; then
  exec build/caustica view scenes/default.lua
fi
mkdir -p out
build/caustica render scenes/default.lua -o out/default.png
echo "no display: the default scene was rendered to $(pwd)/out/default.png"
