#!/usr/bin/env bash
# bench_classes.sh [BUILD] — speed by class of input (issue 34): µs per
# primitive of a whole default run (`bbcgen INPUT -o OUT.glb`, file to .glb)
# and per step, this binary against the one before issue 34 (BENCH_BASE,
# default a87074b, built into a scratch folder), in the same run, RUNS runs
# each (default 3, old and new alternating; medians). Classes: a building
# scan (scripts/bench/make_building.py sampled at 100k points with normals), a
# forest plot scan (scripts/bench/make_plot.py: ground and six generated trees,
# 81,591 points as georeferenced XYZ), the data scans, 1M points sampled on
# the Scopia pine (and 10M with POINTS_10M=1: one run each, minutes), the
# Scopia pine itself, a generated broadleaf of ~480k triangles and conifer
# of ~640k, a non-organic mesh (the FlightGear H-60) and a large one (the
# building tessellated into 245k triangles) and the generated oak of 1.13M
# triangles. For each input: whether the two binaries wrote the same
# geometry and textures (the .glb's binary chunk; its JSON differs by the
# parameter list), epsilon and planes of each, and where they differ the
# fidelity of each (`bbcgen eval` against the input: mean IoU over 64
# views). Writes bench/results/classes.md and classes.json.
set -euo pipefail
build=${1:-build}
root=$(cd "$(dirname "$0")/../.." && pwd)
data="$root/../shared/data"
res="$root/bench/results"
base=${BENCH_BASE:-a87074b}
runs=${RUNS:-3}
mkdir -p "$res"
command -v /usr/bin/time > /dev/null || { echo "bench_classes.sh: GNU time is needed" >&2; exit 3; }
case "$build" in /*) ;; *) build="$root/$build" ;; esac
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
old=$("$root/scripts/dev/build_base.sh" "$base" "$tmp/old")
new="$build/bin/bbcgen"
in="$tmp/in"
mkdir -p "$in"

# The inputs: "class|name|path|extra options".
list=()
python3 "$root/scripts/bench/make_building.py" "$in/building.obj"
"$new" sample "$in/building.obj" --normals --points 100000 -o "$in/building_100k.ply" -q
list+=("building scan (PLY with normals)|building_100k.ply|$in/building_100k.ply|")
i=0
for sp in oak pine birch larch oak pine; do
  i=$((i + 1))
  "$new" tree --species $sp --seed $i --leaves 3000 -o "$in/tree_$i.obj" -q
done
python3 "$root/scripts/bench/make_plot.py" "$in/plot.obj" "$in"/tree_?.obj
"$new" sample "$in/plot.obj" --points 81591 -o "$in/plot.ply" -q
python3 - "$in/plot.ply" "$in/plot_utm.xyz" <<'PY'
import struct, sys
# PLY (doubles x y z, uchar r g b; y up) to XYZ in UTM-like metres, z up
f = open(sys.argv[1], 'rb')
hdr = b''
while not hdr.endswith(b'end_header\n'):
    hdr += f.readline()
n = int([l for l in hdr.decode().split('\n') if l.startswith('element vertex')][0].split()[2])
with open(sys.argv[2], 'w') as o:
    for _ in range(n):
        x, y, z, r, g, b = struct.unpack('<3d3B', f.read(27))
        o.write('%.3f %.3f %.3f %d %d %d\n' % (500000 + x, 5400000 - z, 300 + y, r, g, b))
PY
list+=("forest plot scan (XYZ, UTM)|plot_utm.xyz|$in/plot_utm.xyz|--upaxis z")
for f in adtree/house.xyz adtree/tree7.xyz adtree/tree13.xyz lidr_tree.xyz hippo1.ply b9_training.ply ball.ply; do
  [ -f "$data/points/$f" ] || continue
  up=""
  case "$f" in *.xyz | *b9_training*) up="--upaxis z" ;; esac
  list+=("data scan|$(basename "$f")|$data/points/$f|$up")
done
pine="$data/trees/scopia/pine/pine.obj"
if [ -f "$pine" ]; then
  "$new" sample "$pine" --points 1000000 -o "$in/pine_1M.ply" -q
  list+=("1M points on the Scopia pine|pine_1M.ply|$in/pine_1M.ply|")
  if [ "${POINTS_10M:-0}" = 1 ]; then
    "$new" sample "$pine" --points 10000000 -o "$in/pine_10M.ply" -q
    list+=("10M points on the Scopia pine|pine_10M.ply|$in/pine_10M.ply|")
  fi
  list+=("tree mesh|Scopia pine.obj|$pine|")
fi
"$new" tree --leaves 190000 -o "$in/broadleaf.obj" -q
list+=("large broadleaf mesh|tree --leaves 190000|$in/broadleaf.obj|")
"$new" tree --species pine --leaves 250000 -o "$in/conifer.obj" -q
list+=("large conifer mesh|tree --species pine --leaves 250000|$in/conifer.obj|")
h60="$data/models/flightgear/H-60.ac"
[ -f "$h60" ] && list+=("non-organic mesh|H-60.ac|$h60|")
python3 "$root/scripts/bench/make_building.py" "$in/building_fine.obj" 50
list+=("large non-organic mesh (tessellated)|make_building.py 50|$in/building_fine.obj|")
"$new" tree --leaves 450000 -o "$in/oak_1M.obj" -q
list+=("1.13M-triangle oak|tree --leaves 450000|$in/oak_1M.obj|")

json="$tmp/classes.json"
: > "$json"
for item in "${list[@]}"; do
  IFS='|' read -r cls name path extra <<< "$item"
  n=$runs
  case "$name" in *10M*) n=1 ;; esac
  for r in $(seq "$n"); do
    for which in old new; do
      bin=$old
      [ "$which" = new ] && bin=$new
      echo "bench_classes: $name, $which, run $r of $n" >&2
      # shellcheck disable=SC2086
      /usr/bin/time -f '%e %M' -o "$tmp/time" "$bin" "$path" -o "$tmp/$which.glb" $extra \
        --report "$tmp/r.json" -q
      python3 - "$tmp/r.json" "$tmp/time" "$which" "$cls" "$name" "$r" <<'PY' >> "$json"
import json, sys
rep = json.load(open(sys.argv[1]))
wall, kib = open(sys.argv[2]).read().split()[-2:]
t = rep['times_s']
l = rep['lods'][0]
lt = l['times_s']
prims = rep.get('model_points') or rep['model_triangles']
print(json.dumps({'bench': 'classes', 'binary': sys.argv[3], 'class': sys.argv[4], 'input': sys.argv[5],
                  'run': int(sys.argv[6]), 'primitives': prims, 'points': bool(rep.get('model_points')),
                  'planes': l['planes'], 'epsilon_pct': l['epsilon_pct_used'],
                  'runs_whole': l.get('plane_runs', 1), 'probes': l.get('plane_probe_runs', 0),
                  'wall_s': float(wall), 'peak_mib': int(kib) / 1024.0, 'load_s': t['load'],
                  'step1_s': lt['step1'], 'step2_s': lt['step2'],
                  'search_s': lt.get('steps12_discarded_runs', 0),
                  'step3_s': lt['step3_bake'] + lt['step3_atlas'], 'write_s': t['write']}))
PY
    done
  done
  # the same output? where not, each one's fidelity
  same=$(python3 - "$tmp/old.glb" "$tmp/new.glb" <<'PY'
import struct, sys
def chunk(f):
    b = open(f, 'rb').read()
    n = struct.unpack('<I', b[12:16])[0]
    m = struct.unpack('<I', b[20 + n:24 + n])[0]
    return b[28 + n:28 + n + m]
print(1 if chunk(sys.argv[1]) == chunk(sys.argv[2]) else 0)
PY
)
  iou_old=null iou_new=null
  if [ "$same" = 0 ]; then
    for which in old new; do
      # shellcheck disable=SC2086
      "$new" eval "$path" "$tmp/$which.glb" $extra --json "$tmp/eval.json" -q > /dev/null
      v=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["iou_mean"])' "$tmp/eval.json")
      [ "$which" = old ] && iou_old=$v || iou_new=$v
    done
  fi
  printf '{"bench": "classes_output", "input": "%s", "same_output": %s, "iou_old": %s, "iou_new": %s}\n' \
    "$name" "$same" "$iou_old" "$iou_new" >> "$json"
done

machine="$(nproc) cores, $(awk -F: '/model name/{print $2; exit}' /proc/cpuinfo | sed 's/^ *//')"
{
  echo "# Speed by class of input (scripts/bench/bench_classes.sh)"
  echo
  echo "$(date -u +%F), $machine; \`bbcgen INPUT -o OUT.glb\` with the defaults (\`--upaxis z\` for"
  echo "z-up scans), file to .glb; the binary before issue 34 ($base, old) and this one (new)"
  echo "alternating, medians of $runs runs (1 for 10M points). µs per primitive = wall clock"
  echo "(GNU time: loading and writing included) / points or triangles; steps from \`--report\`:"
  echo "search = the epsilon search's discarded whole runs and its probes; peak memory of the"
  echo "process. Output: the same geometry and textures (the .glb's binary chunk), else each"
  echo "one's mean IoU over 64 views against the input (\`bbcgen eval\`)."
  echo
  python3 - "$json" <<'PY'
import json, statistics, sys
rows = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
outs = {r['input']: r for r in rows if r['bench'] == 'classes_output'}
rows = [r for r in rows if r['bench'] == 'classes']
names = []
for r in rows:
    if r['input'] not in names:
        names.append(r['input'])
med = statistics.median
print('| class | input | primitives | binary | ε % | planes | whole runs + probes | load s | step 1 s | step 2 s | search s | step 3 s | wall s | µs / primitive | peak MiB |')
print('|---|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|')
summary = []
for name in names:
    got = {}
    for b in ('old', 'new'):
        rs = [r for r in rows if r['input'] == name and r['binary'] == b]
        if not rs:
            continue
        k = {f: med([r[f] for r in rs]) for f in ('load_s', 'step1_s', 'step2_s', 'search_s', 'step3_s', 'wall_s', 'peak_mib')}
        r0 = rs[0]
        k['us'] = 1e6 * k['wall_s'] / r0['primitives']
        got[b] = k
        kind = 'points' if r0['points'] else 'triangles'
        print(f"| {r0['class']} | {name} | {r0['primitives']:,} {kind} | {b} | {r0['epsilon_pct']:.3g} | {r0['planes']} | {r0['runs_whole']} + {r0['probes']} | {k['load_s']:.2f} | {k['step1_s']:.2f} | {k['step2_s']:.2f} | {k['search_s']:.2f} | {k['step3_s']:.2f} | {k['wall_s']:.2f} | {k['us']:.1f} | {k['peak_mib']:.0f} |")
    if 'old' in got and 'new' in got:
        o, n = got['old'], got['new']
        print(f"| | | | old / new | | | | | | | | | **{o['wall_s'] / n['wall_s']:.2f}x** | | {o['peak_mib'] / n['peak_mib']:.2f}x |")
    out = outs.get(name)
    if out:
        same = 'same output' if out['same_output'] else f"output differs: IoU old {out['iou_old']:.4f}, new {out['iou_new']:.4f}"
        summary.append(f"- {name}: {same}")
print()
print('Outputs, old against new:')
print()
print('\n'.join(summary))
PY
} > "$res/classes.md"
cp "$json" "$res/classes.json"
cat "$res/classes.md"
