#!/usr/bin/env bash
# code_size.sh — how long the functions and files of src/ are, measured with
# universal-ctags' function extents (first to last line, comments above not
# counted), and whether they keep the project's limits: no function over 150
# lines, at most 15 over 100, no source file over 1,000 lines; the README at
# most 400 lines.
#
#   scripts/code_size.sh [--list N] [SRC_DIR]   report; exit 1 when a limit
#                                              is broken. --list N: the N
#                                              longest functions too.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
list=0
if [ "${1:-}" = --list ]; then
  list=$2
  shift 2
fi
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
