#!/usr/bin/env bash
# bench_small.sh [BUILD] — the inputs of ../shared/data under 50,000
# primitives (the scans, the models, the small trees): a whole default run
# (`bbcgen INPUT -o OUT.glb`, the epsilon search included), this binary
# against BENCH_BASE (default e28ef8b, built into a scratch folder),
# alternating, RUNS runs each (default 3; medians), with step 3's bake time
# from --report; and each one's fidelity against the input (`bbcgen eval`:
# mean IoU, block IoU, coverage ratio, colour error) and the differences.
# Writes bench/results/small.md.
set -euo pipefail
build=${1:-build}
root=$(cd "$(dirname "$0")/../.." && pwd)
d="$root/../shared/data"
base=${BENCH_BASE:-e28ef8b}
runs=${RUNS:-3}
case "$build" in /*) ;; *) build="$root/$build" ;; esac
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
old=$("$root/scripts/dev/build_base.sh" "$base" "$tmp/old")
new="$build/bin/bbcgen"
out="$root/bench/results/small.md"
list=(models/teapot.obj models/cat.3ds models/horse.3ds models/flightgear/H-60.ac
  models/flightgear/dauphin.ac points/adtree/house.xyz points/adtree/tree7.xyz
  points/adtree/tree13.xyz points/lidr_tree.xyz points/hippo1.ply points/b9_training.ply
  points/ball.ply trees/eztree/aspen_small.obj trees/eztree/bush_1.obj
  trees/eztree/oak_medium.obj trees/eztree/pine_medium.obj trees/quaternius/OBJ/Birch_1.obj
  trees/quaternius/OBJ/DeadTree_1.obj trees/quaternius/OBJ/Pine_1.obj
  trees/quaternius/OBJ/Tree_1.obj trees/quaternius/OBJ/Tree_3.obj trees/scopia/bush/bush.obj
  trees/scopia/palm/palm.obj)
wall() { # wall seconds of one run
  local s e
  s=$(date +%s.%N)
  "$@" -q 2> /dev/null
  e=$(date +%s.%N)
  python3 -c "print($e - $s)"
}
median() { printf '%s\n' "$@" | sort -g | sed -n "$((($# + 1) / 2))p"; }
json() { python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print($2)" "$1"; }
{
  echo "# Small inputs: a whole default run (scripts/bench/bench_small.sh)"
  echo
  echo "$(date -u +%F), $(nproc) cores; \`bbcgen INPUT -o OUT.glb\` (\`--upaxis z\` for the z-up"
  echo "scans), old = $base, new = this build, alternating, medians of $runs runs; bake = step 3's"
  echo "bake (--report); fidelity: \`bbcgen eval\` of each output against the input (64 views)."
  echo
  echo "| input | old s | new s | old / new | bake old s | bake new s | IoU old | IoU new | block IoU old | new | coverage old | new | colour error old | new |"
  echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
} > "$out"
for f in "${list[@]}"; do
  in="$d/$f"
  [ -f "$in" ] || continue
  up=()
  case "$f" in *.xyz | *b9_training*) up=(--upaxis z) ;; esac
  ta=() tb=()
  for _ in $(seq "$runs"); do
    ta+=("$(wall "$old" "$in" -o "$tmp/a.glb" "${up[@]}" --report "$tmp/a.json")")
    tb+=("$(wall "$new" "$in" -o "$tmp/b.glb" "${up[@]}" --report "$tmp/b.json")")
  done
  "$new" eval "$in" "$tmp/a.glb" "${up[@]}" --json "$tmp/ea.json" -q > /dev/null
  "$new" eval "$in" "$tmp/b.glb" "${up[@]}" --json "$tmp/eb.json" -q > /dev/null
  ma=$(median "${ta[@]}") mb=$(median "${tb[@]}")
  python3 - "$f" "$ma" "$mb" "$tmp" >> "$out" <<'PY'
import json, sys
f, ma, mb, t = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), sys.argv[4]
ra, rb = (json.load(open(f'{t}/{k}.json'))['lods'][0]['times_s']['step3_bake'] for k in 'ab')
ea, eb = (json.load(open(f'{t}/e{k}.json')) for k in 'ab')
cells = []
for k, scale in (('iou_mean', 1), ('block_iou_mean', 1), ('coverage_ratio_mean', 1), ('mae_mean', 255)):
    cells += ['%.4f' % (ea[k] / scale), '%.4f' % (eb[k] / scale)]
print('| %s | %.2f | %.2f | %.2fx | %.2f | %.2f | %s |' % (f.split('/')[-1], ma, mb, ma / mb, ra, rb, ' | '.join(cells)))
PY
done
echo "wrote $out"
