#!/usr/bin/env bash
# fuzz.sh — builds the libFuzzer harnesses (fuzz/, clang, ASan + UBSan) in
# build-fuzz and runs each for FUZZ_SECONDS (default 60), with a corpus kept
# outside the repository ($FUZZ_DIR, default ~/.cache/bbc-fuzz) seeded from
# small files of ../shared/data and generated inputs (scripts/dev/fuzz_seeds.sh),
# a dictionary per text format (fuzz/*.dict), 2 s at most per input and a
# 2 GB memory limit. Prints per harness executions, coverage (features) and
# crashes; a crash, hang or leak is saved in $FUZZ_DIR/NAME/artifacts and
# the script exits 1 naming it (copy it to tests/fuzz/NAME/ as a regression
# input: tests/test_fuzz_replay.c replays those in `make test`).
#
#   scripts/dev/fuzz.sh [HARNESS...]      (default: all)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${FUZZ_BUILD:-$root/build-fuzz}
secs=${FUZZ_SECONDS:-60}
dir=${FUZZ_DIR:-${HOME:-/tmp}/.cache/bbc-fuzz}
# ours; then Assimp's formats through our mesh building (crashes inside
# Assimp are Debian's libassimp's: `make fuzz` runs them, CI does not)
all=(fuzz_ply fuzz_xyz fuzz_wrl fuzz_forest_map fuzz_forest_model fuzz_batch fuzz_scene fuzz_objr fuzz_obj fuzz_3ds fuzz_glb)
harnesses=("$@")
[ ${#harnesses[@]} -eq 0 ] && harnesses=("${all[@]}")
command -v clang > /dev/null || { echo "fuzz.sh: clang is needed (scripts/dev/setup.sh fuzz)" >&2; exit 3; }
if [ -f "$build/CMakeCache.txt" ] && [ ! -f "$build/Makefile" ]; then rm -rf "$build/CMakeCache.txt" "$build/CMakeFiles"; fi
cmake -S "$root" -B "$build" -DCMAKE_C_COMPILER=clang -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DBBC_FUZZ=ON -DBBC_BUILD_TESTS=OFF -DBBC_BUILD_BENCH=OFF > /dev/null
cmake --build "$build" -j "$(nproc)" --target "${harnesses[@]}" > /dev/null
"$root/scripts/dev/fuzz_seeds.sh" "$dir"
status=0
printf '%-18s %12s %10s %8s %s\n' harness executions features crashes artifacts
for h in "${harnesses[@]}"; do
  corpus="$dir/$h/corpus"
  art="$dir/$h/artifacts"
  mkdir -p "$corpus" "$art"
  dict=""
  case "$h" in
    fuzz_ply) dict="$root/fuzz/ply.dict" ;;
    fuzz_wrl) dict="$root/fuzz/vrml.dict" ;;
    fuzz_forest_map|fuzz_forest_model) dict="$root/fuzz/forest.dict" ;;
    fuzz_batch) dict="$root/fuzz/batch.dict" ;;
  esac
  log="$dir/$h/last.log"
  before=$(find "$art" -type f | wc -l)
  set +e
  LSAN_OPTIONS=suppressions="$root/fuzz/lsan.supp" \
  ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1 \
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    "$build/bin/$h" "$corpus" "$dir/$h/seeds" ${dict:+-dict="$dict"} -max_total_time="$secs" \
    -timeout=2 -rss_limit_mb=2048 -malloc_limit_mb=1024 -max_len=65536 \
    -artifact_prefix="$art/" -print_final_stats=1 > "$log" 2>&1
  rc=$?
  set -e
  execs=$(awk '/number_of_executed_units/{print $NF}' "$log" | tail -1 || true)
  feats=$(grep -o 'ft: [0-9]*' "$log" | tail -1 | awk '{print $2}' || true)
  found=$(( $(find "$art" -type f | wc -l) - before )) # this run's
  printf '%-18s %12s %10s %8s %s\n' "$h" "${execs:-?}" "${feats:-?}" "$found" "$art"
  if [ "$rc" -ne 0 ] || [ "$found" -ne 0 ]; then
    status=1
    echo "fuzz.sh: $h found something (exit $rc): $art, log $log" >&2
    grep -m 3 -E 'ERROR|runtime error|SUMMARY' "$log" >&2 || true
  fi
done
exit $status
