#!/usr/bin/env bash
# setup.sh — checks the Debian packages that building and testing need and
# installs the missing ones (non-interactively) when run as root; otherwise
# prints the exact command to run and fails. Fast when everything is present.
#
#   scripts/dev/setup.sh [build|test|all|fuzz]    (default: all)
set -euo pipefail

what=${1:-all}
# (each list on one line: scripts/dev/fresh_machine.sh reads them)
build_pkgs=(build-essential cmake pkg-config libassimp-dev libstb-dev zlib1g-dev libcjson-dev libmeshoptimizer-dev libepoxy-dev libglfw3-dev libegl-dev libegl-mesa0 libgl1-mesa-dri libedit-dev)
test_pkgs=(libcmocka-dev clang-format nodejs chromium gltfpack assimp-utils parallel xvfb xauth time universal-ctags locales)
fuzz_pkgs=(clang libclang-rt-14-dev libomp-14-dev)

case "$what" in
  build) pkgs=("${build_pkgs[@]}") ;;
  test|all) pkgs=("${build_pkgs[@]}" "${test_pkgs[@]}") ;;
  fuzz) pkgs=("${build_pkgs[@]}" "${fuzz_pkgs[@]}") ;;
  *) echo "setup.sh: unknown target '$what' (build, test, all or fuzz)" >&2; exit 2 ;;
esac

missing=()
status=$(dpkg-query -W -f='${Package} ${db:Status-Abbrev}\n' "${pkgs[@]}" 2>/dev/null || true)
for p in "${pkgs[@]}"; do
  if ! grep -q "^$p ii" <<<"$status"; then missing+=("$p"); fi
done
# npm: part of some nodejs builds (NodeSource), a package of its own in Debian.
if { [ "$what" = test ] || [ "$what" = all ]; } && ! command -v npm > /dev/null; then missing+=(npm); fi
# A locale with a decimal comma, for the writers' locale test (test_load):
# made from the locales package's definitions when missing (as root).
comma_locale() {
  { [ "$what" = test ] || [ "$what" = all ]; } || return 0
  locale -a 2> /dev/null | grep -qi '^de_DE\.utf-\?8$' && return 0
  if [ "$(id -u)" -ne 0 ]; then
    echo "setup.sh: no de_DE.UTF-8 locale (test_load's locale test skips without it);" \
      "make it with:  sudo localedef -i de_DE -f UTF-8 de_DE.UTF-8" >&2
    return 0
  fi
  localedef -i de_DE -f UTF-8 de_DE.UTF-8 2> /dev/null ||
    echo "setup.sh: localedef de_DE.UTF-8 failed (test_load's locale test skips)" >&2
}
[ ${#missing[@]} -eq 0 ] && { comma_locale; exit 0; }

cmd="apt-get install -y --no-install-recommends ${missing[*]}"
if [ "$(id -u)" -ne 0 ]; then
  echo "setup.sh: missing Debian packages: ${missing[*]}" >&2
  echo "Install them with:  sudo apt-get update && sudo $cmd" >&2
  exit 1
fi
echo "setup.sh: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
log=$(mktemp)
trap 'rm -f "$log"' EXIT
# apt_get ARGS...: apt-get, quiet on success, that waits (up to 10 minutes)
# for the package manager's locks when another install or update runs
# instead of failing at once.
apt_get() {
  local waited=0
  while :; do
    if apt-get -o DPkg::Lock::Timeout=600 "$@" > "$log" 2>&1; then return 0; fi
    if grep -q 'Could not get lock\|Unable to lock\|is another process using it' "$log" &&
      [ $waited -lt 600 ]; then
      [ $waited -eq 0 ] && echo "setup.sh: the package manager is busy; waiting for it" >&2
      sleep 10
      waited=$((waited + 10))
      continue
    fi
    return 1
  done
}
# Update the package lists only when they are missing or older than a day.
if [ -z "$(find /var/lib/apt/lists -maxdepth 1 -name '*Packages*' -mmin -1440 2>/dev/null | head -1)" ]; then
  apt_get update -qq || { cat "$log" >&2; echo "setup.sh: apt-get update failed" >&2; exit 1; }
fi
# Quiet on success; the whole apt log on failure.
if ! apt_get install -y --no-install-recommends -qq "${missing[@]}"; then
  apt_get update -qq || true
  if ! apt_get install -y --no-install-recommends -qq "${missing[@]}"; then
    cat "$log" >&2
    echo "setup.sh: installing ${missing[*]} failed" >&2
    exit 1
  fi
fi
echo "setup.sh: installed ${missing[*]}" >&2
comma_locale
