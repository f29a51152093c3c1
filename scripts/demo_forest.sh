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
# Large maps on a 1024 x 1024 landscape (issue 13): 150,000 trees (the
# thesis's Huge Forest) and 1,000,000 trees, the same species.
mkdir -p "$out/big"
bigwater=$("$bin/forest" --demo-terrain "$out/big" --terrain-size 1024 --seed 2 | sed -n 's/^water_level=//p')
for spec in "huge150k 50000 50000 50000" "million 333334 333333 333333"; do
  read -r name n1 n2 n3 <<< "$spec"
  cat > "$out/$name.txt" <<EOT
' $((n1 + n2 + n3)) trees on a 2048 x 2048-unit landscape (1024 x 1024 heightmap).
' Built by scripts/demo_forest.sh (make demo).
hmap big/heightmap.png
hmapfilter 1 2
colmap big/colmap.png
heightscale $heightscale
stretch 2
light 1 1 0.5
farclip 800
roetger 10
waterheight $(awk -v w="$bigwater" -v h="$heightscale" 'BEGIN { printf "%.2f", w * h + 0.6 }')
fog 250 1500
numobjs $((n1 + n2 + n3))
rndtree oak.txt 1.0 $n1 1 1 0 0 0 0
rndtree pine.txt 1.1 $n2 1 1 0 0 0 0
rndtree birch.txt 0.9 $n3 1 1 0 0 0 0
EOT
done
# a camera path across the map (x y z yaw pitch), for --path and --bench
cat > "$out/path.txt" <<EOT
40 0 40 135 -6
300 0 330 120 -4
620 110 480 150 -12
900 0 700 170 -3
990 125 640 -95 -10
EOT

# The Irrlicht engine's example terrain from ../shared/data (its colour map
# has no ground green enough for rndtree, so the trees stand where object2d
# lines put them: 3,000 positions from a fixed pseudo-random sequence).
terrain="$(dirname "$0")/../../shared/data/terrain"
if [ -f "$terrain/irrlicht_terrain-heightmap.bmp" ]; then
  terrain=$(cd "$terrain" && pwd)
  {
    echo "' The Irrlicht engine's example terrain (../shared/data/terrain) with the demo's trees."
    echo "' Built by scripts/demo_forest.sh (make demo)."
    echo "hmap $terrain/irrlicht_terrain-heightmap.bmp"
    echo "hmapfilter 1 2"
    echo "colmap $terrain/irrlicht_terrain-texture.jpg"
    echo "heightscale 0.5"
    echo "stretch 4"
    echo "light 1 1 0.5"
    echo "farclip 400"
    echo "fog 300 1400"
    awk 'BEGIN { s = 12345; split("oak pine birch", sp, " ");
      for (i = 0; i < 3000; i++) {
        s = (s * 1103515245 + 12345) % 2147483648; x = 24 + s % 976;
        s = (s * 1103515245 + 12345) % 2147483648; z = 24 + s % 976;
        s = (s * 1103515245 + 12345) % 2147483648; yaw = s % 360;
        printf "object2d %s.txt 1 1 %d %d 0 %d 0 0\n", sp[i % 3 + 1], x, z, yaw } }'
  } > "$out/irrlicht.txt"
  "$bin/forest" --check "$out/irrlicht.txt" > "$out/check_irrlicht.txt"
fi
sed -n '1,12p' "$out/check.txt"
echo "Fly through it: $bin/forest $out/map.txt   (headless: add --size 800x600 --screenshot F.png)"
