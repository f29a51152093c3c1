#!/usr/bin/env bash
# same_behaviour.sh — runs the same commands with two builds of the tools and
# compares every file they write, byte for byte: the check that a change meant
# to leave behaviour alone (a refactoring) did. Cases: the tree generator, the
# default .glb of three trees, a .wrl with --thesis, an .obj, LOD chains (.glb
# and .gltf), point clouds, `planes --json`, eval, render, a baseline, a batch
# file with `save`, a viewer screenshot, and forest screenshots of three demo
# maps (built once with NEW's tools: the demo script may ask for commands
# an older build lacks; both builds then draw the same files).
#
#   scripts/dev/same_behaviour.sh OLD_BIN_DIR NEW_BIN_DIR [WORK_DIR]
#
# MAPS_BIN_DIR=DIR builds the demo maps with DIR's tools instead (when both
# builds are older than the demo script).
# Exit status 0 when every output is identical, 1 otherwise (the differing
# files named). Real data from ../shared/data is used where present.
set -euo pipefail
if [ $# -lt 2 ]; then
  echo "usage: scripts/dev/same_behaviour.sh OLD_BIN_DIR NEW_BIN_DIR [WORK_DIR]" >&2
  exit 2
fi
old=$(cd "$1" && pwd)
new=$(cd "$2" && pwd)
work=${3:-$(mktemp -d)}
mkdir -p "$work"
work=$(cd "$work" && pwd)
here=$(cd "$(dirname "$0")" && pwd)
data=$(cd "$here/../../.." && pwd)/shared/data

# run_case NAME COMMAND...: COMMAND runs in WORK/{old,new}/NAME with $B the
# tools' folder; the inputs are reached through absolute paths.
run_case() {
  local name=$1
  shift
  for side in old new; do
    local bin=$old
    [ "$side" = new ] && bin=$new
    rm -rf "${work:?}/$side/$name"
    mkdir -p "$work/$side/$name"
    (cd "$work/$side/$name" && B=$bin bash -c "$*") > "$work/$side/$name.log" 2>&1 || {
      echo "$name: the $side build failed; see $work/$side/$name.log" >&2
      return 1
    }
  done
  echo "ran $name"
}

gen="$work/inputs"
mkdir -p "$gen"
"$old/bbcgen" tree --species oak --seed 1 -o "$gen/oak.obj" -q
"$old/bbcgen" tree --species larch --seed 2 -o "$gen/larch.obj" -q

run_case tree_oak '$B/bbcgen tree --species oak --seed 1 -o oak.obj --preview oak.png -q'
run_case tree_palm '$B/bbcgen tree --species palm --seed 3 --leaves 300 -o palm.obj -q'
run_case glb_oak "\$B/bbcgen $gen/oak.obj -o oak.glb -q"
run_case glb_larch "\$B/bbcgen $gen/larch.obj -o larch.glb --preview larch.png -q"
run_case planes_oak "\$B/bbcgen planes $gen/oak.obj --json planes.json -q"
run_case eval_oak "\$B/bbcgen $gen/oak.obj -o oak.glb -q && \
  \$B/bbcgen eval $gen/oak.obj oak.glb --views 16 --size 96 --json eval.json --png eval.png -q"
run_case render_oak "\$B/bbcgen render $gen/oak.obj -o oak.png --size 160"
run_case baseline_oak "\$B/bbcgen baseline $gen/oak.obj -o crossed.glb --method crossed --planes 3 -q && \
  \$B/bbcgen baseline $gen/oak.obj -o simple.glb --method simplify --triangles 500 -q"
run_case lod_oak_gltf "\$B/bbcgen $gen/oak.obj -o chain.gltf --lod 6,10,15 -q"
run_case batch_save "printf 'load $gen/oak.obj\nset epsilon 8\nset nm 1\nbbc\nsave demo\nplanes p.json\n' > b.txt && \
  \$B/bbcgen exec b.txt -q"
run_case view_cloud "\$B/bbcgen view $gen/oak.obj --mode cloud --screenshot v.png --size 160 -q"
if [ -f "$data/trees/scopia/pine/pine.obj" ]; then
  run_case glb_pine "\$B/bbcgen $data/trees/scopia/pine/pine.obj -o pine.glb -q"
  run_case planes_pine "\$B/bbcgen planes $data/trees/scopia/pine/pine.obj --json planes.json -q"
  run_case obj_palm "\$B/bbcgen $data/trees/scopia/palm/palm.obj -o palm.obj -q"
  run_case wrl_thesis_bush "\$B/bbcgen $data/trees/scopia/bush/bush.obj -o bush.wrl --thesis --dds 1 -q"
  run_case glb_ezoak "\$B/bbcgen $data/trees/eztree/oak_medium.obj -o ezoak.glb -q"
  run_case lod_aspen "\$B/bbcgen $data/trees/eztree/aspen_small.obj -o chain.glb --lod 6,10,15 -q"
  run_case obj_quaternius "\$B/bbcgen $data/trees/quaternius/OBJ/Birch_1.obj -o birch.obj -q"
  run_case points_tree7 "\$B/bbcgen $data/points/adtree/tree7.xyz -o tree7.glb -q"
  run_case points_house "\$B/bbcgen $data/points/adtree/house.xyz -o house.glb --nm 1 -q && \$B/bbcgen $data/points/adtree/tree7.xyz -o tree7.wrl -q"
  run_case points_hippo "\$B/bbcgen $data/points/hippo1.ply -o hippo.obj -q"
  run_case model_cat "\$B/bbcgen $data/models/cat.3ds -o cat.glb -q"
fi

# forest: three demo maps, built once with NEW's tools, drawn by both.
if [ ! -f "$work/forest/build/demo/forest/islands.txt" ]; then
  mkdir -p "$work/forest/build"
  ln -sfn "$(cd "${MAPS_BIN_DIR:-$new}" && pwd)" "$work/forest/build/bin"
  (cd "$work/forest" && "$here/demo_forest.sh" build 300) > "$work/forest.log" 2>&1 || {
    echo "the demo maps failed; see $work/forest.log" >&2
    exit 1
  }
fi
maps="$work/forest/build/demo/forest"
run_case forest_map "\$B/forest $maps/map.txt --size 320x200 --camera 250,95,250,135,-6 --screenshot map.png"
run_case forest_islands "\$B/forest $maps/islands.txt --size 320x200 --screenshot islands.png"
run_case forest_mixed "\$B/forest $maps/mixed.txt --size 320x200 --camera 520,0,600,140,-3 --screenshot mixed.png"

status=0
count=0
while IFS= read -r f; do
  count=$((count + 1))
  if [ ! -f "$work/new/$f" ]; then
    echo "only in the old run: $f"
    status=1
  elif ! cmp -s "$work/old/$f" "$work/new/$f"; then
    echo "differs: $f"
    status=1
  fi
done < <(cd "$work/old" && find . -type f ! -name '*.log' | sort)
while IFS= read -r f; do
  [ -f "$work/old/$f" ] || { echo "only in the new run: $f"; status=1; }
done < <(cd "$work/new" && find . -type f ! -name '*.log' | sort)
if [ $status -eq 0 ]; then
  echo "same behaviour: $count files identical ($work)"
else
  echo "behaviour changed ($work)"
fi
exit $status
