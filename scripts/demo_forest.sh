#!/usr/bin/env bash
# demo_forest.sh — the forest engine's demo map, built from nothing
# downloaded: a procedural landscape (forest --demo-terrain) and the
# built-in species turned into Billboard Clouds by bbcgen with levels of
# detail like the thesis's (3.3): the polygon tree near, then clouds of
# 22, 8 and 6 billboards at 256, 64 and 64 texels.
#
#   scripts/demo_forest.sh [BUILD] [TREES_PER_SPECIES]
set -euo pipefail
build=${1:-build}
per=${2:-2000}
bin="$build/bin"
out="$build/demo/forest"
mkdir -p "$out"
echo "== forest: the landscape"
water=$("$bin/forest" --demo-terrain "$out" --terrain-size 512 --seed 1 | sed -n 's/^water_level=//p')
heightscale=0.5
species=(oak pine birch)
for s in "${species[@]}"; do
  if [ ! -f "$out/$s.obj" ] || [ ! -f "$out/${s}_6.glb" ]; then
    echo "== forest: $s and its Billboard Clouds (22, 8 and 6 billboards)"
    "$bin/bbcgen" tree --species "$s" --seed 1 -o "$out/$s.obj" > /dev/null
    "$bin/bbcgen" "$out/$s.obj" -o "$out/${s}_22.glb" --maxplanes 22 --texres 256 -q
    "$bin/bbcgen" "$out/$s.obj" -o "$out/${s}_8.glb" --maxplanes 8 --minplanes 0 --texres 64 -q
    "$bin/bbcgen" "$out/$s.obj" -o "$out/${s}_6.glb" --maxplanes 6 --minplanes 0 --texres 64 -q
  fi
  cat > "$out/$s.txt" <<EOT
' $s: the polygon tree near, Billboard Clouds farther (thesis Appendix B)
fade 6
shadowrad 6.5
shadowcutoff 2.5
LOD
(
    file1 $s.obj lighting mipmap
    min 0
    max 45
)
LOD
(
    file1 ${s}_22.glb mipmap
    min 45
    max 160
)
LOD
(
    file1 ${s}_8.glb mipmap
    min 160
    max 420
)
LOD
(
    file1 ${s}_6.glb mipmap
    min 420
    max 1600
)
EOT
done
cat > "$out/map.txt" <<EOT
' The demo map: 1024 x 1024 units of hills, meadows and a lake, $((per * 3)) trees.
' Built by scripts/demo_forest.sh (make demo).
hmap heightmap.png
hmapfilter 1 2
colmap colmap.png
heightscale $heightscale
stretch 2
light 1 1 0.5
farclip 800
roetger 10
waterheight $(awk -v w="$water" -v h="$heightscale" 'BEGIN { printf "%.2f", w * h + 0.6 }')
fog 250 1500
numobjs $((per * 3))
rndtree oak.txt 1.0 $per 1 1 0 0 0 0
rndtree pine.txt 1.1 $per 1 1 0 0 0 0
rndtree birch.txt 0.9 $per 1 1 0 0 0 0
EOT
"$bin/forest" --check "$out/map.txt" > "$out/check.txt"
sed -n '1,12p' "$out/check.txt"
echo "Fly through it: $bin/forest $out/map.txt   (headless: add --size 800x600 --screenshot F.png)"
