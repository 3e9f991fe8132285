#!/usr/bin/env bash
# Installs what is missing, builds, and runs the main job on the default scene.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
mkdir -p out
build/caustica render scenes/default.lua -o out/default.png
echo "the default scene is in $(pwd)/out/default.png"
