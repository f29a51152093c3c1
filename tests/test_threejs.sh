#!/usr/bin/env bash
# test_threejs.sh BBCGEN — a material cloud relit in three.js: the Quaternius
# Tree_1 made into a cloud twice (the default material and --lighting baked),
# both drawn beside the original in headless Chromium under ambient 0.4 and
# a sun from 4 directions, front and side (scripts/studies/threejs_sun.sh). The
# material cloud's luminance must stay within 0.90-1.10 of the original's on
# every render; the baked one, drawn unlit, must not (it is 1.6-2.9x there).
# Exit 77 (skipped) without chromium, node or the npm packages.
set -euo pipefail
bbcgen=$1
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
orig="$here/../../shared/data/trees/quaternius/OBJ/Tree_1.obj"
[ -f "$orig" ] || { echo "skipped: $orig missing"; exit 77; }
command -v chromium > /dev/null || [ -n "${BBC_CHROMIUM:-}" ] ||
  { echo "skipped: no chromium (Debian: apt-get install chromium)"; exit 77; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$bbcgen" "$orig" -o "$tmp/material.glb" --texres 128 -q
"$bbcgen" "$orig" -o "$tmp/baked.glb" --texres 128 --lighting baked -q
rc=0
"$here/../scripts/studies/threejs_sun.sh" --suns 0:50,90:15,180:15,270:50 --size 192 \
  --json "$tmp/r.json" "$orig" "$tmp/material.glb" "$tmp/baked.glb" > "$tmp/out.txt" 2>&1 || rc=$?
cat "$tmp/out.txt"
[ "$rc" -ne 3 ] || { echo "skipped: three.js harness unavailable"; exit 77; }
[ "$rc" -eq 0 ] || { echo "FAIL: threejs_sun.sh exit $rc"; exit 1; }
python3 - "$tmp/r.json" << 'PY'
import json, sys
s = json.load(open(sys.argv[1]))["summary"]
m, b = s[0], s[1]
print("material %.3f-%.3f, baked %.3f-%.3f" % (m["lumRatio"]["min"], m["lumRatio"]["max"],
                                              b["lumRatio"]["min"], b["lumRatio"]["max"]))
assert m["renders"] == 8 and m["blank"] == 0
assert m["outside"] == 0, "the material cloud left 0.90-1.10"
assert b["lumRatio"]["min"] > 1.2, "the baked cloud should be too bright, drawn unlit"
PY
