#!/usr/bin/env bash
# bench_outline.sh [BUILD] — issue 48 item 3 on a single cloud: what tight
# outlines (`--outline 8`) save against the clipped rectangles (`--outline
# 0`), counted by the forest's pipeline statistics (`forest --bench`:
# vertices and fragments shaded, alpha-discarded ones included). One tree
# (the built-in oak, seed 1, its cloud of 22 billboards at texres 256, as
# the demo forest's near level) stands alone on a procedural landscape with
# the terrain switched off (F4); the camera sees it at three sizes (about
# 130, 260 and 520 pixels tall: frames of 480, 960 and 1920 pixels); the
# sky's fragments (the same view without objects, F5) are taken off.
# Prints a Markdown table. Needs an OpenGL 4.5 context (EGL; llvmpipe here).
set -euo pipefail
build=${1:-build}
bin="$build/bin"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$bin/forest" --demo-terrain "$tmp" --terrain-size 512 --seed 1 > /dev/null
"$bin/bbcgen" tree --species oak --seed 1 -o "$tmp/oak.obj" > /dev/null
for o in 0 8; do
  "$bin/bbcgen" "$tmp/oak.obj" -o "$tmp/oak_$o.glb" --maxplanes 22 --minplanes 0 --texres 256 --outline "$o" \
    --report "$tmp/r$o.json" -q
  cat > "$tmp/one_$o.txt" << EOT
hmap heightmap.png
colmap colmap.png
heightscale 0.5
stretch 2
light 1 1 0.5
farclip 800
numobjs 1
object2d oak_$o.glb 1 1 512 512 0 0 0 0
EOT
done
count() { # MAP SIZE KEYS: "vertices fragments"
  "$bin/forest" "$1" --size "$2x$2" --camera 512,30,555,0,5 --keys "$3 2f" --bench 2> /dev/null |
    sed -n 's/^vertices=\([0-9]*\).* fragments=\([0-9]*\).*/\1 \2/p'
}
echo "| frame px | tree px (about) | vertices, outline 0 | vertices, outline 8 | fragments, outline 0 | fragments, outline 8 | outline 8 / 0 |"
echo "|---:|---:|---:|---:|---:|---:|---:|"
for size in 480 960 1920; do
  read -r _ sky < <(count "$tmp/one_0.txt" "$size" "F4 F5")
  read -r v0 f0 < <(count "$tmp/one_0.txt" "$size" "F4")
  read -r v8 f8 < <(count "$tmp/one_8.txt" "$size" "F4")
  python3 -c "
s, sky, v0, f0, v8, f8 = map(int, '$size $sky $v0 $f0 $v8 $f8'.split())
a, b = f0 - sky, f8 - sky
print('| %d | %d | %d | %d | %d | %d | %.3f |' % (s, round(s * 0.27), v0, v8, a, b, b / a))"
done
python3 - "$tmp/r0.json" "$tmp/r8.json" << 'PY'
import json, sys
t = [json.load(open(p))['lods'][0]['triangles'] for p in sys.argv[1:]]
print('\ntriangles of the cloud: outline 0 %d, outline 8 %d' % tuple(t))
PY
