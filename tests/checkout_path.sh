#!/usr/bin/env bash
# checkout_path.sh SOURCE_DIR — a checkout in a folder whose path holds a
# folder named src, spaces and non-ASCII letters (~/src/my trees/bäume)
# configures, builds two layers of the library, and passes the checks that
# read paths (scripts/dev/layers.sh on that build's object files,
# scripts/dev/code_size.sh). The tracked and untracked files of SOURCE_DIR's
# working tree are copied (git ls-files); exit 77 (skipped) without git.
set -euo pipefail
src=$(cd "$1" && pwd)
command -v git > /dev/null && git -C "$src" rev-parse --is-inside-work-tree > /dev/null 2>&1 ||
  { echo "checkout_path: no git work tree at $src: skipped"; exit 77; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
dir="$tmp/src/my trees/bäume é"
mkdir -p "$dir/p"
(cd "$src" && git ls-files -z -co --exclude-standard | tar --null -T - -cf -) | (cd "$dir/p" && tar -xf -)
build="$dir/build dir"
cmake -S "$dir/p" -B "$build" -DCMAKE_BUILD_TYPE=Release -DBBC_WERROR=ON -DBBC_REQUIRE_TESTS=OFF \
  > "$tmp/configure.log" 2>&1 || { cat "$tmp/configure.log"; exit 1; }
cmake --build "$build" --target bbc_base bbc_raster -j 2 > "$tmp/build.log" 2>&1 ||
  { tail -30 "$tmp/build.log"; exit 1; }
n=$(find "$build/CMakeFiles" -name '*.c.o' | wc -l)
[ "$n" -gt 0 ] || { echo "checkout_path: no object files built under $build"; exit 1; }
bash "$dir/p/scripts/dev/layers.sh" check "$build"
bash "$dir/p/scripts/dev/code_size.sh" > /dev/null
echo "checkout_path: $n objects built and checked under $dir"
