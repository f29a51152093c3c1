#!/usr/bin/env bash
# bench_impostor.sh — the default cloud beside an octahedral impostor, crossed
# billboards and meshoptimizer at equal texels and equal screen sizes
# (issue 49 item 2), on the acceptance trees (scripts/studies/data_trees.sh).
#
#   scripts/bench/bench_impostor.sh [--only a,b] [--views N] [--texels "T ..."]
#       [--sizes "PX ..."] BUILD_DIR OUT_DIR
#
# For each tree and texel budget T: the default cloud in an atlas of
# sqrt(T) texels a side (`atlasmax`), `bbcgen impostor --texels T` (8 x 8
# frames, hemi-octahedral and with --full octahedral, each with --check: its
# frames against the tree on their own texels) and 3 crossed
# billboards (`baseline --texels T`);
# meshoptimizer's simplification at the 1M cloud's triangles once (its
# textures are the original's). Each judged by `bbcgen eval` (N views, 32 by
# default, unlit) at each screen size, and at 128 px under the 16-sun sweep
# (luminance ratio range), over the sphere and over the upper hemisphere.
# Writes OUT_DIR/impostor.json (one object a line) and prints the markdown
# tables (medians and worst cases over the trees);
# outputs are kept under OUT_DIR/<tree>/ and reused when present.
# Needs the build's bbcgen only. Not run by CI or `make bench` (about 40
# minutes on 2 cores for the 17 trees).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
only="" views=32 texels="262144 524288 1048576" sizes="512 128 32"
while [ $# -gt 2 ]; do
  case "$1" in
    --only) only=$2; shift 2 ;;
    --views) views=$2; shift 2 ;;
    --texels) texels=$2; shift 2 ;;
    --sizes) sizes=$2; shift 2 ;;
    -h|--help) sed -n '2,22p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "bench_impostor.sh: unknown option '$1' (try --help)" >&2; exit 1 ;;
  esac
done
case "${1:-}" in -h|--help) sed -n '2,22p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;; esac
[ $# -eq 2 ] || { echo "usage: bench_impostor.sh [OPTIONS] BUILD_DIR OUT_DIR (try --help)" >&2; exit 1; }
build=$1 out=$2
bbcgen=$build/bin/bbcgen
[ -x "$bbcgen" ] || { echo "bench_impostor.sh: no $bbcgen (build first)" >&2; exit 1; }
data=$root/../shared/data
mkdir -p "$out"
json=$out/impostor.json
: > "$json"

# record TREE METHOD TEXELS ATLAS_TEXELS TRIANGLES FILE ORIG: eval at each size and the sweep
record() {
  local tree=$1 method=$2 budget=$3 atlas=$4 tris=$5 file=$6 orig=$7 px
  for px in $sizes; do
    local j=${file%.*}.eval$px.json
    [ -s "$j" ] || "$bbcgen" eval "$orig" "$file" --views "$views" --size "$px" --no-lit \
      --json "$j" > /dev/null
    python3 - "$j" "$tree" "$method" "$budget" "$atlas" "$tris" "$px" >> "$json" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
print(json.dumps({"tree": sys.argv[2], "method": sys.argv[3], "budget": int(sys.argv[4]),
                  "atlas_texels": int(sys.argv[5]), "triangles": int(sys.argv[6]),
                  "size": int(sys.argv[7]), "iou": j["iou_mean"], "block_iou": j["block_iou_mean"],
                  "coverage": j["coverage_ratio_mean"], "mae": j["mae_mean"],
                  "block_iou_side": j["block_iou_side_mean"]}))
PY
  done
  local s=${file%.*}.sun.json
  [ -s "$s" ] || "$bbcgen" eval "$orig" "$file" --views 16 --size 128 --sun sweep --json "$s" \
    > /dev/null
  local u=${file%.*}.sunup.json
  [ -s "$u" ] || "$bbcgen" eval "$orig" "$file" --views 16 --size 128 --sun sweep --upper \
    --json "$u" > /dev/null
  python3 - "$s" "$u" "$tree" "$method" "$budget" >> "$json" <<'PY'
import json, sys
j, u = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
print(json.dumps({"tree": sys.argv[3], "method": sys.argv[4], "budget": int(sys.argv[5]),
                  "sun_min": j["luminance_ratio_min"], "sun_max": j["luminance_ratio_max"],
                  "sunup_min": u["luminance_ratio_min"], "sunup_max": u["luminance_ratio_max"]}))
PY
}

# triangles of a .glb (its accessor counts), for the baselines and the table
tris_of() {
  python3 - "$1" <<'PY'
import json, struct, sys
b = open(sys.argv[1], 'rb').read()
n = struct.unpack('<I', b[12:16])[0]
g = json.loads(b[20:20 + n])
print(sum(g['accessors'][p['indices']]['count'] // 3 for m in g['meshes'] for p in m['primitives']))
PY
}

while IFS=$'\t' read -r name orig; do
  if [ -n "$only" ] && [[ ",$only," != *",$name,"* ]]; then continue; fi
  d=$out/$name
  mkdir -p "$d"
  echo "== $name" >&2
  for t in $texels; do
    side=$(python3 -c "import math; print(int(math.isqrt($t)))")
    c=$d/cloud_$t.glb i=$d/imp_$t.json f=$d/impfull_$t.json x=$d/x3_$t.glb
    [ -s "$c" ] || "$bbcgen" "$orig" -o "$c" --set atlasmax="$side" -q
    # built with --check: each frame against the tree on the frame's own texels
    [ -s "$i" ] && [ -s "${i%.json}.check" ] ||
      "$bbcgen" impostor "$orig" -o "$i" --texels "$t" --check -q > "${i%.json}.check"
    [ -s "$f" ] && [ -s "${f%.json}.check" ] ||
      "$bbcgen" impostor "$orig" -o "$f" --texels "$t" --full --check -q > "${f%.json}.check"
    for k in "$i:impostor" "$f:impostor_full"; do
      python3 - "${k%%:*}" "$name" "${k#*:}" "$t" >> "$json" <<'PY'
import json, re, sys
m = re.search(r"worst ([0-9.]+) .*mean ([0-9.]+)", open(sys.argv[1][:-5] + ".check").read())
print(json.dumps({"tree": sys.argv[2], "method": sys.argv[3], "budget": int(sys.argv[4]),
                  "frames_worst": float(m.group(1)), "frames_mean": float(m.group(2))}))
PY
    done
    [ -s "$x" ] || "$bbcgen" baseline "$orig" -o "$x" --method crossed --planes 3 --texels "$t" -q
    ia=$(python3 -c "import json; j=json.load(open('$i')); print((j['frames']*j['frame_size'])**2)")
    record "$name" cloud "$t" "$((side * side))" "$(tris_of "$c")" "$c" "$orig"
    record "$name" impostor "$t" "$ia" 2 "$i" "$orig"
    record "$name" impostor_full "$t" "$ia" 2 "$f" "$orig"
    record "$name" crossed3 "$t" "$t" "$(tris_of "$x")" "$x" "$orig"
  done
  last=$(echo $texels | awk '{print $NF}')
  ct=$(tris_of "$d/cloud_$last.glb")
  m=$d/simplify.glb
  [ -s "$m" ] || "$bbcgen" baseline "$orig" -o "$m" --method simplify --triangles "$ct" -q
  record "$name" meshopt "$last" 0 "$(tris_of "$m")" "$m" "$orig"
done < <(bash "$root/scripts/studies/data_trees.sh" "$data" "$out/gen" "$bbcgen")

python3 - "$json" <<'PY'
import json, sys, statistics as st
rows = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
ev = [r for r in rows if 'size' in r]
sun = [r for r in rows if 'sun_min' in r]
methods = ['cloud', 'impostor', 'impostor_full', 'crossed3', 'meshopt']
budgets = sorted({r['budget'] for r in ev})
sizes = sorted({r['size'] for r in ev}, reverse=True)
trees = sorted({r['tree'] for r in ev})
print(f"{len(trees)} trees; medians over the trees (worst in brackets); IoU, block IoU (1/8), "
      "coverage ratio (worst: farthest from 1), colour error (MAE, 0-255).\n")
print("| texels | px | method | IoU | block IoU | block IoU side | coverage | colour error |")
print("|---:|---:|---|---:|---:|---:|---:|---:|")
for b in budgets:
    for px in sizes:
        for m in methods:
            s = [r for r in ev if r['budget'] == b and r['size'] == px and r['method'] == m]
            if not s:
                continue
            f = lambda k: st.median(r[k] for r in s)
            wc = max((r['coverage'] for r in s), key=lambda v: abs(v - 1))
            print(f"| {b:,} | {px} | {m} | {f('iou'):.3f} ({min(r['iou'] for r in s):.3f}) | "
                  f"{f('block_iou'):.3f} ({min(r['block_iou'] for r in s):.3f}) | "
                  f"{f('block_iou_side'):.3f} ({min(r['block_iou_side'] for r in s):.3f}) | "
                  f"{f('coverage'):.3f} ({wc:.3f}) | {f('mae'):.1f} ({max(r['mae'] for r in s):.1f}) |")
print("\nUnder the 16-sun sweep (128 px, 16 views, ambient 0.4): cloud/original luminance, "
      "median of each tree's range and the extremes over the trees.\n")
print("| texels | method | median min | median max | lowest | highest |")
print("|---:|---|---:|---:|---:|---:|")
for b in budgets:
    for m in methods:
        s = [r for r in sun if r['budget'] == b and r['method'] == m]
        if s:
            print(f"| {b:,} | {m} | {st.median(r['sun_min'] for r in s):.3f} | "
                  f"{st.median(r['sun_max'] for r in s):.3f} | {min(r['sun_min'] for r in s):.3f} | "
                  f"{max(r['sun_max'] for r in s):.3f} |")
print("\nThe same sweep over 16 views above the horizon only (`eval --upper`: as trees are "
      "seen, and what a hemi-octahedral impostor is made for).\n")
print("| texels | method | median min | median max | lowest | highest |")
print("|---:|---|---:|---:|---:|---:|")
for b in budgets:
    for m in methods:
        s = [r for r in sun if r['budget'] == b and r['method'] == m and 'sunup_min' in r]
        if s:
            print(f"| {b:,} | {m} | {st.median(r['sunup_min'] for r in s):.3f} | "
                  f"{st.median(r['sunup_max'] for r in s):.3f} | {min(r['sunup_min'] for r in s):.3f} | "
                  f"{max(r['sunup_max'] for r in s):.3f} |")
chk = [r for r in rows if 'frames_worst' in r]
if chk:
    print("\nEach impostor's frames against its tree (`bbcgen impostor --check`: along each "
          "frame's direction, on the frame's own texels against the tree drawn 4 x finer, block "
          "IoU over blocks of 8 x 8 texels): the worst frame, median and lowest over the trees, "
          "and the mean over the frames.\n")
    print("| texels | method | worst frame, median | worst frame, lowest | mean, median |")
    print("|---:|---|---:|---:|---:|")
    for b in budgets:
        for m in ['impostor', 'impostor_full']:
            s = [r for r in chk if r['budget'] == b and r['method'] == m]
            if s:
                print(f"| {b:,} | {m} | {st.median(r['frames_worst'] for r in s):.3f} | "
                      f"{min(r['frames_worst'] for r in s):.3f} | "
                      f"{st.median(r['frames_mean'] for r in s):.3f} |")
print("\nPer tree at 1,048,576 texels and 128 px (block IoU):\n")
print("| tree | " + " | ".join(methods) + " |")
print("|---|" + "---:|" * len(methods))
for t in trees:
    cells = []
    for m in methods:
        s = [r for r in ev if r['tree'] == t and r['method'] == m and r['size'] == 128 and
             r['budget'] == max(budgets)]
        cells.append(f"{s[0]['block_iou']:.3f}" if s else "-")
    print(f"| {t} | " + " | ".join(cells) + " |")
PY
