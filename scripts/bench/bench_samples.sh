#!/usr/bin/env bash
# bench_samples.sh [BUILD] — step 3's samples on the 17 trees of the
# acceptance tables (scripts/studies/data_trees.sh): a default run of this build
# (2 samples a texel side from texres 128 up), the same with --set
# samples=4, and BENCH_BASE's default (default 14032c8: 2 samples that
# tested the alpha at the samples' centres only), each judged by `bbcgen
# eval --no-lit` against the original (mean IoU, side coverage ratio, side
# block IoU, brightness R G B), with step 3's seconds (one run each; noisy:
# scripts/bench/bench_small.sh has medians). Writes bench/results/samples.md.
set -euo pipefail
build=${1:-build}
root=$(cd "$(dirname "$0")/../.." && pwd)
base=${BENCH_BASE:-14032c8}
case "$build" in /*) ;; *) build="$root/$build" ;; esac
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
old=$("$root/scripts/dev/build_base.sh" "$base" "$tmp/old")
new="$build/bin/bbcgen"
out="$root/bench/results/samples.md"
trees=$("$root/scripts/studies/data_trees.sh" "$root/../shared/data" "$tmp/gen" "$new")
row() { # label binary args... : one table row
  local name=$1 in=$2 lab=$3 bin=$4
  shift 4
  local t
  t=$("$bin" "$in" -o "$tmp/c.glb" "$@" 2>&1 | grep -o 'step 3 [0-9.]*' | cut -d' ' -f3)
  "$new" eval "$in" "$tmp/c.glb" --no-lit --json "$tmp/e.json" -q > /dev/null
  python3 - "$tmp/e.json" "$name" "$lab" "$t" << 'PY'
import json, sys
j = json.load(open(sys.argv[1]))
b = j["brightness_ratio"]
print(f"| {sys.argv[2]} | {sys.argv[3]} | {sys.argv[4]} | {j['iou_mean']:.4f} | "
      f"{j['coverage_ratio_side_mean']:.3f} | {j['block_iou_side_mean']:.4f} | "
      f"{' '.join(f'{x:.3f}' for x in b)} |")
PY
}
{
  echo "# Step 3's samples (scripts/bench/bench_samples.sh)"
  echo
  echo "$(date -u +%F), $(nproc) cores; \`bbcgen TREE -o OUT.glb\`: new = this build, 4 = this"
  echo "build with \`--set samples=4\`, old = $base; \`bbcgen eval TREE OUT.glb --no-lit\` (64"
  echo "views): mean IoU, side coverage ratio, side block IoU, brightness (cloud / original, R G B)."
  echo
  echo "| tree | build | step 3 s | IoU | side coverage | side block IoU | brightness |"
  echo "|---|---|---:|---:|---:|---:|---|"
  while IFS=$'\t' read -r name in; do
    row "$name" "$in" old "$old"
    row "$name" "$in" 4 "$new" --set samples=4
    row "$name" "$in" new "$new"
  done <<< "$trees"
} > "$out"
echo "wrote $out"
