#!/usr/bin/env bash
# demo_forest.sh — the forest engine's demo map, built from nothing
# downloaded: a procedural landscape (forest --demo-terrain) and the
# built-in species turned into Billboard Clouds by bbcgen with levels of
# detail like the thesis's (3.3): the polygon tree near, then clouds of
# 22, 8 and 6 billboards at 256, 64 and 64 texels.
#
#   scripts/dev/demo_forest.sh [BUILD] [TREES_PER_SPECIES]
set -euo pipefail
build=${1:-build}
per=${2:-2000}
bin="$build/bin"
out="$build/demo/forest"
mkdir -p "$out"
echo "== forest: the landscape"
water=$("$bin/forest" --demo-terrain "$out" --terrain-size 512 --seed 1 | sed -n 's/^water_level=//p')
heightscale=0.5
# model_file NAME COMMENT FADE SHADOWRAD SHADOWCUTOFF FILE:MAX... — a model
# description file (Appendix B): one LOD per FILE up to MAX units, each from
# where the previous ends, the first (the polygon model) lit.
model_file() {
  local name=$1 comment=$2 fade=$3 rad=$4 cut=$5 min=0 flags="lighting mipmap"
  shift 5
  {
    echo "' $comment"
    printf 'fade %s\nshadowrad %s\nshadowcutoff %s\n' "$fade" "$rad" "$cut"
    for lod in "$@"; do
      printf 'LOD\n(\n    file1 %s %s\n    min %s\n    max %s\n)\n' "${lod%%:*}" "$flags" "$min" \
        "${lod##*:}"
      min=${lod##*:}
      flags=mipmap
    done
  } > "$out/$name.txt"
}

# One species: its polygon tree and three Billboard Clouds, and its model
# file (thesis Appendix B) with the LOD ranges.
make_species() {
  local s=$1
  # Material clouds (bbcgen's default: albedo, normal and occlusion maps):
  # forest lights them with its sun like the polygon tree (docs/forest.md);
  # the farthest without the trunk mesh.
  if [ ! -f "$out/$s.obj" ] || [ ! -f "$out/${s}_6.glb" ] || [ ! -f "$stamp" ]; then
    echo "== forest: $s and its Billboard Clouds (22, 8 and 6 billboards)"
    "$bin/bbcgen" tree --species "$s" --seed 1 -o "$out/$s.obj" > /dev/null
    "$bin/bbcgen" "$out/$s.obj" -o "$out/${s}_22.glb" --maxplanes 22 --texres 256 -q
    "$bin/bbcgen" "$out/$s.obj" -o "$out/${s}_8.glb" --maxplanes 8 --minplanes 0 --texres 64 -q
    "$bin/bbcgen" "$out/$s.obj" -o "$out/${s}_6.glb" --maxplanes 6 --minplanes 0 --texres 64 --limbs 0 -q
  fi
  model_file "$s" "$s: the polygon tree near, Billboard Clouds farther (thesis Appendix B)" 6 6.5 2.5 \
    "$s.obj:45" "${s}_22.glb:160" "${s}_8.glb:420" "${s}_6.glb:1600"
}
# Clouds made before forest lit material clouds carried a baked light, and
# far levels a trunk mesh: the stamp says these are material clouds whose
# far level (a tree a few pixels tall) is billboards only (--limbs 0: 2.5x
# fewer vertices on the million map); made again when it is missing.
stamp="$out/clouds_material_v2.stamp"
for s in oak pine birch larch weeping; do make_species "$s"; done
cat > "$out/map.txt" <<EOT
' The demo map: 1024 x 1024 units of hills, meadows and a lake, $((per * 3)) trees.
' Built by scripts/dev/demo_forest.sh (make demo).
hmap heightmap.png
hmapfilter 1 2
colmap colmap.png
heightscale $heightscale
stretch 2
light 1 1 0.5
wind 1 1 0.3
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
# The thesis's maps (3.3) on 1024 x 1024 landscapes (2048 x 2048 units),
# and a million trees.
mkdir -p "$out/big" "$out/flat"
bigwater=$("$bin/forest" --demo-terrain "$out/big" --terrain-size 1024 --seed 2 | sed -n 's/^water_level=//p')
flatwater=$("$bin/forest" --demo-terrain "$out/flat" --terrain-size 1024 --seed 4 | sed -n 's/^water_level=//p')
# big_map NAME DIR WATER HEIGHTSCALE TITLE, then "rndtree" lines on stdin
big_map() {
  local name=$1 dir=$2 wat=$3 hs=$4 title=$5 lines total
  lines=$(cat)
  total=$(echo "$lines" | awk '{ n += $4 } END { print n }')
  cat > "$out/$name.txt" <<EOT
' $title: $total objects on a 2048 x 2048-unit landscape (1024 x 1024 heightmap).
' Built by scripts/dev/demo_forest.sh (make demo).
hmap $dir/heightmap.png
hmapfilter 1 2
colmap $dir/colmap.png
heightscale $hs
stretch 2
light 1 1 0.5
farclip 800
roetger 10
waterheight $(awk -v w="$wat" -v h="$hs" 'BEGIN { printf "%.2f", w * h + 0.6 }')
fog 250 1500
numobjs $total
$lines
EOT
}
big_map mixed big "$bigwater" 0.5 "Mixed Forest (thesis 3.3, map a): five species" <<EOT
rndtree oak.txt 1.0 8000 1 1 0 0 0 0
rndtree pine.txt 1.1 8000 1 1 0 0 0 0
rndtree birch.txt 0.9 8000 1 1 0 0 0 0
rndtree larch.txt 1.0 7000 1 1 0 0 0 0
rndtree weeping.txt 1.0 7000 1 1 0 0 0 0
EOT
big_map huge150k big "$bigwater" 0.5 "Huge Forest (thesis 3.3, map d)" <<EOT
rndtree oak.txt 1.0 50000 1 1 0 0 0 0
rndtree pine.txt 1.1 50000 1 1 0 0 0 0
rndtree birch.txt 0.9 50000 1 1 0 0 0 0
EOT
big_map million big "$bigwater" 0.5 "A million trees" <<EOT
rndtree oak.txt 1.0 333334 1 1 0 0 0 0
rndtree pine.txt 1.1 333333 1 1 0 0 0 0
rndtree birch.txt 0.9 333333 1 1 0 0 0 0
EOT
# The same million with octahedral impostors (bbcgen impostor, 8 x 8 frames,
# 65,536 texels) as the farthest level in place of the 6-billboard clouds
# (issue 49; docs/impostors.md).
for s in oak pine birch; do
  [ "$out/${s}_imp.json" -nt "$out/$s.obj" ] ||
    "$bin/bbcgen" impostor "$out/$s.obj" -o "$out/${s}_imp.json" --frames 8 --texels 65536 -q
  sed "s/${s}_6.glb mipmap/${s}_imp.json/" "$out/$s.txt" > "$out/${s}_i.txt"
done
big_map million_imp big "$bigwater" 0.5 "A million trees, impostors farthest" <<EOT
rndtree oak_i.txt 1.0 333334 1 1 0 0 0 0
rndtree pine_i.txt 1.1 333333 1 1 0 0 0 0
rndtree birch_i.txt 0.9 333333 1 1 0 0 0 0
EOT
# Finland (thesis 3.3, map c): groups of 8 spruces, each group one model
# simplified by bbcgen as a whole (the polygon group near, then clouds of 25,
# 11 and 11 billboards at 256, 128 and 32 texels like the thesis's), on
# flat land (3.3: groups belong on flat ground).
if [ ! -f "$out/spruces.obj" ] || [ ! -f "$out/spruces_11s.glb" ] || [ ! -f "$stamp" ]; then
  echo "== forest: a group of 8 spruces and its Billboard Clouds (25, 11 and 11 billboards)"
  awk -f "$(dirname "$0")/obj_group.awk" "$out/pine.obj" > "$out/spruces.obj.tmp"
  mv "$out/spruces.obj.tmp" "$out/spruces.obj"
  "$bin/bbcgen" "$out/spruces.obj" -o "$out/spruces_25.glb" --maxplanes 25 --texres 256 -q
  "$bin/bbcgen" "$out/spruces.obj" -o "$out/spruces_11.glb" --maxplanes 11 --minplanes 0 --texres 128 -q
  "$bin/bbcgen" "$out/spruces.obj" -o "$out/spruces_11s.glb" --maxplanes 11 --minplanes 0 --texres 32 --limbs 0 -q
fi
model_file spruces \
  "8 spruces as one model (thesis 3.3, Finland): the polygon group near, clouds farther" 8 14 6 \
  spruces.obj:50 spruces_25.glb:200 spruces_11.glb:450 spruces_11s.glb:1600
big_map finland flat "$flatwater" 0.2 "Finland (thesis 3.3, map c): groups of 8 spruces" <<EOT
rndtree spruces.txt 1.0 20000 1 1 0 0 0 0
EOT
# Tropic Islands (thesis 3.3, map b): palms on islands in a sea, with the
# thesis's palm levels (8 billboards at 512 and 128 texels, 5 at 32).
mkdir -p "$out/islands"
islandwater=$("$bin/forest" --demo-terrain "$out/islands" --terrain-size 1024 --seed 6 \
  --terrain-kind islands | sed -n 's/^water_level=//p')
if [ ! -f "$out/palm.obj" ] || [ ! -f "$out/palm_5.glb" ] || [ ! -f "$stamp" ]; then
  echo "== forest: palm and its Billboard Clouds (8, 8 and 5 billboards)"
  "$bin/bbcgen" tree --species palm --seed 1 -o "$out/palm.obj" > /dev/null
  "$bin/bbcgen" "$out/palm.obj" -o "$out/palm_8.glb" --maxplanes 8 --minplanes 0 --texres 512 -q
  "$bin/bbcgen" "$out/palm.obj" -o "$out/palm_8s.glb" --maxplanes 8 --minplanes 0 --texres 128 -q
  "$bin/bbcgen" "$out/palm.obj" -o "$out/palm_5.glb" --maxplanes 5 --minplanes 0 --texres 32 --limbs 0 -q
fi
model_file palm "palm: the polygon tree near, Billboard Clouds farther (thesis 3.3, Tropic Islands)" \
  6 5 2 palm.obj:45 palm_8.glb:160 palm_8s.glb:420 palm_5.glb:1600
big_map islands islands "$islandwater" 0.5 "Tropic Islands (thesis 3.3, map b): palms" <<EOT
rndtree palm.txt 1.0 25000 1 1 0 0 0 0
EOT
touch "$stamp"
for m in mixed islands finland huge150k; do "$bin/forest" --check "$out/$m.txt" > "$out/check_$m.txt"; done
# A camera path across the large maps (corner to corner, low and high).
cat > "$out/path_big.txt" <<EOT
60 0 60 135 -5
520 0 600 140 -3
1000 60 980 120 -10
1450 0 1400 160 -2
1900 140 1950 -135 -14
1500 0 1750 -100 -4
EOT

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
terrain="$(dirname "$0")/../../../shared/data/terrain"
if [ -f "$terrain/irrlicht_terrain-heightmap.bmp" ]; then
  terrain=$(cd "$terrain" && pwd)
  {
    echo "' The Irrlicht engine's example terrain (../shared/data/terrain) with the demo's trees."
    echo "' Built by scripts/dev/demo_forest.sh (make demo)."
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
echo "The thesis's maps (3.3): $out/mixed.txt, islands.txt, finland.txt, huge150k.txt; a million"
echo "trees: $out/million.txt (million_imp.txt: impostors farthest); their benchmark:"
echo "scripts/bench/bench_forest.sh $build"
