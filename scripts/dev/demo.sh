#!/usr/bin/env bash
# demo.sh — what the toolkit does, on a fresh clone with no downloads:
# generate the built-in tree, describe it, make its Billboard Cloud (glTF and
# VRML) with a preview and a report.
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
echo "== 4. Its Billboard Cloud (steps 1 to 3) as glTF, with a preview and a report"
"$bin" "$out/oak.obj" -o "$out/oak_cloud.glb" --epsilon 6 --clustering 0 --quality 2 \
  --report "$out/oak_cloud_report.json" --preview "$out/oak_cloud_preview.png"
echo "== 5. The same cloud as VRML (the thesis's format 0, a baked light, normal maps), and three LODs"
"$bin" "$out/oak.obj" -o "$out/oak_cloud.wrl" --epsilon 6 --clustering 0 --quality 2 --nm 1 -q
"$bin" "$out/oak.obj" -o "$out/oak_lods.glb" --lod 6,10,15 --clustering 0 --quality 2 -q
echo "== 6. How close the cloud looks to the oak (64 views; both lit by a sun as an engine lights them)"
"$bin" eval "$out/oak.obj" "$out/oak_cloud.glb" --sun 30,60 --json "$out/oak_cloud_eval.json" \
  --png "$out/oak_cloud_eval.png"
echo "== 7. A pine, a birch and a bush too"
for s in pine birch bush; do
  "$bin" tree --species "$s" --seed 1 -o "$out/$s.obj" --preview "$out/${s}_preview.png"
done
shared="$(dirname "$0")/../../../shared/data/trees/scopia/pine/pine.obj"
if [ -f "$shared" ]; then
  echo "== 8. A real tree from ../shared/data: the Scopia pine"
  "$bin" info "$shared"
  "$bin" render "$shared" -o "$out/scopia_pine.png" --size 384
fi
echo "== 9. The forest engine's demo map: a landscape with $((3 * 2000)) trees (build/demo/forest/)"
"$(dirname "$0")/demo_forest.sh" "$build" 2000
if "$build/bin/forest" "$out/forest/map.txt" --size 800x500 --camera 250,95,250,135,-6 \
     --screenshot "$out/forest/view.png" --log "$out/forest/log.txt" 2> "$out/forest/draw.txt"; then
  echo "   a view of it drawn without a display: $out/forest/view.png"
else
  echo "   (no headless OpenGL 4.5 here, so no picture: $(tail -1 "$out/forest/draw.txt"))"
fi
echo
echo "Results in $out/:"
ls -1 "$out"
echo
echo "Open $out/oak_cloud.glb in any glTF viewer; $out/oak_cloud_preview.png shows the"
echo "original (top row), the cloud (middle) and the billboards' outlines (bottom)."
