#!/usr/bin/env bash
# bench_speed.sh [BUILD] — the generator's speed per stage against an older
# release, measured in the same run: `bbcgen MODEL -o OUT.glb`
# with the defaults on the Scopia pine, the Scopia copperBeech and a
# generated oak of 1.13M triangles (`bbcgen tree --leaves 450000`), RUNS
# runs each (default 5; old and new alternate), medians per stage (from
# --report: load, step 1, step 2, step 3 bake and atlas, write; wall clock
# and peak memory from GNU time). The older binary is built from BENCH_BASE
# (default 6dc383e, the last commit before the speed work of CHANGELOG.md's
# issue 17) into a scratch
# folder. Writes bench/results/speed.md and speed.json.
set -euo pipefail
build=${1:-build}
root=$(cd "$(dirname "$0")/../.." && pwd)
data="$root/../shared/data"
res="$root/bench/results"
base=${BENCH_BASE:-6dc383e}
runs=${RUNS:-5}
mkdir -p "$res"
command -v /usr/bin/time > /dev/null || { echo "bench_speed.sh: GNU time is needed" >&2; exit 3; }
case "$build" in /*) ;; *) build="$root/$build" ;; esac
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
old=$("$root/scripts/dev/build_base.sh" "$base" "$tmp/old")
new="$build/bin/bbcgen"
"$new" tree --leaves 450000 -q -o "$tmp/big_oak.obj"
models=("$data/trees/scopia/pine/pine.obj" "$data/trees/scopia/copperBeech/copperBeech.obj"
        "$tmp/big_oak.obj")
json="$tmp/speed.json"
: > "$json"
for m in "${models[@]}"; do
  [ -f "$m" ] || { echo "skip: $m missing" >&2; continue; }
  for r in $(seq "$runs"); do
    for which in old new; do
      bin=$old
      [ "$which" = new ] && bin=$new
      /usr/bin/time -f '%e %M' -o "$tmp/time" "$bin" "$m" -o "$tmp/out.glb" --report "$tmp/r.json" -q
      python3 - "$tmp/r.json" "$tmp/time" "$which" "$m" "$r" <<'PY' >> "$json"
import json, sys
rep = json.load(open(sys.argv[1]))
wall, kib = open(sys.argv[2]).read().split()[-2:]
t = rep['times_s']
lt = rep['lods'][0]['times_s']
print(json.dumps({'bench': 'speed', 'binary': sys.argv[3], 'model': sys.argv[4], 'run': int(sys.argv[5]),
                  'triangles': rep['model_triangles'], 'planes': rep['lods'][0]['planes'],
                  'wall_s': float(wall), 'peak_mib': int(kib) / 1024.0, 'load_s': t['load'],
                  'step1_s': lt.get('step1', 0) + lt.get('steps12_discarded_runs', 0),
                  'step2_s': lt.get('step2', 0), 'step3_s': lt.get('step3_bake', 0) + lt.get('step3_atlas', 0),
                  'write_s': t['write']}))
PY
    done
  done
done
machine="$(nproc) cores, $(awk -F: '/model name/{print $2; exit}' /proc/cpuinfo | sed 's/^ *//')"
{
  echo "# The generator's speed per stage (scripts/bench/bench_speed.sh)"
  echo
  echo "$(date -u +%F), $machine; \`bbcgen MODEL -o OUT.glb\` with the defaults, $runs runs each,"
  echo "the older binary ($base) and this one alternating; medians in seconds, peak memory in MiB"
  echo "(GNU time: the whole process, loading included)."
  echo
  echo "| model | triangles | binary | planes | load | step 1 | step 2 | steps 1+2 | step 3 | write | wall | peak MiB |"
  echo "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
  python3 - "$json" <<'PY'
import json, statistics, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
med = lambda xs: statistics.median(xs)
models = []
for r in rows:
    if r['model'] not in models:
        models.append(r['model'])
for m in models:
    name = m.split('shared/data/')[-1] if 'shared/data/' in m else 'generated oak (tree --leaves 450000)'
    got = {}
    for b in ('old', 'new'):
        rs = [r for r in rows if r['model'] == m and r['binary'] == b]
        if not rs:
            continue
        k = {f: med([r[f] for r in rs]) for f in ('load_s', 'step1_s', 'step2_s', 'step3_s', 'write_s', 'wall_s', 'peak_mib')}
        k['steps'] = med([r['step1_s'] + r['step2_s'] for r in rs])
        got[b] = k
        print(f"| {name} | {rs[0]['triangles']:,} | {b} | {rs[0]['planes']} | {k['load_s']:.2f} | {k['step1_s']:.2f} | {k['step2_s']:.2f} | {k['steps']:.2f} | {k['step3_s']:.2f} | {k['write_s']:.2f} | {k['wall_s']:.2f} | {k['peak_mib']:.0f} |")
    if 'old' in got and 'new' in got:
        o, n = got['old'], got['new']
        ratio = lambda f: o[f] / n[f] if n[f] > 0 else float('nan')
        print(f"| {name} | | old / new | | {ratio('load_s'):.2f}x | {ratio('step1_s'):.2f}x | {ratio('step2_s'):.2f}x | {ratio('steps'):.2f}x | {ratio('step3_s'):.2f}x | {ratio('write_s'):.2f}x | **{ratio('wall_s'):.2f}x** | {o['peak_mib'] / n['peak_mib']:.2f}x |")
PY
} > "$res/speed.md"
cp "$json" "$res/speed.json"
cat "$res/speed.md"
