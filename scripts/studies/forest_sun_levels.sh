#!/usr/bin/env bash
# forest_sun_levels.sh OUT [BUILD] — issue 33's brightness table: each tree
# of scripts/studies/data_trees.sh and its default LOD chain (bbcgen ORIGINAL
# --lod-files: material clouds at 512, 128 and 32 px), drawn by `forest`
# alone at the same spot under the same sun, its polygon level and each
# cloud level, seen from four sides (160 x 160 px, the tree scaled to a
# radius of 12 units, 18 units away), under 8 sun azimuths at elevations 15
# and 40 degrees. Writes OUT/sun_levels.md: per tree and level the range of
# the level's mean brightness (Rec. 709 luminance of the pixels the tree
# covers, the four views together) over the polygon level's, and how many
# of the 16 suns fall outside 0.90-1.10.
#
#   --polygon-no-mipmaps   the polygon level drawn without mip levels (a
#                          texture atlas whose mip levels mix its regions,
#                          like the Scopia trees', brightens it)
#   --only NAME,...        only these trees (as lod_chain.sh and sun_sweep.sh)
set -euo pipefail
nomip=0
only=
args=()
while [ $# -gt 0 ]; do
  case $1 in
    --polygon-no-mipmaps) nomip=1; shift ;;
    --only) only=$2; shift 2 ;;
    *) args+=("$1"); shift ;;
  esac
done
out=${args[0]:?usage: forest_sun_levels.sh [--only NAME,...] [--polygon-no-mipmaps] OUT [BUILD]}
build=${args[1]:-build}
here=$(cd "$(dirname "$0")" && pwd)
bin=$(cd "$build/bin" && pwd)
data=$(cd "${BBC_DATA:-$here/../../../shared/data}" && pwd)
mkdir -p "$out"
out=$(cd "$out" && pwd)
py=/usr/bin/python3
"$py" -c 'import numpy, PIL' 2>/dev/null || { echo "needs python3-numpy and python3-pil" >&2; exit 1; }
"$py" - > "$out/flat.png.tmp" <<'PY'
import sys, io
from PIL import Image
b = io.BytesIO(); Image.new('RGB', (65, 65), (0, 0, 0)).save(b, 'PNG'); sys.stdout.buffer.write(b.getvalue())
PY
mv "$out/flat.png.tmp" "$out/flat.png"
cams="128,6,146,0,0 146,6,128,-90,0 128,6,110,180,0 110,6,128,90,0"
# the sun turned by 45 degrees (3 presses of 15) between the 8 shots
keys() {
  local k="shot:$1_0.png" a
  for a in 1 2 3 4 5 6 7; do k="$k right right right shot:$1_$a.png"; done
  echo "$k"
}
"$here/data_trees.sh" "$data" "$out/gen" "$bin/bbcgen" | while IFS=$'\t' read -r name orig; do
  [ -z "$only" ] || [[ ",$only," == *",$name,"* ]] || continue
  d="$out/$name"
  mkdir -p "$d"
  [ -s "$d/chain_LOD2.glb" ] || "$bin/bbcgen" "$orig" -o "$d/chain.glb" --lod-files -q
  cp "$out/flat.png" "$d/flat.png"
  # the tree scaled to a radius of 12 units (forest's log gives its radius)
  mip=mipmap
  [ $nomip = 1 ] && mip=
  printf 'LOD ( file1 "%s" lighting %s min 0 max 1000 )\n' "$orig" "$mip" > "$d/l0.txt"
  printf 'hmap flat.png\nstretch 4\nobject2d l0.txt 1 1 128 128 0 0 0 0\n' > "$d/probe.txt"
  "$bin/forest" "$d/probe.txt" --size 16x16 --log "$d/probe.log" > /dev/null
  radius=$(sed -n 's/.*radius \([0-9.e+-]*\).*/\1/p' "$d/probe.log" | head -1)
  scale=$(awk -v r="$radius" 'BEGIN { printf "%.6g", 12 / r }')
  for l in 0 1 2 3; do
    [ $l -gt 0 ] && printf 'LOD ( file1 chain_LOD%d.glb mipmap min 0 max 1000 )\n' $((l - 1)) > "$d/l$l.txt"
    flag=1
    [ $l = 0 ] && [ $nomip = 1 ] && flag=0
    printf 'hmap flat.png\nstretch 4\nobject2d l%d.txt %s %d 128 128 0 0 0 0\n' $l "$scale" $flag \
      > "$d/m$l.txt"
  done
  printf 'hmap flat.png\nstretch 4\n' > "$d/m4.txt"
  for el in 15 40; do
    c=0
    for cam in $cams; do
      for m in 0 1 2 3 4; do
        "$bin/forest" "$d/m$m.txt" --size 160x160 --camera "$cam" --sun 0,$el \
          --keys "$(keys "$d/s_${el}_${c}_$m")" --log /dev/null > /dev/null
      done
      c=$((c + 1))
    done
  done
  echo "$name: drawn" >&2
done
"$py" - "$out" "$nomip" <<'PY' > "$out/sun_levels.md"
import sys, os, glob
import numpy as np
from PIL import Image
out = sys.argv[1]
print("# forest: cloud levels against the polygon level under one sun\n")
if sys.argv[2] == '1':
    print("The polygon level drawn without mip levels (`--polygon-no-mipmaps`).\n")
print("`scripts/studies/forest_sun_levels.sh OUT`: mean brightness of each level of the default chain "
      "(512, 128, 32 px) over the polygon level's, 4 views, 8 azimuths x elevations 15 and 40 "
      "(16 suns); outside = suns outside 0.90-1.10.\n")
print("| tree | LOD0 (512 px) | LOD1 (128 px) | LOD2 (32 px) | outside (of 16, per level) |")
print("|---|---|---|---|---|")
def lum(p, e):
    a = np.asarray(Image.open(p).convert('RGB')).astype(float)
    b = np.asarray(Image.open(e).convert('RGB')).astype(float)
    m = np.abs(a - b).max(axis=2) > 6
    y = 0.2126 * a[..., 0] + 0.7152 * a[..., 1] + 0.0722 * a[..., 2]
    return y[m].sum(), m.sum()
for d in sorted(glob.glob(os.path.join(out, '*', 'm0.txt'))):
    d = os.path.dirname(d); name = os.path.basename(d)
    ratios = [[], [], []]
    for el in (15, 40):
        for a in range(8):
            s = np.zeros((4, 2))
            for c in range(4):
                for m in range(4):
                    s[m] += lum(f'{d}/s_{el}_{c}_{m}_{a}.png', f'{d}/s_{el}_{c}_4_{a}.png')
            base = s[0, 0] / s[0, 1]
            for m in range(1, 4):
                ratios[m - 1].append(s[m, 0] / s[m, 1] / base)
    cells = ['%.3f-%.3f' % (min(r), max(r)) for r in ratios]
    outside = ' / '.join(str(sum(1 for x in r if abs(x - 1) > 0.10)) for r in ratios)
    print(f'| {name} | ' + ' | '.join(cells) + f' | {outside} |')
PY
echo "wrote $out/sun_levels.md"
