#!/usr/bin/env bash
# fresh_machine.sh — proves the README's two commands work on a machine that
# has none of the project's packages: removes every package scripts/dev/setup.sh
# installs (its build and test lists, and what only they pulled in), then runs
# `make demo` from a fresh clone, removes them again, and runs `make test`
# from another fresh clone. Prints each command's wall time.
#
#   sudo scripts/dev/fresh_machine.sh [--demo-only]
#
# Root only (it removes and installs Debian packages), and it really removes
# them: run it on a scratch machine or a CI runner, not on a workstation you
# depend on. ../shared must be beside the repository (the tests use it).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
demo_only=0
[ "${1:-}" = --demo-only ] && demo_only=1
if [ "$(id -u)" -ne 0 ]; then
  echo "fresh_machine.sh: must run as root (it removes and installs packages)" >&2
  exit 2
fi
command -v git > /dev/null || { echo "fresh_machine.sh: needs git" >&2; exit 2; }

# The package lists, read from setup.sh itself so they cannot drift apart.
# shellcheck disable=SC1090
eval "$(grep -E '^(build_pkgs|test_pkgs)=' "$here/scripts/dev/setup.sh")"
pkgs=("${build_pkgs[@]}" "${test_pkgs[@]}" npm)

strip() {
  local present=()
  for p in "${pkgs[@]}"; do
    dpkg-query -W -f='${db:Status-Abbrev}' "$p" 2> /dev/null | grep -q '^ii' && present+=("$p")
  done
  echo "== removing: ${present[*]:-(none installed)}"
  export DEBIAN_FRONTEND=noninteractive
  if [ ${#present[@]} -gt 0 ]; then
    apt-get remove --purge -y -qq "${present[@]}" > /dev/null
  fi
  # What only they had pulled in (compilers, libraries, cmake's helpers).
  apt-get autoremove --purge -y -qq > /dev/null
  for tool in cc gcc cmake pkg-config clang-format gltfpack assimp; do
    if command -v "$tool" > /dev/null; then echo "   still there: $tool ($(command -v "$tool"))"; fi
  done
  rm -rf "${HOME:-/root}/.cache/bbc-gltf-validator"
}

fresh_clone() {
  local d
  d=$(mktemp -d /tmp/bbc-fresh.XXXXXX)
  git clone -q "$here" "$d/p"
  if [ -d "$here/../shared" ]; then ln -s "$(cd "$here/../shared" && pwd)" "$d/shared"; fi
  echo "$d/p"
}

timed() { # timed LABEL DIR COMMAND...
  local label=$1 dir=$2
  shift 2
  local t0 t1 rc=0
  t0=$(date +%s.%N)
  (cd "$dir" && "$@") > "$dir/../$label.log" 2>&1 || rc=$?
  t1=$(date +%s.%N)
  printf '== %s: exit %d in %.0f s (log: %s)\n' "$label" "$rc" "$(echo "$t1 - $t0" | bc)" \
    "$dir/../$label.log"
  if [ "$rc" -ne 0 ]; then tail -30 "$dir/../$label.log"; fi
  return "$rc"
}

command -v bc > /dev/null || apt-get install -y -qq bc > /dev/null
strip
p=$(fresh_clone)
timed make_demo "$p" make demo
ls "$p/build/demo" | sed 's/^/   /' | head -40
[ "$demo_only" = 1 ] && exit 0
strip
p=$(fresh_clone)
timed make_test "$p" make test
grep -E 'tests passed|tests failed' "$p/../make_test.log" | sed 's/^/   /'
