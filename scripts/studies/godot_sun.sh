#!/usr/bin/env bash
# godot_sun.sh [--suns sweep|headlight|AZ:EL,...] [--views front,side] [--size PX]
#              [--ambient I] [--json OUT.json] [--keep DIR] ORIGINAL CLOUD [CLOUD...]
# — ORIGINAL and each CLOUD drawn by Godot 3 (Debian godot3, GLES3 on Mesa
# under Xvfb) as its importer makes them, under the same camera, an ambient
# light and a DirectionalLight "sun" of energy 1 from each direction (sweep:
# 8 azimuths x elevations 15 and 50), and each cloud's luminance and
# saturation over the covered pixels against the original's (the same
# statistics as scripts/studies/threejs_sun.sh; the table is printed, --json keeps
# every figure).
#
# An .obj ORIGINAL is first written as glTF by `bbcgen baseline --method
# simplify` with every triangle kept (its MTL materials as metallic-roughness,
# roughness from Ns, bbcgen's loader's rule): Godot 3.2's OBJ importer reads
# Ks as metallic, so the original is drawn in the clouds' material model.
# What the importer keeps (alpha MASK -> alpha scissor, double-sided, normal
# map, occlusion map on the ambient light only; KHR_materials_unlit and
# MSFT_lod ignored): docs/lighting.md.
#
# The models are drawn into a Viewport of their own with a transparent
# background: covered pixels are those with alpha > 0.
# Godot 3.2.3's `--editor --quit` crashes at exit, so the editor imports the
# models in the background until every imported scene is there, and is then
# stopped. Needs godot3, xvfb (xvfb-run), python3 with PIL and numpy (Debian:
# godot3 xvfb python3-pil python3-numpy) and build/bin/bbcgen for an .obj
# original. Exit status: 0 done, 1 bad command line, 2 missing file, 3 tools
# missing, 4 an import or a render failed.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
bbcgen=${BBCGEN:-$here/../../build/bin/bbcgen}
suns=sweep views=front,side size=256 ambient=0.4 json= keep=
files=()
while [ $# -gt 0 ]; do
  case $1 in
    --suns) suns=$2; shift 2 ;;
    --views) views=$2; shift 2 ;;
    --size) size=$2; shift 2 ;;
    --ambient) ambient=$2; shift 2 ;;
    --json) json=$2; shift 2 ;;
    --keep) keep=$2; shift 2 ;;
    -h|--help) sed -n '2,26p' "$0"; exit 0 ;;
    -*) echo "godot_sun.sh: unknown option $1" >&2; exit 1 ;;
    *) files+=("$1"); shift ;;
  esac
done
[ ${#files[@]} -ge 2 ] || { echo "usage: godot_sun.sh [options] ORIGINAL CLOUD [CLOUD...]" >&2; exit 1; }
for f in "${files[@]}"; do [ -f "$f" ] || { echo "godot_sun.sh: $f: no such file" >&2; exit 2; }; done
for t in godot3 xvfb-run python3; do
  command -v $t > /dev/null || { echo "godot_sun.sh: $t is needed (Debian: godot3 xvfb python3-pil python3-numpy)" >&2; exit 3; }
done
# Debian's python3 (its PIL and numpy), before any other on the PATH
py=python3
[ -x /usr/bin/python3 ] && py=/usr/bin/python3
$py -c 'import PIL, numpy' 2> /dev/null || { echo "godot_sun.sh: python3 PIL and numpy are needed (Debian: python3-pil python3-numpy)" >&2; exit 3; }
if [ "$suns" = sweep ]; then
  suns=
  for el in 15 50; do for az in 0 45 90 135 180 225 270 315; do suns+="${suns:+,}$az:$el"; done; done
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
proj=$work/p
mkdir -p "$proj/out"
printf 'config_version=4\n[application]\nconfig/name="bbc_godot_sun"\n[rendering]\nquality/driver/driver_name="GLES3"\n' > "$proj/project.godot"
cp "$here/godot_sun.gd" "$proj/"
i=0
for f in "${files[@]}"; do
  case ${f,,} in
    *.obj)
      [ -x "$bbcgen" ] || { echo "godot_sun.sh: $bbcgen is needed for an .obj original (make)" >&2; exit 3; }
      "$bbcgen" baseline "$f" -o "$proj/m$i.glb" --method simplify --triangles 2000000000 -q ;;
    *.glb) cp "$f" "$proj/m$i.glb" ;;
    *) echo "godot_sun.sh: $f: .obj or .glb" >&2; exit 1 ;;
  esac
  i=$((i + 1))
done
n=$i

# Import: the editor in the background until each m<i>.glb has its scene.
xvfb-run -a godot3 --path "$proj" --editor > "$work/import.log" 2>&1 &
ed=$!
imported() {
  for k in $(seq 0 $((n - 1))); do
    compgen -G "$proj/.import/m$k.glb-*.scn" > /dev/null || return 1
  done
}
for _ in $(seq 1 600); do
  imported && break
  kill -0 $ed 2> /dev/null || break
  sleep 1
done
sleep 2
pkill -P $ed 2> /dev/null || true
kill $ed 2> /dev/null || true
wait $ed 2> /dev/null || true
pkill -f "godot3 --path $proj --editor" 2> /dev/null || true
imported || { cat "$work/import.log" >&2; echo "godot_sun.sh: the editor did not import every model" >&2; exit 4; }

if ! timeout 900 xvfb-run -a -s "-screen 0 ${size}x${size}x24" godot3 --path "$proj" -s res://godot_sun.gd -- \
    "$size" 30 "$ambient" "$n" "$suns" "$views" > "$work/render.log" 2>&1; then
  cat "$work/render.log" >&2
  echo "godot_sun.sh: the render failed" >&2
  exit 4
fi
[ -z "$keep" ] || { mkdir -p "$keep"; cp "$proj"/out/*.png "$keep/"; }

$py - "$proj/out" "$n" "$suns" "$views" "$json" "${files[@]}" <<'PY'
import json, sys
import numpy as np
from PIL import Image
out, n, suns, views, jpath = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4].split(','), sys.argv[5]
files = sys.argv[6:]
suns = ['head_light'] if suns == 'headlight' else ['az%s_el%s' % tuple(s.split(':')) for s in suns.split(',')]
def stats(p):
    a = np.asarray(Image.open(p).convert('RGBA')).astype(float)
    m = a[..., 3] > 0
    if not m.any():
        return None
    rgb = a[..., :3][m]
    r, g, b = rgb.mean(0)
    return {'covered': int(m.sum()), 'r': r, 'g': g, 'b': b, 'lum': 0.2126 * r + 0.7152 * g + 0.0722 * b,
            'sat': float((rgb.max(1) - rgb.min(1)).mean())}
rows, bad = [], 0
for v in views:
    for s in suns:
        st = [stats('%s/m%d_%s_%s.png' % (out, k, v, s)) for k in range(n)]
        if st[0] is None:
            print('godot_sun.sh: the original covers no pixel in %s %s' % (v, s), file=sys.stderr)
            sys.exit(4)
        rows.append({'view': v, 'sun': s, 'original': st[0], 'clouds': [
            None if c is None else dict(c, lumRatio=c['lum'] / st[0]['lum'],
                                        satRatio=c['sat'] / st[0]['sat'] if st[0]['sat'] else None,
                                        coverageRatio=c['covered'] / st[0]['covered']) for c in st[1:]]})
print('original %s' % files[0])
for k, f in enumerate(files[1:]):
    print('cloud%d   %s' % (k, f))
print('view   sun            orig lum  ' + '  '.join('cloud%d' % k for k in range(n - 1)))
for r in rows:
    print('%-6s %-14s %8.1f  ' % (r['view'], r['sun'], r['original']['lum']) +
          '  '.join('  -   ' if c is None else '%6.3f' % c['lumRatio'] for c in r['clouds']))
summary = []
for k in range(n - 1):
    lr = [r['clouds'][k]['lumRatio'] if r['clouds'][k] else None for r in rows]
    sr = [r['clouds'][k]['satRatio'] if r['clouds'][k] else None for r in rows]
    v = [x for x in lr if x is not None]
    sv = [x for x in sr if x is not None]
    s = {'file': files[k + 1], 'min': min(v) if v else None, 'max': max(v) if v else None,
         'outside': sum(1 for x in lr if x is None or x < 0.9 or x > 1.1), 'renders': len(lr),
         'satMin': min(sv) if sv else None, 'satMax': max(sv) if sv else None}
    summary.append(s)
    print('cloud%d: min %.3f max %.3f outside %d/%d (0.90-1.10); saturation ratio %.3f-%.3f' %
          (k, s['min'] or 0, s['max'] or 0, s['outside'], s['renders'], s['satMin'] or 0, s['satMax'] or 0))
if jpath:
    json.dump({'tool': 'godot_sun', 'files': files, 'renders': rows, 'summary': summary}, open(jpath, 'w'), indent=1)
PY
