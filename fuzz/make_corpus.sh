#!/usr/bin/env bash
# Makes the seed corpus of each fuzz target under OUT/<target>/ (default build-fuzz/seeds) from
# files that already exist: nothing big is kept twice in the repository.
#   scene_loader  scenes/*.lua (their texture folder removed: the target writes small textures
#                 beside the scene), tests/**/*.lua, ../shared/cs488/*.lua, ../shared/repro/**/*.lua
#   obj_reader    every .obj of the repository and of ../shared (cs488, repro/obj)
#   png_reader    PNGs of up to 128 KiB from assets/, tests/, docs/, and the hostile PNGs that
#                 ../shared/repro/png/make_pngs.py writes (those of up to 128 KiB)
# ../shared is optional: without it the seeds come from the repository alone.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-build-fuzz/seeds}
shared=../shared
rm -rf "$out"
mkdir -p "$out"/{scene_loader,obj_reader,png_reader}

# Copies FILE to OUT/TARGET/ under a name that says where it came from.
seed() {
    local target=$1 file=$2
    local name=${file#./}
    name=${name#../}
    cp "$file" "$out/$target/${name//\//__}"
}

for f in scenes/*.lua; do
    sed 's#\.\./assets/textures/##' "$f" >"$out/scene_loader/${f//\//__}"
done
while IFS= read -r f; do seed scene_loader "$f"; done < <(find tests -name '*.lua' -size -256k)
while IFS= read -r f; do seed obj_reader "$f"; done < <(find . -path ./build\* -prune -o -name '*.obj' -size -1024k -print)
while IFS= read -r f; do seed png_reader "$f"; done < <(find assets tests docs -name '*.png' -size -129k)

if [ -d "$shared" ]; then
    while IFS= read -r f; do seed scene_loader "$f"; done < <(find "$shared/cs488" "$shared/repro" -name '*.lua' -size -256k)
    while IFS= read -r f; do seed obj_reader "$f"; done < <(find "$shared/cs488" "$shared/repro" -name '*.obj' -size -1024k)
    if [ -f "$shared/repro/png/make_pngs.py" ] && command -v python3 >/dev/null; then
        made=$(mktemp -d)
        (cd "$made" && python3 "$OLDPWD/$shared/repro/png/make_pngs.py")
        find "$made" -name '*.png' -size -129k -exec sh -c 'cp "$1" "$2/made_$(basename "$1")"' _ {} "$out/png_reader" \;
        rm -rf "$made"
    fi
else
    echo "make_corpus: $shared not found: seeds from the repository only" >&2
fi
for target in scene_loader obj_reader png_reader; do
    echo "make_corpus: $(ls "$out/$target" | wc -l) seeds for $target in $out/$target"
done
