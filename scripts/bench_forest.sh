#!/usr/bin/env bash
# bench_forest.sh — hands over to scripts/bench/bench_forest.sh (the command
# the developers' guide gives: make demo && scripts/bench_forest.sh build 24 1920x1080).
exec "$(dirname "$0")/bench/bench_forest.sh" "$@"
