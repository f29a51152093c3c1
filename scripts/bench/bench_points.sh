#!/usr/bin/env bash
# bench_points.sh — point clouds to Billboard Clouds (thesis 2.4):
# the data scans, and points sampled on the Scopia pine's surface (1M, and
# 10M when POINTS_10M=1: minutes and some GB), each through steps 1 to 3 to
# a .glb by `bbcgen` with the defaults (upaxis z for the z-up scans), RUNS
# runs each (median; 1 for 10M). Writes bench/results/points.md and .json:
# points, planes, steps 1/2/3 seconds (the --report's), wall seconds and
# peak memory (GNU time), the thesis's 1.76M-point Court for scale (1,672 s).
#
#   scripts/bench/bench_points.sh [BUILD] [RUNS]
set -euo pipefail
build=${1:-build}
runs=${2:-3}
root=$(cd "$(dirname "$0")/../.." && pwd)
data="$root/../shared/data"
res="$root/bench/results"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$res"
command -v /usr/bin/time > /dev/null || { echo "bench_points.sh: GNU time is needed (apt-get install time)" >&2; exit 3; }
bbcgen="$build/bin/bbcgen"
machine="$(uname -m), $(nproc) cores, $(awk -F: '/model name/{print $2; exit}' /proc/cpuinfo | sed 's/^ *//')"
pine="$data/trees/scopia/pine/pine.obj"
inputs=()
for f in points/adtree/house.xyz points/adtree/tree7.xyz points/adtree/tree13.xyz points/b9_training.ply \
         points/ball.ply points/hippo1.ply points/lidr_tree.xyz; do
  [ -f "$data/$f" ] && inputs+=("$data/$f")
done
if [ -f "$pine" ]; then
  "$bbcgen" sample "$pine" -o "$tmp/pine_1M.ply" --points 1000000 -q
  inputs+=("$tmp/pine_1M.ply")
  if [ "${POINTS_10M:-0}" = 1 ]; then
    "$bbcgen" sample "$pine" -o "$tmp/pine_10M.ply" --points 10000000 -q
    inputs+=("$tmp/pine_10M.ply")
  fi
fi
json="$tmp/points.json"
: > "$json"
for f in "${inputs[@]}"; do
  name=$(basename "$f")
  up=""
  case "$f" in */adtree/*|*lidr_tree*|*b9_training*) up="--upaxis z" ;; esac
  n=$runs
  case "$name" in *10M*) n=1 ;; esac
  for i in $(seq 1 "$n"); do
    echo "points bench: $name run $i of $n" >&2
    # shellcheck disable=SC2086
    /usr/bin/time -f "%e %M" -o "$tmp/time.txt" "$bbcgen" "$f" -o "$tmp/out.glb" $up -q \
      --report "$tmp/report.json"
    python3 - "$name" "$machine" "$tmp/time.txt" "$tmp/report.json" >> "$json" <<'PY'
import json, sys
name, machine, tfile, rfile = sys.argv[1:5]
wall, kb = open(tfile).read().split()[-2:]
r = json.load(open(rfile))
l = r['lods'][0]
t = l['times_s']
print(json.dumps({'input': name, 'machine': machine, 'points': r.get('model_points'),
                  'planes': l['planes'], 'billboards': l['billboards'],
                  'step1_s': t['step1'] + t['steps12_discarded_runs'], 'step2_s': t['step2'],
                  'step3_s': t['step3_bake'] + t['step3_atlas'], 'wall_s': float(wall),
                  'peak_mib': int(kb) / 1024}))
PY
  done
done
python3 - "$json" "$res/points.json" > "$res/points.md.tmp" <<'PY'
import json, statistics, sys
rows = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
by = {}
for r in rows: by.setdefault(r['input'], []).append(r)
out = []
print('# Point clouds to Billboard Clouds (scripts/bench/bench_points.sh)\n')
print(f"machine: {rows[0]['machine'] if rows else '-'}; medians of the runs; steps from `--report`, wall and peak memory from GNU time (load and writing included).\n")
print('| input | points | planes | billboards | step 1 s | step 2 s | step 3 s | wall s | peak MiB | runs |')
print('|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|')
for name, rs in by.items():
    med = {k: statistics.median(r[k] for r in rs) for k in ('step1_s', 'step2_s', 'step3_s', 'wall_s', 'peak_mib')}
    out.append({'input': name, 'planes': rs[0]['planes'], 'billboards': rs[0]['billboards'], 'runs': len(rs), **med})
    print(f"| {name} | {rs[0]['points'] or 0:,} | {rs[0]['planes']} | {rs[0]['billboards']} | {med['step1_s']:.2f} | {med['step2_s']:.2f} | {med['step3_s']:.2f} | {med['wall_s']:.2f} | {med['peak_mib']:.0f} | {len(rs)} |")
print('\nThe thesis: the 1,759,743-point Court in 1,672 s (2 GHz Pentium 4).')
json.dump(out, open(sys.argv[2], 'w'), indent=1)
PY
mv "$res/points.md.tmp" "$res/points.md"
cat "$res/points.md"
