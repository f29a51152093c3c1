#!/usr/bin/env bash
# gltf_validate.sh FILE... — validates glTF 2.0 files (.gltf or .glb) with the
# Khronos glTF validator (npm package gltf-validator), installed on first use
# into $BBC_GLTF_VALIDATOR_DIR (default: $HOME/.cache/bbc-gltf-validator).
# Prints "FILE: N errors, M warnings" per file, with every error and warning.
# Exit status: 0 no errors, 1 some file has errors, 3 the validator is
# unavailable (no node/npm, or the install failed: no network).
set -euo pipefail

# The newest release is a prerelease (2.0.0-dev.3.x), which `gltf-validator@2`
# would not match, so the version is pinned.
version=2.0.0-dev.3.10
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
dir=${BBC_GLTF_VALIDATOR_DIR:-${HOME:-/tmp}/.cache/bbc-gltf-validator}

[ $# -gt 0 ] || { echo "usage: gltf_validate.sh FILE..." >&2; exit 2; }
if ! command -v node > /dev/null || ! command -v npm > /dev/null; then
  echo "gltf_validate.sh: node and npm are needed (Debian: apt-get install nodejs npm)" >&2
  exit 3
fi

pkg="$dir/node_modules/gltf-validator/package.json"
if [ ! -f "$pkg" ] || ! grep -q "\"version\": \"$version\"" "$pkg"; then
  mkdir -p "$(dirname "$dir")"
  tmp=$(mktemp -d "$dir.tmp.XXXXXX")
  trap 'rm -rf "$tmp"' EXIT
  echo "gltf_validate.sh: installing gltf-validator@$version into $dir" >&2
  if ! timeout 300 npm install --prefix "$tmp" --no-audit --no-fund --loglevel=error \
      "gltf-validator@$version" > "$tmp.log" 2>&1; then
    cat "$tmp.log" >&2
    rm -f "$tmp.log"
    echo "gltf_validate.sh: cannot install gltf-validator (no network?)" >&2
    exit 3
  fi
  rm -f "$tmp.log"
  # Another process may have installed it meanwhile: then keep that one.
  if [ ! -f "$pkg" ] || ! grep -q "\"version\": \"$version\"" "$pkg"; then
    rm -rf "$dir"
    mv "$tmp" "$dir" || true
  fi
fi

exec node "$here/gltf_validate.mjs" "$dir" "$@"
