#!/usr/bin/env bash
# bench_forest.sh — the forest engine at scale: the thesis's four
# maps and a million trees (built by scripts/dev/demo_forest.sh, `make demo`),
# each flown along the same camera path across the map by `forest --bench`
# in the default renderer, with --gpu-cull (culling in a compute shader) and
# in --naive (the thesis's way of drawing), in the same run. Writes bench/results/forest.md and forest.json.
#
#   scripts/bench/bench_forest.sh [BUILD] [FRAMES] [SIZE]
#
# llvmpipe (Mesa's software renderer) fills pixels slowly and processes
# vertices on the CPU: the figures use a small viewport (SIZE, 320x200) and
# say which renderer drew them.
set -euo pipefail
case "${1:-}" in
  -h|--help)
    echo "usage: scripts/bench/bench_forest.sh [BUILD (build)] [FRAMES (24)] [SIZE (320x200)]"
    echo "  the forest engine along each map's camera path; writes bench/results/forest.md, .json"
    exit 0 ;;
  -*) echo "bench_forest.sh: unknown option $1 (--help)" >&2; exit 1 ;;
esac
[ -z "${1:-}" ] || [ -d "$1" ] || { echo "bench_forest.sh: no build folder $1 (make first)" >&2; exit 2; }
build=${1:-build}
frames=${2:-24}
size=${3:-320x200}
root=$(cd "$(dirname "$0")/../.." && pwd)
res="$root/bench/results"
out="$build/demo/forest"
mkdir -p "$res"
if [ ! -f "$out/million.txt" ] || [ ! -f "$out/islands.txt" ] || [ ! -f "$out/path_big.txt" ]; then
  "$root/scripts/dev/demo_forest.sh" "$build" 2000
fi
json="$res/forest.json.tmp.$$"
: > "$json"
machine="$(uname -m), $(nproc) cores, $(awk -F: '/model name/{print $2; exit}' /proc/cpuinfo | sed 's/^ *//')"
for map in mixed islands finland huge150k million; do
  n=$frames
  [ "$map" = million ] && n=$(( frames / 2 > 4 ? frames / 2 : 4 ))
  for mode in default gpu-cull naive; do
    flag=""
    [ "$mode" = naive ] && flag=--naive
    [ "$mode" = gpu-cull ] && flag=--gpu-cull
    echo "forest bench: $map $mode ($n frames at $size)" >&2
    # shellcheck disable=SC2086
    text=$("$build/bin/forest" "$out/$map.txt" --bench --path "$out/path_big.txt" --frames "$n" \
           --size "$size" $flag 2> /dev/null)
    python3 - "$map" "$mode" "$machine" "$text" >> "$json" <<'PY'
import json, re, shlex, sys
m, mode, machine, text = sys.argv[1:5]
r = {"bench": "forest", "map": m, "mode": mode, "machine": machine}
for line in text.splitlines():
    for tok in shlex.split(line):
        if "=" not in tok:
            continue
        k, v = tok.split("=", 1)
        try:
            r[k] = float(v) if re.search(r"[.e]", v) else int(v)
        except ValueError:
            r[k] = v
print(json.dumps(r))
PY
  done
done
mv "$json" "$res/forest.json"
python3 - "$res/forest.json" > "$res/forest.md.tmp.$$" <<'PY'
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
r0 = rows[0]
print("# Forest engine benchmark\n")
print(f"{r0['machine']}; renderer: {r0.get('renderer', '?')}; viewport {r0.get('size', '?')}; "
      f"the camera path build/demo/forest/path_big.txt across each 2048 x 2048-unit map; "
      f"{r0.get('frames', '?')} frames per run (the million map half as many), medians and 95th "
      "percentiles over the frames. Frame: until the GPU is done; CPU: until the last GL call "
      "returns (llvmpipe shades vertices there); cull: CPU culling and levels of detail of the "
      "objects (0 with --gpu-cull, whose culling is in the frame's GPU time); draw calls: a "
      "multi-draw counts once (its commands in brackets); ready: from the start of loading "
      "to the first frame drawn. What a GPU pays, counted by pipeline statistics queries "
      "(medians per frame): vertices and primitives submitted, fragments shaded (alpha-tested "
      "ones included) and fragments per pixel of the viewport (overdraw).\n")
print("| map | objects | mode | frame ms median | frame ms p95 | CPU ms | cull ms median | cull ms p95 "
      "| trees drawn | billboards drawn | draw calls | vertices | primitives | fragments | fragments/pixel "
      "| load s | ready s | peak MiB | default faster by |")
print("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
by = {(r["map"], r["mode"]): r for r in rows}
count = lambda r, k: f"{int(r[k]):,}" if k in r else "n/a"
for r in rows:
    d = by.get((r["map"], "default"))
    ratio = ""
    if r["mode"] != "default" and d:
        ratio = f"{r['frame_ms_median'] / d['frame_ms_median']:.2f}x"
    calls = f"{r['draw_calls']:,}" + (f" ({r['draw_commands']:,})" if r.get("draw_commands") else "")
    fpp = f"{r['fragments_per_pixel']:.2f}" if "fragments_per_pixel" in r else "n/a"
    print(f"| {r['map']} | {r['objects']:,} | {r['mode']} | {r['frame_ms_median']:.1f} | "
          f"{r['frame_ms_p95']:.1f} | {r['cpu_ms_median']:.1f} | {r['cull_ms_median']:.3f} | "
          f"{r['cull_ms_p95']:.3f} | {r['trees_drawn']:,} | {r['billboards_drawn']:,} | {calls} | "
          f"{count(r, 'vertices')} | {count(r, 'primitives')} | {count(r, 'fragments')} | {fpp} | "
          f"{r['load_s']:.2f} | {r['ready_s']:.2f} | {r['peak_rss_mb']:.0f} | {ratio} |")
print("\nTexture memory per model (MiB, with mip levels):\n")
seen = set()
for r in rows:
    for k, v in r.items():
        if k.startswith("texture_mb[") and k not in seen:
            seen.add(k)
            print(f"- {k[11:-1]}: {v:.2f}")
PY
mv "$res/forest.md.tmp.$$" "$res/forest.md"
cat "$res/forest.md"
