#!/usr/bin/env bash
# layers.sh — the source tree's layers and the direction of their
# dependencies, checked and drawn.
#
#   scripts/dev/layers.sh check [BUILD_DIR]   every #include and, with a build
#                                         folder, every call between layers
#                                         goes downwards (exit 1 otherwise)
#   scripts/dev/layers.sh table [SRC_DIR]     markdown: each folder and the folders
#                                         its files include (from the includes)
#   scripts/dev/layers.sh dot [SRC_DIR]       the same as a Graphviz graph
#   scripts/dev/layers.sh graph BUILD_DIR [SRC_DIR]
#                                         Graphviz: the folders, an arrow where
#                                         one includes another's header (solid)
#                                         or only calls its functions (dashed),
#                                         labelled with the functions called
#   scripts/dev/layers.sh calls BUILD_DIR     markdown: the calls between folders
#                                         (symbols an object file needs from
#                                         another folder's, counted), from the
#                                         object files of any build
#
# The layers (a folder of src/ each) and what each may use are read from
# CMakeLists.txt's bbc_layer(NAME DEPS ...) lines, plus the layers above the
# library, named here: gl (the drawing layer) sees the public headers and the
# application layer; the tools see the application layer, the drawing layer
# and their common folder. include/ (the public headers) is open to all: the
# layers above the library (app, gl, the tools) include none of its internal
# headers and call libbbc's public functions (bbc_*), never its internal ones
# (bbc__*).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
mode=${1:-check}

# allowed LAYER: the folders (under src/) LAYER's files may include or call.
declare -A allowed
while read -r name deps; do
  allowed[$name]="$name $deps"
done < <(awk '/^bbc_layer\(/ { sub(/^bbc_layer\(/, ""); line = $0
           while (line !~ /SOURCES/ && (getline more) > 0) line = line " " more
           sub(/SOURCES.*/, "", line); gsub(/DEPS/, "", line); print line }' \
           "$root/CMakeLists.txt")
# The application layer links the library's layers (CMakeLists.txt) but,
# like every layer above the library, sees only its public headers and
# calls only its public functions: what bbcgen needs, a user can do.
allowed[app]="app"
allowed[gl]="gl app"
allowed[tools/bbcgen]="tools/bbcgen tools/common app gl"
allowed[tools/forest]="tools/forest tools/common gl"
allowed[tools/common]="tools/common"
allowed[tools/paramdoc]="tools/paramdoc"
# The public API (bbc_*, not bbc__*) of libbbc's layers is open to the layers
# above the library, and that of the forest runtime to those that draw it.
libbbc="base io raster planes cloud eval gen"
declare -A public
for l in "${!allowed[@]}"; do public[$l]=${allowed[$l]}; done
for l in app forest gl tools/bbcgen tools/forest tools/paramdoc; do public[$l]="${public[$l]} $libbbc"; done
public[gl]="${public[gl]} forest"
public[tools/forest]="${public[tools/forest]} forest"

# object_source BUILD OBJECT: the object's source path in the tree
# (src/...c.o), from where CMake puts it: BUILD/CMakeFiles/TARGET.dir/src/...
# (the checkout's own path may hold a folder named src, spaces or any letter).
object_source() {
  local rel=${2#"$1"/CMakeFiles/}
  echo "${rel#*.dir/}"
}
# layer_of FILE (a path under src/): its layer's folder.
layer_of() {
  local rel=${1#src/}
  case "$rel" in
    tools/*) rel=${rel#tools/} && echo "tools/${rel%%/*}" ;;
    *) echo "${rel%%/*}" ;;
  esac
}

# The include edges of a source tree: "FROM_FOLDER TO_FOLDER FILE HEADER",
# TO_FOLDER being where the header lives (include for the public headers,
# "system" for <...> headers is not listed, "?" when no folder has it).
include_edges() {
  local src=$1
  (cd "$src/.." && find src -name '*.[ch]' | sort) | while read -r f; do
    local from
    from=$(layer_of "$f")
    { grep -o '^#include "[^"]*"' "$src/../$f" || true; } | sed 's/#include "\(.*\)"/\1/' | while read -r h; do
      local to="?"
      if [ -f "$src/../include/$h" ]; then
        to=include
      elif [ -f "$src/../$(dirname "$f")/$h" ]; then
        to=$from
      else
        local hit
        hit=$(cd "$src/.." && find src -name "$(basename "$h")" | head -1)
        [ -n "$hit" ] && to=$(layer_of "$hit")
      fi
      echo "$from $to $f $h"
    done
  done
}

case "$mode" in
  check)
    build=${2:-}
    bad=0
    # 1. includes: no "../", and only the layer itself, the layers it may use
    #    and the public headers.
    if grep -rn '^#include "[^"]*\.\./' "$root/src" "$root/include"; then
      echo "layers: an include names a parent folder (above)" >&2
      bad=1
    fi
    while read -r from to file header; do
      [ "$to" = include ] && continue
      if [ "$to" = "?" ]; then
        echo "layers: $file includes \"$header\", found in no folder" >&2
        bad=1
      elif [ -z "${allowed[$from]+x}" ]; then
        echo "layers: $file is in src/$from, which is no layer (CMakeLists.txt, this script)" >&2
        bad=1
      elif ! grep -qw -- "$to" <<<"${allowed[$from]}"; then
        echo "layers: $file (layer $from) includes $header of layer $to: upwards or sideways" >&2
        bad=1
      fi
    done < <(include_edges "$root/src")
    # 2. calls: every symbol an object file needs from another layer is
    #    defined in a layer it may use (the objects in BUILD_DIR).
    if [ -n "$build" ]; then
      tmp=$(mktemp -d)
      trap 'rm -rf "$tmp"' EXIT
      # the objects of the current targets (a build folder may hold stale ones)
      find "$build"/CMakeFiles/bbc_*.dir "$build"/CMakeFiles/{bbcgl,bbcgen,forest,bbc_paramdoc}.dir \
        -path '*/src/*' -name '*.c.o' 2> /dev/null | while read -r o; do
        rel=$(object_source "$build" "$o")
        [ -f "$root/${rel%.o}" ] || continue # the object of a source that is gone
        printf '%s\n' "$(layer_of "${rel%.o}") $rel ${o#"$build"/}"
      done | sort > "$tmp/objects"
      [ -s "$tmp/objects" ] || { echo "layers: no object files in $build" >&2; exit 1; }
      while read -r layer rel o; do
        nm --defined-only -g "$build/$o" | awk -v l="$layer" '$2 ~ /[TDBRC]/ { print $3, l }'
      done < "$tmp/objects" | sort -u > "$tmp/defined"
      while read -r layer rel o; do
        nm -u "$build/$o" | awk -v l="$layer" -v o="$rel" '{ print $2, l, o }'
      done < "$tmp/objects" | sort > "$tmp/needed"
      join "$tmp/needed" "$tmp/defined" | while read -r sym from obj to; do
        [ "$from" = "$to" ] && continue
        can=${allowed[$from]:-}
        [[ $sym == bbc__* ]] || can=${public[$from]:-}
        if ! grep -qw -- "$to" <<<"$can"; then
          echo "layers: ${obj#src/} (layer $from) calls $sym of layer $to: upwards or sideways" >&2
          echo bad >> "$tmp/bad"
        fi
      done
      [ -f "$tmp/bad" ] && bad=1
    fi
    if [ $bad -eq 0 ]; then
      echo "layers: every include${build:+ and call} goes downwards"
    fi
    exit $bad
    ;;
  table | dot)
    src=${2:-$root/src}
    include_edges "$src" | awk '$1 != $2 { print $1, $2 }' | sort | uniq -c |
      if [ "$mode" = table ]; then
        echo "| folder | includes headers of (number of #include lines) |"
        echo "|---|---|"
        awk '{ e[$2] = e[$2] (e[$2] ? ", " : "") $3 " (" $1 ")" }
             END { for (k in e) print "| " k " | " e[k] " |" }' | sort
      else
        # every folder also includes include/ (the public headers): left out
        awk 'BEGIN { print "digraph layers {"
                     print "  rankdir=BT; nodesep=0.3; ranksep=0.45;"
                     print "  node [shape=box, style=rounded, fontname=\"Helvetica\", fontsize=11];"
                     print "  edge [fontname=\"Helvetica\", fontsize=9, color=\"#555555\"];" }
             $3 != "include" { printf "  \"%s\" -> \"%s\" [label=\"%d\"];\n", $2, $3, $1 }
             END { print "}" }'
      fi
    ;;
  graph)
    build=${2:?usage: scripts/dev/layers.sh graph BUILD_DIR [SRC_DIR]}
    src=${3:-$root/src}
    tmpg=$(mktemp)
    inc=$(include_edges "$src" | awk '$1 != $2 && $2 != "include" { print $1, $2 }' | sort -u)
    "$0" calls "$build" | awk -F'|' 'NR > 2 { gsub(/ /, "", $2); n = split($3, e, ",")
        for (i = 1; i <= n; i++) { split(e[i], p, "("); gsub(/ /, "", p[1]); sub(/\)/, "", p[2])
                                   print $2, p[1], p[2] + 0 } }' | sort > "$tmpg"
    # the library's folders (when it is cut into layers): a box around them
    lib=""
    for l in $libbbc; do [ -d "$src/$l" ] && lib="$lib $l"; done
    [ -d "$src/core" ] && lib="core io forest" # the tree before the layers: one library
    anchor=$(awk '{ print $1 }' <<< "$lib")
    echo "digraph layers {"
    echo "  rankdir=BT; nodesep=0.35; ranksep=0.5; compound=true;"
    echo "  node [shape=box, style=rounded, fontname=\"Helvetica\", fontsize=11];"
    echo "  edge [fontname=\"Helvetica\", fontsize=9, color=\"#444444\"];"
    if [ -n "$lib" ]; then
      echo "  subgraph cluster_lib { label=\"libbbc\"; fontname=\"Helvetica\";"
      echo "    fontsize=10; style=dashed; color=\"#888888\";"
      for l in $lib; do echo "    \"$l\";"; done
      echo "  }"
    fi
    # solid: a folder includes another's header (labelled with the calls)
    while read -r from to; do
      [ -n "$from" ] || continue
      n=$(awk -v f="$from" -v t="$to" '$1 == f && $2 == t { print $3 }' "$tmpg")
      echo "  \"$from\" -> \"$to\" [label=\"${n:-0}\"];"
    done <<< "$inc"
    # dashed: calls through a public header only; from outside the library
    # into it, one arrow to its box with the sum
    while read -r from to n; do
      grep -qx "$from $to" <<< "$inc" && continue
      if [ -n "$lib" ] && ! grep -qw -- "$from" <<< "$lib" && grep -qw -- "$to" <<< "$lib"; then
        echo "$from $n"
      else
        echo "  \"$from\" -> \"$to\" [label=\"$n\", style=dashed];" >&3
      fi
    done < "$tmpg" 3>&1 | awk -v a="$anchor" '/^  / { print; next } { s[$1] += $2 } END {
        for (f in s) printf "  \"%s\" -> \"%s\" [lhead=cluster_lib, label=\"%d\", style=dashed];\n", f, a, s[f] }'
    echo "}"
    rm -f "$tmpg"
    ;;
  calls)
    build=${2:?usage: scripts/dev/layers.sh calls BUILD_DIR}
    tmp=$(mktemp -d)
    trap 'rm -rf "$tmp"' EXIT
    find "$build/CMakeFiles" -path '*/src/*' -name '*.c.o' | while read -r o; do
      rel=$(object_source "$build" "$o")
      echo "$(layer_of "${rel%.o}") $o"
    done | sort -u -k2 > "$tmp/objects"
    while read -r layer o; do
      nm --defined-only -g "$o" | awk -v l="$layer" '$2 ~ /[TDBRC]/ { print $3, l }'
    done < "$tmp/objects" | sort -u > "$tmp/defined"
    while read -r layer o; do
      nm -u "$o" | awk -v l="$layer" '{ print $2, l }'
    done < "$tmp/objects" | sort -u > "$tmp/needed"
    echo "| folder | calls into (distinct functions) |"
    echo "|---|---|"
    join "$tmp/needed" "$tmp/defined" | awk '$2 != $3 { print $2, $3 }' | sort | uniq -c |
      awk '{ e[$2] = e[$2] (e[$2] ? ", " : "") $3 " (" $1 ")" }
           END { for (k in e) print "| " k " | " e[k] " |" }' | sort
    ;;
  *)
    echo "usage: scripts/dev/layers.sh check [BUILD_DIR] | table [SRC_DIR] | dot [SRC_DIR] |" \
      "graph BUILD_DIR [SRC_DIR] | calls BUILD_DIR" >&2
    exit 2
    ;;
esac
