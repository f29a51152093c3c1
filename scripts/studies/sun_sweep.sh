#!/usr/bin/env bash
# sun_sweep.sh [--bbcgen PATH] [--jobs N] [--only NAME,...] [--args "BBCGEN OPTIONS"]
#              [--threejs "THREEJS_SUN OPTIONS"] OUTDIR — the
# relighting acceptance of issue 31, in three.js (scripts/studies/threejs_sun.sh):
# every tree of ../shared/data (14) and the generated airy species (larch,
# weeping, winter) made into a cloud twice — the default (.glb: albedo,
# normal and occlusion maps, lit) and `--lighting baked` (today's prelit,
# unlit) — and each drawn beside its original under ambient 0.4 + a sun
# from 8 azimuths x 2 elevations (15, 50 degrees), front and side views.
# Writes OUTDIR/<tree>/{material,baked}.glb, OUTDIR/<tree>/threejs.json and
# OUTDIR/sun_sweep.md (the table: per tree and cloud the range of the
# cloud/original luminance ratio over the 32 renders, and how many fall
# outside 0.90-1.10; and the material cloud's colours against the
# original's, unlit, per channel, from `bbcgen eval --no-lit`). Exit status 0 when every material cloud is inside
# the band on every render, 1 when some is not, 2/3 missing inputs/tools.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
data=${BBC_DATA:-$root/../shared/data}
bbcgen=$root/build/bin/bbcgen
jobs=2
only=
args=
tjs=
while [ $# -gt 1 ]; do
  case $1 in
    --bbcgen) bbcgen=$2; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    --only) only=$2; shift 2 ;;
    --args) args=$2; shift 2 ;;
    --threejs) tjs=$2; shift 2 ;;
    *) echo "sun_sweep.sh: unknown option $1" >&2; exit 1 ;;
  esac
done
[ $# -eq 1 ] || { echo "usage: sun_sweep.sh [--bbcgen PATH] [--jobs N] [--only NAME,...] [--args OPTS] [--threejs OPTS] OUTDIR" >&2; exit 1; }
out=$1
[ -x "$bbcgen" ] || { echo "sun_sweep.sh: no bbcgen at $bbcgen (build first)" >&2; exit 2; }
[ -d "$data/trees" ] || { echo "sun_sweep.sh: no $data/trees" >&2; exit 2; }
mkdir -p "$out/gen"

# name<TAB>original
trees=$("$here/data_trees.sh" "$data" "$out/gen" "$bbcgen")

wanted() { [ -z "$only" ] || [[ ",$only," == *",$1,"* ]]; }

# The clouds, $jobs trees at a time.
make_clouds() {
  local name=$1 orig=$2
  mkdir -p "$out/$name"
  # shellcheck disable=SC2086 # $args: options, split on purpose
  [ -s "$out/$name/material.glb" ] || "$bbcgen" "$orig" -o "$out/$name/material.glb" -q $args
  [ -s "$out/$name/baked.glb" ] || "$bbcgen" "$orig" -o "$out/$name/baked.glb" --lighting baked -q
}
running=0
while IFS=$'\t' read -r name orig; do
  wanted "$name" || continue
  make_clouds "$name" "$orig" &
  running=$((running + 1))
  if [ "$running" -ge "$jobs" ]; then wait -n; running=$((running - 1)); fi
done <<< "$trees"
wait

# three.js, one tree at a time (Chromium takes both cores).
while IFS=$'\t' read -r name orig; do
  wanted "$name" || continue
  echo "sun_sweep.sh: $name" >&2
  # Colours: the material cloud's albedo against the original's (unlit).
  "$bbcgen" eval "$orig" "$out/$name/material.glb" --no-lit --views 32 \
    --json "$out/$name/albedo.json" -q > /dev/null
  # shellcheck disable=SC2086
  "$here/threejs_sun.sh" $tjs --json "$out/$name/threejs.json" "$orig" \
    "$out/$name/material.glb" "$out/$name/baked.glb" > "$out/$name/threejs.txt"
done <<< "$trees"

python3 "$here/sun_sweep_table.py" "$out" > "$out/sun_sweep.md"
cat "$out/sun_sweep.md"
! grep -q "^| .* | FAIL" "$out/sun_sweep.md"
