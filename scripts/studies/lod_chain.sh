#!/usr/bin/env bash
# lod_chain.sh [--bbcgen PATH] [--only NAME,...] [--args "BBCGEN OPTIONS"] OUTDIR — the
# LOD chain acceptance of issue 32: every tree of ../shared/data (14) and the
# generated airy species made into the default chain (`--lod-files`: levels
# from 512, 128 and 32 pixels), then each level judged alone at its own
# screen size by `bbcgen eval` (64 views). Writes OUTDIR/<tree>/chain.glb
# (+ chain_LOD<k>.glb, r.json, eval.json) and OUTDIR/lod_chain.md: per level
# the screen size, epsilon used, billboards, triangles, texels, texres, side
# coverage ratio and side block IoU; a tree passes when texels and
# triangles fall along its chain and every level's side coverage ratio is
# within 0.85-1.15. Exit status 0 when every tree passes, 1 when some does
# not, 2 missing inputs.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
data=${BBC_DATA:-$root/../shared/data}
bbcgen=$root/build/bin/bbcgen
only=
args=
while [ $# -gt 1 ]; do
  case $1 in
    --bbcgen) bbcgen=$2; shift 2 ;;
    --only) only=$2; shift 2 ;;
    --args) args=$2; shift 2 ;;
    *) echo "lod_chain.sh: unknown option $1" >&2; exit 1 ;;
  esac
done
[ $# -eq 1 ] || { echo "usage: lod_chain.sh [--bbcgen PATH] [--only NAME,...] [--args OPTS] OUTDIR" >&2; exit 1; }
out=$1
[ -x "$bbcgen" ] || { echo "lod_chain.sh: no bbcgen at $bbcgen (build first)" >&2; exit 2; }
[ -d "$data/trees" ] || { echo "lod_chain.sh: no $data/trees" >&2; exit 2; }
mkdir -p "$out/gen"
trees=$("$here/data_trees.sh" "$data" "$out/gen" "$bbcgen")
wanted() { [ -z "$only" ] || [[ ",$only," == *",$1,"* ]]; }
while IFS=$'\t' read -r name orig; do
  wanted "$name" || continue
  echo "lod_chain.sh: $name" >&2
  mkdir -p "$out/$name"
  # shellcheck disable=SC2086 # $args: options, split on purpose
  "$bbcgen" "$orig" -o "$out/$name/chain.glb" --lod-files --report "$out/$name/r.json" -q $args
  "$bbcgen" eval "$orig" "$out/$name/chain.glb" --no-lit --json "$out/$name/eval.json" -q \
    > "$out/$name/eval.txt"
done <<< "$trees"
python3 "$here/lod_chain_table.py" "$out" > "$out/lod_chain.md"
cat "$out/lod_chain.md"
! grep -q "FAIL" "$out/lod_chain.md"
