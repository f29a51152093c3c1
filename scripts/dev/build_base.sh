#!/usr/bin/env bash
# build_base.sh REV DIR — bbcgen as it was at commit REV, built (Release)
# into DIR for the benchmarks that measure against an older binary
# (bench_speed.sh, bench_classes.sh); prints the binary's path.
set -euo pipefail
rev=$1
dir=$2
root=$(cd "$(dirname "$0")/../.." && pwd)
echo "building $rev as the older binary" >&2
mkdir -p "$dir/src"
git -C "$root" archive "$rev" | tar -x -C "$dir/src"
cmake -S "$dir/src" -B "$dir/build" -DCMAKE_BUILD_TYPE=Release -DBBC_BUILD_TESTS=OFF \
  -DBBC_BUILD_BENCH=OFF > /dev/null
cmake --build "$dir/build" -j "$(nproc)" --target bbcgen > /dev/null
echo "$dir/build/bin/bbcgen"
