#!/usr/bin/env bash
# bench.sh — benchmarks: tree generator and model loading, medians of runs,
# peak memory. Writes bench/results/latest.md and latest.json.
set -euo pipefail
build=${1:-build}
root=$(cd "$(dirname "$0")/.." && pwd)
data="$root/../shared/data"
res="$root/bench/results"
mkdir -p "$res"
json="$res/latest.json.tmp.$$"
: > "$json"
machine="$(uname -m), $(nproc) cores, $(awk -F: '/model name/{print $2; exit}' /proc/cpuinfo | sed 's/^ *//')"
echo "machine: $machine" >&2

for cfg in "oak 500" "oak 50000" "oak 500000" "pine 50000" "birch 50000" "bush 50000"; do
  set -- $cfg
  "$build/bin/bench_treegen" "$1" "$2" 5 | tee -a "$json"
done
# End to end: `bbcgen tree` generating and writing OBJ+MTL+PNG (~100k triangles).
tmpd=$(mktemp -d)
times=()
for r in 1 2 3; do
  t0=$(date +%s.%N)
  "$build/bin/bbcgen" tree --leaves 44000 -q -o "$tmpd/t.obj"
  t1=$(date +%s.%N)
  times+=("$(echo "$t1 - $t0" | bc -l)")
done
tris=$("$build/bin/bbcgen" info --json "$tmpd/t.obj" |
       python3 -c 'import json, sys; print(json.load(sys.stdin)["triangles"])')
sorted=($(printf '%s\n' "${times[@]}" | sort -g))
printf '{"bench": "tree_cli", "species": "oak", "leaves": 44000, "triangles": %s, "runs": 3, "median_s": %.4f, "min_s": %.4f, "max_s": %.4f, "peak_mib": 0}\n' \
  "$tris" "${sorted[1]}" "${sorted[0]}" "${sorted[2]}" | tee -a "$json"
rm -rf "$tmpd"

for m in trees/scopia/pine/pine.obj trees/scopia/copperBeech/copperBeech.obj \
         trees/eztree/ash_large_hi.obj models/cat.3ds models/flightgear/H-60.ac \
         points/b9_training.ply; do
  if [ -f "$data/$m" ]; then
    "$build/bin/bench_load" "$data/$m" 3 | tee -a "$json"
  else
    echo "skip: $data/$m missing" >&2
  fi
done

{
  echo "# Benchmarks"
  echo
  echo "$(date -u +%Y-%m-%d), $machine. Medians of 5 (generator) or 3 (loading) runs."
  echo
  echo "| benchmark | input | triangles (points) | median s | min s | max s | peak MiB |"
  echo "|---|---|---:|---:|---:|---:|---:|"
  python3 - "$json" <<'PY' 2>/dev/null || sed 's/^/    /' "$json"
import json, sys, os
for line in open(sys.argv[1]):
    r = json.loads(line)
    name = f"{r['species']} leaves={r['leaves']}" if r['bench'] in ('treegen', 'tree_cli') else os.path.relpath(r['model'], os.path.join(os.path.dirname(sys.argv[1]), '../../../shared/data'))
    peak = f"{r['peak_mib']:.0f}" if r['peak_mib'] else "-"
    size = f"{r['triangles']:,}" if r['triangles'] else f"({r.get('points', 0):,})"
    print(f"| {r['bench']} | {name} | {size} | {r['median_s']:.3f} | {r['min_s']:.3f} | {r['max_s']:.3f} | {peak} |")
PY
} > "$res/latest.md.tmp.$$"
mv "$json" "$res/latest.json"
mv "$res/latest.md.tmp.$$" "$res/latest.md"
cat "$res/latest.md"
