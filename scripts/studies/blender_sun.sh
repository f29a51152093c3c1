#!/usr/bin/env bash
# blender_sun.sh [options] ORIGINAL CLOUD... — renders ORIGINAL and each
# Billboard Cloud in Blender EEVEE (headless, under Xvfb) under the same sun
# and camera and reports how bright each cloud looks relative to the
# original. Options and figures: see scripts/studies/blender_sun.py (its header).
# Needs Debian's blender (3.4), python3-numpy (the glTF importer) and xvfb.
# Exit status: 0 ok, 1 bad command line, 2 missing file, 3 tools missing,
# 4 render/import failure.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
missing=()
command -v blender > /dev/null || missing+=(blender)
command -v xvfb-run > /dev/null || missing+=(xvfb)
if [ ${#missing[@]} -gt 0 ]; then
  echo "blender_sun.sh: missing ${missing[*]}" \
    "(Debian: apt-get install blender python3-numpy xvfb)" >&2
  exit 3
fi
exec xvfb-run -a blender -b --factory-startup --python-exit-code 4 \
  --python "$here/blender_sun.py" -- "$@"
