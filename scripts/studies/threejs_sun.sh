#!/usr/bin/env bash
# threejs_sun.sh [options] ORIGINAL CLOUD [CLOUD...] — renders ORIGINAL and
# each CLOUD in three.js (headless Chromium, WebGL2 on SwiftShader) under the
# same camera, ambient light and a white directional "sun" from several
# directions, and reports how bright each cloud looks relative to the
# original (mean sRGB colour and luminance of the covered pixels). See
# threejs_sun.mjs for the options, the method and the output.
#
# Needs node, npm and Chromium (Debian: apt-get install nodejs npm chromium;
# another binary via $BBC_CHROMIUM). The npm packages three and puppeteer-core
# are installed on first use into $BBC_THREEJS_DIR (default:
# $HOME/.cache/bbc-threejs).
# Exit status: 0 success, 1 bad command line, 2 missing file, 3 tools
# unavailable (no node/npm/chromium, or the install failed: no network),
# 4 a render failed (load error, blank original).
set -euo pipefail

# Pinned: three's examples/jsm loaders change between releases, and
# puppeteer-core 25 needs node >= 22 (Debian 12/13 ship node 18/20).
three_version=0.181.0
puppeteer_version=24.43.1
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
dir=${BBC_THREEJS_DIR:-${HOME:-/tmp}/.cache/bbc-threejs}
chromium=${BBC_CHROMIUM:-}

usage() {
  echo "usage: threejs_sun.sh [--suns sweep|AZ:EL,...] [--views front,side] [--elevation DEG]" >&2
  echo "         [--size PX] [--fov DEG] [--ambient I] [--sun-intensity I] [--json OUT.json]" >&2
  echo "         [--keep DIR] [--timeout S] ORIGINAL CLOUD [CLOUD...]" >&2
}
case "${1:-}" in
  -h|--help) usage; exit 0 ;;
  '') usage; exit 1 ;;
esac

if ! command -v node > /dev/null || ! command -v npm > /dev/null; then
  echo "threejs_sun.sh: node and npm are needed (Debian: apt-get install nodejs npm)" >&2
  exit 3
fi
if [ -z "$chromium" ]; then
  for c in /usr/bin/chromium /usr/bin/chromium-browser /usr/bin/google-chrome; do
    if [ -x "$c" ]; then chromium=$c; break; fi
  done
fi
if [ -z "$chromium" ] || [ ! -x "$chromium" ]; then
  echo "threejs_sun.sh: Chromium is needed (Debian: apt-get install chromium; or set BBC_CHROMIUM)" >&2
  exit 3
fi

installed() {  # installed NAME VERSION: is that version under $dir?
  local pkg="$dir/node_modules/$1/package.json"
  [ -f "$pkg" ] && grep -q "\"version\": \"$2\"" "$pkg"
}
if ! installed three "$three_version" || ! installed puppeteer-core "$puppeteer_version"; then
  mkdir -p "$(dirname "$dir")"
  tmp=$(mktemp -d "$dir.tmp.XXXXXX")
  trap 'rm -rf "$tmp"' EXIT
  echo "threejs_sun.sh: installing three@$three_version puppeteer-core@$puppeteer_version into $dir" >&2
  # PUPPETEER_SKIP_DOWNLOAD: puppeteer-core downloads no browser anyway; the
  # variable also keeps any postinstall from trying.
  if ! PUPPETEER_SKIP_DOWNLOAD=1 timeout 300 npm install --prefix "$tmp" --no-audit --no-fund \
      --loglevel=error "three@$three_version" "puppeteer-core@$puppeteer_version" > "$tmp.log" 2>&1; then
    cat "$tmp.log" >&2
    rm -f "$tmp.log"
    echo "threejs_sun.sh: cannot install three/puppeteer-core (no network?)" >&2
    exit 3
  fi
  rm -f "$tmp.log"
  # Another process may have installed them meanwhile: then keep that one.
  if ! installed three "$three_version" || ! installed puppeteer-core "$puppeteer_version"; then
    rm -rf "$dir"
    mv "$tmp" "$dir" || true
  fi
fi

# The .mjs resolves puppeteer-core from $dir itself (createRequire) and
# serves three's ES modules from $dir/node_modules/three to the page through
# an import map; NODE_PATH is set too for anything else it may import.
export NODE_PATH="$dir/node_modules${NODE_PATH:+:$NODE_PATH}"
exec node "$here/threejs_sun.mjs" "$dir" "$chromium" "$@"
