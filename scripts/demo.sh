#!/usr/bin/env bash
# demo.sh — what the toolkit does today, on a fresh clone with no downloads:
# generate the built-in tree, describe it, render it.
set -euo pipefail
build=${1:-build}
bin="$build/bin/bbcgen"
out="$build/demo"
mkdir -p "$out"
echo "== 1. Generate the built-in oak (seeded, deterministic)"
"$bin" tree --species oak --seed 1 -o "$out/oak.obj" --preview "$out/oak_preview.png"
echo "== 2. Describe it"
"$bin" info "$out/oak.obj"
"$bin" info --json "$out/oak.obj" > "$out/oak_info.json"
echo "== 3. Steps 1 and 2 of the Billboard Cloud algorithm: its planes (epsilon 6 %)"
"$bin" planes "$out/oak.obj" --epsilon 6 --clustering 0 --json "$out/oak_planes.json"
echo "== 4. Its Billboard Cloud (step 3, first version) as glTF, and a render of it"
"$bin" "$out/oak.obj" -o "$out/oak_cloud.glb" --epsilon 6 --clustering 0 --quality 2
"$bin" render "$out/oak_cloud.glb" -o "$out/oak_cloud.png"
echo "== 5. A pine, a birch and a bush too"
for s in pine birch bush; do
  "$bin" tree --species "$s" --seed 1 -o "$out/$s.obj" --preview "$out/${s}_preview.png"
done
shared="$(dirname "$0")/../../shared/data/trees/scopia/pine/pine.obj"
if [ -f "$shared" ]; then
  echo "== 6. A real tree from ../shared/data: the Scopia pine"
  "$bin" info "$shared"
  "$bin" render "$shared" -o "$out/scopia_pine.png" --size 384
fi
echo
echo "Results in $out/:"
ls -1 "$out"
echo
echo "Step 3 is a first version (front images only, no normal maps, no VRML, no report);"
echo "see README.md, Status."
