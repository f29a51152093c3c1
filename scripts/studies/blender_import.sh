#!/usr/bin/env bash
# blender_import.sh FILE... — what Blender's importers make of each file
# (objects, triangles, materials, textures, alpha): one JSON line per file,
# from scripts/studies/blender_import.py. Needs Debian's blender (and python3-numpy
# for glTF). Exit status: 0 ok, 3 blender missing, 4 Blender failed.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
command -v blender > /dev/null || {
  echo "blender_import.sh: no blender (Debian: apt-get install blender python3-numpy)" >&2
  exit 3
}
files=()
for f in "$@"; do files+=("$(realpath "$f")"); done
blender -b --factory-startup --python-exit-code 4 --python "$here/blender_import.py" \
  -- "${files[@]}" 2> /dev/null | sed -n 's/^BBC_IMPORT //p'
