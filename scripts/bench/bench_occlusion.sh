#!/usr/bin/env bash
# bench_occlusion.sh [BUILD] [FRAMES] — issue 48 item 2: occlusion by the
# terrain on the thesis's four maps and the million map (built by
# scripts/dev/demo_forest.sh, `make demo`): along path_big.txt (FRAMES frames,
# default 12, at 320x200) the default against --reference (no occlusion):
# trees drawn, vertices, fragments a pixel and culling time (medians, as
# `forest --bench` prints them); then the pictures of the start view and
# three path positions at 960x540 in both modes, compared byte by byte (the
# PNG writer is deterministic: the same pixels, the same file). Prints a
# Markdown table. Needs an OpenGL 4.5 context (EGL; llvmpipe here).
set -euo pipefail
build=${1:-build}
frames=${2:-12}
out="$build/demo/forest"
path="$out/path_big.txt"
[ -f "$out/million.txt" ] && [ -f "$path" ] || {
  echo "bench_occlusion.sh: no $out/million.txt: run make demo first" >&2
  exit 2
}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
field() { sed -n "s/.*\b$1=\([^ ]*\).*/\1/p" | head -1; }
echo "| map | mode | trees drawn | vertices | fragments a pixel | culling ms (median) | pictures against --reference (start view, 3 path positions) |"
echo "|---|---|---:|---:|---:|---:|---|"
for map in mixed islands finland huge150k million; do
  for mode in reference default; do
    flag=()
    [ "$mode" = reference ] && flag=(--reference)
    text=$("$build/bin/forest" "$out/$map.txt" --bench --path "$path" --frames "$frames" \
      --size 320x200 "${flag[@]}" 2> /dev/null)
    t=$(echo "$text" | field trees_drawn) v=$(echo "$text" | field vertices)
    f=$(echo "$text" | field fragments_per_pixel) c=$(echo "$text" | field cull_ms_median)
    diffs=""
    if [ "$mode" = default ]; then
      i=0
      for line in "" 2 4 5; do
        cam=()
        [ -n "$line" ] && cam=(--camera "$(sed -n "${line}p" "$path" | awk '{print $1","$2","$3","$4","$5}')")
        "$build/bin/forest" "$out/$map.txt" --size 960x540 "${cam[@]}" --screenshot "$tmp/d$i.png" \
          > /dev/null 2>&1
        "$build/bin/forest" "$out/$map.txt" --size 960x540 "${cam[@]}" --screenshot "$tmp/r$i.png" \
          --reference > /dev/null 2>&1
        i=$((i + 1))
      done
      diffs=$(for k in 0 1 2 3; do
        if cmp -s "$tmp/d$k.png" "$tmp/r$k.png"; then echo -n "same "; else echo -n "DIFFERENT "; fi
      done)
    fi
    echo "| $map | $mode | $t | $v | $f | $c | $diffs |"
  done
done
