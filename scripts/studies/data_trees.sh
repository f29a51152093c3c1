#!/usr/bin/env bash
# data_trees.sh DATA GEN_DIR BBCGEN — the trees the acceptance tables are
# measured on, one "name<TAB>original" line each: the 14 trees of
# ../shared/data and the generated airy species (larch, weeping, winter,
# seed 7), grown into GEN_DIR/<species>/<species>.obj when missing.
# Sourced by scripts/studies/sun_sweep.sh and scripts/studies/lod_chain.sh.
set -euo pipefail
data=$1 gen=$2 bbcgen=$3
for sp in larch weeping winter; do
  [ -f "$gen/$sp/$sp.obj" ] || { mkdir -p "$gen/$sp" &&
    "$bbcgen" tree --species "$sp" --seed 7 -o "$gen/$sp/$sp.obj" -q; }
done
cat <<LIST
eztree_oak	$data/trees/eztree/oak_medium.obj
eztree_pine	$data/trees/eztree/pine_medium.obj
eztree_ash	$data/trees/eztree/ash_large_hi.obj
eztree_bush	$data/trees/eztree/bush_1.obj
eztree_aspen	$data/trees/eztree/aspen_small.obj
scopia_pine	$data/trees/scopia/pine/pine.obj
scopia_copperBeech	$data/trees/scopia/copperBeech/copperBeech.obj
scopia_palm	$data/trees/scopia/palm/palm.obj
scopia_bush	$data/trees/scopia/bush/bush.obj
quaternius_Birch_1	$data/trees/quaternius/OBJ/Birch_1.obj
quaternius_DeadTree_1	$data/trees/quaternius/OBJ/DeadTree_1.obj
quaternius_Pine_1	$data/trees/quaternius/OBJ/Pine_1.obj
quaternius_Tree_1	$data/trees/quaternius/OBJ/Tree_1.obj
quaternius_Tree_3	$data/trees/quaternius/OBJ/Tree_3.obj
gen_larch	$gen/larch/larch.obj
gen_weeping	$gen/weeping/weeping.obj
gen_winter	$gen/winter/winter.obj
LIST
