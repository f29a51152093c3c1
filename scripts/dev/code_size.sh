#!/usr/bin/env bash
# code_size.sh — how long the functions and files of src/ are, measured with
# universal-ctags' function extents (first to last line, comments above not
# counted), and whether they keep the project's limits: no function over 150
# lines, at most 15 over 100, no source file over 1,000 lines; the README at
# most 400 lines.
#
#   scripts/dev/code_size.sh [--list N] [SRC_DIR]   report; exit 1 when a limit
#                                              is broken. --list N: the N
#                                              longest functions too.
#   scripts/dev/code_size.sh --table [SRC_DIR]      today's figures as the
#                                              markdown table of
#                                              docs/architecture.md
#   scripts/dev/code_size.sh --check-doc [SRC_DIR]  exit 1 when that table in
#                                              docs/architecture.md (between
#                                              its code_size markers) is not
#                                              today's (make docs rewrites it)
#   scripts/dev/code_size.sh --write-doc [SRC_DIR]  rewrites it
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
list=0
mode=report
case "${1:-}" in
  --list) list=$2; shift 2 ;;
  --table|--check-doc|--write-doc) mode=${1#--}; shift ;;
esac
src=${1:-$root/src}
command -v ctags > /dev/null || { echo "code_size.sh: needs universal-ctags" >&2; exit 2; }
ctags --version | grep -q Universal || { echo "code_size.sh: needs universal-ctags" >&2; exit 2; }

lengths=$(ctags --fields=+ne --kinds-C=f -o - -R "$src" |
  awk -F'\t' '{ ln = en = 0
    for (i = 4; i <= NF; i++) { if ($i ~ /^line:/) ln = substr($i, 6); if ($i ~ /^end:/) en = substr($i, 5) }
    if (en) print en - ln + 1, $2, $1 }' | sed "s#$src/##" | sort -rn)
over150=$(awk '$1 > 150' <<<"$lengths" | wc -l)
over100=$(awk '$1 > 100' <<<"$lengths" | wc -l)
functions=$(wc -l <<<"$lengths")
files=$(find "$src" -name '*.[ch]' -exec wc -l {} + | grep -v ' total$' | sort -rn)
bigfiles=$(awk '$1 > 1000' <<<"$files" | wc -l)
readme=$(wc -l < "$root/README.md")

# table: the limits' figures as markdown rows (not the function count or the
# README's length, which change with most commits).
table() {
  local lf lfile
  lf=$(head -1 <<<"$lengths")
  lfile=$(head -1 <<<"$files" | sed "s#$src/##")
  printf '| figure | today (scripts/dev/code_size.sh --table) | limit |\n|---|---:|---:|\n'
  printf '| functions over 150 lines | %s | 0 |\n' "$over150"
  printf '| functions over 100 lines | %s | 15 |\n' "$over100"
  printf '| longest function | %s (`%s`, %s) | 150 |\n' "$(cut -d' ' -f1 <<<"$lf")" \
    "$(cut -d' ' -f3 <<<"$lf")" "$(cut -d' ' -f2 <<<"$lf")"
  printf '| source files over 1,000 lines | %s | 0 |\n' "$bigfiles"
  printf '| longest source file | %s (`%s`) | 1,000 |\n' "$(awk '{print $1}' <<<"$lfile")" \
    "$(awk '{print $2}' <<<"$lfile")"
}
doc=$root/docs/architecture.md
begin='<!-- code_size.sh --table: begin -->' end='<!-- code_size.sh --table: end -->'
# doc_with TABLE: docs/architecture.md with TABLE between the markers.
doc_with() {
  grep -qxF "$begin" "$doc" && grep -qxF "$end" "$doc" ||
    { echo "code_size.sh: $doc has no code_size markers" >&2; exit 2; }
  awk -v b="$begin" -v e="$end" -v t="$1" '$0 == b { print; print t; skip = 1; next }
    $0 == e { skip = 0 } !skip { print }' "$doc"
}
case "$mode" in
  table) table; exit 0 ;;
  check-doc)
    if ! doc_with "$(table)" | cmp -s - "$doc"; then
      echo "code_size.sh: the size table in docs/architecture.md is out of date: run make docs" >&2
      diff <(doc_with "$(table)") "$doc" >&2 || true
      exit 1
    fi
    exit 0 ;;
  write-doc)
    new=$(doc_with "$(table)")
    printf '%s\n' "$new" > "$doc.tmp" && mv "$doc.tmp" "$doc"
    exit 0 ;;
esac

echo "functions: $functions; over 150 lines: $over150 (limit 0); over 100 lines: $over100 (limit 15)"
echo "longest function: $(head -1 <<<"$lengths")"
echo "source files over 1,000 lines: $bigfiles (limit 0); longest: $(head -1 <<<"$files" | sed "s#$src/##")"
echo "README.md: $readme lines (limit 400)"
if [ "$list" -gt 0 ]; then
  echo "the $list longest functions (lines, file, name):"
  head -"$list" <<<"$lengths" | sed 's/^/  /'
fi
if [ "$over150" -gt 0 ] || [ "$over100" -gt 15 ] || [ "$bigfiles" -gt 0 ] || [ "$readme" -gt 400 ]; then
  awk '$1 > 150 { print "  over 150: " $0 }' <<<"$lengths"
  awk '$1 > 1000 { print "  file over 1,000: " $0 }' <<<"$files"
  exit 1
fi
